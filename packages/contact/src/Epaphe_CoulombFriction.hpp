#pragma once
// Coulomb friction in the contact correction (thesis eqs. 2.29 and 2.31), with either normal law:
// a joint solve over the active set, 3 unknowns per active node a (lambda_a and the tangential force
// s_a in the tangent plane of n_a); see the top of Epaphe_SurfaceContact.hpp for the rows, the
// stick/slip classification (radial return) and its anti-cycling rules. Without the motion over the
// step (q_n not given) there is no friction direction and the normal law alone applies.
#include "Epaphe_ContactEnforcement.hpp"

namespace epaphe {

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
  const char* name() const override { return "Coulomb friction"; }
  void enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
               const DenseVector* qn) override;
  bool closesGaps() const override { return frictionless_->closesGaps(); }
  double addedStiffness() const override { return frictionless_->addedStiffness(); }
  bool frictional() const override { return true; }
  int lastPasses() const override { return lastPasses_; }
  void reset() override;

private:
  void prepare(const ContactStepViews& v, const std::vector<int>& active, const DenseVector& q, const DenseVector& qn);
  void solve(const ContactStepViews& v, std::vector<int>& active);
  // the phases of one solve (`active`: the uploaded active set, its first nA entries):
  // friction system MCf_ and right-hand side rhs_ of the current states, in the unknowns that are
  // not known beforehand (unknownOffset_)
  void assembleSystem(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // T_ab = B_a C_ab B_b^T of the active pairs, B_a the rows (n_a, e1_a, e2_a): C in the nodes' own
  // bases, once per step (the passes read it instead of turning C_ab into the bases each time)
  void localFlexibility(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // solves it in place (ld: MCf_'s leading dimension); solH_, then sol_, hold (lambda, s1, s2) of
  // every active node, the known ones included
  void solveSystem(const ContactStepViews& v, const std::vector<int>& activeH, int nA, int ld);
  // unknownOffset_ of the current states: per active node its first unknown, [nA] their count
  void countUnknowns(const ContactStepViews& v, const std::vector<int>& activeH, int nA);
  // Lagrange: drops the nodes with lambda < 0 from activeH (nA updated); true when any was dropped
  bool releasePulled(std::vector<int>& activeH, int& nA, int& releases, int nc);
  // proposed next state and direction of each active node; returns how many change
  int classify(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // the proposed states and directions become the current ones (slide -> stick switches counted)
  void commitClassification(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  // v.force, v.dir, v.mu, v.tangent from the solution, and the next step's warm start
  void storeForces(const ContactStepViews& v, const std::vector<int>& activeH, int nA);

  static constexpr int kStick = 2, kSlide = 1;
  static constexpr int kMaxFrictionPasses = 20;
  static constexpr int kMaxReturns = 2;  // slide -> stick switches per node and solve, then it keeps sliding
  double mu_, kp_, h_;
  bool penalty_;
  bool warm_;
  std::unique_ptr<ContactEnforcement> frictionless_;
  int lastPasses_ = 0;
  Kokkos::View<double* [3][3]> basis_;   // per node: rows n_a, e1_a, e2_a (tangent-plane basis)
  Kokkos::View<double* [3]> disp_;       // d_a = u_a(q*) - u_a(q_n)
  Kokkos::View<double** [3][3]> local_;  // T_ab (localFlexibility), indexed like C
  Kokkos::View<double* [3]> column_;     // a sliding node's column c_0 in its basis (countUnknowns, per pass)
  Kokkos::View<int*> state_, nextState_, bestState_;  // kStick, kSlide
  Kokkos::View<double*[3]> nextTangent_, bestTangent_;
  Kokkos::View<int*> returns_;
  Kokkos::View<double**, Kokkos::LayoutLeft> MCf_;  // friction system, 3 nc x 3 nc
  Kokkos::View<double**, Kokkos::LayoutLeft>::HostMirror MCfH_;
  Kokkos::View<double*> sol_;  // the solution, (lambda, s1, s2) per active node, known ones included
  Kokkos::View<double*>::HostMirror solH_;
  Kokkos::View<double*> rhs_;  // right-hand side / solution of the solved unknowns
  Kokkos::View<double*>::HostMirror rhsH_;
  Kokkos::View<int*> unknownOffset_;  // per active position: its first solved unknown; [nA]: their count
  Kokkos::View<int*>::HostMirror unknownOffsetH_;
  Kokkos::View<int*> prev_;                // last step's final state (0: not in contact)
  Kokkos::View<double* [3]> prevTangent_;  // and direction
  std::vector<int> keep_, ipiv_;
};

}  // namespace epaphe
