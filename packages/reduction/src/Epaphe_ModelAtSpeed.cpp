#include "Epaphe_ModelAtSpeed.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_ReductionShared.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SameGraph.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>

namespace epaphe {

namespace {

/// max over nodes of |u_n| (u: 3 per node)
double largestLength(const std::vector<double>& u) {
  double m = 0;
  for (std::size_t n = 0; 3 * n + 2 < u.size(); ++n)
    m = std::max(m, std::sqrt(u[3 * n] * u[3 * n] + u[3 * n + 1] * u[3 * n + 1] + u[3 * n + 2] * u[3 * n + 2]));
  return m;
}

/// x (over the free DOFs, this rank's rows) from nodal values u (3 per node): the inverse of nodalValues
void freeValues(const FullModel& model, const std::vector<double>& u, MultiVector& x) {
  const auto map = x.getMap();
  auto v = x.getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (std::size_t i = 0; i < model.eq.size(); ++i) {
    const int g = model.eq[i];
    if (g >= 0 && map->isNodeGlobalElement(g)) v(map->getLocalElement(g), 0) = u[i];
  }
}

}  // namespace

FullModel modelAtSpeed(const FullModel& rest, const RotationOptions& o, SpeedReport* report) {
  return modelAtSpeed(rest, assembleCentrifugal(rest, o.axis), o, report);
}

FullModel modelAtSpeed(const FullModel& rest, const CentrifugalTerms& c, const RotationOptions& o,
                       SpeedReport* report) {
  Stopwatch watch;
  EPAPHE_REQUIRE(std::isfinite(o.speed),
                 "body '" << rest.name << "': rotation speed " << o.speed << " rad/s is not a finite number");
  const double w2 = o.speed * o.speed;

  // (K_e - Omega^2 M_perp) u_s = Omega^2 f_c
  // Every matrix at speed on rest.K's graph (assembleCentrifugal, assembleGeometricStiffness with a
  // pattern): their sums are loops over values, not new graphs (sumOnGraph)
  auto statics = o.spinSoftening ? sumOnGraph(1.0, *rest.K, -w2, *c.perpendicularMass) : rest.K;
  MultiVector f(*c.load, Teuchos::Copy), us(c.load->getMap(), 1);
  f.scale(w2);
  const std::string what = " of body '" + rest.name + "' at " + std::to_string(o.speed) +
                           " rad/s (a speed above the first critical one in the plane of rotation makes it singular)";
  // A stress-stiffened state with a starting guess skips the linear one (it is not needed to choose)
  const bool guessed =
      o.staticState == StaticState::StressStiffened && o.stressStiffening && o.initialState.size() == rest.eq.size();
  std::vector<double> u;
  if (guessed) {
    u = o.initialState;
    freeValues(rest, u, us);
  } else {
    makeSolver(statics, o.solver, "K_e - Omega^2 M_perp" + what)->solve(f, us);
    u = nodalValues(rest, us);
  }
  const double linear = guessed ? 0.0 : largestLength(u);

  // The stress-stiffened state, (K_e - Omega^2 M_perp + K_sigma(u_s)) u_s = Omega^2 f_c (docs/user/
  // rotating-bodies.md), by chord passes on one factor: A_0 =
  // K_e - Omega^2 M_perp + K_sigma(u_0) at the starting state is factored, and each pass adds
  // A_0^{-1} r, r = Omega^2 f_c - (K_e - Omega^2 M_perp + K_sigma(u)) u, until the correction is below
  // 1e-10 of u's size. The solution is the fixed point's (r = 0); a pass costs K_sigma's assembly, two
  // products and a solve instead of a factorization. A_0 is factored again at the current state when
  // a pass contracts the correction by less than 4x (a far start).
  int passes = 0;
  bool stiffened = false;
  if (o.stressStiffening && o.staticState != StaticState::Linear) {
    std::vector<double> last = u;
    MultiVector x(us, Teuchos::Copy), r(c.load->getMap(), 1), Ax(c.load->getMap(), 1), dx(c.load->getMap(), 1);
    std::unique_ptr<SparseSolver> chord;
    double previous = 0;
    for (passes = 1; passes <= 50; ++passes) {
      const auto Ks = assembleGeometricStiffness(rest, last, *rest.K);
      if (!chord)
        chord = makeSolver(sumOnGraph(1.0, *statics, 1.0, *Ks), o.solver, "K_e - Omega^2 M_perp + K_sigma" + what);
      statics->apply(x, r);
      Ks->apply(x, Ax);
      r.update(1.0, f, -1.0, Ax, -1.0);  // r = f - statics x - K_sigma x
      chord->solve(r, dx);
      x.update(1.0, dx, 1.0);
      const double change = dx.getVector(0)->normInf(), size = x.getVector(0)->normInf();
      last = nodalValues(rest, x);
      if (change <= 1e-10 * size) break;
      if (previous > 0 && change > 0.25 * previous) chord.reset();
      previous = change;
    }
    EPAPHE_REQUIRE(passes <= 50, "body '"
                                     << rest.name << "' at " << o.speed << " rad/s: the stress-stiffened static "
                                     << "state did not converge in 50 passes; set 'Rotation->Static state' to Linear");
    const double moved = guessed ? 0.0 : std::abs(largestLength(last) / linear - 1);
    stiffened = o.staticState == StaticState::StressStiffened || moved > o.staticTolerance;
    if (report) report->stiffenedChange = moved;
    if (stiffened) u.swap(last);
  }

  FullModel at = rest;
  at.K = statics;
  if (o.stressStiffening) at.K = sumOnGraph(1.0, *statics, 1.0, *assembleGeometricStiffness(rest, u, *rest.K));
  for (int n = 0; n < at.numNodes(); ++n)
    for (int d = 0; d < 3; ++d) at.mesh.coords[n][d] += u[3 * static_cast<std::size_t>(n) + d];

  if (report) {
    report->speed = o.speed;
    report->linearLargest = linear;
    report->stiffened = stiffened;
    report->passes = passes;
    report->staticDisplacement = u;
    report->largestDisplacement = 0;
    report->largestNode = -1;
    for (int n = 0; n < rest.numNodes(); ++n) {
      const double* un = &u[3 * static_cast<std::size_t>(n)];
      const double len = std::sqrt(un[0] * un[0] + un[1] * un[1] + un[2] * un[2]);
      if (len > report->largestDisplacement) {
        report->largestDisplacement = len;
        report->largestNode = n;
      }
    }
    // Omega ||G|| / sqrt(||K(Omega)|| ||M||), G = 2 int rho N^T [a]_x N: kg/s against kg/s
    const double scale = std::sqrt(at.K->getFrobeniusNorm() * rest.M->getFrobeniusNorm());
    report->coriolisRatio = scale > 0 ? 2 * std::abs(o.speed) * c.coriolis->getFrobeniusNorm() / scale : 0;
    report->coriolis = c.coriolis;
    report->seconds = watch.seconds();
  }
  return at;
}

std::vector<double> reducedCoriolis(const CrsMatrix& halfG, const FullModel& full, const std::vector<double>& recovery,
                                    int n) {
  const auto map = halfG.getRowMap();
  EPAPHE_REQUIRE(recovery.size() == full.eq.size() * static_cast<std::size_t>(n),
                 "body '" << full.name << "': a recovery of " << recovery.size() << " entries for " << full.eq.size()
                          << " DOFs and " << n << " reduced coordinates");
  // V over the free DOFs (the recovery's rows at clamped DOFs are zero), then G V and V^T (G V)
  const MultiVector V = basisOnFreeDofs(full, recovery, n, map);
  MultiVector GV(map, static_cast<std::size_t>(n));
  halfG.apply(V, GV);
  std::vector<double> local(static_cast<std::size_t>(n) * n, 0.0), G(local.size());
  {
    auto v = V.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto w = GV.getLocalViewHost(Tpetra::Access::ReadOnly);
    const int m = static_cast<int>(V.getLocalLength());
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        double s = 0;
        for (int r = 0; r < m; ++r) s += v(r, i) * w(r, j);
        local[static_cast<std::size_t>(j) * n + i] = s;
      }
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), G.data());
  // G_r = 2 V^T (G/2) V, skew: (A - A^T) / 2 of it, exactly skew
  for (int j = 0; j < n; ++j)
    for (int i = 0; i <= j; ++i) {
      const double v = G[static_cast<std::size_t>(j) * n + i] - G[static_cast<std::size_t>(i) * n + j];
      G[static_cast<std::size_t>(j) * n + i] = v;
      G[static_cast<std::size_t>(i) * n + j] = -v;
    }
  return G;
}

std::vector<double> gyroscopicFrequencies(const std::vector<double>& K, const std::vector<double>& M,
                                          const std::vector<double>& G, double speed, int n) {
  // A = [0 I; -M^-1 K, -M^-1 speed G] (2n x 2n, column-major): M^-1 [K, speed G] by one Cholesky solve
  const std::size_t nn = static_cast<std::size_t>(n) * n;
  std::vector<double> rhs(2 * nn), chol = M;
  for (std::size_t k = 0; k < nn; ++k) {
    rhs[k] = K[k];
    rhs[nn + k] = G.empty() ? 0.0 : speed * G[k];
  }
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.POTRF('L', n, chol.data(), n, &info);
  EPAPHE_REQUIRE(info == 0,
                 "gyroscopic frequencies: the mass matrix is not positive definite (dpotrf info " << info << ")");
  lapack.POTRS('L', n, 2 * n, chol.data(), n, rhs.data(), n, &info);
  const int N = 2 * n;
  std::vector<double> A(static_cast<std::size_t>(N) * N, 0.0);
  for (int i = 0; i < n; ++i) A[static_cast<std::size_t>(n + i) * N + i] = 1.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      A[static_cast<std::size_t>(j) * N + n + i] = -rhs[static_cast<std::size_t>(j) * n + i];
      A[static_cast<std::size_t>(n + j) * N + n + i] = -rhs[nn + static_cast<std::size_t>(j) * n + i];
    }
  std::vector<double> wr(static_cast<std::size_t>(N)), wi(wr.size()), none(1);
  double query = 0;
  lapack.GEEV('N', 'N', N, A.data(), N, wr.data(), wi.data(), none.data(), 1, none.data(), 1, &query, -1, &info);
  std::vector<double> work(static_cast<std::size_t>(query));
  lapack.GEEV('N', 'N', N, A.data(), N, wr.data(), wi.data(), none.data(), 1, none.data(), 1, work.data(),
              static_cast<int>(work.size()), &info);
  EPAPHE_REQUIRE(info == 0, "gyroscopic frequencies: LAPACK dgeev failed (info " << info << ")");
  // a real model's eigenvalues come in conjugate pairs s, conj(s): keep those with Im s >= 0, one per
  // whirl (a zero frequency, a rigid-body or static mode, twice: keep half of them)
  std::vector<double> f;
  int zeros = 0;
  for (int k = 0; k < N; ++k) {
    if (wi[k] > 0)
      f.push_back(wi[k] / (2 * M_PI));
    else if (wi[k] == 0)
      ++zeros;
  }
  for (int k = 0; k < zeros / 2; ++k) f.push_back(0.0);
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace epaphe
