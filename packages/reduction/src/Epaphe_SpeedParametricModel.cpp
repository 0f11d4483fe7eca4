#include "Epaphe_SpeedParametricModel.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_ReductionShared.hpp"
#include "Epaphe_Runtime.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

// LAPACK's divide-and-conquer SVD (Teuchos::LAPACK has no wrapper for it)
extern "C" void dgesdd_(const char* jobz, const int* m, const int* n, double* a, const int* lda, double* s, double* u,
                        const int* ldu, double* vt, const int* ldvt, double* work, const int* lwork, int* iwork,
                        int* info);

namespace epaphe {

namespace {

using Dense = std::vector<double>;  // column-major unless said

/// C = A^T B for column-major A (m x p), B (m x q): C is p x q.
Dense transposeTimes(const double* A, int lda, const double* B, int ldb, int m, int p, int q) {
  Dense C(static_cast<std::size_t>(p) * q, 0.0);
  if (m > 0 && p > 0 && q > 0)
    Teuchos::BLAS<int, double>().GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, p, q, m, 1.0, A, lda, B, ldb, 0.0, C.data(),
                                      p);
  return C;
}

void symmetrize(Dense& A, int n) {
  for (int j = 0; j < n; ++j)
    for (int i = j + 1; i < n; ++i) {
      const double v = 0.5 * (A[static_cast<std::size_t>(j) * n + i] + A[static_cast<std::size_t>(i) * n + j]);
      A[static_cast<std::size_t>(j) * n + i] = A[static_cast<std::size_t>(i) * n + j] = v;
    }
}

/// T^T X (columns of T x columns of X, on every rank) for distributed T and X on one map.
Dense transposeTimesDistributed(const MultiVector& T, const MultiVector& X) {
  const int N = static_cast<int>(T.getNumVectors()), q = static_cast<int>(X.getNumVectors());
  const int m = static_cast<int>(T.getLocalLength());
  auto t = T.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
  const int ldt = m > 0 ? static_cast<int>(t.stride(1)) : 1, ldx = m > 0 ? static_cast<int>(x.stride(1)) : 1;
  Dense local = transposeTimes(t.data(), std::max(ldt, 1), x.data(), std::max(ldx, 1), m, N, q), global(local.size());
  Teuchos::reduceAll(*T.getMap()->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(),
                     global.data());
  return global;
}

/// T^T A T (N x N, on every rank) for the basis T over the rows of matrices A (a MultiVector over A's
/// domain map), for several A on one basis: T is laid out row-major once, and again on A's column map
/// only when that map differs from the previous matrix's. The product A T is formed row by row on T's
/// rows held row-major (each stored entry of A scales a contiguous row of N values: a Tpetra apply over
/// N columns walks A once per column), then T^T (A T) by GEMMs over column blocks J of the upper
/// triangle only, T(:, 1..end J)^T (A T)(:, J): A is symmetric, so the lower triangle is the upper's
/// transpose, and the blocks of 64 columns take (N + 64) / 2N of the full product's flops (56 % for
/// N = 676) for the same result to round-off.
class Projector {
public:
  explicit Projector(const MultiVector& T) : T_(T), N_(static_cast<int>(T.getNumVectors())) {
    const std::size_t rows = T.getLocalLength();
    TR_.resize(rows * N_);
    auto own = T.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (int j = 0; j < N_; ++j)
      for (std::size_t r = 0; r < rows; ++r) TR_[r * N_ + j] = own(r, j);
  }

  Dense operator()(const CrsMatrix& A) {
    const int N = N_;
    EPAPHE_REQUIRE(A.getNodeNumRows() == T_.getLocalLength(), "projecting a matrix of "
                                                                  << A.getNodeNumRows() << " local rows on a basis of "
                                                                  << T_.getLocalLength() << ": their row maps differ");
    const auto importer = A.getGraph()->getImporter();
    const Dense* byRow = &TR_;  // no importer: the column map is the row map
    if (!importer.is_null()) {
      if (columns_.is_null() || !columns_->isSameAs(*A.getColMap())) {
        MultiVector imported(A.getColMap(), static_cast<std::size_t>(N));
        imported.doImport(T_, *importer, Tpetra::INSERT);
        const std::size_t cols = imported.getLocalLength();
        byColumn_.assign(cols * N, 0.0);
        auto t = imported.getLocalViewHost(Tpetra::Access::ReadOnly);
        for (int j = 0; j < N; ++j)
          for (std::size_t c = 0; c < cols; ++c) byColumn_[c * N + j] = t(c, j);
        columns_ = A.getColMap();
      }
      byRow = &byColumn_;
    }
    const std::size_t rows = A.getNodeNumRows();
    Dense AT(rows * N, 0.0);  // row-major
    typename CrsMatrix::local_inds_host_view_type idx;
    typename CrsMatrix::values_host_view_type val;
    for (std::size_t r = 0; r < rows; ++r) {
      A.getLocalRowView(static_cast<LO>(r), idx, val);
      double* out = &AT[r * N];
      for (std::size_t k = 0; k < idx.extent(0); ++k) {
        const double v = val(k);
        const double* in = &(*byRow)[static_cast<std::size_t>(idx(k)) * N];
        for (int j = 0; j < N; ++j) out[j] += v * in[j];
      }
    }
    // the row-major rows x N arrays are column-major N x rows: T^T (A T) = TR' AT'^T, upper blocks
    Dense local(static_cast<std::size_t>(N) * N, 0.0), global(local.size());
    constexpr int block = 64;
    if (rows > 0)
      for (int j0 = 0; j0 < N; j0 += block) {
        const int nb = std::min(block, N - j0), upto = j0 + nb;
        Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, upto, nb, static_cast<int>(rows), 1.0,
                                          TR_.data(), N, AT.data() + j0, N, 0.0,
                                          local.data() + static_cast<std::size_t>(j0) * N, N);
      }
    Teuchos::reduceAll(*T_.getMap()->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(),
                       global.data());
    // the lower triangle from the upper: the blocks' diagonal parts hold both, averaged as before
    for (int j = 0; j < N; ++j)
      for (int i = j + 1; i < N; ++i) {
        const std::size_t up = static_cast<std::size_t>(i) * N + j, low = static_cast<std::size_t>(j) * N + i;
        global[low] = (i / block == j / block) ? 0.5 * (global[low] + global[up]) : global[up];
        global[up] = global[low];
      }
    return global;
  }

private:
  const MultiVector& T_;
  int N_;
  Dense TR_, byColumn_;  // T's own rows, and T on the last column map (row-major)
  Teuchos::RCP<const Map> columns_;
};

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

/// K (n x n, column-major) overwritten by its Cholesky factor, or an Error naming `what` and the speed:
/// a parametric model's stiffness that is not positive definite is past a critical speed of the body.
void factorAtSpeed(Dense& K, int n, double speed, const std::string& what) {
  int info = 0;
  Teuchos::LAPACK<int, double>().POTRF('L', n, K.data(), n, &info);
  EPAPHE_REQUIRE(info == 0, what << ": the parametric model at " << speed << " rad/s is not positive definite "
                                 << "(LAPACK dpotrf info " << info << "): the speed range passes a critical "
                                 << "speed of the body; narrow 'Rotation->Speed range'");
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

namespace {

/// The samples of a parametric model: the static state and one reduction at each speed (ascending).
struct Samples {
  std::vector<ReducedModel> red;
  std::vector<Dense> grow;                       // u_s, 3 per node
  std::vector<Teuchos::RCP<const CrsMatrix>> K;  // K(Omega_s) of the full model
  StaticState staticState = StaticState::Linear;
  ReductionReport rep;
};

using Reduce = std::function<ReducedModel(const FullModel&, const ReducedModel*, ReductionReport*)>;

/// One model at speed (from the source, fastest first) and one reduction (`reduce`) per sample speed.
Samples reduceAtSamples(SpeedSampleSource& source, std::vector<double>& speeds, const Reduce& reduce) {
  const FullModel& rest = source.reference();
  std::sort(speeds.begin(), speeds.end());
  EPAPHE_REQUIRE(
      speeds.size() >= 2 && std::adjacent_find(speeds.begin(), speeds.end()) == speeds.end() && speeds.front() >= 0,
      "body '" << rest.name << "': a parametric model needs 2 or more distinct sample speeds >= 0");
  const int S = static_cast<int>(speeds.size());
  const std::size_t rows = rest.eq.size();
  Samples out;
  out.red.resize(static_cast<std::size_t>(S));
  out.grow.resize(static_cast<std::size_t>(S));
  out.K.resize(static_cast<std::size_t>(S));
  for (int s = S - 1; s >= 0; --s) {
    SpeedSample at = source.sample(speeds[s]);
    EPAPHE_REQUIRE(at.staticDisplacement.size() == rows && at.model.eq == rest.eq,
                   "body '" << rest.name << "': the model at " << speeds[s] << " rad/s has "
                            << at.staticDisplacement.size() / 3 << " nodes or another DOF numbering than the model at "
                            << "the reference speed; every sample speed must number the same DOFs");
    out.grow[s] = std::move(at.staticDisplacement);
    ReductionReport r;
    out.red[s] = reduce(at.model, s + 1 < S ? &out.red[s + 1] : nullptr, &r);
    out.K[s] = at.model.K;
    out.rep.factorSeconds += r.factorSeconds;
    out.rep.constraintSeconds += r.constraintSeconds;
    out.rep.eigenSeconds += r.eigenSeconds;
    out.rep.staticSeconds += at.seconds;
    out.rep.retainedDofs = r.retainedDofs;
    out.rep.condensedDofs = r.condensedDofs;
  }
  out.staticState = source.staticState();
  return out;
}

/// Y (rows x cols, column-major) overwritten by its left singular vectors (LAPACK dgesdd, divide and
/// conquer: measured 1.8x faster than dgesvd on the 10,332 x 796 basis of a {40,20,3} blade): an
/// orthonormal basis of its columns' span. Returns how many to keep: those whose singular value is
/// above 1e-8 of the largest. An SVD of Y, not the eigenvectors of Y^T Y: the small singular values
/// carry the boundary-dominated modes and must not be squared into round-off.
int svdInPlace(Dense& Y, int rows, int cols, const std::string& body) {
  if (cols == 0) return 0;
  // 'O': Y overwritten by U when rows >= cols; else 'S': U (rows x rows) apart, copied into Y's first columns
  const bool tall = rows >= cols;
  const int k = std::min(rows, cols), ldvt = tall ? cols : k;
  const char jobz = tall ? 'O' : 'S';
  std::vector<double> sigma(static_cast<std::size_t>(k));
  Dense u(tall ? 1 : static_cast<std::size_t>(rows) * rows), vt(static_cast<std::size_t>(ldvt) * cols);
  std::vector<int> iwork(8 * static_cast<std::size_t>(k));
  int info = 0, lwork = -1;
  double query = 0;
  dgesdd_(&jobz, &rows, &cols, Y.data(), &rows, sigma.data(), u.data(), &rows, vt.data(), &ldvt, &query, &lwork,
          iwork.data(), &info);
  lwork = static_cast<int>(query);
  Dense work(static_cast<std::size_t>(std::max(lwork, 1)));
  dgesdd_(&jobz, &rows, &cols, Y.data(), &rows, sigma.data(), u.data(), &rows, vt.data(), &ldvt, work.data(), &lwork,
          iwork.data(), &info);
  EPAPHE_REQUIRE(info == 0, "body '" << body << "': the SVD of the parametric model's basis vectors failed "
                                     << "(LAPACK dgesdd info " << info << ")");
  if (!tall) std::copy(u.begin(), u.end(), Y.begin());
  int r = 0;
  while (r < k && sigma[r] > 1e-8 * sigma[0]) ++r;  // descending
  return r;
}

/// svdInPlace's result for a tall Y (rows >= 2 cols, the common basis's case: 10,332 x 796 on a
/// {40,20,3} blade) by the QR factorization Y = Q R (dgeqrf), the SVD of the cols x cols R (the same
/// singular values, U_R in place of U) and Q applied to the kept columns of U_R only (dormqr): the
/// left singular vectors U = Q [U_R; 0] without forming Q, nor the columns of U that are dropped. dgesdd
/// on Y takes the same QR first but forms all of Q and multiplies all of U_R by it.
int orthonormalise(Dense& Y, int rows, int cols, const std::string& body) {
  if (cols == 0 || rows < 2 * cols) return svdInPlace(Y, rows, cols, body);
  Teuchos::LAPACK<int, double> lapack;
  std::vector<double> tau(static_cast<std::size_t>(cols));
  int info = 0;
  double query = 0;
  lapack.GEQRF(rows, cols, Y.data(), rows, tau.data(), &query, -1, &info);
  Dense work(static_cast<std::size_t>(std::max(1.0, query)));
  lapack.GEQRF(rows, cols, Y.data(), rows, tau.data(), work.data(), static_cast<int>(work.size()), &info);
  EPAPHE_REQUIRE(info == 0, "body '" << body << "': the QR factorization of the parametric model's basis vectors "
                                     << "failed (LAPACK dgeqrf info " << info << ")");
  Dense R(static_cast<std::size_t>(cols) * cols, 0.0);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i <= j; ++i) R[static_cast<std::size_t>(j) * cols + i] = Y[static_cast<std::size_t>(j) * rows + i];
  const int r = svdInPlace(R, cols, cols, body);  // R = U_R S V^T, U_R in R
  Dense U(static_cast<std::size_t>(rows) * r, 0.0);
  for (int j = 0; j < r; ++j)
    std::copy_n(&R[static_cast<std::size_t>(j) * cols], cols, &U[static_cast<std::size_t>(j) * rows]);
  lapack.ORMQR('L', 'N', rows, r, cols, Y.data(), rows, tau.data(), U.data(), rows, &query, -1, &info);
  work.resize(static_cast<std::size_t>(std::max(1.0, query)));
  lapack.ORMQR('L', 'N', rows, r, cols, Y.data(), rows, tau.data(), U.data(), rows, work.data(),
               static_cast<int>(work.size()), &info);
  EPAPHE_REQUIRE(info == 0, "body '" << body << "': applying the parametric model's basis's Q failed (LAPACK dormqr "
                                     << "info " << info << ")");
  std::copy(U.begin(), U.end(), Y.begin());
  return r;
}

/// u - Psi u_b (3 per node, mesh order): a displacement u less the constraint modes Psi (the first nb
/// columns of the row-major recovery R, ld columns a row) times its values u_b at the retained DOFs
/// (nodeDof's first nb): its interior part, zero on the retained rows. nb = 0: u itself.
Dense interiorPart(const Dense& R, std::size_t ld, const std::vector<int>& nodeDof, int nb, const Dense& u) {
  std::vector<double> ub(static_cast<std::size_t>(nb));
  for (std::size_t i = 0; i < u.size() && nb > 0; ++i)
    if (const int j = nodeDof[i]; j >= 0 && j < nb) ub[j] = u[i];
  Dense r(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    double v = u[i];
    for (int j = 0; j < nb; ++j) v -= R[i * ld + j] * ub[j];
    r[i] = v;
  }
  return r;
}

/// The vectors a common basis is made of (column-major, `rows` each, up to `capacity`), each added
/// scaled: by its own length, or by `scale` when given (> 0); zero vectors are left out.
struct BasisVectors {
  BasisVectors(std::size_t n, int capacity) : rows(n), Y(n * static_cast<std::size_t>(capacity), 0.0) {}
  template <class F>
  void add(F value, double scale = 0.0) {
    double norm = 0;
    for (std::size_t i = 0; i < rows; ++i) norm += value(i) * value(i);
    norm = std::sqrt(norm);
    if (norm == 0) return;
    if (scale > 0) norm = scale;
    for (std::size_t i = 0; i < rows; ++i) Y[static_cast<std::size_t>(count) * rows + i] = value(i) / norm;
    ++count;
  }
  std::size_t rows;
  Dense Y;
  int count = 0;
};

/// The coordinates q of a displacement u (3 per node, mesh order) in the span of the common basis T
/// = p.base.recovery, T q = u: for a Craig-Bampton basis T = [I 0; Psi V], u's values at the retained
/// DOFs and V^T (u - Psi u_b) (V orthonormal and zero on the retained rows); for a massless boundary's
/// orthonormal T, T^T u.
Dense coordinatesOnBasis(const SpeedParametricModel& p, const Dense& u) {
  const int N = p.base.size, nb = p.base.massless() ? 0 : p.boundarySize;
  const Dense& T = p.base.recovery;
  Dense q(static_cast<std::size_t>(N), 0.0);
  for (std::size_t i = 0; i < u.size() && nb > 0; ++i)
    if (const int j = p.base.nodeDof[i]; j >= 0 && j < nb) q[j] = u[i];
  const Dense r = interiorPart(T, static_cast<std::size_t>(N), p.base.nodeDof, nb, u);
  for (std::size_t i = 0; i < u.size(); ++i)
    for (int c = nb; c < N; ++c) q[c] += T[i * N + c] * r[i];
  return q;
}

/// The static state over the speed range by Galerkin on the common basis (eq. (79), docs/theory/reduction.md),
/// u_s(xi) = T K_T(xi)^-1 b(xi), from the reduced load's coefficients b(xi) = sum_k xi^k beta_k (interpolate()
/// passes them through the samples' b(xi_s) = T^T K(Omega_s) u_s = K_T(xi_s) q_s). At a sample this is u_s
/// (the Galerkin solution is exact when the solution lies in the space); between samples it follows
/// the stiffness K_T(xi), where a polynomial through the samples' u_s would miss the static state's
/// curvature in Omega^2 (a {40,20,3} blade with 2 samples: 18.5 % off the direct reduction's tip growth
/// at mid-range). The field is then fitted by a polynomial in xi, p.growth, at Chebyshev-Lobatto points
/// of degree 2, 4 or 8, the first whose fit matches the Galerkin solution at the next degree's new
/// points to 1e-7 of `largest`, the largest displacement (the fit's error is kept in p.growthFitError).
void galerkinStaticState(SpeedParametricModel& p, const std::vector<Dense>& beta, std::size_t rows, double largest) {
  const int N = p.base.size;
  const double xiMin = p.xiOf(p.minSpeed());
  Teuchos::LAPACK<int, double> lapack;
  std::map<double, Dense> solved;  // u_s(xi) by xi
  auto solve = [&](double xi) -> const Dense& {
    if (auto it = solved.find(xi); it != solved.end()) return it->second;
    Dense K = polynomial(p.base.K, p.stiffness, xi), b = polynomial(beta[0], {beta.begin() + 1, beta.end()}, xi);
    int info = 0;
    factorAtSpeed(K, N, p.maxSpeed() * std::sqrt(xi), "body '" + p.base.name + "'");
    lapack.POTRS('L', N, 1, K.data(), N, b.data(), N, &info);
    Dense u(rows);  // T q: the row-major rows x N recovery is T^T column-major
    Teuchos::BLAS<int, double>().GEMV(Teuchos::TRANS, N, static_cast<int>(rows), 1.0, p.base.recovery.data(), N,
                                      b.data(), 1, 0.0, u.data(), 1);
    return solved.emplace(xi, std::move(u)).first->second;
  };
  auto node = [&](int k, int P) { return xiMin + (1 - xiMin) * 0.5 * (1 - std::cos(M_PI * k / P)); };
  auto fit = [&](int P) {
    std::vector<double> xs;
    for (int k = 0; k <= P; ++k) xs.push_back(node(k, P));
    const Dense V = vandermondeInverse(xs);
    std::vector<Dense> g(static_cast<std::size_t>(P + 1), Dense(rows, 0.0));
    for (int s = 0; s <= P; ++s) {
      const Dense& u = solve(xs[s]);
      for (int k = 0; k <= P; ++k) {
        const double w = V[static_cast<std::size_t>(s) * (P + 1) + k];
        for (std::size_t i = 0; i < rows; ++i) g[k][i] += w * u[i];
      }
    }
    return g;
  };
  for (int P = 2;; P *= 2) {
    std::vector<Dense> g = fit(P);
    double error = 0;
    for (int k = 1; k < 2 * P; k += 2) {  // the next degree's new points
      const double xi = node(k, 2 * P);
      const Dense& u = solve(xi);
      const Dense f = polynomial(g[0], {g.begin() + 1, g.end()}, xi);
      for (std::size_t i = 0; i < rows; ++i) error = std::max(error, std::abs(f[i] - u[i]));
    }
    p.growth = std::move(g);
    p.growthFitError = largest > 0 ? error / largest : 0;
    if (p.growthFitError <= 1e-7 || P == 8) break;
  }
}

/// The model on the common basis T = p.base.recovery (rows x N, row-major), eq. (78): T^T M T, the coefficients
/// of T^T K(Omega) T as a polynomial in xi = (Omega / Omega_max)^2 through the samples, and the static
/// state u_s(Omega) (galerkinStaticState).
void interpolate(SpeedParametricModel& p, const FullModel& rest, const Samples& samples) {
  const int N = p.base.size, S = static_cast<int>(p.speeds.size());
  const Dense& T = p.base.recovery;
  const auto map = rest.K->getRowMap();
  const MultiVector Tf = basisOnFreeDofs(rest, T, N, map);
  std::vector<Dense> Ks(static_cast<std::size_t>(S));
  Projector project(Tf);
  for (int s = 0; s < S; ++s) Ks[s] = project(*samples.K[s]);
  p.base.M = project(*rest.M);
  std::vector<double> xi;
  for (double w : p.speeds) xi.push_back(p.xiOf(w));
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
  p.stiffness.clear();
  for (int k = 1; k < S; ++k) p.stiffness.push_back(coefficient(Ks, k));
  // the reduced load at the samples, K_T(xi_s) q_s, and its coefficients in xi
  std::vector<Dense> loads(static_cast<std::size_t>(S), Dense(static_cast<std::size_t>(N)));
  double largest = 0;
  for (int s = 0; s < S; ++s) {
    const Dense q = coordinatesOnBasis(p, samples.grow[s]);
    Teuchos::BLAS<int, double>().GEMV(Teuchos::NO_TRANS, N, N, 1.0, Ks[s].data(), N, q.data(), 1, 0.0, loads[s].data(),
                                      1);
    for (double v : samples.grow[s]) largest = std::max(largest, std::abs(v));
  }
  std::vector<Dense> beta;
  for (int k = 0; k < S; ++k) beta.push_back(coefficient(loads, k));
  galerkinStaticState(p, beta, samples.grow[0].size(), largest);
}

/// A parametric model's fields common to both methods, from the first sample's reduction.
SpeedParametricModel shell(const FullModel& rest, const Samples& samples, const std::vector<double>& speeds, int nR,
                           int N) {
  SpeedParametricModel p;
  p.speeds = speeds;
  p.staticState = samples.staticState;
  p.boundarySize = nR;
  p.base = samples.red[0];
  p.base.name = rest.name;
  p.base.coords = rest.mesh.coords;
  p.base.size = N;
  p.base.numModes = N - nR;
  p.base.modeFrequencies.clear();
  p.base.fullFrequencies.clear();
  p.base.staticDisplacement.clear();
  p.base.boundaryModes.clear();
  p.base.residualFlexibility.clear();
  p.base.speed = 0;
  p.base.recovery.assign(rest.eq.size() * static_cast<std::size_t>(N), 0.0);
  return p;
}

}  // namespace

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
  CraigBamptonOptions co = options;
  co.checkFrequencies = 0;
  co.basisOnly = true;
  Samples samples =
      reduceAtSamples(source, speeds, [&](const FullModel& at, const ReducedModel* previous, ReductionReport* r) {
        CraigBamptonOptions o = co;
        o.startModes = previous;  // the next faster sample's modes start Anasazi's search
        return craigBampton(at, retained, o, r);
      });
  const std::vector<ReducedModel>& red = samples.red;
  const int S = static_cast<int>(speeds.size());
  const std::size_t rows = rest.eq.size();  // 3 per node
  const int nR = red[0].size - red[0].numModes, modes = red[0].numModes;

  // Interior vectors (zero on the retained DOFs): the fixed-interface modes scaled to unit length, the
  // constraint-mode changes Psi_s - Psi_1 scaled by the length of Psi_1's column (a change is measured
  // against the mode it changes), then an orthonormal basis of their span (orthonormalise: a
  // constraint mode is in the span to 1e-8 of its length; the frequencies at the samples stay within
  // 2e-9 of the direct reduction's, test_speed.cpp). The drop keeps the basis, and the projections,
  // small: on a 10,000-DOF blade with 82 retained nodes and 4 samples it keeps 424 of 796 vectors.
  BasisVectors Y(rows, S * modes + (S - 1) * nR + S);
  std::vector<double> psiNorm(static_cast<std::size_t>(nR), 0.0);
  for (std::size_t i = 0; i < rows; ++i)
    for (int j = 0; j < nR; ++j) {
      const double v = red[0].recovery[i * red[0].size + j];
      psiNorm[j] += v * v;
    }
  for (double& v : psiNorm) v = std::sqrt(v);
  for (int s = 0; s < S; ++s) {
    const std::size_t n = static_cast<std::size_t>(red[s].size);
    for (int j = 0; j < modes; ++j) Y.add([&](std::size_t i) { return red[s].recovery[i * n + nR + j]; });
    if (s > 0)
      for (int j = 0; j < nR; ++j)
        Y.add([&](std::size_t i) { return red[s].recovery[i * n + j] - red[0].recovery[i * red[0].size + j]; },
              psiNorm[j]);
  }
  // the static states' interior parts u_s - Psi_1 u_s,b (for the Galerkin static state between samples)
  for (int s = 0; s < S; ++s) {
    const Dense v =
        interiorPart(red[0].recovery, static_cast<std::size_t>(red[0].size), red[0].nodeDof, nR, samples.grow[s]);
    Y.add([&](std::size_t i) { return v[i]; });
  }
  const int r = orthonormalise(Y.Y, static_cast<int>(rows), Y.count, rest.name);
  const int N = nR + r;

  SpeedParametricModel p = shell(rest, samples, speeds, nR, N);
  // T (rows x N, row-major as a recovery): the first sample's constraint modes, then the kept U of Y.
  Dense& T = p.base.recovery;
  for (std::size_t i = 0; i < rows; ++i)
    for (int j = 0; j < nR; ++j) T[i * N + j] = red[0].recovery[i * red[0].size + j];
  for (std::size_t i = 0; i < rows; ++i)
    for (int c = 0; c < r; ++c) T[i * N + nR + c] = Y.Y[static_cast<std::size_t>(c) * rows + i];
  interpolate(p, rest, samples);
  if (const auto G = source.coriolis(); !G.is_null()) p.base.coriolis = reducedCoriolis(*G, rest, T, N);
  ReductionReport rep = samples.rep;
  rep.seconds = total.seconds();
  rep.projectSeconds = rep.seconds - rep.factorSeconds - rep.constraintSeconds - rep.eigenSeconds - rep.staticSeconds;
  if (report) *report = rep;
  return p;
}

SpeedParametricModel parametricMasslessBoundary(const FullModel& rest, const std::vector<int>& retained,
                                                const CraigBamptonOptions& options, const RotationOptions& rotation,
                                                std::vector<double> speeds, ReductionReport* report) {
  BuiltInSpeedSource source(rest, rotation);
  return parametricMasslessBoundary(source, retained, options, std::move(speeds), report);
}

SpeedParametricModel parametricMasslessBoundary(SpeedSampleSource& source, const std::vector<int>& retained,
                                                const CraigBamptonOptions& options, std::vector<double> speeds,
                                                ReductionReport* report) {
  Stopwatch total;
  const FullModel& rest = source.reference();
  EPAPHE_REQUIRE(std::any_of(rest.eq.begin(), rest.eq.end(), [](int g) { return g < 0; }),
                 "body '" << rest.name << "': the massless-boundary parametric model is built for a held body "
                          << "only, and this one has no clamped DOF");
  EPAPHE_REQUIRE(options.candidates <= options.modes,
                 "body '" << rest.name << "': the massless-boundary parametric model selects no modes by "
                          << "participation (" << options.candidates << " candidates asked)");
  Samples samples = reduceAtSamples(source, speeds, [&](const FullModel& at, const ReducedModel*, ReductionReport* r) {
    return masslessBoundary(at, retained, options, r);
  });
  const std::vector<ReducedModel>& red = samples.red;
  const int S = static_cast<int>(speeds.size());
  const std::size_t rows = rest.eq.size();
  const int nR = red[0].size - red[0].numModes;

  // The span of every sample's recovery columns, span{K(Omega_s)^-1 E_b, Phi_s} (the static responses
  // to forces on the retained DOFs and the modes), each column scaled to unit length: at a sample the
  // massless reduction of the projected model then has that sample's modes (Rayleigh-Ritz) and its
  // static responses (Galerkin, exact when the solution is in the space), to the basis's 1e-8.
  BasisVectors Y(rows, S * (red[0].size + 1));
  for (int s = 0; s < S; ++s) {
    const std::size_t n = static_cast<std::size_t>(red[s].size);
    for (std::size_t j = 0; j < n; ++j) Y.add([&](std::size_t i) { return red[s].recovery[i * n + j]; });
    Y.add([&](std::size_t i) { return samples.grow[s][i]; });  // for the Galerkin static state between samples
  }
  const int N = orthonormalise(Y.Y, static_cast<int>(rows), Y.count, rest.name);
  SpeedParametricModel p = shell(rest, samples, speeds, nR, N);
  for (std::size_t i = 0; i < rows; ++i)
    for (int c = 0; c < N; ++c) p.base.recovery[i * N + c] = Y.Y[static_cast<std::size_t>(c) * rows + i];
  interpolate(p, rest, samples);
  // T^T M e_d: a rigid translation's load on the basis (the kept modes' Phi^T M e_d at a speed)
  const MultiVector Td = rigidTranslations(rest);
  MultiVector MT(Td.getMap(), 3);
  rest.M->apply(Td, MT);
  const MultiVector Tf = basisOnFreeDofs(rest, p.base.recovery, N, Td.getMap());
  p.base.modalTranslation = transposeTimesDistributed(Tf, MT);
  ReductionReport rep = samples.rep;
  rep.seconds = total.seconds();
  rep.projectSeconds = rep.seconds - rep.factorSeconds - rep.constraintSeconds - rep.eigenSeconds - rep.staticSeconds;
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
  for (int i = 0; i < count && i < static_cast<int>(w2.size()); ++i)
    f.push_back(std::sqrt(std::max(w2[i], 0.0)) / (2 * M_PI));
  return f;
}

ReducedModel SpeedParametricModel::at(double speed, int modes, const std::string& context,
                                      std::vector<double>* basis) const {
  const double slack = 1e-9 * (maxSpeed() - minSpeed());
  EPAPHE_REQUIRE(speed >= minSpeed() - slack && speed <= maxSpeed() + slack,
                 context << ": speed " << speed << " rad/s is outside the model's range [" << minSpeed() << ", "
                         << maxSpeed() << "] rad/s; widen 'Rotation->Speed range' to include it");
  if (base.massless()) return masslessAt(speed, modes, context);
  const int N = base.size, nb = boundarySize, ni = N - nb;
  EPAPHE_REQUIRE(modes >= 0 && modes <= ni, context << ": " << modes << " fixed-interface modes asked of a parametric "
                                                    << "model with " << ni << " interior DOFs");
  const Dense K = stiffnessAt(speed);
  auto block = [&](const Dense& A, int r0, int nr, int c0, int nc) {
    Dense B(static_cast<std::size_t>(nr) * nc);
    for (int j = 0; j < nc; ++j)
      for (int i = 0; i < nr; ++i)
        B[static_cast<std::size_t>(j) * nr + i] = A[static_cast<std::size_t>(c0 + j) * N + r0 + i];
    return B;
  };
  // S = [I 0; Psi' Phi'], Psi' = -K_ii^-1 K_ib, K_ii Phi' = M_ii Phi' Lambda (the lowest `modes`)
  Dense Kii = block(K, nb, ni, nb, ni), Mii = block(base.M, nb, ni, nb, ni), Psi = block(K, nb, ni, 0, nb);
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  Dense chol = Kii;
  factorAtSpeed(chol, ni, speed, context);  // its interior block, clamped at the retained DOFs
  lapack.POTRS('L', ni, nb, chol.data(), ni, Psi.data(), ni, &info);
  for (double& v : Psi) v = -v;
  Dense vec;
  const Dense lambda = denseEigenpairs(Kii, Mii, ni, &vec);
  const int n = nb + modes;
  Dense Sm(static_cast<std::size_t>(N) * n, 0.0);  // N x n column-major
  for (int j = 0; j < nb; ++j) {
    Sm[static_cast<std::size_t>(j) * N + j] = 1;
    for (int i = 0; i < ni; ++i)
      Sm[static_cast<std::size_t>(j) * N + nb + i] = Psi[static_cast<std::size_t>(j) * ni + i];
  }
  for (int k = 0; k < modes; ++k)
    for (int i = 0; i < ni; ++i)
      Sm[static_cast<std::size_t>(nb + k) * N + nb + i] = vec[static_cast<std::size_t>(k) * ni + i];

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
  if (!base.coriolis.empty()) {  // G_r = S^T G_T S, skew as G_T is
    Dense GS(KS.size());
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, N, n, N, 1.0, base.coriolis.data(), N, Sm.data(), N, 0.0, GS.data(),
              N);
    r.coriolis = transposeTimes(Sm.data(), N, GS.data(), N, N, n, n);
    for (int j = 0; j < n; ++j)  // exactly skew: (A - A^T) / 2
      for (int i = 0; i <= j; ++i) {
        const std::size_t ij = static_cast<std::size_t>(j) * n + i, ji = static_cast<std::size_t>(i) * n + j;
        const double v = 0.5 * (r.coriolis[ij] - r.coriolis[ji]);
        r.coriolis[ij] = v;
        r.coriolis[ji] = -v;
      }
  }
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

/// The massless-boundary model at `speed` (Epaphe_ReducedModel.hpp) of the dense model on the common
/// basis: its lowest `modes` modes Z (K_T z = w^2 M_T z), the boundary rows B of T (B z = phi_b), the
/// static responses K_T^-1 B^T to forces on the retained DOFs, and from them G, K, M and the recovery
/// T [Res G^-1, Z - Res G^-1 Phi_b] as masslessBoundary() builds them from the full model.
ReducedModel SpeedParametricModel::masslessAt(double speed, int modes, const std::string& context) const {
  const int N = base.size, nb = boundarySize;
  EPAPHE_REQUIRE(modes >= 1 && modes <= N - nb, context << ": " << modes << " modes asked of a parametric model on "
                                                        << N << " basis vectors with " << nb << " retained DOFs");
  const Dense K = stiffnessAt(speed);
  Dense Z;
  const Dense lambda = denseEigenpairs(K, base.M, N, &Z);
  EPAPHE_REQUIRE(lambda[0] > 0, context << ": the parametric model at " << speed << " rad/s has a zero or negative "
                                        << "eigenvalue (" << lambda[0] << "): the speed is past a critical one");
  const std::size_t rows = base.recovery.size() / static_cast<std::size_t>(N);
  Dense B(static_cast<std::size_t>(nb) * N, 0.0);  // nb x N, column-major: T's rows at the retained DOFs
  std::vector<std::size_t> rowOf(static_cast<std::size_t>(nb), rows);
  for (std::size_t i = 0; i < rows; ++i)
    if (const int r = base.nodeDof[i]; r >= 0) {
      rowOf[r] = i;
      for (int c = 0; c < N; ++c) B[static_cast<std::size_t>(c) * nb + r] = base.recovery[i * N + c];
    }
  // X = K_T^-1 B^T (N x nb)
  Dense X(static_cast<std::size_t>(N) * nb), chol = K;
  for (int r = 0; r < nb; ++r)
    for (int c = 0; c < N; ++c) X[static_cast<std::size_t>(r) * N + c] = B[static_cast<std::size_t>(c) * nb + r];
  Teuchos::LAPACK<int, double> lapack;
  Teuchos::BLAS<int, double> blas;
  int info = 0;
  lapack.POTRF('L', N, chol.data(), N, &info);
  EPAPHE_REQUIRE(info == 0, context << ": the massless-boundary parametric model at " << speed << " rad/s is "
                                    << "singular or indefinite (LAPACK dpotrf info " << info << ")");
  lapack.POTRS('L', N, nb, chol.data(), N, X.data(), N, &info);
  ReducedModel r = base;
  r.kind = ReductionKind::MasslessBoundary;
  r.coriolis.clear();  // not kept on a massless boundary (refused by the scene's checks)
  r.numModes = modes;
  r.size = nb + modes;
  r.modeFrequencies.clear();
  Dense w2(static_cast<std::size_t>(modes));
  for (int k = 0; k < modes; ++k) {
    w2[k] = lambda[k];
    r.modeFrequencies.push_back(std::sqrt(lambda[k]) / (2 * M_PI));
  }
  // Phi_b = B Z (nb x modes); G = B X - Phi_b w^-2 Phi_b^T; Res = X - Z w^-2 Phi_b^T (N x nb)
  r.boundaryModes.assign(static_cast<std::size_t>(nb) * modes, 0.0);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nb, modes, N, 1.0, B.data(), nb, Z.data(), N, 0.0,
            r.boundaryModes.data(), nb);
  Dense ZW(static_cast<std::size_t>(N) * modes), PW(static_cast<std::size_t>(nb) * modes);
  for (int k = 0; k < modes; ++k)
    for (int i = 0; i < N; ++i)
      ZW[static_cast<std::size_t>(k) * N + i] = Z[static_cast<std::size_t>(k) * N + i] / w2[k];
  for (int k = 0; k < modes; ++k)
    for (int i = 0; i < nb; ++i)
      PW[static_cast<std::size_t>(k) * nb + i] = r.boundaryModes[static_cast<std::size_t>(k) * nb + i] / w2[k];
  Dense G(static_cast<std::size_t>(nb) * nb), Res = X;
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nb, nb, N, 1.0, B.data(), nb, X.data(), N, 0.0, G.data(), nb);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, nb, nb, modes, -1.0, PW.data(), nb, r.boundaryModes.data(), nb, 1.0,
            G.data(), nb);
  symmetrize(G, nb);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, N, nb, modes, -1.0, ZW.data(), N, r.boundaryModes.data(), nb, 1.0,
            Res.data(), N);
  r.residualFlexibility = G;
  const Dense Ginv = spdInverse(G, nb, context + ": the residual flexibility at " + std::to_string(speed) + " rad/s",
                                "keep fewer modes or use 'Craig-Bampton'");
  const int n = r.size;
  r.K = r.residualStiffness();
  r.M.assign(static_cast<std::size_t>(n) * n, 0.0);
  for (int k = 0; k < modes; ++k) {
    r.K[static_cast<std::size_t>(nb + k) * n + nb + k] += w2[k];
    r.M[static_cast<std::size_t>(nb + k) * n + nb + k] = 1.0;
  }
  // recovery on the basis: A = [Res G^-1, Z - Res G^-1 Phi_b] (N x n), then T A, exact on the retained rows
  Dense A(static_cast<std::size_t>(N) * n);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, N, nb, nb, 1.0, Res.data(), N, Ginv.data(), nb, 0.0, A.data(), N);
  std::copy(Z.begin(), Z.begin() + static_cast<std::ptrdiff_t>(N) * modes,
            A.begin() + static_cast<std::ptrdiff_t>(N) * nb);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, N, modes, nb, -1.0, A.data(), N, r.boundaryModes.data(), nb, 1.0,
            A.data() + static_cast<std::size_t>(N) * nb, N);
  r.recovery.assign(rows * n, 0.0);
  blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, n, static_cast<int>(rows), N, 1.0, A.data(), N, base.recovery.data(), N,
            0.0, r.recovery.data(), n);
  for (int b = 0; b < nb; ++b)
    for (int c = 0; c < n; ++c) r.recovery[rowOf[b] * n + c] = c == b ? 1.0 : 0.0;
  // Phi^T M e_d = Z^T (T^T M e_d)
  r.modalTranslation.assign(static_cast<std::size_t>(modes) * 3, 0.0);
  blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, modes, 3, N, 1.0, Z.data(), N, base.modalTranslation.data(), N, 0.0,
            r.modalTranslation.data(), modes);
  r.speed = speed;
  r.staticDisplacement = staticDisplacementAt(speed);
  for (std::size_t a = 0; a < r.coords.size(); ++a)
    for (int d = 0; d < 3; ++d) r.coords[a][d] += r.staticDisplacement[3 * a + d];
  return r;
}

}  // namespace epaphe
