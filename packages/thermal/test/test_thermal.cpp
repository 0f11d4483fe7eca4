// The thermal package's parts: the elements' sums, the assembly's conservation, the reduced basis'
// steady state, sub-cycling's heat balance and error, the refusals, and thermal growth.
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_HeatElement.hpp"
#include "Epaphe_ThermalGrowth.hpp"
#include "Epaphe_ThermalModel.hpp"
#include "Epaphe_ThermalReduction.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace epaphe;

namespace {

const ThermalMaterial kTitanium{7.0, 560.0, 4430.0};

/// A block 10 x 4 x 4 mm, held at T_ref on x+, convection 500 W/(m^2 K) towards T_ref + 80 on y+.
ThermalFullModel block() {
  ThermalDefinition def;
  def.material = kTitanium;
  def.referenceTemperature = 20.0;
  Mesh mesh = makeBoxMesh({0, 0, 0}, {0.01, 0.004, 0.004}, {10, 4, 4});
  def.fixedNodes = mesh.nodeSets.at("x+");
  def.convection.push_back({mesh.nodeSets.at("y+"), 500.0, 100.0});
  return assembleThermalModel("block", mesh, def, Teuchos::DefaultComm<int>::getComm());
}

}  // namespace

TEST(Thermal, ElementsConserveAConstantFieldAndSumToVolumeAndArea) {
  const double x[8][3] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}, {0, 0, 3}, {2, 0, 3}, {2, 1, 3}, {0, 1, 3}};
  double K[64], C[64];
  hex8Heat(x, kTitanium, K, C);
  double total = 0;
  for (int a = 0; a < 8; ++a) {
    double row = 0;
    for (int b = 0; b < 8; ++b) {
      row += K[a * 8 + b];
      total += C[a * 8 + b];
      EXPECT_EQ(K[a * 8 + b], K[b * 8 + a]);
    }
    EXPECT_NEAR(row, 0.0, 1e-12 * kTitanium.conductivity);  // a uniform temperature conducts nothing
  }
  EXPECT_NEAR(total, 6.0 * kTitanium.density * kTitanium.specificHeat, 1e-9 * total);  // rho c V
  const double f[4][3] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0.5}, {0, 1, 0.5}};
  double H[16], area[4];
  quad4Face(f, H, area);
  EXPECT_NEAR(area[0] + area[1] + area[2] + area[3], 2.0 * std::sqrt(1.25), 1e-12);
  EXPECT_NEAR(std::accumulate(H, H + 16, 0.0), 2.0 * std::sqrt(1.25), 1e-12);
}

TEST(Thermal, AssemblyHoldsTheCapacityAndTheConvectionOfTheBlock) {
  const ThermalFullModel m = block();
  EXPECT_EQ(m.numFree, m.numNodes() - 25);
  MultiVector one(m.C->getDomainMap(), 1), Cone(m.C->getRangeMap(), 1), Kone(m.K->getRangeMap(), 1);
  one.putScalar(1.0);
  m.C->apply(one, Cone);
  m.K->apply(one, Kone);
  std::vector<double> c(1), g(1);
  Cone.norm1(Teuchos::ArrayView<double>(c));
  m.load->norm1(Teuchos::ArrayView<double>(g));
  // the free nodes' share of rho c V: all of it but what the fixed face's nodes carry (C is positive
  // entry by entry for 8-node hexahedra), and the convection's h (T_inf - T_ref) A
  const double rcV = kTitanium.density * kTitanium.specificHeat * 0.01 * 0.004 * 0.004;
  EXPECT_LT(c[0], rcV);
  EXPECT_GT(c[0], rcV * (1 - 2.0 / 10));
  // the y+ face's nodes at x+ are held: the free nodes carry 19/20 of its area (half an element of 10 is held)
  EXPECT_NEAR(g[0], 500.0 * 80.0 * (0.01 * 0.004) * 0.95, 1e-9 * g[0]);
  EXPECT_THROW(
      assembleThermalModel("bad", makeBoxMesh({0, 0, 0}, {1, 1, 1}, {1, 1, 1}),
                           ThermalDefinition{{0.0, 1.0, 1.0}, 0.0, {}, {}}, Teuchos::DefaultComm<int>::getComm()),
      Error);
}

TEST(Thermal, ReducedBasisIsOrthonormalAndItsSteadyStateIsTheFullOnes) {
  const ThermalFullModel full = block();
  const int spot = full.mesh.nodeSets.at("x-")[12];
  ThermalReductionOptions opt;
  opt.modes = 6;
  const ReducedThermalModel red = reduceThermal(full, {spot}, opt);
  // 6 modes, the spot's static response, the convection's steady state, the spot's Krylov vector
  ASSERT_EQ(red.numModes(), 9);
  for (int i = 1; i < red.numModes(); ++i) EXPECT_LE(red.rate[i - 1], red.rate[i]);
  // steady state of 2 W at the spot with the convection: K theta = Q + g, solved by the full model
  MultiVector rhs(full.K->getRangeMap(), 1), theta(full.K->getDomainMap(), 1), Ktheta(full.K->getRangeMap(), 1);
  rhs.update(1.0, *full.load, 0.0);
  {
    auto r = rhs.getLocalViewHost(Tpetra::Access::ReadWrite);
    r(full.eq[spot], 0) += 2.0;
  }
  ThermalIntegrator integ(red);
  const double power = 2.0;
  integ.advance(1e4 / red.rate[0], &power);  // 10^4 slowest time constants: steady to round-off
  auto th = theta.getLocalViewHost(Tpetra::Access::ReadWrite);
  for (int n = 0; n < full.numNodes(); ++n)
    if (full.eq[n] >= 0) th(full.eq[n], 0) = integ.temperature(n) - 20.0;
  full.K->apply(theta, Ktheta);
  Ktheta.update(-1.0, rhs, 1.0);
  std::vector<double> res(1), ref(1);
  Ktheta.normInf(Teuchos::ArrayView<double>(res));
  rhs.normInf(Teuchos::ArrayView<double>(ref));
  EXPECT_LT(res[0], 1e-9 * ref[0]);
  std::printf("block: steady residual |K theta - Q - g| / |Q + g| = %.2e with %d basis vectors\n", res[0] / ref[0],
              red.numModes());
}

TEST(Thermal, SubCyclingKeepsEveryJouleAndItsErrorIsFirstOrderInTheWindow) {
  const ThermalFullModel full = block();
  const std::vector<int> spots{full.mesh.nodeSets.at("x-")[12], full.mesh.nodeSets.at("x-")[7]};
  const ReducedThermalModel red = reduceThermal(full, spots, ThermalReductionOptions{});
  // a rub that comes and goes: power 3 (1 + sin(2 pi t / 0.2)) W on the first spot, 1 W on the second
  const double dt = 1e-4, duration = 1.0;
  const int steps = static_cast<int>(std::lround(duration / dt));
  auto power = [&](int n, double* p) {
    p[0] = 3.0 * (1 + std::sin(2 * M_PI * (n + 0.5) * dt / 0.2));
    p[1] = 1.0;
  };
  ThermalIntegrator every(red);
  double work = 0, p[2];
  for (int n = 0; n < steps; ++n) {
    power(n, p);
    every.advance(dt, p);
    work += (p[0] + p[1]) * dt;
  }
  double previous = 0;
  for (int window : {10, 100, 1000}) {
    ThermalIntegrator sub(red);
    for (int n = 0; n < steps; ++n) {
      power(n, p);
      sub.addHeat(p, dt);
      if ((n + 1) % window == 0) sub.advanceWindow();
    }
    EXPECT_NEAR(sub.heatReceived(), work, 1e-12 * work);
    EXPECT_NEAR(sub.time(), duration, 1e-12);
    const double error = std::abs(sub.temperature(spots[0]) - every.temperature(spots[0]));
    const double rise = every.temperature(spots[0]) - 20.0;
    std::printf("window %5d steps (%.0e s): spot temperature error %.3e K of a rise of %.3f K\n", window, window * dt,
                error, rise);
    if (window <= 100) {  // windows of up to 1/20 of the input's period: within 2 % of the rise
      EXPECT_LT(error, 0.02 * rise);
    }
    EXPECT_GT(error, previous);  // and the error grows with the window
    previous = error;
  }
  EXPECT_NEAR(every.heatReceived(), work, 1e-12 * work);
}

TEST(Thermal, InsulatedBodiesAndFixedHeatedNodesAreRefused) {
  ThermalDefinition def;
  def.material = kTitanium;
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  const ThermalFullModel insulated =
      assembleThermalModel("can", makeBoxMesh({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), def, comm);
  try {
    reduceThermal(insulated, {0}, ThermalReductionOptions{});
    FAIL() << "an insulated body was reduced";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("insulated"), std::string::npos) << e.what();
  }
  const ThermalFullModel held = block();
  EXPECT_THROW(reduceThermal(held, {held.mesh.nodeSets.at("x+")[0]}, ThermalReductionOptions{}), Error);
}

// A free bar heated uniformly grows by alpha L theta (Epaphe_ThermalGrowth.hpp): held isostatically
// (3-2-1: one corner fixed, the next along x held across, the one along y held along z), so nothing
// resists the expansion; the linear displacement alpha theta (x - x_A) is in the elements' span, so
// the finite-element growth is exact to round-off, whatever Poisson's ratio.
TEST(Thermal, FreeBarHeatedUniformlyGrowsByAlphaLTheta) {
  const double L = 0.1, b = 0.01, alpha = 8.6e-6, theta = 100.0;
  const Mesh mesh = makeBoxMesh({0, 0, 0}, {L, b, b}, {10, 2, 2});
  const FullModel free =
      assembleHexModel("bar", mesh, Material{4430, 1.1e11, 0.34}, {}, Teuchos::DefaultComm<int>::getComm());
  const std::vector<double> uniform(static_cast<std::size_t>(free.numNodes()), theta);
  const MultiVector F = thermalLoads(free, alpha, uniform, 1);
  const int n = free.numFree;
  const std::vector<double> K = gatherDense(*free.K);
  auto fh = F.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto nodeAt = [&](double x, double y, double z) {
    for (int i = 0; i < free.numNodes(); ++i)
      if (std::abs(mesh.coords[i][0] - x) < 1e-12 && std::abs(mesh.coords[i][1] - y) < 1e-12 &&
          std::abs(mesh.coords[i][2] - z) < 1e-12)
        return i;
    return -1;
  };
  const int A = nodeAt(0, 0, 0), B = nodeAt(L, 0, 0), C = nodeAt(0, b, 0);
  const std::vector<int> held{3 * A, 3 * A + 1, 3 * A + 2, 3 * B + 1, 3 * B + 2, 3 * C + 2};
  std::vector<int> keep;
  for (int i = 0; i < n; ++i)
    if (std::find(held.begin(), held.end(), i) == held.end()) keep.push_back(i);
  const int r = static_cast<int>(keep.size());
  std::vector<double> Kr(static_cast<std::size_t>(r) * r);
  for (int j = 0; j < r; ++j)
    for (int i = 0; i < r; ++i)
      Kr[static_cast<std::size_t>(j) * r + i] = K[static_cast<std::size_t>(keep[j]) * n + keep[i]];
  const std::vector<double> Kinv = spdInverse(Kr, r, "K of the held bar", "hold it isostatically");
  std::vector<double> u(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < r; ++j) u[keep[i]] += Kinv[static_cast<std::size_t>(j) * r + i] * fh(keep[j], 0);
  double worst = 0;
  for (int i = 0; i < free.numNodes(); ++i)
    for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(u[3 * i + d] - alpha * theta * mesh.coords[i][d]));
  std::printf("free bar: growth alpha L theta = %.6e m; worst nodal error %.2e m (%.1e of it)\n", alpha * L * theta,
              worst, worst / (alpha * L * theta));
  EXPECT_LT(worst, 1e-10 * alpha * L * theta);
}
