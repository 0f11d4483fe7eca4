#pragma once
// Node k's motion relative to its surface, D_k v (Epaphe_SurfaceContact.hpp, point 3), as kernel
// accessors: the operator's entries, a column of F D^T, and the difference of two vectors.
#include "Epaphe_Flexibility.hpp"

#include <Kokkos_Core.hpp>

namespace epaphe {

/// D_k as a list of entries (DOF triple, weight): entry 0 the node itself with weight 1, then the
/// grid nodes (p, q) of a carried surface with weights -w_p w_q (DOF -1: clamped, fixed), whose motion
/// is in the carrying body's frame and turned into the node's by rot(k) (R of a turning surface, else
/// the identity). The grid part is kept as its two factors: the grid nodes along u with a weight w_p
/// (not zero, ascending p) and those along v; entry m >= 1 is the pair (a, b) = ((m - 1) / nv_k,
/// (m - 1) % nv_k) of them, in the order forEachEntry() visits. Copy into kernels by value.
struct RelativeMotion {
  Kokkos::View<int* [3]> own;        ///< [k] the node's DOF triple (entry 0)
  Kokkos::View<int* [4]> grid;       ///< [k] its surface's first grid node in gridDof, input nv, nu_k, nv_k
  Kokkos::View<int**> pu;            ///< [k][a] the a-th grid index along u with a weight
  Kokkos::View<int**> pv;            ///< [k][b] the b-th grid index along v with a weight
  Kokkos::View<double**> wu;         ///< [k][a] its weight w_p
  Kokkos::View<double**> wv;         ///< [k][b] its weight w_q
  Kokkos::View<int* [3]> gridDof;    ///< [grid node] its DOF triple in q (-1: clamped)
  Kokkos::View<double* [3][3]> rot;  ///< [k] R_k turning the grid's motion into the node's frame

  /// The number of entries of D_k (1: the node alone).
  KOKKOS_INLINE_FUNCTION int count(int k) const { return 1 + grid(k, 2) * grid(k, 3); }
  /// The node's own DOF d (entry 0's).
  KOKKOS_INLINE_FUNCTION int ownDof(int k, int d) const { return own(k, d); }
  /// Calls f(m, dof, w) for every entry m of D_k in order: dof its DOF triple, w its weight.
  template <class Fn>
  KOKKOS_INLINE_FUNCTION void forEachEntry(int k, const Fn& f) const {
    f(0, &own(k, 0), 1.0);
    const int first = grid(k, 0), inNv = grid(k, 1), nu = grid(k, 2), nv = grid(k, 3);
    int m = 1;
    for (int a = 0; a < nu; ++a) {
      const int row = first + pu(k, a) * inNv;
      const double w = -wu(k, a);
      for (int b = 0; b < nv; ++b, ++m) f(m, &gridDof(row + pv(k, b), 0), w * wv(k, b));
    }
  }
  /// r = D_k v for any accessor v(i) of the system coordinates:
  ///   r_d = v(node DOF d) + sum_e R_k(d, e) sum_(m >= 1) w_m v(grid DOF (m, e)).
  template <class V>
  KOKKOS_INLINE_FUNCTION void apply(int k, const V& v, double r[3]) const {
    double g[3] = {0.0, 0.0, 0.0};
    const int first = grid(k, 0), inNv = grid(k, 1), nu = grid(k, 2), nv = grid(k, 3);
    for (int a = 0; a < nu; ++a) {
      const int row = first + pu(k, a) * inNv;
      const double wa = -wu(k, a);
      for (int b = 0; b < nv; ++b) {
        const double w = wa * wv(k, b);
        const int* dof = &gridDof(row + pv(k, b), 0);
        for (int e = 0; e < 3; ++e)
          if (dof[e] >= 0) g[e] += w * v(dof[e]);
      }
    }
    for (int d = 0; d < 3; ++d) r[d] = v(own(k, d)) + rot(k, d, 0) * g[0] + rot(k, d, 1) * g[1] + rot(k, d, 2) * g[2];
  }
  /// The entry of D_k in row e at DOF (m, e2), given its weight w: w at the node's own DOF e (m = 0),
  /// w R_k(e, e2) at a grid node's (turned into the node's frame).
  KOKKOS_INLINE_FUNCTION double coefficient(int k, int m, double w, int e, int e2) const {
    return m == 0 ? (e2 == e ? w : 0.0) : w * rot(k, e, e2);
  }
};

/// Column 3 k + e of F D^T as an accessor of the system rows, for RelativeMotion::apply, at the
/// rows D_a reads for another node a: a's own DOFs and its surface's grid DOFs. On node k's own
/// dense block it is w_0 times F's column at k's DOF e (F itself); on another dense block it is not
/// read (a's body carries no surface, SurfaceContact refuses that, so no patch of k's is on a's
/// block; a's grid DOFs on a dense block make a a patch node, whose C uses T); in a diagonal block
/// of F, F_ii times the weights of node k's entries at DOF i (the only rows where D_k^T is not zero).
/// Made per item inside kernels: it refers to the kernel's own copies, copies no view.
struct FlexibleColumn {
  const Flexibility::Packed& F;         ///< the flexibility, packed
  const RelativeMotion& D;              ///< the entries of D
  const Kokkos::View<int*>& nodeBlock;  ///< [k] the block of node k
  /// node k and direction e of the column
  ///@{
  int k, e;
  ///@}
  /// F D^T (i, 3 k + e).
  KOKKOS_INLINE_FUNCTION double operator()(int i) const {
    if (F.denseRow(i) >= 0) {
      const int own = nodeBlock(k), b0 = F.blocks(own, 0), n = F.blocks(own, 1);
      return i >= b0 && i < b0 + n  // (a dense row: its block is dense)
                 ? F.dense(F.start(own) + static_cast<std::size_t>(D.ownDof(k, e) - b0) * n + (i - b0))
                 : 0.0;
    }
    double s = 0.0;
    const RelativeMotion& Dk = D;
    const int node = k, dir = e;
    D.forEachEntry(k, [&](int m, const int* dof, double w) {
      for (int e2 = 0; e2 < 3; ++e2)
        if (dof[e2] == i) s += Dk.coefficient(node, m, w, dir, e2);
    });
    return F.diag(i) * s;
  }
};

/// a(i) - b(i) as an accessor.
template <class V>
struct Difference {
  /// the two vectors
  ///@{
  V a, b;
  ///@}
  /// a(i) - b(i).
  KOKKOS_INLINE_FUNCTION double operator()(int i) const { return a(i) - b(i); }
};

}  // namespace epaphe
