// Run-ups (Epaphe_RunUp.hpp): the speed law's angle is the integral of its speed, and on an
// oscillator whose stiffness follows the speed the energy balance closes with the drive's work.
#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_RunUp.hpp"
#include "Epaphe_SpeedLaw.hpp"
#include "TestModels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace epaphe {
namespace {

TEST(SpeedLaw, TheAngleIsTheIntegralOfTheSpeed) {
  SpeedLaw law;
  law.ramp = true;
  law.start = 100;
  law.end = 300;
  law.t0 = 0.1;
  law.t1 = 0.5;
  law = law.scaled(-1);
  EXPECT_EQ(law.fastest(), 300);
  // the trapezoid rule is exact on a piecewise-linear speed whose corners are grid points
  const int n = 10000;
  const double dt = 1.0 / n;
  double integral = 0;
  for (int i = 1; i <= n; ++i) {
    const double t = i * dt;
    integral += 0.5 * dt * (law.speed(t - dt) + law.speed(t));
    ASSERT_NEAR(law.angle(t), integral, 1e-10 * std::abs(integral)) << "t = " << t;
  }
  EXPECT_NEAR(law.speed(0.3), -200, 1e-12);
  EXPECT_EQ(law.speed(0.05), -100);
  EXPECT_EQ(law.speed(0.7), -300);
}

TEST(RunUp, TheDriveWorkClosesTheEnergyBalance) {
  // m = 2 kg, k(xi) = 800 + 2400 xi N/m, xi = (Omega / 100)^2, Omega from 50 to 100 rad/s: k from 1400
  // to 3200 N/m; released from 1 mm
  ReducedModel model = test::oscillator(2.0, 800.0);
  const double h = 1e-3;
  CentralDifference cd(model, h, DampingOptions{});
  RunUpModel r;
  r.law.ramp = true;
  r.law.start = 50;
  r.law.end = 100;
  r.law.t0 = 0.01;
  r.law.t1 = 0.2;
  r.maxSpeed = 100;
  r.stiffness = {model.K, test::oscillator(2.0, 2400.0).K};
  CostSplit cost;
  std::ostringstream out;
  ExplicitLoop loop({{"oscillator", &cd, 0, 3, true}}, h, 300, nullptr, cost, out);
  auto q = Kokkos::create_mirror_view(loop.current());
  q(0) = 1e-3;
  Kokkos::deep_copy(loop.current(), q);
  q(0) = 1e-3 * (1 - 0.5 * h * h * 1400.0 / 2.0);
  Kokkos::deep_copy(loop.previous(), q);
  RunUp runUp({{0, &cd, &r}}, nullptr, {});
  EnergyMonitor monitor(loop, {1, 1e-6, 0.0});
  loop.addObserver(&runUp);
  loop.addObserver(&monitor);
  ASSERT_TRUE(loop.run());
  const double drive = loop.accumulators().driveWork.at(0);
  // one refresh at the start, then one per step whose level of xi (grid 1e-3) differs from the last
  // step's: every step of the ramp here (xi moves by about 4e-3 a step)
  long long changes = 1;
  for (int n = 1; n < 300; ++n) changes += r.level(n * h) != r.level((n - 1) * h);
  EXPECT_EQ(runUp.refreshes(), changes);
  EXPECT_GT(changes, 150);
  EXPECT_GT(std::abs(drive), 0.1 * monitor.last().total) << "the stiffening does work on the oscillator";
  EXPECT_LT(loop.accumulators().maxBalanceError, 1e-12);
  // the stiffness in use at the end is k(1) = 3200 N/m: the strain energy of q_n is 1600 q_n^2
  auto c = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), loop.current());
  EXPECT_NEAR(cd.strain(loop.current()), 1600.0 * c(0) * c(0), 1e-12 * 1600.0 * c(0) * c(0));
}

}  // namespace
}  // namespace epaphe
