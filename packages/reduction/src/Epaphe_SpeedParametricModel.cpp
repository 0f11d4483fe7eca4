#include "Epaphe_SpeedParametricModel.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>

namespace epaphe {

namespace {

using Dense = std::vector<double>;  // column-major unless said

/// C = A^T B for column-major A (m x p), B (m x q): C is p x q.
Dense transposeTimes(const double* A, int lda, const double* B, int ldb, int m, int p, int q) {
  Dense C(static_cast<std::size_t>(p) * q, 0.0);
  if (m > 0 && p > 0 && q > 0)
    Teuchos::BLAS<int, double>().GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, p, q, m, 1.0, A, lda, B, ldb, 0.0, C.data(), p);
  return C;
}

void symmetrize(Dense& A, int n) {
  for (int j = 0; j < n; ++j)
    for (int i = j + 1; i < n; ++i) {
      const double v = 0.5 * (A[static_cast<std::size_t>(j) * n + i] + A[static_cast<std::size_t>(i) * n + j]);
      A[static_cast<std::size_t>(j) * n + i] = A[static_cast<std::size_t>(i) * n + j] = v;
    }
}

/// T^T A T (N x N, on every rank) for the basis T over A's rows.
Dense project(const CrsMatrix& A, const MultiVector& T) {
  MultiVector X(T.getMap(), T.getNumVectors());
  A.apply(T, X);
  const int N = static_cast<int>(T.getNumVectors());
  const int m = static_cast<int>(T.getLocalLength());
  auto t = T.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
  const int ldt = m > 0 ? static_cast<int>(t.stride(1)) : 1, ldx = m > 0 ? static_cast<int>(x.stride(1)) : 1;
  Dense local = transposeTimes(t.data(), std::max(ldt, 1), x.data(), std::max(ldx, 1), m, N, N), global(local.size());
  Teuchos::reduceAll(*T.getMap()->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(),
                     global.data());
  symmetrize(global, N);
  return global;
}

/// The inverse of the Vandermonde matrix V_sk = xi_s^k (S x S, column-major) by Gauss-Jordan with
/// partial pivoting; the xi_s are distinct.
Dense vandermondeInverse(const std::vector<double>& xi) {
  const int S = static_cast<int>(xi.size());
  Dense A(static_cast<std::size_t>(S) * S), X(A.size(), 0.0);
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < S; ++k) A[static_cast<std::size_t>(k) * S + s] = std::pow(xi[s], k);
  for (int i = 0; i < S; ++i) X[static_cast<std::size_t>(i) * S + i] = 1;
  for (int c = 0; c < S; ++c) {
    int p = c;
    for (int r = c + 1; r < S; ++r)
      if (std::abs(A[static_cast<std::size_t>(c) * S + r]) > std::abs(A[static_cast<std::size_t>(c) * S + p])) p = r;
    for (int k = 0; k < S; ++k) {
      std::swap(A[static_cast<std::size_t>(k) * S + c], A[static_cast<std::size_t>(k) * S + p]);
      std::swap(X[static_cast<std::size_t>(k) * S + c], X[static_cast<std::size_t>(k) * S + p]);
    }
    const double d = A[static_cast<std::size_t>(c) * S + c];
    for (int k = 0; k < S; ++k) {
      A[static_cast<std::size_t>(k) * S + c] /= d;
      X[static_cast<std::size_t>(k) * S + c] /= d;
    }
    for (int r = 0; r < S; ++r) {
      if (r == c) continue;
      const double f = A[static_cast<std::size_t>(c) * S + r];
      for (int k = 0; k < S; ++k) {
        A[static_cast<std::size_t>(k) * S + r] -= f * A[static_cast<std::size_t>(k) * S + c];
        X[static_cast<std::size_t>(k) * S + r] -= f * X[static_cast<std::size_t>(k) * S + c];
      }
    }
  }
  return X;  // X V = I: coefficient k of the interpolant is sum_s X_ks y_s
}

/// sum_k xi^k coefficient_k, coefficient_0 given apart.
Dense polynomial(const Dense& c0, const std::vector<Dense>& higher, double xi) {
  Dense out = c0;
  double p = 1;
  for (const Dense& c : higher) {
    p *= xi;
    for (std::size_t i = 0; i < out.size(); ++i) out[i] += p * c[i];
  }
  return out;
}

}  // namespace

std::vector<double> sampleSpeeds(double minSpeed, double maxSpeed, int count) {
  EPAPHE_REQUIRE(count >= 2, "a speed range needs 2 or more sample speeds, not " << count);
  EPAPHE_REQUIRE(minSpeed >= 0 && maxSpeed > minSpeed && std::isfinite(maxSpeed),
                 "speed range [" << minSpeed << ", " << maxSpeed << "] rad/s: give 0 <= minimum < maximum");
  const double a = minSpeed * minSpeed, b = maxSpeed * maxSpeed;
  std::vector<double> s;
  for (int k = 0; k < count; ++k) {
    const double x = 0.5 * (a + b) - 0.5 * (b - a) * std::cos(M_PI * k / (count - 1));
    s.push_back(k == 0 ? minSpeed : (k == count - 1 ? maxSpeed : std::sqrt(x)));
  }
  return s;
}

SpeedParametricModel parametricCraigBampton(const FullModel& rest, const std::vector<int>& retained,
                                            const CraigBamptonOptions& options, const RotationOptions& rotation,
                                            std::vector<double> speeds, ReductionReport* report) {
  BuiltInSpeedSource source(rest, rotation);
  return parametricCraigBampton(source, retained, options, std::move(speeds), report);
}

SpeedParametricModel parametricCraigBampton(SpeedSampleSource& source, const std::vector<int>& retained,
                                            const CraigBamptonOptions& options, std::vector<double> speeds,
                                            ReductionReport* report) {
  Stopwatch total;
  const FullModel& rest = source.reference();
  std::sort(speeds.begin(), speeds.end());
  EPAPHE_REQUIRE(speeds.size() >= 2 && std::adjacent_find(speeds.begin(), speeds.end()) == speeds.end() &&
                     speeds.front() >= 0,
                 "body '" << rest.name << "': a parametric model needs 2 or more distinct sample speeds >= 0");
  const int S = static_cast<int>(speeds.size());
  const std::size_t rows = rest.eq.size();  // 3 per node

  // One model at speed (from the source, fastest first) and one Craig-Bampton reduction per sample.
  std::vector<ReducedModel> red(static_cast<std::size_t>(S));
  std::vector<Dense> grow(static_cast<std::size_t>(S));
  std::vector<Teuchos::RCP<const CrsMatrix>> K(static_cast<std::size_t>(S));
  ReductionReport rep;
  for (int s = S - 1; s >= 0; --s) {
    SpeedSample at = source.sample(speeds[s]);
    EPAPHE_REQUIRE(at.staticDisplacement.size() == rows && at.model.eq == rest.eq,
                   "body '" << rest.name << "': the model at " << speeds[s] << " rad/s has "
                            << at.staticDisplacement.size() / 3 << " nodes or another DOF numbering than the model at "
                            << "the reference speed; every sample speed must number the same DOFs");
    grow[s] = std::move(at.staticDisplacement);
    ReductionReport r;
    CraigBamptonOptions co = options;
    co.checkFrequencies = 0;
    co.basisOnly = true;
    red[s] = craigBampton(at.model, retained, co, &r);
    K[s] = at.model.K;
    rep.factorSeconds += r.factorSeconds;
    rep.constraintSeconds += r.constraintSeconds;
    rep.eigenSeconds += r.eigenSeconds + at.seconds;
    rep.retainedDofs = r.retainedDofs;
    rep.condensedDofs = r.condensedDofs;
  }
  const int nR = red[0].size - red[0].numModes, modes = red[0].numModes;

  // Interior vectors (zero on the retained DOFs): the fixed-interface modes scaled to unit length, the
  // constraint-mode changes Psi_s - Psi_1 scaled by the length of Psi_1's column (a change is measured
  // against the mode it changes), then an orthonormal basis of their span: the left singular vectors
  // of their matrix Y (LAPACK dgesvd), those whose singular value is below 1e-8 of the largest dropped
  // (a constraint mode is then in the span to 1e-8 of its length; the frequencies at the samples stay
  // within 2e-9 of the direct reduction's, test_speed.cpp). An SVD of Y, not the eigenvectors of
  // Y^T Y: the small singular values carry the boundary-dominated modes and must not be squared into
  // round-off. The drop keeps the basis, and the projections below, small: on a 10,000-DOF blade
  // with 82 retained nodes and 4 samples it keeps 424 of 796 vectors.
  const int m = S * modes + (S - 1) * nR;
  Dense Y(rows * static_cast<std::size_t>(m), 0.0);  // column-major rows x m
  int col = 0;
  std::vector<double> psiNorm(static_cast<std::size_t>(nR), 0.0);
  for (std::size_t i = 0; i < rows; ++i)
    for (int j = 0; j < nR; ++j) {
      const double v = red[0].recovery[i * red[0].size + j];
      psiNorm[j] += v * v;
    }
  for (double& v : psiNorm) v = std::sqrt(v);
  auto addColumn = [&](auto value, double scale) {
    double norm = 0;
    for (std::size_t i = 0; i < rows; ++i) norm += value(i) * value(i);
    norm = std::sqrt(norm);
    if (norm == 0) return;
    if (scale > 0) norm = scale;
    for (std::size_t i = 0; i < rows; ++i) Y[static_cast<std::size_t>(col) * rows + i] = value(i) / norm;
    ++col;
  };
  for (int s = 0; s < S; ++s) {
    const std::size_t n = static_cast<std::size_t>(red[s].size);
    for (int j = 0; j < modes; ++j) addColumn([&](std::size_t i) { return red[s].recovery[i * n + nR + j]; }, 0.0);
    if (s > 0)
      for (int j = 0; j < nR; ++j)
        addColumn([&](std::size_t i) { return red[s].recovery[i * n + j] - red[0].recovery[i * red[0].size + j]; },
                  psiNorm[j]);
  }
  const int mc = col, rowsI = static_cast<int>(rows);
  std::vector<double> sigma(static_cast<std::size_t>(std::max(mc, 1)));
  if (mc > 0) {
    Teuchos::LAPACK<int, double> lapack;
    int info = 0;
    double query = 0, unused = 0;
    lapack.GESVD('O', 'N', rowsI, mc, Y.data(), rowsI, sigma.data(), nullptr, 1, nullptr, 1, &query, -1, nullptr, &info);
    Dense work(static_cast<std::size_t>(query));
    lapack.GESVD('O', 'N', rowsI, mc, Y.data(), rowsI, sigma.data(), nullptr, 1, nullptr, 1, work.data(),
                 static_cast<int>(work.size()), &unused, &info);
    EPAPHE_REQUIRE(info == 0, "body '" << rest.name << "': the SVD of the parametric model's interior vectors failed "
                                       << "(LAPACK dgesvd info " << info << ")");
  }
  int r = 0;
  while (r < mc && sigma[r] > 1e-8 * sigma[0]) ++r;  // descending
  const int N = nR + r;

  SpeedParametricModel p;
  p.speeds = speeds;
  p.staticState = source.staticState();
  p.boundarySize = nR;
  p.base = red[0];
  p.base.name = rest.name;
  p.base.coords = rest.mesh.coords;
  p.base.size = N;
  p.base.numModes = r;
  p.base.modeFrequencies.clear();
  p.base.fullFrequencies.clear();
  p.base.staticDisplacement.clear();
  p.base.speed = 0;
  // T (rows x N, row-major as a recovery): the first sample's constraint modes, then the kept U of Y.
  Dense& T = p.base.recovery;
  T.assign(rows * static_cast<std::size_t>(N), 0.0);
  for (std::size_t i = 0; i < rows; ++i)
    for (int j = 0; j < nR; ++j) T[i * N + j] = red[0].recovery[i * red[0].size + j];
  for (std::size_t i = 0; i < rows; ++i)
    for (int c = 0; c < r; ++c) T[i * N + nR + c] = Y[static_cast<std::size_t>(c) * rows + i];

  // T over the free DOFs as a distributed multivector, then T^T K(Omega_s) T and T^T M T.
  const auto map = rest.K->getRowMap();
  MultiVector Tf(map, static_cast<std::size_t>(N));
  {
    auto t = Tf.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (std::size_t i = 0; i < rows; ++i) {
      const int g = rest.eq[i];
      if (g < 0 || !map->isNodeGlobalElement(g)) continue;
      const LO l = map->getLocalElement(g);
      for (int j = 0; j < N; ++j) t(l, j) = T[i * N + j];
    }
  }
  std::vector<Dense> Ks(static_cast<std::size_t>(S));
  for (int s = 0; s < S; ++s) Ks[s] = project(*K[s], Tf);
  p.base.M = project(*rest.M, Tf);

  // Interpolation in xi = (Omega / Omega_max)^2.
  std::vector<double> xi;
  for (double w : speeds) xi.push_back((w / speeds.back()) * (w / speeds.back()));
  const Dense X = vandermondeInverse(xi);
  auto coefficient = [&](const std::vector<Dense>& y, int k) {
    Dense c(y[0].size(), 0.0);
    for (int s = 0; s < S; ++s) {
      const double w = X[static_cast<std::size_t>(s) * S + k];
      for (std::size_t i = 0; i < c.size(); ++i) c[i] += w * y[s][i];
    }
    return c;
  };
  p.base.K = coefficient(Ks, 0);
  for (int k = 1; k < S; ++k) p.stiffness.push_back(coefficient(Ks, k));
  for (int k = 0; k < S; ++k) p.growth.push_back(coefficient(grow, k));
  rep.seconds = total.seconds();
  rep.projectSeconds = rep.seconds - rep.factorSeconds - rep.constraintSeconds - rep.eigenSeconds;
  if (report) *report = rep;
  return p;
}

std::vector<double> SpeedParametricModel::stiffnessAt(double speed) const {
  const double xi = (speed / maxSpeed()) * (speed / maxSpeed());
  return polynomial(base.K, stiffness, xi);
}

std::vector<double> SpeedParametricModel::staticDisplacementAt(double speed) const {
  const double xi = (speed / maxSpeed()) * (speed / maxSpeed());
  return polynomial(growth[0], std::vector<Dense>(growth.begin() + 1, growth.end()), xi);
}

std::vector<double> SpeedParametricModel::frequenciesAt(double speed, int count) const {
  std::vector<double> w2 = denseEigenpairs(stiffnessAt(speed), base.M, base.size);
  std::vector<double> f;
  for (int i = 0; i < count && i < static_cast<int>(w2.size()); ++i) f.push_back(std::sqrt(std::max(w2[i], 0.0)) / (2 * M_PI));
  return f;
}

ReducedModel SpeedParametricModel::at(double speed, int modes, const std::string& context,
                                      std::vector<double>* basis) const {
  const double slack = 1e-9 * (maxSpeed() - minSpeed());
  EPAPHE_REQUIRE(speed >= minSpeed() - slack && speed <= maxSpeed() + slack,
                 context << ": speed " << speed << " rad/s is outside the model's range [" << minSpeed() << ", "
                         << maxSpeed() << "] rad/s; widen 'Rotation->Speed range' to include it");
  const int N = base.size, nb = boundarySize, ni = N - nb;
  EPAPHE_REQUIRE(modes >= 0 && modes <= ni, context << ": " << modes << " fixed-interface modes asked of a parametric "
                                                    << "model with " << ni << " interior DOFs");
  const Dense K = stiffnessAt(speed);
  auto block = [&](const Dense& A, int r0, int nr, int c0, int nc) {
    Dense B(static_cast<std::size_t>(nr) * nc);
    for (int j = 0; j < nc; ++j)
      for (int i = 0; i < nr; ++i) B[static_cast<std::size_t>(j) * nr + i] = A[static_cast<std::size_t>(c0 + j) * N + r0 + i];
    return B;
  };
  // S = [I 0; Psi' Phi'], Psi' = -K_ii^-1 K_ib, K_ii Phi' = M_ii Phi' Lambda (the lowest `modes`)
  Dense Kii = block(K, nb, ni, nb, ni), Mii = block(base.M, nb, ni, nb, ni), Psi = block(K, nb, ni, 0, nb);
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  Dense chol = Kii;
  lapack.POTRF('L', ni, chol.data(), ni, &info);
  EPAPHE_REQUIRE(info == 0, context << ": the interior stiffness of the parametric model at " << speed
                                    << " rad/s is not positive definite (LAPACK dpotrf info " << info
                                    << "): the speed is past a critical one of the clamped interior");
  lapack.POTRS('L', ni, nb, chol.data(), ni, Psi.data(), ni, &info);
  for (double& v : Psi) v = -v;
  Dense vec;
  const Dense lambda = denseEigenpairs(Kii, Mii, ni, &vec);
  const int n = nb + modes;
  Dense Sm(static_cast<std::size_t>(N) * n, 0.0);  // N x n column-major
  for (int j = 0; j < nb; ++j) {
    Sm[static_cast<std::size_t>(j) * N + j] = 1;
    for (int i = 0; i < ni; ++i) Sm[static_cast<std::size_t>(j) * N + nb + i] = Psi[static_cast<std::size_t>(j) * ni + i];
  }
  for (int k = 0; k < modes; ++k)
    for (int i = 0; i < ni; ++i) Sm[static_cast<std::size_t>(nb + k) * N + nb + i] = vec[static_cast<std::size_t>(k) * ni + i];

  ReducedModel r = base;
  r.kind = modes == 0 ? ReductionKind::Guyan : ReductionKind::CraigBampton;
  r.size = n;
  r.numModes = modes;
  Teuchos::BLAS<int, double> blas;
  Dense KS(static_cast<std::size_t>(N) * n), MS(KS.size());
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, N, n, N, 1.0, K.data(), N, Sm.data(), N, 0.0, KS.data(), N);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, N, n, N, 1.0, base.M.data(), N, Sm.data(), N, 0.0, MS.data(), N);
  r.K = transposeTimes(Sm.data(), N, KS.data(), N, N, n, n);
  r.M = transposeTimes(Sm.data(), N, MS.data(), N, N, n, n);
  symmetrize(r.K, n);
  symmetrize(r.M, n);
  // recovery T S: row-major T (rows x N) is column-major T^T (N x rows); (T S)^T = S^T T^T
  const int rows = static_cast<int>(base.recovery.size() / static_cast<std::size_t>(N));
  r.recovery.assign(static_cast<std::size_t>(rows) * n, 0.0);
  blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, n, rows, N, 1.0, Sm.data(), N, base.recovery.data(), N, 0.0,
            r.recovery.data(), n);
  r.modeFrequencies.clear();
  for (int k = 0; k < modes; ++k) r.modeFrequencies.push_back(std::sqrt(std::max(lambda[k], 0.0)) / (2 * M_PI));
  r.speed = speed;
  r.staticDisplacement = staticDisplacementAt(speed);
  for (std::size_t a = 0; a < r.coords.size(); ++a)
    for (int d = 0; d < 3; ++d) r.coords[a][d] += r.staticDisplacement[3 * a + d];
  if (basis) *basis = std::move(Sm);
  return r;
}

SpeedParametricModel::FixedBasis SpeedParametricModel::onFixedBasis(double speed, int modes,
                                                                    const std::string& context) const {
  FixedBasis f;
  Dense S;
  f.model = at(speed, modes, context, &S);
  const int N = base.size, n = f.model.size;
  Teuchos::BLAS<int, double> blas;
  Dense CS(static_cast<std::size_t>(N) * n);
  for (std::size_t k = 0; k <= stiffness.size(); ++k) {
    const Dense& C = k == 0 ? base.K : stiffness[k - 1];
    // R_k = S^T C_k S
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, N, n, N, 1.0, C.data(), N, S.data(), N, 0.0, CS.data(), N);
    f.stiffness.push_back(transposeTimes(S.data(), N, CS.data(), N, N, n, n));
    symmetrize(f.stiffness.back(), n);
  }
  return f;
}

}  // namespace epaphe
