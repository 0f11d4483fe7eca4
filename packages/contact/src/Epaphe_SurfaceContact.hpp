#pragma once
// Contact of the nodes of one or more reduced bodies with B-spline surfaces, rigid or carried by
// another flexible body (thesis section 2.5). All bodies' reduced coordinates are stacked in one
// system vector q (body b at q[offset_b, offset_b + size_b)), whose flexibility F is block diagonal
// (Epaphe_Flexibility.hpp: a block is dense, or diagonal for a full body with lumped mass).
// After the explicit predictor has produced q* (eq. 2.2 without contact):
//
//   1. the surfaces carried by a body are rebuilt from its moved grid nodes (BSplineSurface::update,
//      no refactorisation), and the positions of the contact nodes x_a = X_a + u_a(q*) are formed
//      (contact nodes and surface grid nodes are retained DOFs);
//   2. closest point on each surface by Newton-Raphson, warm-started (section 2.5.1); the gap
//      g*_a = (x_a - S(u_a, v_a)) . n_a, n_a the unit outward normal (eq. 2.28);
//   3. node a's motion relative to the surface is D_a q, D_a the 3 x N operator
//          D_a q = u_a(q) - sum_(p,q) w_p(u_a) w_q(v_a) u_pq(q),
//      u_pq the grid nodes of a carried surface and w_p w_q the weights of the interpolating spline
//      at the foot point, S = sum w_p w_q P_pq (rows of the operators B_u, B_v of eq. 2.26 contracted
//      with the cubic basis, eq. 2.22; weights below 1e-12 of the largest are dropped); a rigid
//      surface has no second term. All that follows uses D_a, so a node on a rigid surface and two
//      flexible bodies in contact (eq. 2.33: both flexibilities in MC) are the same code. A surface
//      may turn (thesis section 3.3: the contact zone turns, the bodies stay): at time t it is its
//      reference (or its carrying body's moved grid) turned by R(t) about its axis. The node is
//      projected in the surface's frame, x_s = c + R^T (x_a - c), and the normal and foot point are
//      turned back (n_a = R n_s). Each body vibrates in its own frame, so the grid motion of a
//      turning carried surface is turned into the node's frame:
//          D_a q = u_a(q) - R sum_(p,q) w_p w_q u_pq(q);
//      the node's correction then acts along n_a, the carrying body's along R^T n_a = n_s, its own
//      frame's normal;
//   4. the correction direction of each node (VCT, eq. 2.31): c_a = n_a + mu_a t_a; frictionless
//      (mu = 0, or no q_n given) c_a = n_a exactly;
//   5. for the active nodes (g*_a < 0), the forces lambda >= 0:
//        Lagrange (forward increment, Carpenter, Taylor & Katona 1991), eqs. 2.30-2.33:
//          MC lambda = -g*,  MC_ab = n_a^T C_ab c_b,  C_ab = D_a F D_b^T,  F = (M/h^2 + D/2h)^{-1}
//          (optionally lumped: MC_aa = sum_b MC_ab), nodes with lambda_a < 0 released and the
//          system solved again; the normal gap is closed exactly;
//        penalty, eq. 2.34:  lambda_a = k_p (-g*_a);
//   6. the correction q = q* + F G lambda (eqs. 2.35-2.36), G_a = D_a^T c_a: the node is pushed
//      along c_a and the surface's grid nodes back along -w c_a.
//
// Coulomb friction (mu > 0 and q_n given): a joint solve over the active set (F_ab below is C_ab,
// the relative flexibility, and d_a the relative motion D_a (q* - q_n)). Per active node a,
// 3 unknowns: lambda_a and the tangential force s_a = s1 e1_a + s2 e2_a in the tangent plane of n_a
// (e1, e2: an orthonormal basis of it); the force on the node is f_a = lambda_a n_a + s_a, and the
// correction moves node a by sum_b F_ab f_b. With d_a = u_a(q*) - u_a(q_n) the predicted motion:
//   normal:   g*_a + n_a^T sum_b F_ab f_b = 0 (Lagrange; penalty: lambda_a = k_p (-g*_a) instead,
//             the same tangential treatment with that known normal force);
//   stuck:    e_i,a^T (d_a + sum_b F_ab f_b) = 0, i = 1, 2: no tangential motion over the step
//             relative to q_n, whatever the coupling through F;
//   sliding:  s_a = mu lambda_a t_a, t_a the unit friction direction (against the sliding).
// The system is solved in the unknowns not known beforehand (a sliding node's s_a is mu lambda_a t_a,
// a penalty node's lambda_a is k_p (-g*_a): both move to the right-hand side), nA + 2 x (stuck
// nodes) for Lagrange, by Gaussian elimination with partial pivoting (LAPACK's GESV above 64).
// Classification, repeated while any node's state or sliding direction changes (at most 20 passes, then the pass with
// the fewest changes is solved again and kept): stuck -> sliding when |s_a| > mu lambda_a, with t_a = s_a / |s_a|;
// sliding -> stuck when the trial force s_trial = mu lambda_a t_a - K_a^{-1} w_a
// (w_a: tangential part of the corrected motion, K_a = [e_i^T F_aa e_j] the node's 2 x 2 tangential
// flexibility: the force that would stop it, the others' forces held) lies in the cone
// |s_trial| <= mu lambda_a, else t_a = (alpha I + mu lambda_a K_a)^{-1} K_a s_trial with |t_a| = 1, the
// direction against the node's slip (docs/theory/contact.md, eq. (74); s_trial / |s_trial| when K_a is
// isotropic). A node
// switching sliding -> stuck more than twice in one solve keeps sliding (anti-cycling). The solve
// starts with the nodes that move tangentially (|d_t| > 1e-14 of their scale) sliding against
// that motion, the others stuck (so a node with no predicted motion still gets friction). After
// the solve, the force of each node is stored as lambda_a c_a, c_a = n_a + mu_a t_a (t_a: unit
// direction of s_a, mu_a = |s_a| / lambda_a <= mu), used by the correction and workIncrement().
//
// The per-node work (positions, projection, directions, friction system, contact matrix rows,
// correction) runs as named Kokkos kernels on the default execution space (OpenMP).
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_ContactDetection.hpp"
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_Flexibility.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_RelativeFlexibility.hpp"
#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace epaphe {

class CoatingContact;

/// The contact operator: the detection (ContactDetection), the relative flexibility and the
/// correction (RelativeFlexibility), the law (ContactEnforcement) and the active set's passes.
class SurfaceContact {
public:
  /// The general form: nodes of any bodies against rigid or carried surfaces. `flexibility` is the
  /// system's F = (M/h^2 + D/2h)^{-1}, block diagonal with the blocks `blocks` (each dense, or
  /// diagonal for a full body with lumped mass). Surfaces outlive this object. A surface carried by
  /// the body of a contact node is refused (no self-contact).
  SurfaceContact(ContactNodes nodes, std::vector<ContactSurface> surfaces, std::vector<ContactBlock> blocks,
                 const ContactOptions& options, const Flexibility& flexibility);
  /// One body against rigid surfaces: `nodes` of `body` (each must have its 3 DOFs among the
  /// reduced coordinates); `flexibility`: the body's F, size x size.
  SurfaceContact(const ReducedModel& body, const std::vector<int>& nodes, std::vector<const BSplineSurface*> surfaces,
                 const ContactOptions& options, const Flexibility& flexibility);

  /// Time of the configuration the next correct() / measureGaps() sees (turning surfaces).
  void setTime(double t) { time_ = t; }

  /// Detects contact at the predicted q* (`qPredicted`) and corrects it in place to q_{n+1};
  /// `qCurrent` = q_n gives each node's motion over the step, hence the friction direction t_a.
  void correct(const DenseVector& qPredicted, const DenseVector& qCurrent, CostSplit& cost);
  /// The same without q_n, i.e. with no motion over the step: no friction direction (t_a = 0,
  /// c_a = n_a) whatever the friction coefficient is.
  void correct(const DenseVector& q, CostSplit& cost);

  /// Gaps of the nodes at q without correcting anything (for output); gap() then returns them.
  /// Every node is projected: written gaps are exact whatever the skipping.
  void measureGaps(const DenseVector& q, CostSplit& cost);
  /// The next step starts as a restart would: friction's classification starts cold (called at
  /// checkpoints, so that restarts are bit for bit; the detection's state is checkpointed instead).
  void resetWarmStarts() { enforcement_->reset(); }
  /// The detection's skipping state (ContactDetection::skipState), for checkpoints.
  std::vector<double> detectionState() const { return detection_->skipState(); }
  /// Restores the state detectionState() returned.
  void setDetectionState(const std::vector<double>& state) { detection_->setSkipState(state); }
  /// The contact nodes' reference positions (3 per node, in the order of ContactNodes).
  void setReferencePositions(const std::vector<double>& X) { detection_->setReferencePositions(X); }
  /// The detection.
  const ContactDetection& detection() const { return *detection_; }
  /// See ContactDetection::setPenetrationOffsets (initial penetrations resolved gently).
  void setPenetrationOffsets(const std::vector<double>& depth, double rampEnd) {
    detection_->setPenetrationOffsets(depth, rampEnd);
  }
  /// Projections of a node on a surface done and skipped by the detections of correct() since
  /// construction.
  long long projections() const { return projections_; }
  /// Projections skipped because the node was certified out of contact.
  long long projectionsSkipped() const { return projectionsSkipped_; }
  /// The least the corrections of this run had to read of the flexibility (bytes, summed over the steps;
  /// RelativeFlexibility::leastBytes at each step's last pass).
  double flexibilityBytes() const { return flexibilityBytes_; }

  /// Work of the contact forces of the last correction over [t_{n-1}, t_{n+1}] / 2:
  /// sum_a lambda_a c_a . D_a (qNext - qPrev) / 2 (on both bodies when the surface is carried), c_a = n_a + mu_a t_a
  /// the direction the correction used (so friction dissipation is negative contact work and the balance is exact).
  double workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const;
  /// The last correction's forces on the system's coordinates, g = sum_a lambda_a D_a^T c_a (eq. 2.33),
  /// into `g` (q's size): the force on each DOF, which workIncrement() is g . (qNext - qPrev) / 2 of.
  void generalizedForce(const DenseVector& g) const;
  /// workIncrement() split into the normal forces' part (lambda_a n_a) and the friction forces'
  /// (lambda_a mu_a t_a), in that order; for diagnoses (a run that stops), not called by the loop.
  std::array<double, 2> workIncrementSplit(const DenseVector& qNext, const DenseVector& qPrev) const;
  /// The heat friction makes at each node over the last step (J, into out[k], numNodes() values, on
  /// the host): the friction force f_a = lambda_a mu_a t_a times the slip, the surface's motion under
  /// the node h V_s (a turning surface: V_s = omega axis x (foot point - center)) less the node's
  /// relative motion D_a (qNext - qPrev) / 2, f_a . (h V_s - D_a (qNext - qPrev) / 2) >= 0 while it
  /// slides (docs/theory/divergence.md, eq. 42). On still surfaces their sum is minus
  /// workIncrementSplit()[1], up to the order of the sum.
  /// With `normalWork` and `counterfaceWork` (numNodes() values each, or null), the same kernel also gives
  /// each node's share of the energy record's supplied work (docs/theory/heat.md, eq. 63): the normal force's
  /// work on the bodies lambda_a (c_a - mu_a t_a) . D_a (qNext - qPrev) / 2 and the counterface's work through
  /// friction f_a . h V_s, so that heat = counterface work - friction work node by node.
  void frictionHeatByNode(const DenseVector& qNext, const DenseVector& qPrev, double h, double* out,
                          double* normalWork = nullptr, double* counterfaceWork = nullptr) const;

  /// The number of contact nodes.
  int numNodes() const { return static_cast<int>(nodes_.size()); }
  /// The number of active nodes after the last correct().
  int numActive() const { return numActive_; }
  /// Node labels (node numbers in their bodies) and the block of each node, in contact order.
  const std::vector<int>& nodes() const { return nodes_; }
  /// The block (body) of each node, in contact order.
  const std::vector<int>& nodeBlocks() const { return nodeBlock_; }
  /// Per node, after correct(): gap before correction (g*) -- or after measureGaps(), the gap at
  /// that q --, force lambda (N, >= 0), surface index (-1: beyond every surface), Newton
  /// iterations, and the total normal force.
  Kokkos::View<double*>::HostMirror gap() const { return host_.gap; }
  /// Per node, the force lambda (N, >= 0) of the last correction.
  Kokkos::View<double*>::HostMirror force() const { return host_.force; }
  /// Per node, the surface selected (-1: beyond every surface).
  Kokkos::View<int*>::HostMirror surfaceIndex() const { return host_.surf; }
  /// Per node, after correct(): the friction coefficient mu_a actually applied, c_a = n_a + mu_a t_a
  /// (mu while sliding, 0 <= mu_a <= mu when stuck, 0 without contact or tangential force), and the
  /// unit direction t_a of the friction force (zero when there is none); both stay zero when
  /// 'Friction coefficient' = 0.
  Kokkos::View<double*>::HostMirror appliedFriction() const { return host_.mu; }
  /** \fn int SurfaceContact::lastIterations() const
      The largest Newton iteration count of the last detection. */
  /// Per node, the unit direction t_a of the friction force (zero when there is none).
  Kokkos::View<double* [3]>::HostMirror tangent() const { return host_.tangent; } int lastIterations() const {
    return lastIterations_;
  }
  /// Passes that added nodes to the active set (lifetime count of steps that needed one).
  int addPasses() const { return lastAddPasses_; }
  /// Stick/slide classification passes of the last friction solve (0 without friction).
  int lastFrictionPasses() const { return lastFrictionPasses_; }
  /// The sum of the nodes' normal forces of the last correction (N).
  double totalForce() const;
  /// The state carried from one step to the next, for checkpoints: the warm-start foot point
  /// (u, v) of every node on every surface (surface s, node k at 2 (s numNodes() + k); NaN: cold
  /// start). Everything else (friction state and direction, active set, forces) is rebuilt at each
  /// step from q* and q_n, and the carried surfaces from q*.
  std::vector<double> warmStarts() const;
  /// Restores what warmStarts() returned (same nodes and surfaces).
  void setWarmStarts(const std::vector<double>& uv);
  /// Diagonal stiffness the method adds at each contact DOF (k_p for penalty, 0 for Lagrange),
  /// for the stable-step estimate.
  double addedStiffness() const { return enforcement_->addedStiffness(); }
  /// The law's enforcement.
  const ContactEnforcement& enforcement() const { return *enforcement_; }
  /// See ContactEnforcement::setStaticCompliance (the quasi-static self-locking check).
  void setStaticCompliance(const std::vector<double>& blocks) { enforcement_->setStaticCompliance(blocks); }
  /// The abradable coating's law when a surface has a coating (null otherwise), its views (wear,
  /// elements), and its state for checkpoints: every element's wear, then the plastic dissipation.
  const CoatingContact* coating() const { return coating_; }
  /// The coatings' views: every element's law, grid and wear.
  const CoatingViews& coatingViews() const { return detection_->views().coat; }
  /// The coating's state, for checkpoints: every element's wear (m), then the plastic dissipation (J).
  std::vector<double> coatingState() const;
  /// Restores the state coatingState() returned.
  void setCoatingState(const std::vector<double>& state);

private:
  /// The per-node results the enforcement writes (owned here; v_ holds them unmanaged).
  struct StepResults {
    Kokkos::View<double*> force, mu;
    Kokkos::View<double*[3]> dir, tangent, row;
    Kokkos::View<int*> active;
  };
  /// Host copies of the per-node results (the same memory as the views on a host backend).
  struct HostResults {
    Kokkos::View<double*>::HostMirror gap, force, mu;
    Kokkos::View<int*>::HostMirror surf;
    Kokkos::View<double* [3]>::HostMirror tangent;
  };
  void detect(const DenseVector& q, bool all);
  void correctImpl(const DenseVector& q, const DenseVector* qCurrent, CostSplit& cost);
  // the steps of correctImpl: the active set of the detection (false: no contact, the step is done);
  // the nodes that the correction makes penetrate added to it (false: none); the correction applied
  bool startStep();
  bool addPenetrating();
  void finishStep(const DenseVector& q);
  // construction, after the relative flexibility: detection_, the per-node views, the step's views
  void initDetection(const ContactNodes& nodes);
  void initWorkViews(const ContactNodes& nodes, int N);
  void initStepViews();

  ContactOptions opt_;
  std::vector<int> nodes_, nodeBlock_;
  std::vector<ContactSurface> surfaces_;
  std::unique_ptr<RelativeFlexibility> flex_;
  std::unique_ptr<ContactDetection> detection_;
  std::unique_ptr<ContactEnforcement> enforcement_;
  CoatingContact* coating_ = nullptr;  // enforcement_ when a surface has a coating
  bool frictional_ = false;            // enforcement_ applies friction
  // what the enforcement sees, unmanaged: the detection's views (shared, not copies), D and C (flex_),
  // and the per-node results it writes (results_): force, direction c_a, mu_a, t_a
  StepResults results_;
  ContactStepViews v_;
  HostResults host_;
  DenseVector dq_;                // the correction F G lambda
  Kokkos::View<int*> corrected_;  // nodes added to the active set by the last check
  double gapTolerance_ = 0.0;     // a corrected gap above -gapTolerance_ adds no node
  double time_ = 0.0;
  long long projections_ = 0, projectionsSkipped_ = 0;
  double flexibilityBytes_ = 0;
  std::vector<int> activeH_;  // indices of the active nodes
  int numActive_ = 0, lastIterations_ = 0;
  static constexpr int kMaxAddPasses = 10;
  int lastAddPasses_ = 0;
  int lastFrictionPasses_ = 0;  // passes of the last stick/slide classification
};

}  // namespace epaphe
