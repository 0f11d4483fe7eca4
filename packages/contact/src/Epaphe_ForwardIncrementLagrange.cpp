#include "Epaphe_ForwardIncrementLagrange.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_SmallDense.hpp"

namespace epaphe {

void normalDirections(const ContactStepViews& v) {
  const auto normal = v.normal;
  const auto tangent = v.tangent;
  const auto dir = v.dir;
  const auto muA = v.mu;
  forEach(
      "epaphe::contact::normal_direction", normal.extent(0), 5, KOKKOS_LAMBDA(const int k) {
        for (int d = 0; d < 3; ++d) {
          dir(k, d) = normal(k, d);
          tangent(k, d) = 0.0;
        }
        muA(k) = 0.0;
      });
  fence();
}

ForwardIncrementLagrange::ForwardIncrementLagrange(bool lumped, int numNodes)
    : lumped_(lumped), MC_("epaphe::contact::MC", numNodes, numNodes) {
  keep_.reserve(numNodes);
  row_.reserve(numNodes);
  ipiv_.reserve(numNodes);
  lambda_.reserve(numNodes);
  A_.reserve(static_cast<std::size_t>(numNodes) * numNodes);
}

Teuchos::RCP<const Teuchos::ParameterList> ForwardIncrementLagrange::getValidParameters() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Lagrange"));
  deck::addBool(*pl, "Lump contact matrix", false, "Lump the Lagrange contact matrix MC (section 2.5.2)");
  return pl;
}

void ForwardIncrementLagrange::enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector&,
                                       const DenseVector*) {
  normalDirections(v);
  // Active set iteration (frictionless: c_a = n_a): solve MC lambda = -g* (eq. 2.33), release
  // nodes pulled by the surface.
  int nA = static_cast<int>(active.size());
  const int nc = static_cast<int>(v.force.extent(0));
  const auto MC = unmanaged(MC_);
  row_.resize(static_cast<std::size_t>(nA));  // each active node's row of MC: made at the first pass
  for (int a = 0; a < nA; ++a) row_[a] = a;
  for (int pass = 0; pass <= nc && nA > 0; ++pass) {
    if (pass == 0) {  // (a pass releases nodes: MC's rows and columns of the others stay as they were)
      const auto act = v.upload(active);
      const auto C = v.C;
      const auto normal = v.normal;
      const auto dir = v.dir;
      // MC_ab = n_a^T C_ab c_b (eq. 2.32), C_ab = D_a F D_b^T, one row per active node.
      forEach(
          "epaphe::contact::matrix", nA, 10L * nA, KOKKOS_LAMBDA(const int a) {
            const int ka = act(a);
            for (int b = 0; b < nA; ++b) {
              const int kb = act(b);
              double s = 0.0;
              for (int d = 0; d < 3; ++d)
                for (int e = 0; e < 3; ++e) s += normal(ka, d) * C(ka, kb, d, e) * dir(kb, e);
              MC(a, b) = s;
            }
          });
      fence();
    }
    std::vector<double>& A = A_;
    A.resize(static_cast<std::size_t>(nA) * nA);
    for (int b = 0; b < nA; ++b)
      for (int a = 0; a < nA; ++a) A[static_cast<std::size_t>(b) * nA + a] = MC(row_[a], row_[b]);
    if (lumped_) {  // row sums on the diagonal (section 2.5.2)
      for (int a = 0; a < nA; ++a) {
        double s = 0;
        for (int b = 0; b < nA; ++b) {
          s += A[static_cast<std::size_t>(b) * nA + a];
          A[static_cast<std::size_t>(b) * nA + a] = 0;
        }
        A[static_cast<std::size_t>(a) * nA + a] = s;
      }
    }
    lambda_.assign(static_cast<std::size_t>(nA), 0.0);
    for (int a = 0; a < nA; ++a) lambda_[a] = -v.gap(active[a]);
    if (v.rows)  // a normal law's own rows: alpha_a (MC lambda)_a + beta_a lambda_a = gamma_a
      for (int a = 0; a < nA; ++a) {
        const int k = active[a];
        for (int b = 0; b < nA; ++b) A[static_cast<std::size_t>(b) * nA + a] *= v.row(k, 0);
        A[static_cast<std::size_t>(a) * nA + a] += v.row(k, 1);
        lambda_[a] = v.row(k, 2);
      }
    const int info = solveDense(nA, A.data(), nA, lambda_.data(), ipiv_);
    EPAPHE_REQUIRE(info == 0, "contact: the contact matrix of "
                                  << nA << " active nodes is singular (zero pivot at unknown " << info
                                  << "); try lumping it ('Lump contact matrix')");
    keep_.clear();
    int kept = 0;
    for (int a = 0; a < nA; ++a)
      if (lambda_[a] >= 0.0) {
        keep_.push_back(active[a]);
        row_[kept++] = row_[a];
      }
    if (static_cast<int>(keep_.size()) == nA) break;
    active.swap(keep_);
    nA = static_cast<int>(active.size());
  }
  for (int k = 0; k < nc; ++k) v.force(k) = 0.0;  // also nodes released on a former solve
  for (int a = 0; a < nA; ++a) v.force(active[a]) = lambda_[a];
}

PenaltyContact::PenaltyContact(double stiffness) : kp_(stiffness) {
  EPAPHE_REQUIRE(kp_ > 0, "contact: penalty stiffness = " << kp_ << " N/m; it must be > 0");
}

Teuchos::RCP<const Teuchos::ParameterList> PenaltyContact::getValidParameters() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Penalty"));
  deck::addDouble(*pl, "Penalty stiffness", 1e10, "kp (N/m) of the penalty method", 1e-300);
  return pl;
}

void PenaltyContact::enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector&,
                             const DenseVector*) {
  normalDirections(v);
  const int nc = static_cast<int>(v.force.extent(0));
  for (int k = 0; k < nc; ++k) v.force(k) = 0.0;
  for (int k : active) v.force(k) = v.rows ? v.row(k, 2) : kp_ * (-v.gap(k));  // eq. 2.34, or the law's force
}

}  // namespace epaphe
