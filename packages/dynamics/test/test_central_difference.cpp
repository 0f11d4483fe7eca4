// Central difference and contact correction on models small enough to solve by hand.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestModels.hpp"

#include <gtest/gtest.h>

#include <Teuchos_LAPACK.hpp>

#include <cmath>
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
