#pragma once
// Contact detection (thesis section 2.5.1, eq. 2.28): where each contact node is, which surface
// it faces, its closest point there and its gap, for any number of surfaces.
//
// One fused kernel per step over blocks of 16 contact nodes does, per node k:
//   x_k = X_k + u_k(q)                        (contact nodes are retained DOFs)
//   for each surface s:  x_s = c_s + R_s^T (x_k - c_s)   (a turning surface: its own frame)
//                        Newton-Raphson closest point from the last foot point (warm start),
//                        made for the block's nodes on s four at a time (closestPoints)
//   select the surface of smallest gap among those the node is not beyond (an open edge),
//   and turn its normal and foot point back into the bodies' frame (n = R n_s).
// Carried surfaces (on a flexible body) are rebuilt from their moved grid nodes before it.
//
// Model only what the step needs: a node whose last projection found it at gap g_k > 0 from every
// surface (foot point inside every surface, Newton converged) cannot touch any before it has moved
// by g_k relative to them. Its gap is a 1-Lipschitz function of its position on a surface it faces
// (a signed distance), so while
//     g_k - 2 (|x_k - x_k,last| + sum_s [|omega_s| (t - t_last) r_s + (T_s - T_s,last)]) > 0
// (r_s: the largest distance of surface s's control points from its axis, or, for a rigid surface
// that is a radial graph about it, the sampled slope max |d rho / d phi| of that graph (a casing out
// of round by a clearance law: the law's slope, 1/840 of the radius on rotor 37); T_s: how far a carried
// surface's points can have moved by deformation, below; 2: a safety factor for the foot point's
// motion near an edge), the node is out of contact whatever its projection would give: it skips its
// Newton projection and keeps its last foot point and gap, and `skipped(k)` is set with the lower
// bound `bound(k)` of its true gap. A consumer that needs such a node's exact gap (the Lagrange
// add-pass test when the bound does not decide) calls refine(). A carried surface deforms: a point
// S(u, v) = sum N_i(u) N_j(v) P_ij of it moves at most max_ij |dP_ij| in a step (the basis is
// non-negative and sums to 1, eq. 2.22), so T_s adds that up over the steps (and r_s is its control
// points' current largest radius). Output steps (measureGaps) project every node, so written gaps
// are exact; checkpoints keep the skipping's state (skipState), so restarts are bit for bit.
// A coated surface (ContactSurface::coating) is seen through its coating: the gap is to the current
// profile, t - u_p in front of the surface at the element under the foot point; its skipping bound
// uses the unworn thickness t (the profile only recedes).
// Warm start: the last foot point moved on by its rate between the two projections before (a surface
// turning past the node, a node sliding along it), so that Newton starts within the step's
// vibration of the answer instead of a step's travel away (rotor 37: 2.95 -> 2.19 iterations).
#include "Epaphe_AbradableCoating.hpp"
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_SpeedLaw.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_DenseTypes.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_ParameterList.hpp>

#include <array>
#include <vector>

namespace epaphe {

/// How far a closed rigid surface can move relative to any point, per radian it turns about `axis`
/// (unit) through `center`, when it is a radial graph rho(phi, z) about that axis (closed around it
/// at constant z, once around): 1.5 max |d rho / d phi|, sampled 16 x 16 a patch; +infinity otherwise.
/// The detection's bound on a turning surface's motion (see above).
double radialTurnRate(const BSplineSurface& surface, const std::array<double, 3>& axis,
                      const std::array<double, 3>& center);

/// A surface the nodes may touch. Rigid: `surface` only. Carried by a flexible body: `moving` is
/// the same surface (rebuilt at each step, in its body's frame), `block` its body, and per grid node
/// of the input layout (node (i, j) at i * inputNv + j) its 3 DOF indices in q (-1: a clamped DOF)
/// and its reference position.
struct ContactSurface {
  /// The surface as built (rigid), or at its reference configuration (carried).
  const BSplineSurface* surface = nullptr;
  BSplineSurface* moving = nullptr;  ///< a carried surface, rebuilt at each step; null when rigid
  int block = -1;                    ///< the body carrying it (-1: rigid)
  std::vector<int> gridDofs;         ///< per grid node, its 3 DOF indices in q (-1: clamped)
  std::vector<double> gridX;         ///< per grid node, its reference position, 3 per node (m)
  /// A surface (rigid or carried) may turn about `axis` (unit) through `center` at `omega` rad/s in
  /// the contact nodes' frame (thesis section 3.3: the contact zone of a rotating blade turns, the
  /// blade stays): at time t (setTime) it is its surface rotated by omega t + phase. Nodes are
  /// projected in the surface's frame (x_s = c + R^T (x - c)); normals and foot points are turned
  /// back; a carrying body's grid motion is turned by R in D_a (see Epaphe_SurfaceContact.hpp).
  double omega = 0.0;
  double phase = 0.0;  ///< angle (rad) at t = 0: the surface is turned by omega t + phase
  /// A run-up (law.ramp): the surface is turned by law.angle(t) + phase instead (Epaphe_SpeedLaw.hpp).
  SpeedLaw law{};
  /// the turning axis (unit) and a point of it (m)
  ///@{
  std::array<double, 3> axis{0.0, 0.0, 1.0}, center{0.0, 0.0, 0.0};
  ///@}
  /// An abradable coating in front of a rigid surface (Epaphe_AbradableCoating.hpp; elements {0, 0}:
  /// none): the node's gap is measured to the coating's current profile.
  CoatingMaterial coating{};
  /// The surface is seen by the nodes of this block only (-1: by every node). An instance of a
  /// stage ('Instances') sees its own copy of each surface, turned back by the instance's pose.
  int onlyBlock = -1;
};

/// The closest-point Newton iterations and the detection's options (the deck's Contact keys).
struct DetectionOptions {
  double nrTolerance = 1e-8;    ///< crit_NR: Newton stop on the parameter step
  int nrMaxIterations = 50;     ///< Newton's iteration limit
  double edgeTolerance = 1e-3;  ///< a node beyond an open edge by less (in patches) still touches
  bool skipDistant = true;      ///< skip the projection of nodes certified out of contact
};

/// What a detection cannot see, guarded (Epaphe_ContactGuards.hpp): a node moving farther than a
/// patch per step, and nodes inside a surface at t = 0.
enum class InitialPenetration { Refuse = 0, ResolveGently = 1 };
/// What the run guards allow (the deck's Contact keys).
struct GuardOptions {
  /// A node moving farther than the smallest patch in a step is a warning, not an error.
  bool allowLargeMotion = false;
  /// Refuse nodes inside a surface at t = 0, or push them out over a ramp.
  InitialPenetration initialPenetration = InitialPenetration::Refuse;
  double rampTime = 0.0;  ///< T (s); 0: 100 time steps
};
/// The guards' keys of a validated Contact list (see ContactDetection::getValidParameters).
GuardOptions guardOptions(const Teuchos::ParameterList& contact);
/// The detection's keys of a Contact list holding them (see ContactDetection::getValidParameters).
DetectionOptions detectionOptions(const Teuchos::ParameterList& contact);

/// The skipping of nodes certified out of contact, per node k unless said: position, time and
/// smallest gap of the last projection; eligible: it may be skipped.
struct SkipViews {
  Kokkos::View<double* [3]> xLast;  ///< [k] position at the last projection
  /// [k] time and smallest gap of the last projection
  ///@{
  Kokkos::View<double*> tLast, gLast;
  ///@}
  /// [k] may be skipped; skipped this step; to project in refine()
  ///@{
  Kokkos::View<int*> eligible, skipped, refine;
  ///@}
  Kokkos::View<double*> bound;        ///< a lower bound of a skipped node's gap
  Kokkos::View<double*> travel;       ///< [s] T_s: the carried surface's summed largest control-point motion
  Kokkos::View<double**> travelLast;  ///< [k][s] T_s at the node's last projection
  /// [k] how far the last correction moved a node out of contact, |D_k dq| (SurfaceContact's
  /// corrected gaps): a node is skipped only when its bound exceeds twice it, so that the step's
  /// correction rarely sends it to refine()
  Kokkos::View<double*> correctionMove;
};

/// Everything the detection kernel reads and writes, allocated once at setup; copied by value into
/// the kernel (views only). Per node k unless said; per surface s for the surface data.
struct DetectionViews {
  /// A view of 3-vectors, [k][3].
  using Vec3 = Kokkos::View<double* [3]>;
  Kokkos::View<int* [3]> dof;         ///< q index of each contact node DOF
  Vec3 X;                             ///< reference positions
  Vec3 x;                             ///< positions at the last detect()
  Kokkos::View<SurfaceView*> surf;    ///< [s] the surfaces (a carried one re-copied after its update)
  Kokkos::View<double* [3][3]> rot;   ///< [s] R(omega t + phase)
  Kokkos::View<double* [9]> turn;     ///< [s] omega, axis (3), center (3), r_s, turning (1) or not (0)
  Kokkos::View<int*> onlyBlock;       ///< [s] ContactSurface::onlyBlock
  Kokkos::View<int*> block;           ///< [k] the node's block (body)
  Kokkos::View<double** [2]> uv;      ///< [k][s] warm start (NaN: cold start from the nearest grid node)
  Kokkos::View<double** [2]> uvRate;  ///< [k][s] d(u, v)/dt of the foot point between its last two projections
  Kokkos::View<Projection**> found;   ///< [k][s] this detection's projections (the kernel's scratch)
  Kokkos::View<double*> gap;          ///< selected gap (1e300: beyond every surface)
  Kokkos::View<int*> selected;        ///< selected surface (-1: none)
  Vec3 normal;                        ///< unit normal n_k at the foot point, bodies' frame
  Kokkos::View<double* [2]> foot;     ///< foot point parameters (u, v) on the selected surface
  Vec3 footX;                         ///< foot point, bodies' frame
  Kokkos::View<int*> iterations;      ///< Newton iterations of this step (max over surfaces; 0: skipped)
  SkipViews skip;                     ///< the skipping of distant nodes
  /// initial penetrations resolved gently (setPenetrationOffsets): the depth d_k >= 0 added to the
  /// gap on surface offsetSurf(k) (-1: none), ramped down to 0 at the ramp's end
  Kokkos::View<double*> offset;
  Kokkos::View<int*> offsetSurf;  ///< [k] the surface the offset applies to (-1: none)
  /// abradable coatings: the gap on a coated surface is to its profile, the surface moved towards
  /// the node by t - u_p of the element under the foot point (element(k), -1: none); skipping bounds
  /// use the unworn profile (t), which no node can have passed unprojected
  CoatingViews coat;
  Kokkos::View<int*> element;  ///< [k] the coating element under the foot point (-1: none)

  /// The same views, unmanaged (Epaphe_Parallel.hpp: unmanaged): what the step copies into its
  /// kernels, counting no references; this object keeps the memory.
  DetectionViews untracked() const;
};

/// Contact detection (see the file's opening comment): closest points and gaps of the contact nodes on
/// every surface, with the skipping of distant nodes, warm starts and initial-penetration offsets.
class ContactDetection {
public:
  /// `dofs` and `X`: 3 per node; `blocks`: 1 per node, the block (body) of each, which a surface's
  /// onlyBlock selects (empty: every node in block 0). Surfaces outlive this object.
  ContactDetection(const std::vector<int>& dofs, const std::vector<double>& X, std::vector<ContactSurface> surfaces,
                   const DetectionOptions& options, const std::vector<int>& blocks = {});
  /// Its deck keys in the Contact list: Newton tolerance, Newton max iterations, Edge tolerance,
  /// Skip distant nodes, and the guards' Allow large motion per step, Initial penetration,
  /// Penetration ramp time.
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();

  /// The contact nodes' reference positions X (3 per node), e.g. a rotating body's static position
  /// as its speed changes; the skipping sees the change as a motion of the nodes.
  void setReferencePositions(const std::vector<double>& X);
  /// Detects at q and time t. `all`: project every node (no skipping).
  void detect(const DenseVector& q, double t, bool all);
  /// Projects the nodes flagged in views().skip.refine (at the q and t of the last detect()), clears
  /// the flags and their `skipped` state; returns how many.
  int refine();
  /// Every node projects at the next detect() (a changed warm start, initial penetrations).
  void reset();
  /// The skipping's state carried from one step to the next, for checkpoints (per node: eligible,
  /// position, time, gap and T_s at its last projection, the foot points' rates; T_s and each
  /// carried surface's last control points): restored by setSkipState, a restart skips exactly as
  /// the uninterrupted run.
  std::vector<double> skipState() const;
  /// Restores the state skipState() returned.
  void setSkipState(const std::vector<double>& state);

  /// The views the kernels read and write (gaps, normals, foot points, skipping).
  const DetectionViews& views() const { return v_; }
  /// The same views, unmanaged (DetectionViews::untracked(), made once: the views are not reallocated).
  const DetectionViews& untrackedViews() const { return u_; }
  /// The number of contact nodes.
  int numNodes() const { return static_cast<int>(v_.gap.extent(0)); }
  /// The number of surfaces.
  int numSurfaces() const { return static_cast<int>(surfaces_.size()); }
  /// The surfaces, in the contact's order.
  const std::vector<ContactSurface>& surfaces() const { return surfaces_; }
  /// The smallest distance between neighbouring grid nodes of any surface (its patch size, at the
  /// reference configuration), and that surface's index: the scale of the run guards
  /// (Epaphe_ContactGuards.hpp).
  double smallestPatch() const { return smallestPatch_; }
  /// The index of the surface of smallestPatch().
  int smallestPatchSurface() const { return smallestPatchSurface_; }
  /// Initial penetrations resolved gently: node k's gap on the surface selected by the last
  /// detect() is raised by depth[k] (0: none) times (1 - t / rampEnd) while t < rampEnd, so the
  /// enforcement pushes the bodies apart over the ramp instead of in one step. Such nodes are never
  /// skipped during the ramp. The gaps written during the ramp are these effective gaps.
  void setPenetrationOffsets(const std::vector<double>& depth, double rampEnd);
  /// The time the initial penetrations' offsets vanish (0: none were set).
  double penetrationRampEnd() const { return rampEnd_; }
  /// Nodes projected by the last detect() (with refine()), and their Newton iterations (max).
  int lastProjected() const { return lastProjected_; }
  /// Projections (a node on a surface) of the last detect() (with refine()): a projected node counts
  /// once per surface it is projected on, every surface but another instance's copy.
  long long lastProjections() const { return lastProjections_; }
  /// The projections of a detect() that skips no node.
  long long projectionsUnskipped() const { return projectionsUnskipped_; }
  /// The largest Newton iteration count of the last detect().
  int lastIterations() const { return lastIterations_; }
  /// Warm starts, surface s and node k at 2 (s numNodes() + k) (see SurfaceContact::warmStarts).
  std::vector<double> warmStarts() const;
  /// Restores warm starts from warmStarts().
  void setWarmStarts(const std::vector<double>& uv);

private:
  void rebuildCarried(const DenseVector& q);
  void project(bool all, bool refineOnly);

  DetectionOptions opt_;
  std::vector<ContactSurface> surfaces_;
  DetectionViews v_;
  DetectionViews u_;                                       // v_.untracked()
  std::vector<Kokkos::View<double*[3]>> gridX_, gridPos_;  // [s] carried surfaces' grid (empty: rigid)
  std::vector<Kokkos::View<int* [3]>> gridDof_;
  std::vector<Kokkos::View<double* [3]>::HostMirror> gridPosH_;
  std::vector<std::vector<double>>
      ctrlLast_;  // [s] a carried surface's control points at the last rebuild (empty: none yet)
  double time_ = 0.0;
  double rampEnd_ = 0.0;  // offsets vanish at this time (0: no offsets)
  double smallestPatch_ = 1e300;
  int smallestPatchSurface_ = -1;
  int lastProjected_ = 0, lastIterations_ = 0;
  std::vector<int> surfacesOf_;  // per node: the surfaces it is projected on
  long long lastProjections_ = 0, projectionsUnskipped_ = 0;
  bool anyCarried_ = false;
  DenseVector q_;  // the coordinates of the last detect() (for refine())
};

}  // namespace epaphe
