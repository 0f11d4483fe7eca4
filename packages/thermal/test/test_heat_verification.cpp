// The reduced thermal model against independent references (docs/theory/heat.md):
//  - the semi-infinite solid under a constant surface flux q: surface temperature
//    2 q sqrt(t / (pi k rho c)) (Carslaw & Jaeger, "Conduction of heat in solids", 1959, sec. 2.9),
//    on a long bar over the times its mesh resolves;
//  - the bar heated by q at x = 0 and held at T_ref at x = L: steady profile q (L - x) / k, and the
//    series solution theta(0, t) = q L / k (1 - sum_n 8 / ((2n-1)^2 pi^2) exp(-(2n-1)^2 t / tau)),
//    tau = 4 L^2 / (pi^2 alpha) its first decay time (Carslaw & Jaeger sec. 3.4; docs/theory/heat.md eq. 62);
//  - the reduction against the full finite-element model (every mode) on a block with a hot spot.
#include "Epaphe_ThermalModel.hpp"
#include "Epaphe_ThermalReduction.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace epaphe;

namespace {

const ThermalMaterial kTitanium{7.0, 560.0, 4430.0};

struct Bar {
  ThermalFullModel full;
  std::vector<int> heated;   // the x = 0 face's nodes
  std::vector<double> area;  // their areas
};

/// A bar along x, length L, square section s x s of one element, n elements along x, held at T_ref
/// on x = L.
Bar bar(double L, double s, int n) {
  ThermalDefinition def;
  def.material = kTitanium;
  Mesh mesh = makeBoxMesh({0, 0, 0}, {L, s, s}, {n, 1, 1});
  def.fixedNodes = mesh.nodeSets.at("x+");
  Bar b;
  b.heated = mesh.nodeSets.at("x-");
  b.area = faceAreas(mesh, b.heated);
  b.full = assembleThermalModel("bar", mesh, def, Teuchos::DefaultComm<int>::getComm());
  return b;
}

/// The mean temperature of the heated face.
double faceTemperature(const ThermalIntegrator& integ, const std::vector<int>& nodes) {
  double t = 0;
  for (int n : nodes) t += integ.temperature(n);
  return t / static_cast<double>(nodes.size());
}

}  // namespace

TEST(HeatVerification, SemiInfiniteSolidUnderAConstantFlux) {
  const double L = 0.02, s = 0.5e-3, q = 1e6;  // 1 MW/m^2
  const int n = 200;                           // h = 0.1 mm
  const Bar b = bar(L, s, n);
  const double alpha = kTitanium.diffusivity(), h = L / n;
  // resolved: the diffusion length sqrt(alpha t) spans 3 elements or more; semi-infinite: the heat
  // has not reached the far end, 2 sqrt(alpha t) <= L / 3 (erfc(3) = 2e-5)
  const double t0 = 9 * h * h / alpha, t1 = (L / 6) * (L / 6) / alpha;
  std::vector<double> power;
  for (double a : b.area) power.push_back(q * a);
  for (int modes : {20, 40, 60}) {
    ThermalReductionOptions opt;
    opt.modes = modes;
    const ReducedThermalModel red = reduceThermal(b.full, b.heated, opt);
    ThermalIntegrator integ(red);
    double worst = 0, worstAt = 0;
    const int samples = 24;
    for (int k = 0; k <= samples; ++k) {
      const double t = t0 * std::pow(t1 / t0, static_cast<double>(k) / samples);
      integ.advance(t - integ.time(), power.data());
      const double exact = 2 * q * std::sqrt(t / (M_PI * kTitanium.effusivity() * kTitanium.effusivity()));
      const double e = std::abs(faceTemperature(integ, b.heated) - exact) / exact;
      if (e > worst) {
        worst = e;
        worstAt = t;
      }
    }
    std::printf(
        "semi-infinite solid, %d modes + %zu static responses, t in [%.3f, %.2f] s: worst relative "
        "error %.2e at t = %.3f s\n",
        modes, b.heated.size(), t0, t1, worst, worstAt);
    if (modes == 60) {
      EXPECT_LT(worst, 0.02);
    }
  }
}

TEST(HeatVerification, BarHeatedAtOneEndAgainstTheSeriesSolution) {
  const double L = 0.05, s = 1e-3, q = 1e5;
  const int n = 50;
  const Bar b = bar(L, s, n);
  const double alpha = kTitanium.diffusivity(), k = kTitanium.conductivity;
  const double tau = 4 * L * L / (M_PI * M_PI * alpha);
  ThermalReductionOptions opt;
  opt.modes = 10;
  const ReducedThermalModel red = reduceThermal(b.full, b.heated, opt);
  std::vector<double> power;
  for (double a : b.area) power.push_back(q * a);
  ThermalIntegrator integ(red);
  auto series = [&](double t) {
    double sum = 0;
    for (int m = 1; m < 2000; m += 2) sum += 8 / (m * m * M_PI * M_PI) * std::exp(-m * m * t / tau);
    return q * L / k * (1 - sum);
  };
  double worst = 0;
  std::vector<double> deficit;  // steady minus transient at x = 0, at t = 1, 2 tau
  for (int k10 = 1; k10 <= 20; ++k10) {
    const double t = 0.1 * k10 * tau;
    integ.advance(t - integ.time(), power.data());
    const double theta = faceTemperature(integ, b.heated);
    worst = std::max(worst, std::abs(theta - series(t)) / series(t));
    if (k10 == 10 || k10 == 20) deficit.push_back(q * L / k - theta);
  }
  const double measuredTau = tau / std::log(deficit[0] / deficit[1]);
  std::printf(
      "bar: theta(0, t) against the series over [0.1, 2] tau: worst relative error %.2e; first decay time "
      "%.4f s, series %.4f s (%.1e)\n",
      worst, measuredTau, tau, measuredTau / tau - 1);
  EXPECT_LT(worst, 2e-3);
  EXPECT_NEAR(measuredTau / tau, 1.0, 1e-3);
  // the rate of the slowest mode is that of the series' first term, to the mesh's discretization error
  EXPECT_NEAR(red.rate[0] * tau, 1.0, 1e-3);
  // steady: linear elements hold the linear profile exactly, and the static response is in the basis
  integ.advance(1e3 * tau, power.data());
  double steady = 0;
  for (int node = 0; node < b.full.numNodes(); ++node) {
    const double x = b.full.mesh.coords[node][0];
    steady = std::max(steady, std::abs(integ.temperature(node) - q * (L - x) / k) / (q * L / k));
  }
  std::printf("bar: steady profile q (L - x) / k to %.2e of q L / k\n", steady);
  EXPECT_LT(steady, 1e-10);
}

TEST(HeatVerification, ReductionAgainstTheFullModelOnAHotSpot) {
  // a block 10 x 4 x 4 mm of 1 mm cubes held at T_ref on x+, cooled on y+; a contact node on x- heated
  // 4 W for 50 ms, off 50 ms, for 1 s (a rub that comes and goes)
  ThermalDefinition def;
  def.material = kTitanium;
  Mesh mesh = makeBoxMesh({0, 0, 0}, {0.01, 0.004, 0.004}, {10, 4, 4});
  def.fixedNodes = mesh.nodeSets.at("x+");
  def.convection.push_back({mesh.nodeSets.at("y+"), 500.0, 0.0});
  const ThermalFullModel full = assembleThermalModel("block", mesh, def, Teuchos::DefaultComm<int>::getComm());
  const std::vector<int> spot{full.mesh.nodeSets.at("x-")[12]};
  const ReducedThermalModel reference = fullThermalModel(full, spot);
  std::printf("full model: %d free nodes, %d basis vectors\n", full.numFree, reference.numModes());
  double errors[2][3], lowest = 0, lowestReduced = 0, peak = 0;
  const int modeCounts[3] = {0, 5, 20};
  for (int blocks = 1; blocks <= 2; ++blocks)
    for (int im = 0; im < 3; ++im) {
      ThermalReductionOptions opt;
      opt.modes = modeCounts[im];
      opt.krylovBlocks = blocks;
      const ReducedThermalModel red = reduceThermal(full, spot, opt);
      ThermalIntegrator a(reference), b(red);
      double worstSpot = 0, worstField = 0;
      for (int w = 0; w < 100; ++w) {
        const double p = w % 2 == 0 ? 4.0 : 0.0;
        for (int sub = 0; sub < 5; ++sub) {
          a.advance(0.01, &p);
          b.advance(0.01, &p);
          peak = std::max(peak, a.temperature(spot[0]));
          worstSpot = std::max(worstSpot, std::abs(a.temperature(spot[0]) - b.temperature(spot[0])));
          for (int n = 0; n < full.numNodes(); ++n) {
            worstField = std::max(worstField, std::abs(a.temperature(n) - b.temperature(n)));
            lowest = std::min(lowest, a.temperature(n));
            if (blocks == 2 && im == 2) lowestReduced = std::min(lowestReduced, b.temperature(n));
          }
        }
      }
      std::printf(
          "reduction, %2d modes + %d Krylov block(s) (%d vectors): worst error at the spot %.3e K, over the field "
          "%.3e K, of a peak rise %.3f K (%.1f %%)\n",
          modeCounts[im], blocks, red.numModes(), worstSpot, worstField, peak, 100 * worstField / peak);
      errors[blocks - 1][im] = worstField / peak;
    }
  std::printf("lowest temperature: full model %.3e K, reduced (20 modes, 2 blocks) %.3e K, of a peak %.3f K\n", lowest,
              lowestReduced, peak);
  // a point input switched on and off is the basis' hard case (its first instants are local, beyond
  // any handful of modes): the error falls with the modes and with the Krylov block K^{-1} C K^{-1} e
  for (int blocks = 0; blocks < 2; ++blocks) {
    EXPECT_LT(errors[blocks][1], errors[blocks][0]);
    EXPECT_LT(errors[blocks][2], errors[blocks][1]);
  }
  for (int im = 0; im < 3; ++im) EXPECT_LT(errors[1][im], errors[0][im]);
  EXPECT_LT(errors[1][2], 0.01);  // measured 0.4 %
  // the lumped capacity on cubes (K's off-diagonal entries <= 0): heat in never cools a node (to
  // round-off); the reduced model's undershoot, a truncation's, stays within 1 % of the peak
  EXPECT_GE(lowest, -1e-12 * peak);
  EXPECT_GE(lowestReduced, -0.01 * peak);
}
