#include "Epaphe_CentralDifference.hpp"

#include "Epaphe_Error.hpp"

#include <KokkosBlas1_axpby.hpp>
#include <KokkosBlas1_dot.hpp>
#include <KokkosBlas2_gemv.hpp>
#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include <cmath>

namespace epaphe {
namespace {

DenseMatrix toView(const std::vector<double>& a, int n, const char* label) {
  DenseMatrix v(std::string(label), n, n);
  auto h = Kokkos::create_mirror_view(v);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) h(i, j) = a[static_cast<std::size_t>(j) * n + i];
  Kokkos::deep_copy(v, h);
  return v;
}

/// Inverse of a symmetric positive definite matrix (column-major), by Cholesky.
std::vector<double> spdInverse(std::vector<double> A, int n, const char* what) {
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.POTRF('U', n, A.data(), n, &info);
  EPAPHE_REQUIRE(info == 0, what << " is not positive definite (Cholesky failed at column " << info
                                 << "): check the mass matrix and the damping coefficients");
  lapack.POTRI('U', n, A.data(), n, &info);
  EPAPHE_REQUIRE(info == 0, what << ": inversion failed (LAPACK info " << info << ")");
  for (int j = 0; j < n; ++j)
    for (int i = j + 1; i < n; ++i) A[static_cast<std::size_t>(j) * n + i] = A[static_cast<std::size_t>(i) * n + j];
  return A;
}

}  // namespace

void rayleighFromRatios(double f1, double xi1, double f2, double xi2, double& alpha, double& beta) {
  EPAPHE_REQUIRE(f1 > 0 && f2 > f1, "Rayleigh damping: frequencies " << f1 << " and " << f2
                                                                      << " Hz; give 0 < f1 < f2");
  const double w1 = 2 * M_PI * f1, w2 = 2 * M_PI * f2;
  beta = 2 * (xi2 * w2 - xi1 * w1) / (w2 * w2 - w1 * w1);
  alpha = 2 * w1 * w2 * (xi1 * w2 - xi2 * w1) / (w2 * w2 - w1 * w1);
  EPAPHE_REQUIRE(alpha >= 0 && beta >= 0, "Rayleigh damping: ratios " << xi1 << " at " << f1 << " Hz and " << xi2
                     << " at " << f2 << " Hz give alpha = " << alpha << ", beta = " << beta
                     << "; a negative coefficient would feed energy into some modes: choose closer ratios");
}

std::vector<double> dampingMatrix(const ReducedModel& model, const DampingOptions& damping) {
  const int n = model.size;
  std::vector<double> D(static_cast<std::size_t>(n) * n, 0.0);
  if (damping.type == DampingType::Rayleigh) {
    for (std::size_t k = 0; k < D.size(); ++k) D[k] = damping.alpha * model.M[k] + damping.beta * model.K[k];
  } else if (damping.type == DampingType::Modal) {
    std::vector<double> V;
    const std::vector<double> w = denseEigenpairs(model.K, model.M, n, &V);
    // MV = M V; D = (MV) diag(2 xi omega) (MV)^T
    std::vector<double> MV(D.size()), MVs(D.size());
    Teuchos::BLAS<int, double> blas;
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, 1.0, model.M.data(), n, V.data(), n, 0.0, MV.data(), n);
    for (int j = 0; j < n; ++j) {
      const double c = 2 * damping.ratio * std::sqrt(std::max(w[j], 0.0));
      for (int i = 0; i < n; ++i) MVs[static_cast<std::size_t>(j) * n + i] = c * MV[static_cast<std::size_t>(j) * n + i];
    }
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, n, n, n, 1.0, MVs.data(), n, MV.data(), n, 0.0, D.data(), n);
  }
  return D;
}

StableStep criticalTimeStep(const ReducedModel& model, const std::vector<int>& stiffenedDofs, double addedStiffness,
                            const DampingOptions& damping) {
  const int n = model.size;
  std::vector<double> K = model.K;
  for (int i : stiffenedDofs) K[static_cast<std::size_t>(i) * n + i] += addedStiffness;
  const std::vector<double> f = denseFrequencies(K, model.M, n);
  StableStep s;
  s.omegaMax = 2 * M_PI * f.back();
  s.critical = 2.0 / s.omegaMax;
  double xi = 0;
  if (damping.type == DampingType::Rayleigh) xi = 0.5 * (damping.alpha / s.omegaMax + damping.beta * s.omegaMax);
  if (damping.type == DampingType::Modal) xi = damping.ratio;
  s.critical *= std::sqrt(1 + xi * xi) - xi;
  return s;
}

CentralDifference::CentralDifference(const ReducedModel& model, double h, const DampingOptions& damping) : h_(h) {
  const int n = model.size;
  EPAPHE_REQUIRE(h > 0 && std::isfinite(h), "time step = " << h << " s; it must be a finite value > 0");
  damped_ = damping.type != DampingType::None;
  const std::vector<double> D = dampingMatrix(model, damping);
  // P = [M/h^2 + D/2h]^{-1}
  std::vector<double> lhs(D.size());
  for (std::size_t k = 0; k < lhs.size(); ++k) lhs[k] = model.M[k] / (h * h) + D[k] / (2 * h);
  const std::vector<double> P = spdInverse(lhs, n, ("M/h^2 + D/2h of body '" + model.name + "'").c_str());
  // A = -P K, B = -P D / h
  std::vector<double> A(D.size()), B(D.size());
  Teuchos::BLAS<int, double> blas;
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0, P.data(), n, model.K.data(), n, 0.0, A.data(), n);
  A_ = toView(A, n, "epaphe::dynamics::A");
  if (damped_) {
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0 / h, P.data(), n, D.data(), n, 0.0, B.data(), n);
    B_ = toView(B, n, "epaphe::dynamics::B");
  }
  K_ = toView(model.K, n, "epaphe::dynamics::K");
  M_ = toView(model.M, n, "epaphe::dynamics::M");
  D_ = toView(D, n, "epaphe::dynamics::D");
  P_ = toView(P, n, "epaphe::dynamics::P");
  f_ = DenseVector("epaphe::dynamics::f", n);
  Pf_ = DenseVector("epaphe::dynamics::Pf", n);
  tmp_ = DenseVector("epaphe::dynamics::tmp", n);
  tmp2_ = DenseVector("epaphe::dynamics::tmp2", n);
}

void CentralDifference::setConstantForce(const std::vector<double>& f) {
  EPAPHE_REQUIRE(f.size() == f_.extent(0), "external force has " << f.size() << " entries, the model " << f_.extent(0));
  auto fh = Kokkos::create_mirror_view(f_);
  forced_ = false;
  for (std::size_t i = 0; i < f.size(); ++i) {
    fh(i) = f[i];
    forced_ = forced_ || f[i] != 0.0;
  }
  Kokkos::deep_copy(f_, fh);
  KokkosBlas::gemv("N", 1.0, P_, f_, 0.0, Pf_);
}

void CentralDifference::predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar) const {
  // The per-step work of a small dense model is a few microseconds: an OpenMP kernel launch per
  // vector operation would cost more than the work (measured: 2 threads 4.5x slower than 1 on a
  // 112-DOF model). The vectors live in host memory (OpenMP), so the step runs as plain loops and
  // one BLAS dgemv (OpenBLAS, which threads large products itself).
  static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, DenseVector::memory_space>::accessible,
                "the explicit step runs on host memory");
  const int n = static_cast<int>(qn.extent(0));
  double* qs = qstar.data();
  const double* q0 = qn.data();
  const double* q1 = qnm1.data();
  for (int i = 0; i < n; ++i) qs[i] = 2.0 * q0[i] - q1[i];                          // 2 q_n - q_{n-1}
  Teuchos::BLAS<int, double> blas;
  blas.GEMV(Teuchos::NO_TRANS, n, n, 1.0, A_.data(), n, q0, 1, 1.0, qs, 1);       // + A q_n
  if (damped_) {                                                                    // + B (q_n - q_{n-1})
    double* d = tmp_.data();
    for (int i = 0; i < n; ++i) d[i] = q0[i] - q1[i];
    blas.GEMV(Teuchos::NO_TRANS, n, n, 1.0, B_.data(), n, d, 1, 1.0, qs, 1);
  }
  if (forced_) {                                                                    // + P f
    const double* pf = Pf_.data();
    for (int i = 0; i < n; ++i) qs[i] += pf[i];
  }
}

double CentralDifference::halfStepEnergy(const DenseVector& qn, const DenseVector& qnp1) const {
  // 1/2 v^T M v with v = (q_{n+1} - q_n)/h, plus 1/2 q_n^T K q_{n+1}
  Kokkos::deep_copy(tmp2_, qnp1);
  KokkosBlas::axpby(-1.0 / h_, qn, 1.0 / h_, tmp2_);
  KokkosBlas::gemv("N", 1.0, M_, tmp2_, 0.0, tmp_);
  const double kin = 0.5 * KokkosBlas::dot(tmp2_, tmp_);
  KokkosBlas::gemv("N", 1.0, K_, qnp1, 0.0, tmp_);
  return kin + 0.5 * KokkosBlas::dot(qn, tmp_);
}

double CentralDifference::dampingIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const {
  if (!damped_) return 0.0;
  Kokkos::deep_copy(tmp2_, qnp1);
  KokkosBlas::axpy(-1.0, qnm1, tmp2_);
  KokkosBlas::gemv("N", 1.0, D_, tmp2_, 0.0, tmp_);
  return KokkosBlas::dot(tmp2_, tmp_) / (4 * h_);
}

double CentralDifference::externalWorkIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const {
  if (!forced_) return 0.0;
  Kokkos::deep_copy(tmp2_, qnp1);
  KokkosBlas::axpy(-1.0, qnm1, tmp2_);
  return 0.5 * KokkosBlas::dot(f_, tmp2_);
}

double CentralDifference::strain(const DenseVector& q) const {
  KokkosBlas::gemv("N", 1.0, K_, q, 0.0, tmp_);
  return 0.5 * KokkosBlas::dot(q, tmp_);
}

double CentralDifference::kinetic(const DenseVector& v) const {
  KokkosBlas::gemv("N", 1.0, M_, v, 0.0, tmp_);
  return 0.5 * KokkosBlas::dot(v, tmp_);
}

}  // namespace epaphe
