#include "Epaphe_StableStep.hpp"

#include "Epaphe_BodyOperator.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace epaphe {

namespace {
/// |last component| of the unit eigenvector of the symmetric tridiagonal T (diagonal `alpha`,
/// off-diagonal `beta`) for its eigenvalue `theta`: inverse iteration, two solves with T - theta I
/// factored once (LU with partial pivoting; theta moved by 1e-13 of itself if a pivot is exactly 0).
double lastComponent(const std::vector<double>& alpha, const std::vector<double>& beta, double theta) {
  const int m = static_cast<int>(alpha.size());
  if (m == 1) return 1.0;
  Teuchos::LAPACK<int, double> lapack;
  std::vector<double> dl, d, du, du2(static_cast<std::size_t>(m)), x;
  std::vector<int> ipiv(static_cast<std::size_t>(m));
  int info = 1;
  double shift = theta;
  for (int attempt = 0; attempt < 8 && info != 0; ++attempt, shift += 1e-13 * std::abs(theta) + 1e-300) {
    dl.assign(beta.begin(), beta.begin() + (m - 1));
    du = dl;
    d = alpha;
    for (double& v : d) v -= shift;
    lapack.GTTRF(m, dl.data(), d.data(), du.data(), du2.data(), ipiv.data(), &info);
  }
  if (info != 0) return 1.0;  // no factor: the bound beta_j itself, which never declares convergence early
  x.assign(static_cast<std::size_t>(m), 1.0);
  for (int pass = 0; pass < 2; ++pass) {
    lapack.GTTRS('N', m, 1, dl.data(), d.data(), du.data(), du2.data(), ipiv.data(), x.data(), m, &info);
    double norm = 0;
    for (double v : x) norm = std::max(norm, std::abs(v));
    for (double& v : x) v /= norm;
  }
  double norm2 = 0;
  for (double v : x) norm2 += v * v;
  return std::abs(x[static_cast<std::size_t>(m) - 1]) / std::sqrt(norm2);
}
}  // namespace

HighestEigenvalue highestEigenvalue(const ReducedModel& model, const std::vector<int>& stiffenedDofs,
                                    double addedStiffness) {
  EPAPHE_REQUIRE(model.sparse(), "highestEigenvalue: body '" << model.name << "' is not a full model with lumped mass");
  const int n = model.size;
  std::vector<double> s(static_cast<std::size_t>(n)), spring(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) s[i] = 1.0 / std::sqrt(model.lumpedMass[i]);
  for (int i : stiffenedDofs) spring[i] = addedStiffness;
  HighestEigenvalue r;
  // Gershgorin: every eigenvalue of M^{-1} (K + k S) is at most max_i sum_j |(K + k S)_ij| / m_i.
  const SparseRows& K = model.sparseK;
  for (int i = 0; i < n; ++i) {
    double row = spring[i];
    for (std::size_t k = K.rowStart[i]; k < K.rowStart[i + 1]; ++k) row += std::abs(K.values[k]);
    r.gershgorin = std::max(r.gershgorin, row / model.lumpedMass[i]);
  }
  // Lanczos on A = M^{-1/2} (K + k S) M^{-1/2}: A x = s .* ((K + k S) (s .* x)), s = m^{-1/2}
  const BodyOperator Kop = BodyOperator::sparse(K, "epaphe::dynamics::lanczos::K");
  std::vector<double> v(static_cast<std::size_t>(n)), vPrev(v.size(), 0.0);
  const DenseVector wView("epaphe::dynamics::lanczos::w", n), svView("epaphe::dynamics::lanczos::sv", n);
  double* w = wView.data();
  double* sv = svView.data();
  std::uint64_t seed = 0x9e3779b97f4a7c15ull;  // fixed: the same estimate at every run
  double norm = 0;
  for (double& x : v) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    x = static_cast<double>(seed >> 11) / 9007199254740992.0 - 0.5;
    norm += x * x;
  }
  for (double& x : v) x /= std::sqrt(norm);
  std::vector<double> alpha, beta;  // T: diagonal alpha, off-diagonal beta
  Teuchos::LAPACK<int, double> lapack;
  const int maxIterations = std::min(n, 1000);
  double betaPrev = 0;
  for (int j = 0; j < maxIterations; ++j) {
    for (int i = 0; i < n; ++i) sv[i] = s[i] * v[i];
    Kop.apply(1.0, svView, 0.0, wView);
    double a = 0;
    for (int i = 0; i < n; ++i) {
      w[i] = s[i] * (w[i] + spring[i] * sv[i]);
      a += w[i] * v[i];
    }
    double b = 0;
    for (int i = 0; i < n; ++i) {
      w[i] -= a * v[i] + betaPrev * vPrev[i];  // w = A v_j - alpha_j v_j - beta_{j-1} v_{j-1}
      b += w[i] * w[i];
    }
    b = std::sqrt(b);
    alpha.push_back(a);
    r.iterations = j + 1;
    // The largest Ritz value theta of T_j and its residual bound beta_j |last component of its vector|.
    const int m = j + 1;
    if (m % 10 == 0 || m == maxIterations || b <= 1e-14 * std::abs(a)) {
      // T's eigenvalues alone (dsteqr without vectors: O(m^2), where the m x m eigenvectors cost
      // O(m^3) and 3 s of the setup at a thousand iterations), then the largest one's eigenvector by
      // two steps of inverse iteration on the tridiagonal T - theta I (dgttrf/dgttrs, O(m)).
      std::vector<double> d(alpha), e(beta), none(1);
      int info = 0;
      lapack.STEQR('N', m, d.data(), e.data(), none.data(), 1, none.data(), &info);
      EPAPHE_REQUIRE(info == 0,
                     "stable step of body '" << model.name << "': LAPACK dsteqr failed (info " << info << ")");
      r.ritz = d[m - 1];
      r.residual = b * lastComponent(alpha, beta, r.ritz);
      if (r.residual <= 1e-10 * r.ritz) {
        r.converged = true;
        break;
      }
    }
    if (b == 0.0) break;  // an invariant subspace without convergence: the Gershgorin bound
    beta.push_back(b);
    betaPrev = b;
    for (int i = 0; i < n; ++i) {
      vPrev[i] = v[i];
      v[i] = w[i] / b;
    }
  }
  r.value = r.converged ? std::min(r.ritz + r.residual, r.gershgorin) : r.gershgorin;
  return r;
}

StableStep criticalTimeStep(const ReducedModel& model, const std::vector<int>& stiffenedDofs, double addedStiffness,
                            const DampingOptions& damping) {
  StableStep s;
  if (model.sparse()) {
    s.omegaMax = std::sqrt(highestEigenvalue(model, stiffenedDofs, addedStiffness).value);
  } else if (model.massless()) {
    // The retained DOFs carry no mass: the last kept mode sets the step. (Penalty springs, which would
    // stiffen the modes through Phi_b, are refused for such a body: see Simulation's checkReductions.)
    EPAPHE_REQUIRE(addedStiffness == 0.0, "body '" << model.name
                                                   << "' has a massless boundary: no penalty springs "
                                                      "on it (use Lagrange contact)");
    s.omegaMax = 2 * M_PI * model.modeFrequencies.back();
  } else {
    const int n = model.size;
    std::vector<double> K = model.K;
    for (int i : stiffenedDofs) K[static_cast<std::size_t>(i) * n + i] += addedStiffness;
    const std::vector<double> f = denseFrequencies(K, model.M, n);
    s.omegaMax = 2 * M_PI * f.back();
  }
  s.critical = 2.0 / s.omegaMax;
  double xi = 0;
  if (damping.type == DampingType::Rayleigh) xi = 0.5 * (damping.alpha / s.omegaMax + damping.beta * s.omegaMax);
  if (damping.type == DampingType::Modal) xi = damping.ratio;
  s.critical *= std::sqrt(1 + xi * xi) - xi;
  return s;
}

}  // namespace epaphe
