#include "Epaphe_CentralDifference.hpp"

#include "Epaphe_Parallel.hpp"

#include "Epaphe_Error.hpp"

#include <KokkosSparse_spmv.hpp>
#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace epaphe {
BodyOperator BodyOperator::dense(const std::vector<double>& a, int n, const std::string& label) {
  BodyOperator op;
  op.kind_ = Kind::Dense;
  op.dense_ = DenseMatrix(label, n, n);
  auto h = Kokkos::create_mirror_view(op.dense_);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) h(i, j) = a[static_cast<std::size_t>(j) * n + i];
  Kokkos::deep_copy(op.dense_, h);
  return op;
}

BodyOperator BodyOperator::sparse(const SparseRows& a, const std::vector<double>& rowScale, const std::string& label) {
  BodyOperator op;
  op.kind_ = Kind::Sparse;
  const int n = a.rows();
  Sparse::row_map_type::non_const_type rows(label + "::rows", n + 1);
  Sparse::index_type::non_const_type cols(label + "::cols", a.cols.size());
  Sparse::values_type::non_const_type values(label + "::values", a.values.size());
  auto rh = Kokkos::create_mirror_view(rows);
  auto ch = Kokkos::create_mirror_view(cols);
  auto vh = Kokkos::create_mirror_view(values);
  for (int i = 0; i <= n; ++i) rh(i) = a.rowStart[i];
  for (int i = 0; i < n; ++i)
    for (std::size_t k = a.rowStart[i]; k < a.rowStart[i + 1]; ++k) {
      ch(k) = a.cols[k];
      vh(k) = rowScale.empty() ? a.values[k] : rowScale[i] * a.values[k];
    }
  Kokkos::deep_copy(rows, rh);
  Kokkos::deep_copy(cols, ch);
  Kokkos::deep_copy(values, vh);
  op.sparse_ = Sparse(label, n, n, a.values.size(), values, rows, cols);
  return op;
}

BodyOperator BodyOperator::diagonal(const std::vector<double>& d, const std::string& label) {
  BodyOperator op;
  op.kind_ = Kind::Diagonal;
  op.diagonal_ = DenseVector(label, d.size());
  auto h = Kokkos::create_mirror_view(op.diagonal_);
  for (std::size_t i = 0; i < d.size(); ++i) h(i) = d[i];
  Kokkos::deep_copy(op.diagonal_, h);
  return op;
}

std::size_t BodyOperator::bytes() const {
  switch (kind_) {
    case Kind::Dense: return dense_.span() * sizeof(double);
    case Kind::Sparse:
      return sparse_.nnz() * (sizeof(double) + sizeof(int)) + (sparse_.numRows() + 1) * sizeof(std::size_t);
    case Kind::Diagonal: return diagonal_.span() * sizeof(double);
    default: return 0;
  }
}

void BodyOperator::apply(double alpha, const DenseVector& x, double beta, const DenseVector& y) const {
  // The per-step work of a small dense model is a few microseconds: an OpenMP kernel launch per
  // vector operation would cost more than the work (measured: 2 threads 4.5x slower than 1 on a
  // 112-DOF model). The vectors live in host memory (OpenMP), so dense and diagonal operators run as
  // plain loops and one BLAS dgemv (OpenBLAS, which threads large products itself); the sparse
  // product is KokkosKernels' spmv.
  static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, DenseVector::memory_space>::accessible,
                "the explicit step runs on host memory");
  const int n = static_cast<int>(y.extent(0));
  switch (kind_) {
    case Kind::Dense: {
      // One block of rows per thread when the product pays for a parallel region (forEach: about 50
      // bytes of the matrix per ns on one core, measured: 419 x 419 in 19.5 us; a 112 x 112 one
      // stays on the calling thread). Each block is a BLAS dgemv on its rows (column-major: rows
      // r0..r1 start at dense_ + r0, leading dimension n), so each core streams half the matrix
      // from its own cache. The blocks do not depend on the path taken: same bits either way.
      const int T = Kokkos::DefaultHostExecutionSpace().concurrency();
      const long ns = static_cast<long>(dense_.span() * sizeof(double) / 50);
      const double* A = dense_.data();
      const double* xv = x.data();
      double* yv = y.data();
      forEach("epaphe::dynamics::gemv", T, ns / T, [=](const int t) {
        const int r0 = static_cast<int>(static_cast<long>(n) * t / T);
        const int r1 = static_cast<int>(static_cast<long>(n) * (t + 1) / T);
        if (r1 > r0)
          Teuchos::BLAS<int, double>().GEMV(Teuchos::NO_TRANS, r1 - r0, n, alpha, A + r0, n, xv, 1, beta, yv + r0, 1);
      });
      break;
    }
    case Kind::Sparse:
      KokkosSparse::spmv("N", alpha, sparse_, x, beta, y);
      break;
    case Kind::Diagonal: {
      const double* d = diagonal_.data();
      const double* xv = x.data();
      double* yv = y.data();
      if (beta == 0.0)
        for (int i = 0; i < n; ++i) yv[i] = alpha * d[i] * xv[i];
      else
        for (int i = 0; i < n; ++i) yv[i] = alpha * d[i] * xv[i] + beta * yv[i];
      break;
    }
    case Kind::None:
      throw Error("BodyOperator: applying an empty operator");
  }
}

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

std::vector<double> modalDamping(const ReducedModel& model, const DampingOptions& damping) {
  std::vector<double> d;
  for (double w2 : model.modalStiffness()) {
    if (damping.type == DampingType::Rayleigh) d.push_back(damping.alpha + damping.beta * w2);
    else if (damping.type == DampingType::Modal) d.push_back(2 * damping.ratio * std::sqrt(w2));
    else d.push_back(0.0);
  }
  return d;
}

std::vector<double> dampingMatrix(const ReducedModel& model, const DampingOptions& damping) {
  const int n = model.size;
  std::vector<double> D(static_cast<std::size_t>(n) * n, 0.0);
  if (model.massless()) {
    const std::vector<double> d = modalDamping(model, damping);
    const int nb = model.boundarySize();
    for (int k = 0; k < model.numModes; ++k) D[static_cast<std::size_t>(nb + k) * n + nb + k] = d[k];
  } else if (damping.type == DampingType::Rayleigh) {
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
  const BodyOperator Kop = BodyOperator::sparse(K, {}, "epaphe::dynamics::lanczos::K");
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
  std::vector<double> alpha, beta;   // T: diagonal alpha, off-diagonal beta
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
      w[i] -= a * v[i] + betaPrev * vPrev[i];   // w = A v_j - alpha_j v_j - beta_{j-1} v_{j-1}
      b += w[i] * w[i];
    }
    b = std::sqrt(b);
    alpha.push_back(a);
    r.iterations = j + 1;
    // The largest Ritz value theta of T_j and its residual bound beta_j |last component of its vector|.
    const int m = j + 1;
    if (m % 10 == 0 || m == maxIterations || b <= 1e-14 * std::abs(a)) {
      std::vector<double> d(alpha), e(beta), z(static_cast<std::size_t>(m) * m), work(std::max(1, 2 * m - 2));
      int info = 0;
      lapack.STEQR('I', m, d.data(), e.data(), z.data(), m, work.data(), &info);
      EPAPHE_REQUIRE(info == 0, "stable step of body '" << model.name << "': LAPACK dsteqr failed (info " << info << ")");
      r.ritz = d[m - 1];
      r.residual = b * std::abs(z[static_cast<std::size_t>(m - 1) * m + m - 1]);
      if (r.residual <= 1e-10 * r.ritz) {
        r.converged = true;
        break;
      }
    }
    if (b == 0.0) break;   // an invariant subspace without convergence: the Gershgorin bound
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
    EPAPHE_REQUIRE(addedStiffness == 0.0, "body '" << model.name << "' has a massless boundary: no penalty springs "
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

std::string fullModelDampingProblem(const DampingOptions& damping) {
  if (damping.type == DampingType::Modal)
    return "modal damping needs every mode of the full model; use Rayleigh damping with Beta = 0 (D = Alpha M), "
           "or reduce the body";
  if (damping.type == DampingType::Rayleigh && damping.beta != 0.0) {
    std::ostringstream os;
    os << "Rayleigh Beta = " << damping.beta << " makes M/h^2 + D/2h non-diagonal (a linear solve per step); set "
       << "Beta = 0 (and no 'Rayleigh frequencies', which give Beta > 0), or reduce the body";
    return os.str();
  }
  return "";
}

CentralDifference::CentralDifference(const ReducedModel& model, double h, const DampingOptions& damping) : h_(h) {
  const int n = model.size;
  EPAPHE_REQUIRE(h > 0 && std::isfinite(h), "time step = " << h << " s; it must be a finite value > 0");
  damped_ = damping.type != DampingType::None;
  if (model.sparse()) {
    // M = diag(m), D = alpha M, P = [M/h^2 + D/2h]^{-1} and B = -P D / h diagonal, A = -P K sparse
    const std::string problem = fullModelDampingProblem(damping);
    EPAPHE_REQUIRE(problem.empty(), "body '" << model.name << "' is a full model with lumped mass: " << problem);
    const double alpha = damping.type == DampingType::Rayleigh ? damping.alpha : 0.0;
    std::vector<double> D(static_cast<std::size_t>(n)), P(D.size()), minusP(D.size()), B(D.size());
    for (int i = 0; i < n; ++i) {
      const double m = model.lumpedMass[i];
      D[i] = alpha * m;
      P[i] = 1.0 / (m / (h * h) + D[i] / (2 * h));   // P = [M/h^2 + D/2h]^{-1}
      minusP[i] = -P[i];
      B[i] = -P[i] * D[i] / h;                        // B = -P D / h
    }
    A_ = BodyOperator::sparse(model.sparseK, minusP, "epaphe::dynamics::A");   // A = -P K
    K_ = BodyOperator::sparse(model.sparseK, {}, "epaphe::dynamics::K");
    M_ = BodyOperator::diagonal(model.lumpedMass, "epaphe::dynamics::M");
    D_ = BodyOperator::diagonal(D, "epaphe::dynamics::D");
    P_ = BodyOperator::diagonal(P, "epaphe::dynamics::P");
    if (damped_) B_ = BodyOperator::diagonal(B, "epaphe::dynamics::B");
  } else if (model.massless()) {
    // q = [u_b, eta] (Epaphe_ReducedModel.hpp). The modes step by the central difference,
    //   eta* = 2 eta_n - eta_{n-1} + A_e eta_n + B_e (eta_n - eta_{n-1}),  A_e = -P_e Omega^2, B_e = -P_e D_e / h,
    // P_e = (I/h^2 + D_e/2h)^{-1}, all diagonal, and the massless boundary follows them, u_b* = Phi_b eta*:
    // in the common form this is A = [-I, Phi_b (I + A_e); 0, A_e], B = [-I, Phi_b (I + B_e); 0, B_e].
    // The contact correction q += F f (f: forces on u_b) must move eta by P_e Phi_b^T f and u_b by
    // Phi_b times that plus the static residual G f, so F = [G + Phi_b P_e Phi_b^T, Phi_b P_e; P_e Phi_b^T, P_e].
    // Energy: the modes obey the identity at the top of the header; the residual part stores
    // 1/2 r^T G^{-1} r, r = u_b - Phi_b eta = G f_{n-1} after step n-1, and the force of step n does
    // work f_n . (r_{n+1} - r_{n-1}) / 2 on it, which is exactly
    //   1/4 (r_{n+1}^T G^{-1} r_{n+1} - r_{n-1}^T G^{-1} r_{n-1}) + 1/4 (r_{n+1} - r_{n-1})^T G^{-1} (r_{n+1} - r_{n-1}):
    // a stored half-step energy 1/4 (r_n^T G^{-1} r_n + r_{n+1}^T G^{-1} r_{n+1}) and a dissipation
    // >= 0 (the lag of the static residual behind the force) counted with damping, as h K_res in D.
    const int nb = model.boundarySize(), m = model.numModes;
    const std::vector<double> w2 = model.modalStiffness(), d = modalDamping(model, damping);
    const auto& Phi = model.boundaryModes;
    auto phi = [&](int c, int k) { return Phi[static_cast<std::size_t>(k) * nb + c]; };
    auto at = [n](std::vector<double>& X, int i, int j) -> double& { return X[static_cast<std::size_t>(j) * n + i]; };
    std::vector<double> A(static_cast<std::size_t>(n) * n, 0.0), B(A.size(), 0.0), P(A.size(), 0.0), D(A.size(), 0.0),
        Kmid(static_cast<std::size_t>(n), 0.0);
    for (int k = 0; k < m; ++k) {
      const double Pe = 1.0 / (1.0 / (h * h) + d[k] / (2 * h)), Ae = -Pe * w2[k], Be = -Pe * d[k] / h;
      at(A, nb + k, nb + k) = Ae;
      at(B, nb + k, nb + k) = Be;
      at(P, nb + k, nb + k) = Pe;
      at(D, nb + k, nb + k) = d[k];
      Kmid[nb + k] = w2[k];
      for (int c = 0; c < nb; ++c) {
        at(A, c, nb + k) = phi(c, k) * (1.0 + Ae);
        at(B, c, nb + k) = phi(c, k) * (1.0 + Be);
        at(P, c, nb + k) = at(P, nb + k, c) = phi(c, k) * Pe;
        for (int c2 = 0; c2 < nb; ++c2) at(P, c, c2) += phi(c, k) * Pe * phi(c2, k);
      }
    }
    for (int c = 0; c < nb; ++c) {
      at(A, c, c) = -1.0;
      at(B, c, c) = -1.0;
      for (int c2 = 0; c2 < nb; ++c2) at(P, c, c2) += model.residualFlexibility[static_cast<std::size_t>(c2) * nb + c];
    }
    const std::vector<double> Kres = model.residualStiffness();   // of the residual r = u_b - Phi_b eta
    std::vector<double> Ddiss(A.size());
    for (std::size_t k = 0; k < Ddiss.size(); ++k) Ddiss[k] = D[k] + h * Kres[k];
    damped_ = true;   // B carries the boundary's rows; the residual dissipates
    A_ = BodyOperator::dense(A, n, "epaphe::dynamics::A");
    B_ = BodyOperator::dense(B, n, "epaphe::dynamics::B");
    K_ = BodyOperator::dense(model.K, n, "epaphe::dynamics::K");   // = K_res + diag(Kmid)
    Kmid_ = BodyOperator::diagonal(Kmid, "epaphe::dynamics::Kmid");
    Kres_ = BodyOperator::dense(Kres, n, "epaphe::dynamics::Kres");
    M_ = BodyOperator::dense(model.M, n, "epaphe::dynamics::M");
    D_ = BodyOperator::dense(Ddiss, n, "epaphe::dynamics::D");
    P_ = BodyOperator::dense(P, n, "epaphe::dynamics::P");
    residual_ = true;
  } else {
    const std::vector<double> D = dampingMatrix(model, damping);
    // P = [M/h^2 + D/2h]^{-1}
    std::vector<double> lhs(D.size());
    for (std::size_t k = 0; k < lhs.size(); ++k) lhs[k] = model.M[k] / (h * h) + D[k] / (2 * h);
    const std::vector<double> P = spdInverse(lhs, n, "M/h^2 + D/2h of body '" + model.name + "'",
                                             "check the mass matrix and the damping coefficients");
    // A = -P K, B = -P D / h
    std::vector<double> A(D.size()), B(D.size());
    Teuchos::BLAS<int, double> blas;
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0, P.data(), n, model.K.data(), n, 0.0, A.data(), n);
    A_ = BodyOperator::dense(A, n, "epaphe::dynamics::A");
    if (damped_) {
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, -1.0 / h, P.data(), n, D.data(), n, 0.0, B.data(), n);
      B_ = BodyOperator::dense(B, n, "epaphe::dynamics::B");
    }
    K_ = BodyOperator::dense(model.K, n, "epaphe::dynamics::K");
    M_ = BodyOperator::dense(model.M, n, "epaphe::dynamics::M");
    D_ = BodyOperator::dense(D, n, "epaphe::dynamics::D");
    P_ = BodyOperator::dense(P, n, "epaphe::dynamics::P");
  }
  f_ = DenseVector("epaphe::dynamics::f", n);
  Pf_ = DenseVector("epaphe::dynamics::Pf", n);
  tmp_ = DenseVector("epaphe::dynamics::tmp", n);
  tmp2_ = DenseVector("epaphe::dynamics::tmp2", n);
}

Flexibility CentralDifference::flexibility() const {
  return P_.denseMatrix().extent(0) > 0 ? Flexibility(P_.denseMatrix()) : Flexibility::diagonal(P_.diagonalEntries());
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
  P_.apply(1.0, f_, 0.0, Pf_);
}

void CentralDifference::predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar) const {
  const int n = static_cast<int>(qn.extent(0));
  double* qs = qstar.data();
  const double* q0 = qn.data();
  const double* q1 = qnm1.data();
  for (int i = 0; i < n; ++i) qs[i] = 2.0 * q0[i] - q1[i];                          // 2 q_n - q_{n-1}
  A_.apply(1.0, qn, 1.0, qstar);                                                    // + A q_n
  if (damped_) {                                                                    // + B (q_n - q_{n-1})
    double* d = tmp_.data();
    for (int i = 0; i < n; ++i) d[i] = q0[i] - q1[i];
    B_.apply(1.0, tmp_, 1.0, qstar);
  }
  if (forced_) {                                                                    // + P f
    const double* pf = Pf_.data();
    for (int i = 0; i < n; ++i) qs[i] += pf[i];
  }
}

double CentralDifference::halfStepEnergy(const DenseVector& qn, const DenseVector& qnp1) const {
  // 1/2 v^T M v with v = (q_{n+1} - q_n)/h, plus 1/2 q_n^T K q_{n+1}
  copy(tmp2_, qnp1);
  epaphe::axpby(-1.0 / h_, qn, 1.0 / h_, tmp2_);
  M_.apply(1.0, tmp2_, 0.0, tmp_);
  const double kin = 0.5 * epaphe::dot(tmp2_, tmp_);
  if (!residual_) {
    K_.apply(1.0, qnp1, 0.0, tmp_);
    return kin + 0.5 * epaphe::dot(qn, tmp_);
  }
  // massless boundary: modes as above, plus 1/4 (q_n^T K_res q_n + q_{n+1}^T K_res q_{n+1})
  Kmid_.apply(1.0, qnp1, 0.0, tmp_);
  double e = kin + 0.5 * epaphe::dot(qn, tmp_);
  Kres_.apply(1.0, qnp1, 0.0, tmp_);
  e += 0.25 * epaphe::dot(qnp1, tmp_);
  Kres_.apply(1.0, qn, 0.0, tmp_);
  return e + 0.25 * epaphe::dot(qn, tmp_);
}

double CentralDifference::dampingIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const {
  if (!damped_) return 0.0;
  copy(tmp2_, qnp1);
  epaphe::axpby(-1.0, qnm1, 1.0, tmp2_);
  D_.apply(1.0, tmp2_, 0.0, tmp_);
  return epaphe::dot(tmp2_, tmp_) / (4 * h_);
}

double CentralDifference::externalWorkIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const {
  if (!forced_) return 0.0;
  copy(tmp2_, qnp1);
  epaphe::axpby(-1.0, qnm1, 1.0, tmp2_);
  return 0.5 * epaphe::dot(f_, tmp2_);
}

double CentralDifference::strain(const DenseVector& q) const {
  K_.apply(1.0, q, 0.0, tmp_);
  return 0.5 * epaphe::dot(q, tmp_);
}

double CentralDifference::kinetic(const DenseVector& v) const {
  M_.apply(1.0, v, 0.0, tmp_);
  return 0.5 * epaphe::dot(v, tmp_);
}

}  // namespace epaphe
