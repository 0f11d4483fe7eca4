#include "Epaphe_ModelAtSpeed.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"
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

}  // namespace

FullModel modelAtSpeed(const FullModel& rest, const RotationOptions& o, SpeedReport* report) {
  Stopwatch watch;
  EPAPHE_REQUIRE(std::isfinite(o.speed),
                 "body '" << rest.name << "': rotation speed " << o.speed << " rad/s is not a finite number");
  const double w2 = o.speed * o.speed;
  const CentrifugalTerms c = assembleCentrifugal(rest, o.axis);

  // (K_e - Omega^2 M_perp) u_s = Omega^2 f_c
  auto statics =
      o.spinSoftening ? Tpetra::MatrixMatrix::add(1.0, false, *rest.K, -w2, false, *c.perpendicularMass) : rest.K;
  MultiVector f(*c.load, Teuchos::Copy), us(c.load->getMap(), 1);
  f.scale(w2);
  const std::string what = " of body '" + rest.name + "' at " + std::to_string(o.speed) +
                           " rad/s (a speed above the first critical one in the plane of rotation makes it singular)";
  // A stress-stiffened state with a starting guess skips the linear one (it is not needed to choose)
  const bool guessed =
      o.staticState == StaticState::StressStiffened && o.stressStiffening && o.initialState.size() == rest.eq.size();
  std::vector<double> u;
  if (guessed)
    u = o.initialState;
  else {
    makeSolver(statics, o.solver, "K_e - Omega^2 M_perp" + what)->solve(f, us);
    u = nodalValues(rest, us);
  }
  const double linear = guessed ? 0.0 : largestLength(u);

  // The stress-stiffened state: (K_e - Omega^2 M_perp + K_sigma(u_s)) u_s = Omega^2 f_c by fixed point,
  // each pass with K_sigma of the last u_s, until u_s moves by less than 1e-8 of its size.
  int passes = 0;
  bool stiffened = false;
  if (o.stressStiffening && o.staticState != StaticState::Linear) {
    std::vector<double> last = u;
    MultiVector v(c.load->getMap(), 1);
    for (passes = 1; passes <= 50; ++passes) {
      auto A = Tpetra::MatrixMatrix::add(1.0, false, *statics, 1.0, false, *assembleGeometricStiffness(rest, last));
      makeSolver(A, o.solver, "K_e - Omega^2 M_perp + K_sigma" + what)->solve(f, v);
      std::vector<double> next = nodalValues(rest, v);
      double change = 0, size = 0;
      for (std::size_t k = 0; k < next.size(); ++k) {
        change = std::max(change, std::abs(next[k] - last[k]));
        size = std::max(size, std::abs(next[k]));
      }
      last.swap(next);
      if (change <= 1e-8 * size) break;
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
  if (o.stressStiffening)
    at.K = Tpetra::MatrixMatrix::add(1.0, false, *statics, 1.0, false, *assembleGeometricStiffness(rest, u));
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
  MultiVector V(map, static_cast<std::size_t>(n)), GV(map, static_cast<std::size_t>(n));
  {
    auto v = V.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (std::size_t i = 0; i < full.eq.size(); ++i) {
      const int g = full.eq[i];
      if (g < 0 || !map->isNodeGlobalElement(g)) continue;
      const LO l = map->getLocalElement(g);
      for (int j = 0; j < n; ++j) v(l, j) = recovery[i * n + j];
    }
  }
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
