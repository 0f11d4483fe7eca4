#pragma once
// The relative flexibility of the contact nodes and the correction it drives (thesis eqs. 2.26,
// 2.32-2.36; the operator D_a is described in Epaphe_SurfaceContact.hpp, point 3).
//
//   D_a          node a's motion relative to its surface, as entries (RelativeMotion): the node's DOFs
//                with weight 1, the grid nodes of a carried surface with -w_p w_q (motionEntries);
//   C_ab         = D_a F D_b^T, the relative flexibility of the active pairs (update);
//   dq           = F G lambda, G_a = D_a^T c_a, the correction (correction).
//
// F D_b^T is never formed. Its part on node b's own dense block is F's columns at b's DOFs, read in
// place; a carried surface on a diagonal block has no dense rows (its part is a scaling of D's
// entries). A node on a carried surface of a dense block (a "patch node") reads its surface's grid
// through the 4 x 4 control points of its patch: the control columns G = F (B_u x B_v)^T, made once
// (ControlColumns), give -R sum_rs b_r b_s G(:, ., i + r, j + s), 16 columns instead of up to 46 x 46
// grid nodes; and two patch nodes on one block meet through H = (B_u x B_v) G on the grid, the
// flexibility between control points (made once). Per step, Y_b = H's 48 columns at b's patch,
// weighted by its basis, on the control points the active patches read (U); then C_ab's grid part
// reads Y_b at a's 16 points.
#include "Epaphe_ContactDetection.hpp"
#include "Epaphe_DenseTypes.hpp"
#include "Epaphe_Flexibility.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_RelativeMotion.hpp"

#include <Kokkos_Core.hpp>

#include <memory>
#include <vector>

namespace epaphe {

/// One body's block of the system coordinates: q[offset, offset + size).
struct ContactBlock {
  /// q[offset, offset + size)
  ///@{
  int offset = 0, size = 0;
  ///@}
};

/// The contact nodes: per node its 3 DOF indices in the system q, its reference position, the block
/// of its body and a label (its node number in that body, for output).
struct ContactNodes {
  std::vector<int> dofs;    ///< 3 per node
  std::vector<double> X;    ///< 3 per node
  std::vector<int> block;   ///< 1 per node
  std::vector<int> labels;  ///< 1 per node
  /// Appends a node: its label, its block, its 3 DOF indices in q and its reference position (m).
  void add(int label, int blk, const int dof[3], const double x[3]) {
    labels.push_back(label);
    block.push_back(blk);
    for (int d = 0; d < 3; ++d) {
      dofs.push_back(dof[d]);
      X.push_back(x[d]);
    }
  }
};

/// The carried surfaces' grids and interpolation operators, concatenated: per surface s, grid DOFs
/// from gridOff(s), operators B_u, B_v (row-major) from opOff(s, 0..1); info(s) = {block (-1:
/// rigid), nu, nv, input nv, periodic u, periodic v}. Made once.
struct CarriedSurfaceViews {
  Kokkos::View<int* [3]> gridDof;  ///< [grid node] its 3 DOF indices in q (-1: clamped)
  Kokkos::View<int*> gridOff;      ///< [s] the first grid node of surface s in gridDof
  Kokkos::View<int* [2]> opOff;    ///< [s] where B_u and B_v of surface s start in `ops`
  Kokkos::View<double*> ops;       ///< the operators B_u, B_v of every carried surface, row-major
  Kokkos::View<int* [6]> info;     ///< [s] block, nu, nv, input nv, periodic u, periodic v
  int maxGrid[2] = {0, 0};         ///< largest nu, nv of a carried surface
  /// [winOff(s, dir) + i] the grid nodes whose weight at a foot point in interval i of direction dir
  /// of surface s can reach 1e-12 of the largest: {first, count}, a run of grid nodes (wrapping round
  /// a closed direction); the others' weights are below that and count as zero (motionEntries)
  Kokkos::View<int* [2]> window;
  Kokkos::View<int* [2]> winOff;  ///< [s][dir] where surface s's windows start in `window`
  int maxWindow[2] = {0, 0};      ///< the longest window of each direction
};

/// F times the carried surfaces' interpolation and its offsets, made once (offsets -1: none).
struct ControlColumns {
  /// per carried surface on a dense block: F (B_u x B_v) on the block's rows, column (e2, a, b) of the
  /// extended control grid (nuE x nvE) at off(s) + ((e2 nuE + a) nvE + b) n
  Kokkos::View<double*> G;
  Kokkos::View<long*> off;     ///< [s] where surface s's columns start in G (-1: none)
  Kokkos::View<int* [2]> dim;  ///< [s] nuE, nvE of surface s's extended control grid
  /// ...the flexibility between the control points of s and of s2, two such surfaces of one block:
  /// H(s, s2) = (B_u x B_v)_s F^T (B_u x B_v)_s2^T on their grids (F^T: what C needs, stored by its
  /// transpose), at hOff(s, s2): row 3 nvE A + 3 B + e2 ((A, B) a control point of s: a patch's
  /// 4 x 4 points are 4 runs of 12), column (e2', A', B') of s2 as in G
  Kokkos::View<double*> H;
  Kokkos::View<long**> hOff;  ///< [s][s2] where H(s, s2) starts (-1: none)
  /// per such surface: the active nodes' coefficients on its control columns at coefOff(s) +
  /// (e2 nuE + a) nvE + b (summed over the nodes, then applied by the correction)
  Kokkos::View<double*> coef;
  Kokkos::View<long*> coefOff;  ///< [s] where surface s's coefficients start in coef (-1: none)
  /// [s] the first surface carried by the same moving surface (s itself but for the copies a stage
  /// makes, one per instance, ContactSurface::onlyBlock): a copy shares its G, H and coefficients,
  /// which are made and applied once
  Kokkos::View<int*> canon;
  std::shared_ptr<void> memoryG;  ///< keeps G (a LargeTable, Epaphe_Parallel.hpp)
  std::shared_ptr<void> memoryH;  ///< keeps H (a LargeTable)
};

/// The relative flexibility of the contact nodes and the correction (see the file's opening comment):
/// D_k's entries, C_ab of the active pairs and dq = F G lambda.
class RelativeFlexibility {
public:
  /// Checks the blocks against the flexibility, each node's DOFs against its body's block, and the
  /// carried surfaces' grid DOFs (a surface carried by the body of a contact node is refused: no
  /// self-contact); a carried surface's `surface` is set to its `moving` one. The nodes' labels
  /// name them in messages.
  RelativeFlexibility(const Flexibility& flexibility, const std::vector<ContactBlock>& blocks,
                      const ContactNodes& nodes, std::vector<ContactSurface>& surfaces);

  /// For every node on a surface at the last detection `dv`: the entries of D_k, i.e. the spline
  /// weights of its foot point on a carried surface.
  void motionEntries(const DetectionViews& dv);
  /// Every C_ab is made anew at the next update() (D changed: a new step).
  void forgetPairs();
  /// C_ab of the pairs of the active nodes (`activeH`, uploaded to `active`), at the detection `dv`
  /// (its selected surfaces on the host: `surfH`). Pairs of nodes active at the last update() of
  /// this step keep theirs.
  void update(const std::vector<int>& activeH, const Kokkos::View<int*>& active,
              const Kokkos::View<int*>::HostMirror& surfH, const DetectionViews& dv);
  /// dq = F G lambda (eqs. 2.35-2.36) of the first nA nodes of `active` (ascending), their forces
  /// `force`, directions `dir` and selected surfaces `surf`; n: the system size.
  void correction(const Kokkos::View<int*>& active, int nA, const Kokkos::View<double*>& force,
                  const Kokkos::View<double* [3]>& dir, const Kokkos::View<int*>& surf, const DenseVector& dqOut,
                  int n) const;

  /// D_k's entries and C_ab, unmanaged (Epaphe_Parallel.hpp): views shared with the enforcement,
  /// copied by the step's kernels; this object keeps the memory.
  RelativeMotion motion() const {
    return RelativeMotion{unmanaged(D_.own), unmanaged(D_.grid), unmanaged(D_.pu),      unmanaged(D_.pv),
                          unmanaged(D_.wu),  unmanaged(D_.wv),   unmanaged(D_.gridDof), unmanaged(D_.rot)};
  }
  /// The least the last update() and a correction of its nodes must read of F (bytes): H between the
  /// control points U the active patches hold, (3 |U_s|) (3 |U_s2|) entries for each pair of surfaces of
  /// a block, F's columns at U for the correction (3 |U_s| a surface, its block's rows), and the
  /// correction's own columns of an active node on a dense block (3 a node, or the whole block when
  /// smaller). benchmark.step's bound counts it with the integration's matrices.
  double leastBytes() const { return leastBytes_; }
  /// An upper estimate of one RelativeMotion::apply (ns): about 1 ns per entry of D_k, its own and
  /// the longest windows' product on a carried surface (the kernels' work estimates: a loop over the
  /// nodes applying D pays for the thread team on a flexible casing, not on a rigid one).
  double applyNs() const { return 1.0 + static_cast<double>(carried_.maxWindow[0]) * carried_.maxWindow[1]; }
  /** \fn const Flexibility::Packed& RelativeFlexibility::flexibility() const
      The system flexibility F, packed as the kernels read it. */
  /// C_ab of the active pairs, unmanaged (see motion()).
  Kokkos::View<double** [3][3]> C() const { return unmanaged(C_); } const Flexibility::Packed& flexibility() const {
    return F_;
  }

private:
  void initBlocks(const std::vector<ContactBlock>& blocks, const Flexibility& flexibility);
  void initNodeBlocks(const ContactNodes& nodes);
  void initCarriedSurfaces(const ContactNodes& nodes, std::vector<ContactSurface>& surfaces);
  void controlColumns(const std::vector<ContactSurface>& surfaces);
  void gridColumns(const std::vector<ContactSurface>& surfaces, const std::vector<double>& G);
  void patchBases(const std::vector<int>& activeH, const Kokkos::View<int*>::HostMirror& surfH,
                  const DetectionViews& dv);
  void patchGroups(const std::vector<int>& activeH, const Kokkos::View<int*>::HostMirror& surfH);
  void relativeColumns(const Kokkos::View<int*>& active, int nA, const DetectionViews& dv);
  void relativePairs(const std::vector<int>& activeH, const Kokkos::View<int*>& active);

  Flexibility::Packed F_;
  Kokkos::View<int* [2]> blocks_;  // offset, size of each block
  Kokkos::View<int*> nodeBlk_;     // block of each node
  CarriedSurfaceViews carried_;
  ControlColumns ctrl_;
  RelativeMotion D_;                // D_k's entries: the node's DOFs, its grid nodes' weights, R of the surface
  Kokkos::View<double**> wu_, wv_;  // spline weights of the nodes' foot points on their windows (motionEntries)
  Kokkos::View<int*> patch_;        // per node: its surface's block if that has control columns, else -1
  // per patch node (made by patchBases for the active ones): its patch's cubic basis, b(u) then
  // b(v), and first control point
  Kokkos::View<double* [8]> pbasis_;
  Kokkos::View<int* [2]> pcell_;
  // per active patch node whose surface has H: its patch's 16 control points (r, s), b_r b_s and the
  // point's index in U (made by patchBases, read by relativePairs)
  Kokkos::View<double* [16]> pweight_;
  Kokkos::View<int* [16]> ppoint_;
  // U, the control points the active patches read (made by patchBases): per canonical surface s with
  // H, uMap_(uMapOff_(s) + A nvE + B) its index u in U (-1: not read); U's point u is point
  // uPoint_(u, 1) = A nvE + B of surface uPoint_(u, 0), in the order the active nodes' patches first
  // read them: active node a's and its predecessors' are U's first uEnd_(a)
  Kokkos::View<int*> uMap_;
  Kokkos::View<long*> uMapOff_;
  Kokkos::View<int* [2]> uPoint_;
  Kokkos::View<int*> uEnd_;
  int nU_ = 0;                  // U's points
  double leastBytes_ = 0;       // leastBytes() of the last patchBases()
  Kokkos::View<int*> rowEdge_;  // the correction's blocks of rows, one a thread: T + 1 edges (patchBases)
  // the active nodes by patch (patchBases): the nodes of group g, indices in the active list
  // (ascending), are groupNode_(groupStart_(g) .. groupStart_(g + 1) - 1), those on one surface whose
  // patches start at one control point (a node without a patch: a group of its own); groupEnd_(g): the
  // points of U its nodes' Y need (relativeColumns reads their rows of H once for the group)
  Kokkos::View<int*> groupNode_, groupStart_, groupEnd_;
  int nGroups_ = 0;
  std::vector<int> groupOf_, groupFirst_;
  // per active patch node: w[r'][3 s' + e2'] = b_r' b_s', as relativeColumns weighs a column's 4 runs of 12
  Kokkos::View<double* [48]> rowWeight_;  // patchGroups' work space (room for every node: constructor)
  // per active patch node k: Y_k(e2', u, e2) = sum_r's' b_r' b_s' H((u, e2), (e2', i_k + r', j_k + s'))
  // at 9 u + 3 e2' + e2 (relativeColumns)
  Kokkos::View<double**> Y_;
  Kokkos::View<double** [3][3]> C_;  // C_ab = D_a F D_b^T (active pairs)
  Kokkos::View<int*> known_;         // per node: its row and column of C made at this step
  Kokkos::View<int**> fixedC_;       // per pair: C_ab made from their own entries alone (constant)
  bool symmetric_ = false;           // F symmetric (to 1e-12 of its largest entry): C_ba = C_ab^T
};

}  // namespace epaphe
