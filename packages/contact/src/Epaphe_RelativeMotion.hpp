#pragma once
// Node k's motion relative to its surface, D_k v (Epaphe_SurfaceContact.hpp, point 3), as kernel
// accessors: the operator's entries, a column of F D^T, and the difference of two vectors.
#include "Epaphe_Flexibility.hpp"

#include <Kokkos_Core.hpp>

namespace epaphe {

/// D_k as a list of entries (DOF triple, weight): the node itself with weight 1, then the grid
/// nodes of a carried surface with weights -w_p w_q (DOF -1: clamped, fixed), whose motion is in
/// the carrying body's frame and turned into the node's by rot(k) (R of a turning surface, else the
/// identity). Copy into kernels by value.
struct RelativeMotion {
  Kokkos::View<int** [3]> dof;       ///< [k][m] the DOF triple of entry m (-1: clamped)
  Kokkos::View<double**> w;          ///< [k][m] the weight of entry m
  Kokkos::View<int*> count;          ///< [k] the number of entries
  Kokkos::View<double* [3][3]> rot;  ///< [k] R_k turning the grid's motion into the node's frame

  /// r = D_k v for any accessor v(i) of the system coordinates:
  ///   r_d = v(node DOF d) + sum_e R_k(d, e) sum_(m >= 1) w_m v(grid DOF (m, e)).
  template <class V>
  KOKKOS_INLINE_FUNCTION void apply(int k, const V& v, double r[3]) const {
    double g[3] = {0.0, 0.0, 0.0};
    for (int m = 1; m < count(k); ++m)
      for (int e = 0; e < 3; ++e) {
        const int i = dof(k, m, e);
        if (i >= 0) g[e] += w(k, m) * v(i);
      }
    for (int d = 0; d < 3; ++d)
      r[d] = w(k, 0) * v(dof(k, 0, d)) + rot(k, d, 0) * g[0] + rot(k, d, 1) * g[1] + rot(k, d, 2) * g[2];
  }
  /// The entry of D_k in row e at DOF (m, e2): w_0 at the node's own DOF e, w_m R_k(e, e2) at a
  /// grid node's (turned into the node's frame).
  KOKKOS_INLINE_FUNCTION double coefficient(int k, int m, int e, int e2) const {
    return m == 0 ? (e2 == e ? w(k, 0) : 0.0) : w(k, m) * rot(k, e, e2);
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
                 ? D.w(k, 0) * F.dense(F.start(own) + static_cast<std::size_t>(D.dof(k, 0, e) - b0) * n + (i - b0))
                 : 0.0;
    }
    double s = 0.0;
    for (int m = 0; m < D.count(k); ++m)
      for (int e2 = 0; e2 < 3; ++e2)
        if (D.dof(k, m, e2) == i) s += D.coefficient(k, m, e, e2);
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
