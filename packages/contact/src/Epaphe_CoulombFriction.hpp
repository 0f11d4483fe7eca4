#pragma once
// Coulomb friction in the contact correction (thesis eqs. 2.29 and 2.31), with either normal law:
// a joint solve over the active set, 3 unknowns per active node a (lambda_a and the tangential force
// s_a in the tangent plane of n_a); see the top of Epaphe_SurfaceContact.hpp for the rows, the
// stick/slip classification (the return of eq. (74): a sliding node's force against its slip) and its
// anti-cycling rules. Without the motion over the
// step (q_n not given) there is no friction direction and the normal law alone applies.
//
// Self-locking (docs/theory/divergence.md, eqs. (48)-(50)): at each sliding node a, with friction
// direction t_a, c_a = n_a + mu t_a, the others' forces held, a compressive force pushes the node
// out (Lagrange: closes its gap with lambda_a > 0; penalty: the known force does not drive it
// deeper) iff n_a^T W c_a + kappa > 0, W the node's compliance, kappa = 1/k_p under penalty. Two
// margins m = (n^T W c + kappa) / (n^T W n + kappa) = 1 - mu / mu*_a are checked, at every step,
// for the sliding nodes only (a few flops each, no pass of its own): W = C_aa, the Delassus block
// the correction solves with (eq. (48), kappa = 0: the step itself), and W = S_a, the body's static
// compliance (eq. (50)): no compressive equilibrium exists, friction drives the normal force without
// bound (sprag-slip).
#include "Epaphe_ContactEnforcement.hpp"

namespace epaphe {

/// Coulomb friction with a normal law (see the file's opening comment): a joint normal-tangential solve
/// over the active set with stick/slip classification, and the self-locking check.
class CoulombFriction final : public ContactEnforcement {
public:
  /// mu > 0; normal law: penalty (stiffness kp) or Lagrange; h: the time step (turning surfaces'
  /// own motion over a step); `frictionless`: the law applied when q_n is not given. `warm`: a node
  /// in contact at the last step starts its stick/slip classification from that step's final state
  /// (and sliding direction, turned into the new tangent plane) instead of from its predicted
  /// motion: the classification usually settles in one pass (reset() makes the next step cold).
  CoulombFriction(double mu, bool penalty, double kp, double h, int numNodes,
                  std::unique_ptr<ContactEnforcement> frictionless, bool warm = true);
  /// Its deck keys in the Contact list: Friction coefficient.
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  /// "Coulomb friction".
  const char* name() const override { return "Coulomb friction"; }
  void enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
               const DenseVector* qn) override;
  bool closesGaps() const override { return frictionless_->closesGaps(); }
  double addedStiffness() const override { return frictionless_->addedStiffness(); }
  bool frictional() const override { return true; }
  int lastPasses() const override { return lastPasses_; }
  void reset() override;
  const SelfLocking* selfLocking() const override { return &lock_; }
  void setStaticCompliance(const std::vector<double>& blocks) override;

private:
  void prepare(const ContactStepViews& v, const std::vector<int>& active, const DenseVector& q, const DenseVector& qn);
  void solve(const ContactStepViews& v, std::vector<int>& active);
  // the phases of one solve (`active`: the uploaded active set, its first nA entries):
  // friction system MCf and right-hand side rhs of the current states, in the unknowns that are
  // not known beforehand (unknownOffset)
  void assembleSystem(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // T_ab = B_a C_ab B_b^T of the active pairs, B_a the rows (n_a, e1_a, e2_a): C in the nodes' own
  // bases, once per step (the passes read it instead of turning C_ab into the bases each time)
  void localFlexibility(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // solves it in place (ld: MCf's leading dimension); solH, then sol, hold (lambda, s1, s2) of
  // every active node, the known ones included
  void solveSystem(const ContactStepViews& v, const std::vector<int>& activeH, int nA, int ld);
  // unknownOffset of the current states: per active node its first unknown, [nA] their count
  void countUnknowns(const ContactStepViews& v, const std::vector<int>& activeH, int nA);
  // Lagrange: drops the nodes with lambda < 0 from activeH (nA updated); true when any was dropped
  bool releasePulled(std::vector<int>& activeH, int& nA, int& releases, int nc);
  // proposed next state and direction of each active node; returns how many change
  int classify(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // the proposed states and directions become the current ones (slide -> stick switches counted)
  void commitClassification(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // v.force, v.dir, v.mu, v.tangent from the solution, and the next step's warm start
  void storeForces(const ContactStepViews& v, const std::vector<int>& activeH, int nA);
  // lock_: the self-locking margins of the sliding nodes (eqs. (48)-(50) of docs/theory/divergence.md)
  void checkSelfLocking(const ContactStepViews& v, const std::vector<int>& activeH, int nA);

  static constexpr int kStick = 2, kSlide = 1;
  static constexpr int kMaxFrictionPasses = 20;
  static constexpr int kMaxReturns = 2;     // slide -> stick switches per node and solve, then it keeps sliding
  static constexpr int kClassifyLanes = 8;  // nodes whose returns classify() iterates together
  double mu_, kp_, h_;
  bool penalty_;
  bool warm_;
  std::unique_ptr<ContactEnforcement> frictionless_;
  int lastPasses_ = 0;
  Kokkos::View<double* [3][3]> basis_;   // per node: rows n_a, e1_a, e2_a (tangent-plane basis)
  Kokkos::View<double* [3]> disp_;       // d_a = u_a(q*) - u_a(q_n)
  Kokkos::View<double** [3][3]> local_;  // T_ab (localFlexibility), indexed like C
  Kokkos::View<double* [3]> column_;     // a sliding node's column c_0 in its basis (countUnknowns, per pass)
  Kokkos::View<double* [3]> force_;      // by active position: the node's force in its basis (solveSystem, per pass)
  Kokkos::View<int*> state_, nextState_, bestState_;  // kStick, kSlide
  Kokkos::View<double*[3]> nextTangent_, bestTangent_;
  Kokkos::View<int*> returns_;
  /// The friction system of a pass and its solution, with their host copies.
  struct System {
    Kokkos::View<double**, Kokkos::LayoutLeft> MCf;  ///< friction system, 3 nc x 3 nc
    Kokkos::View<double**, Kokkos::LayoutLeft>::HostMirror MCfH;
    Kokkos::View<double*> sol;  ///< the solution, (lambda, s1, s2) per active node, known ones included
    Kokkos::View<double*>::HostMirror solH;
    Kokkos::View<double*> rhs;  ///< right-hand side / solution of the solved unknowns
    Kokkos::View<double*>::HostMirror rhsH;
    Kokkos::View<int*> unknownOffset;  ///< per active position: its first solved unknown; [nA]: their count
    Kokkos::View<int*>::HostMirror unknownOffsetH;
    std::vector<int> ipiv;  ///< the pivots of the solve
  };
  System sys_;
  Kokkos::View<int*> prev_;                // last step's final state (0: not in contact)
  Kokkos::View<double* [3]> prevTangent_;  // and direction
  std::vector<int> keep_;
  std::vector<double> static_;  // per node S_a, 9 entries row-major (empty: none given)
  SelfLocking lock_;
};

}  // namespace epaphe
