#pragma once
// Forward-increment Lagrange multipliers (Carpenter, Taylor & Katona 1991; thesis section 2.5.2,
// eqs. 2.30-2.33), frictionless: c_a = n_a, and over the active set
//     MC lambda = -g*,   MC_ab = n_a^T C_ab n_b,   C_ab = D_a F D_b^T,
// optionally lumped (MC_aa = sum_b MC_ab); nodes with lambda_a < 0 are released and the system
// solved again. The normal gap of every active node closes exactly.
#include "Epaphe_ContactEnforcement.hpp"

namespace epaphe {

/// Forward-increment Lagrange multipliers, frictionless (see the file's opening comment).
class ForwardIncrementLagrange final : public ContactEnforcement {
public:
  /// `lumped`: lump MC (MC_aa = sum_b MC_ab); `numNodes`: the contact nodes (work arrays sized once).
  ForwardIncrementLagrange(bool lumped, int numNodes);
  /// Its deck keys in the Contact list: Lump contact matrix.
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  /// "Lagrange".
  const char* name() const override { return "Lagrange"; }
  void enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
               const DenseVector* qn) override;
  bool closesGaps() const override { return true; }

private:
  bool lumped_;
  Kokkos::View<double**, Kokkos::LayoutLeft> MC_;  // nc x nc, the first nA x nA used
  std::vector<int> keep_, ipiv_, row_;             // row_: each active node's row of MC (enforce)
  std::vector<double> lambda_, A_;                 // work space, sized once
};

/// Penalty (thesis eq. 2.34), frictionless: lambda_a = k_p (-g*_a), c_a = n_a.
class PenaltyContact final : public ContactEnforcement {
public:
  /// The penalty stiffness k_p (N/m).
  explicit PenaltyContact(double stiffness);
  /// Its deck keys in the Contact list: Penalty stiffness.
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  /// "Penalty".
  const char* name() const override { return "Penalty"; }
  void enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
               const DenseVector* qn) override;
  bool closesGaps() const override { return false; }
  double addedStiffness() const override { return kp_; }

private:
  double kp_;
};

/// c_k = n_k, t_k = 0, mu_k = 0 for every node (the frictionless laws' directions).
void normalDirections(const ContactStepViews& v);

}  // namespace epaphe
