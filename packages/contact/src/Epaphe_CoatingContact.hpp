#pragma once
// Contact with an abradable coating (Legrand, Batailly & Pierre 2012; the element law in
// Epaphe_AbradableCoating.hpp): the enforcement strategy for nodes facing a coated surface. The
// detection measures each node's gap g*_a to the coating's current profile and finds the element
// e(a) under it; the node's penetration p_a into the profile is the element's compression beyond
// its plastic shortening, delta_a = u_p + p_a, and the element's force A_e sigma(delta_a) pushes it
// back along n_a.
//
// Lagrange (forward increment, as eq. 2.33 for a rigid surface): the correction lambda makes the
// node's corrected penetration p_a = -(g*_a + n_a^T sum_b C_ab c_b lambda_b) and the element's force
// agree, on the branch of the law the node is on:
//   elastic  lambda_a = k_e p_a,  k_e = A_e E / t:
//              (MC lambda)_a + lambda_a / k_e = -g*_a
//   plastic  lambda_a = k_t delta_a + lambda_0,  k_t = A_e E H / (t (E + H)),  lambda_0 = A_e E sigma_Y / (E + H):
//              k_t (MC lambda)_a + lambda_a = k_t (u_p - g*_a) + lambda_0      (H = 0: lambda_a = lambda_0)
//   rigid    the element crushed (delta_a = t), the surface behind holds the node:
//              (MC lambda)_a = -(g*_a + t - u_p)
// (ContactStepViews::row). The coating's compliance enters the solve implicitly, so the step is
// stable for any coating stiffness. Branches are classified from the solution (p_a against the
// yield and the thickness) and the system solved again until none changes (at most 20 passes;
// first guess from the predicted penetration); friction (CoulombFriction) and the release of
// pulled nodes are the inner law's, on these rows. Thickness 0 is the rigid row exactly.
// Penalty: the element's force at the predicted penetration, explicitly (a known force), plus the
// penalty stiffness beyond the crushed coating; stable while h^2 k_e / m stays small (addedStiffness).
// After the step (commit), each loaded element's plastic shortening follows the return mapping at its
// node's final compression, in a Kokkos kernel (nodes in order: two nodes on one element keep the
// larger shortening), and the plastic dissipation and the elastic energy held are summed.
#include <memory>
#include <vector>

#include "Epaphe_ContactEnforcement.hpp"

namespace epaphe {

/// The enforcement of contact with an abradable coating (see the file's opening comment): states each
/// node's row on its branch of the element law and lets the deck's law solve the rows.
class CoatingContact final : public ContactEnforcement {
public:
  /// `inner`: the law of the deck (Lagrange or penalty, with friction when mu > 0), which solves
  /// the rows this law states; kp: the penalty stiffness beyond a crushed coating (penalty only).
  CoatingContact(std::unique_ptr<ContactEnforcement> inner, bool penalty, double kp, const CoatingViews& coat,
                 int numNodes);
  /// "Abradable coating".
  const char* name() const override { return "Abradable coating"; }
  void enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
               const DenseVector* qn) override;
  bool closesGaps() const override { return inner_->closesGaps(); }
  double addedStiffness() const override;
  bool frictional() const override { return inner_->frictional(); }
  int lastPasses() const override { return inner_->lastPasses(); }
  void reset() override { inner_->reset(); }
  const SelfLocking* selfLocking() const override { return inner_->selfLocking(); }
  void setStaticCompliance(const std::vector<double>& blocks) override { inner_->setStaticCompliance(blocks); }
  void commit(const ContactStepViews& v, const std::vector<int>& active) override;

  /// Plastic dissipation summed over the run (J), and the elastic energy the loaded elements hold
  /// after the last step (J).
  double plasticDissipation() const { return energy_(0); }
  /// The elastic energy the loaded elements hold after the last step (J).
  double elasticEnergy() const { return energy_(1); }
  /// Restores the dissipation (checkpoints; the elastic energy follows at the next step).
  void setPlasticDissipation(double d) { energy_(0) = d; }
  /// Per contact node, the plastic dissipation of the elements it shortened at the last step (J): where the coating's
  /// dissipation is made, for heat from rubbing (docs/theory/heat.md, eq. 64). Per step, not summed over the run, so
  /// that a restart continues it bit for bit.
  Kokkos::View<const double*> dissipationByNode() const { return nodeDissipation_; }
  /// Branch passes of the last Lagrange step.
  int lastBranchPasses() const { return lastBranchPasses_; }

  /// A node's branch of the law: crushed (the rigid surface behind), elastic, plastic
  ///@{
  static constexpr int kRigid = 0, kElastic = 1, kPlastic = 2;
  ///@}

private:
  void setRows(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  void penetrations(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA);
  int classify(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA, bool guess);

  std::unique_ptr<ContactEnforcement> inner_;
  bool penalty_;
  double kp_;
  CoatingViews coat_;
  Kokkos::View<int*> branch_, changed_;
  Kokkos::View<double*> p_;                // corrected penetration into the profile (penalty: predicted)
  Kokkos::View<double*> upNext_, sigma_;   // per active position: shortening and stress at commit
  Kokkos::View<double[2]> energy_;         // plastic dissipation (run), elastic energy (last step)
  Kokkos::View<double*> nodeDissipation_;  // per contact node, the plastic dissipation it made at the last step (J)
  bool nodeDissipationSet_ = false;        // nodeDissipation_ may hold non-zero values
  int lastBranchPasses_ = 0;
  static constexpr int kMaxPasses = 20;
};

}  // namespace epaphe
