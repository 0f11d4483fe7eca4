// Central difference and contact correction on models small enough to solve by hand.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestModels.hpp"

#include <gtest/gtest.h>

#include <Teuchos_LAPACK.hpp>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

using namespace epaphe;
using epaphe::test::oscillator;

namespace {

void set(const DenseVector& v, double a, double b, double c) {
  auto h = Kokkos::create_mirror_view(v);
  h(0) = a;
  h(1) = b;
  h(2) = c;
  Kokkos::deep_copy(v, h);
}
double at(const DenseVector& v, int i) {
  auto h = Kokkos::create_mirror_view(v);
  Kokkos::deep_copy(h, v);
  return h(i);
}

}  // namespace

TEST(CentralDifference, MatchesTheExactDiscreteSolution) {
  // q_n = cos(Omega n h) with cos(Omega h) = 1 - (omega h)^2 / 2 solves the undamped recurrence.
  const double m = 2.0, k = 800.0, w = std::sqrt(k / m), h = 0.05;
  const ReducedModel r = oscillator(m, k);
  CentralDifference cd(r, h, {});
  const double Om = std::acos(1 - 0.5 * w * w * h * h) / h;
  DenseVector qm("qm", 3), q("q", 3), qp("qp", 3);
  set(qm, std::cos(-Om * h), 0, 0);
  set(q, 1.0, 0, 0);
  const double e0 = cd.halfStepEnergy(qm, q);
  for (int n = 1; n <= 500; ++n) {
    cd.predict(q, qm, qp);
    std::swap(qm, q);
    std::swap(q, qp);
    EXPECT_NEAR(at(q, 0), std::cos(Om * n * h), 1e-10) << "step " << n;
  }
  EXPECT_NEAR(cd.halfStepEnergy(qm, q), e0, 1e-10 * e0);  // the discrete energy is conserved
}

TEST(CentralDifference, CriticalStepIsTwoOverOmega) {
  const ReducedModel r = oscillator(2.0, 800.0);
  EXPECT_NEAR(criticalTimeStep(r, {}, 0.0, {}).critical, 2.0 / 20.0, 1e-12);
  // a penalty spring of 1000 on the 3 DOFs: omega^2 = 1800 / 2
  EXPECT_NEAR(criticalTimeStep(r, {0, 1, 2}, 1000.0, {}).critical, 2.0 / 30.0, 1e-12);
}

TEST(CentralDifference, RayleighEnergyBalanceIsExact) {
  const ReducedModel r = oscillator(1.0, 100.0);
  DampingOptions d;
  d.type = DampingType::Rayleigh;
  d.alpha = 0.5;
  d.beta = 1e-3;
  CentralDifference cd(r, 0.01, d);
  DenseVector qm("qm", 3), q("q", 3);
  set(qm, 0.0, 0.0, 0.0);
  set(q, 0.01, 0.02, -0.01);
  const auto b = test::freeSteps(cd, qm, q, 2000);
  EXPECT_LT(b.end, 0.01 * b.start);                          // it decays
  EXPECT_NEAR(b.end + b.damping, b.start, 1e-12 * b.start);  // and every joule is accounted for
}

namespace {
/// The plane x = 0 as a 4 x 4 grid, normal -x (bodies live at x < 0).
BSplineSurface wall() {
  std::vector<double> g;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) g.insert(g.end(), {0.0, -1.0 + 2.0 * j / 3.0, -1.0 + 2.0 * i / 3.0});
  SurfaceOptions o;
  o.closureU = o.closureV = Closure::Open;
  BSplineSurface s("wall", 4, 4, g, o);
  // S_u along z, S_v along y: S_u x S_v = -x
  return s;
}
}  // namespace

TEST(SurfaceContact, LagrangeClosesTheGapExactly) {
  const double m = 3.0, h = 1e-3, v = 2.0;
  ReducedModel r = oscillator(m, 0.0);
  r.coords = {{-0.5 * h * v, 0.1, 0.2}};
  const BSplineSurface s = wall();
  CentralDifference cd(r, h, {});
  SurfaceContact c(r, {0}, {&s}, {}, cd.flexibility());
  DenseVector qm("qm", 3), q("q", 3), qp("qp", 3);
  set(qm, -h * v, 0, 0);  // moving at +v
  cd.predict(q, qm, qp);
  CostSplit cost;
  c.correct(qp, cost);
  EXPECT_EQ(c.numActive(), 1);
  EXPECT_NEAR(c.gap()(0), -0.5 * h * v, 1e-12);                  // predicted penetration
  EXPECT_NEAR(r.coords[0][0] + at(qp, 0), 0.0, 1e-12);           // corrected onto the wall
  EXPECT_NEAR(c.force()(0), 0.5 * m * v / h, 1e-6 * m * v / h);  // lambda = -g* / (h^2/m)
  EXPECT_NEAR(at(qp, 1), 0.0, 1e-15);                            // frictionless: no tangential push
}

TEST(SurfaceContact, PenaltyForceIsKpTimesPenetration) {
  const double m = 3.0, h = 1e-3, v = 2.0, kp = 1e5;
  ReducedModel r = oscillator(m, 0.0);
  r.coords = {{-0.5 * h * v, 0.1, 0.2}};
  const BSplineSurface s = wall();
  CentralDifference cd(r, h, {});
  ContactOptions o;
  o.set("Method", "Penalty");
  o.set("Penalty stiffness", kp);
  SurfaceContact c(r, {0}, {&s}, o, cd.flexibility());
  DenseVector qm("qm", 3), q("q", 3), qp("qp", 3);
  set(qm, -h * v, 0, 0);
  cd.predict(q, qm, qp);
  CostSplit cost;
  c.correct(qp, cost);
  const double pen = 0.5 * h * v;
  EXPECT_NEAR(c.force()(0), kp * pen, 1e-9 * kp * pen);         // eq. 2.34
  EXPECT_NEAR(at(qp, 0), h * v - h * h / m * kp * pen, 1e-12);  // eq. 2.35
}

TEST(SurfaceContact, SeparatedNodeFeelsNothing) {
  ReducedModel r = oscillator(1.0, 0.0);
  r.coords = {{-0.1, 0.0, 0.0}};
  const BSplineSurface s = wall();
  CentralDifference cd(r, 1e-3, {});
  SurfaceContact c(r, {0}, {&s}, {}, cd.flexibility());
  DenseVector q("q", 3);
  CostSplit cost;
  c.correct(q, cost);
  EXPECT_EQ(c.numActive(), 0);
  EXPECT_NEAR(c.gap()(0), 0.1, 1e-12);
  EXPECT_EQ(c.force()(0), 0.0);
}

TEST(CentralDifference, ModalDampingGivesTwoXiOmegaOnEveryMode) {
  // Two masses and three springs (wall-k-m1-k-m2-k-wall) plus a third free DOF: modes with omega = 0
  // and two elastic modes; V^T D V must be diag(2 xi omega).
  ReducedModel r = oscillator(1.0, 0.0);
  const double k = 100.0;
  r.K = {2 * k, -k, 0, -k, 2 * k, 0, 0, 0, 0};
  r.M = {1.0, 0, 0, 0, 2.0, 0, 0, 0, 3.0};
  DampingOptions d;
  d.type = DampingType::Modal;
  d.ratio = 0.02;
  const std::vector<double> D = dampingMatrix(r, d);
  std::vector<double> V(r.K), B(r.M), w(3), work(64);
  int info = 0;
  Teuchos::LAPACK<int, double>().SYGV(1, 'V', 'U', 3, V.data(), 3, B.data(), 3, w.data(), work.data(), 64, &info);
  ASSERT_EQ(info, 0);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double s = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) s += V[a * 3 + i] * D[j * 3 + i] * V[b * 3 + j];
      const double expected = a == b ? 2 * d.ratio * std::sqrt(std::max(w[a], 0.0)) : 0.0;
      EXPECT_NEAR(s, expected, 1e-12) << "mode pair " << a << ", " << b;
    }
}

TEST(CentralDifference, RayleighFromTwoRatios) {
  double a = 0, b = 0;
  rayleighFromRatios(100.0, 0.01, 1000.0, 0.02, a, b);
  auto xi = [&](double f) {
    const double w = 2 * M_PI * f;
    return a / (2 * w) + b * w / 2;
  };
  EXPECT_NEAR(xi(100.0), 0.01, 1e-14);
  EXPECT_NEAR(xi(1000.0), 0.02, 1e-14);
  EXPECT_THROW(rayleighFromRatios(100.0, 0.05, 1000.0, 0.001, a, b), Error);  // would need alpha or beta < 0
}

// A dense operator's product y = alpha A x + beta y, split in one block of rows per thread when it
// pays (forEach): the same numbers as the product written out, and the same bits whether the blocks
// run on the thread team or on the calling thread.
TEST(BodyOperator, DenseProductByRowBlocks) {
  const int n = 419;  // cube-rings' reduced size: 1.4 MB, above the parallel threshold
  std::vector<double> a(static_cast<std::size_t>(n) * n), x0(n), y0(n);
  for (int j = 0; j < n; ++j) {
    x0[j] = std::sin(0.7 * j + 0.3);
    y0[j] = std::cos(1.3 * j);
    for (int i = 0; i < n; ++i) a[static_cast<std::size_t>(j) * n + i] = std::sin(0.011 * i * j + 0.5 * i - 0.2 * j);
  }
  const BodyOperator A = BodyOperator::dense(a, n, "test::A");
  auto run = [&](long serialNs) {
    setSerialWorkNs(serialNs);
    DenseVector x("x", n), y("y", n);
    for (int i = 0; i < n; ++i) {
      x(i) = x0[i];
      y(i) = y0[i];
    }
    A.apply(2.0, x, -0.5, y);
    Kokkos::fence();
    return std::vector<double>(y.data(), y.data() + n);
  };
  const auto team = run(0), serial = run(1L << 40);
  setSerialWorkNs(kDefaultSerialWorkNs);
  for (int i = 0; i < n; ++i) {
    double s = 0, scale = 0;
    for (int j = 0; j < n; ++j) {
      s += a[static_cast<std::size_t>(j) * n + i] * x0[j];
      scale += std::fabs(a[static_cast<std::size_t>(j) * n + i] * x0[j]);
    }
    EXPECT_NEAR(team[i], 2.0 * s - 0.5 * y0[i], 1e-14 * (2.0 * scale + 0.5 * std::fabs(y0[i]))) << "row " << i;
    EXPECT_EQ(team[i], serial[i]) << "row " << i << ": the thread team and the calling thread differ";
  }
}

// ---- Coriolis terms (Epaphe_CentralDifference.hpp, docs/theory/integration.md) -------------------------
namespace {

/// A point mass m on an isotropic spring k turning at Omega about z, in its own frame: spin softening
/// k - m Omega^2 in the plane of rotation, and (with `coriolis`) G = 2 m [e_z]_x per unit speed. Along z,
/// the spring `kz`.
ReducedModel whirlingMass(double m, double k, double kz, double omega, bool coriolis) {
  ReducedModel r = test::oscillator(m, k);
  r.K[0] = r.K[4] = k - m * omega * omega;
  r.K[8] = kz;
  r.speed = omega;
  if (coriolis) {
    r.coriolis.assign(9, 0.0);
    r.coriolis[1] = 2 * m;   // G(1, 0): y'' + 2 Omega x'
    r.coriolis[3] = -2 * m;  // G(0, 1): x'' - 2 Omega y'
  }
  return r;
}

/// The two frequencies (rad/s, signed: e^{i w t} of z = x + i y) of the complex record z_n, from the
/// least-squares recurrence z_{n+1} = c1 z_n + c0 z_{n-1} (Prony's method with two exponentials): the
/// roots r of r^2 = c1 r + c0 are e^{i w h}. Also the largest | |r| - 1 |.
std::array<double, 3> pronyFrequencies(const std::vector<std::complex<double>>& z, double h) {
  using C = std::complex<double>;
  C a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;  // normal equations of [z_n, z_{n-1}] [c1; c0] = z_{n+1}
  for (std::size_t n = 1; n + 1 < z.size(); ++n) {
    a11 += std::conj(z[n]) * z[n];
    a12 += std::conj(z[n]) * z[n - 1];
    a22 += std::conj(z[n - 1]) * z[n - 1];
    b1 += std::conj(z[n]) * z[n + 1];
    b2 += std::conj(z[n - 1]) * z[n + 1];
  }
  const C det = a11 * a22 - a12 * std::conj(a12);
  const C c1 = (b1 * a22 - a12 * b2) / det, c0 = (a11 * b2 - std::conj(a12) * b1) / det;
  const C s = std::sqrt(c1 * c1 + 4.0 * c0), r1 = (c1 + s) / 2.0, r2 = (c1 - s) / 2.0;
  return {std::arg(r1) / h, std::arg(r2) / h, std::max(std::abs(std::abs(r1) - 1), std::abs(std::abs(r2) - 1))};
}

/// The central difference's own whirl frequency near `guess` (rad/s): the root theta / h of
/// -4 sin^2(theta/2) / h^2 - 2 Omega sin(theta) / h + w1^2 = 0, the scheme's recurrence for z = x + i y
/// (z_n = e^{i theta n}, w1^2 = k/m - Omega^2), by Newton.
double discreteWhirl(double w1sq, double omega, double h, double guess) {
  double t = guess * h;
  for (int i = 0; i < 50; ++i) {
    const double f = -4 * std::sin(t / 2) * std::sin(t / 2) / (h * h) - 2 * omega * std::sin(t) / h + w1sq;
    const double df = -2 * std::sin(t) / (h * h) - 2 * omega * std::cos(t) / h;
    t -= f / df;
  }
  return t / h;
}

/// z = x + i y of q over `steps` free steps from q_{-1} = q_0 = (a, 0, 0); the energy E_{n+1/2} at the
/// start and its largest change.
struct Whirl {
  std::vector<std::complex<double>> z;
  double energy = 0, drift = 0;
};
Whirl whirl(const CentralDifference& cd, int steps) {
  DenseVector qm("qm", 3), q("q", 3), qp("qp", 3);
  set(qm, 1e-3, 0, 0);
  set(q, 1e-3, 0, 0);
  Whirl w;
  w.energy = cd.halfStepEnergy(qm, q);
  for (int n = 0; n < steps; ++n) {
    cd.predict(q, qm, qp);
    std::swap(qm, q);
    std::swap(q, qp);
    w.z.emplace_back(at(q, 0), at(q, 1));
    w.drift = std::max(w.drift, std::abs(cd.halfStepEnergy(qm, q) - w.energy));
  }
  return w;
}

}  // namespace

// Closed form (stated before measuring): with Coriolis and spin softening the isotropic mass whirls in
// its turning frame at w = sqrt(k/m) - Omega (forward) and -(sqrt(k/m) + Omega) (backward): z'' + 2 i Omega
// z' + (k/m - Omega^2) z = 0 gives (w + Omega)^2 = k/m. Without Coriolis both are +-sqrt(k/m - Omega^2).
// Measured from the time history (Prony), asserted to 1e-4 of the closed form: the scheme's own
// frequencies (discreteWhirl) differ from it by O((w h)^2) / 24 = 2.6e-5 at w h = 0.025; they are also
// asserted, to 1e-9 (what the record resolves). The energy E_{n+1/2} is constant to round-off: the
// gyroscopic force does no work.
TEST(CentralDifference, CoriolisSplitsTheWhirlIntoSqrtKOverMPlusMinusOmega) {
  const double m = 2.0, k = 800.0, w0 = std::sqrt(k / m), omega = 5.0, h = 1e-3;
  for (bool coriolis : {true, false}) {
    const CentralDifference cd(whirlingMass(m, k, k, omega, coriolis), h, {});
    const Whirl w = whirl(cd, 20000);
    auto f = pronyFrequencies(w.z, h);
    if (f[0] < f[1]) std::swap(f[0], f[1]);
    const double w1sq = w0 * w0 - omega * omega;
    const double forward = coriolis ? w0 - omega : std::sqrt(w1sq), backward = coriolis ? -(w0 + omega) : -forward;
    const double om = coriolis ? omega : 0.0;
    std::printf(
        "%s Coriolis: whirls %.9f and %.9f rad/s, closed form %.9f and %.9f (%.2e, %.2e); energy drift "
        "%.2e of %.3e J\n",
        coriolis ? "with" : "without", f[0], f[1], forward, backward, f[0] / forward - 1, f[1] / backward - 1, w.drift,
        w.energy);
    EXPECT_NEAR(f[0], forward, 1e-4 * std::abs(forward));
    EXPECT_NEAR(f[1], backward, 1e-4 * std::abs(backward));
    EXPECT_NEAR(f[0], discreteWhirl(w1sq, om, h, forward), 1e-9 * std::abs(forward));
    EXPECT_NEAR(f[1], discreteWhirl(w1sq, om, h, backward), 1e-9 * std::abs(backward));
    EXPECT_LT(f[2], 1e-9);                 // undamped: |r| = 1
    EXPECT_LT(w.drift, 1e-11 * w.energy);  // no work by the gyroscopic force
  }
}

// The stable step of (K, M) stays sufficient with the Coriolis terms (the energy argument of the header):
// in-plane w1 = sqrt(k/m - Omega^2) the highest, a run at 0.99 x 2 / w1 keeps its energy (to round-off)
// and its amplitude. For this model the scheme's own limit is larger, h = 2 w0 / w1^2 = 1.033 x 2 / w1
// (the roots of (1 + i Omega h) r^2 - (2 - h^2 w1^2) r + (1 - i Omega h) leave the unit circle there): a run
// at 1.05 x 2 / w1 grows.
TEST(CentralDifference, CoriolisLeavesTheStableStepOfKAndM) {
  const double m = 2.0, k = 800.0, omega = 5.0;
  const ReducedModel r = whirlingMass(m, k, 0.25 * k, omega, true);
  const double hc = criticalTimeStep(r, {}, 0.0, {}).critical;
  EXPECT_NEAR(hc, 2.0 / std::sqrt(k / m - omega * omega), 1e-12 * hc);
  const Whirl stable = whirl(CentralDifference(r, 0.99 * hc, {}), 20000);
  double largest = 0;
  for (const auto& z : stable.z) largest = std::max(largest, std::abs(z));
  EXPECT_LT(stable.drift, 1e-9 * stable.energy);
  EXPECT_LT(largest, 50 * 1e-3);  // bounded: E = 1/2 v^T (M - h^2 K / 4) v + ..., positive definite
  const Whirl unstable = whirl(CentralDifference(r, 1.05 * hc, {}), 200);
  EXPECT_GT(std::abs(unstable.z.back()), 1e3 * 1e-3);  // |r| = 1.41 a step: 1e27 after 200 (finite)
}

// With Rayleigh damping the balance E + damping work = E_0 closes with the damping alone: the Coriolis
// part of the velocity term does no work.
TEST(CentralDifference, CoriolisEnergyBalanceWithDampingIsExact) {
  DampingOptions d;
  d.type = DampingType::Rayleigh;
  d.alpha = 0.5;
  d.beta = 1e-4;
  const CentralDifference cd(whirlingMass(2.0, 800.0, 800.0, 5.0, true), 1e-3, d);
  DenseVector qm("qm", 3), q("q", 3);
  set(qm, 0.0, 0.0, 0.0);
  set(q, 1e-3, 2e-3, -1e-3);
  const auto b = test::freeSteps(cd, qm, q, 20000);
  EXPECT_LT(b.end, 0.01 * b.start);
  EXPECT_NEAR(b.end + b.damping, b.start, 1e-12 * b.start);
}
