// A free ring's in-plane bending frequencies against the thin-ring formula (Hoppe 1871; Blevins,
// Formulas for natural frequency and mode shape, table 9-1):
//   omega_n^2 = E I n^2 (n^2 - 1)^2 / (rho A R^4 (n^2 + 1)),   I / A = h^2 / 12,
// R the mean radius, h the radial thickness. The built-in casing mesh, one element through its
// thickness and 144 around, free: with incompatible modes each n = 2..6 within 2 % (0.3 % at n = 2 to
// 1.3 % at n = 6, halved and more from 72 around: the discretization); the trilinear element locks
// (parasitic shear) and is far above. The casing of a whole stage is this ring.
#include "Epaphe_Centrifugal.hpp"
#include "Epaphe_EigenSolver.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_Mesh.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

using namespace epaphe;

namespace {

const double kRadius = 0.3, kThickness = 0.008, kYoung = 2.1e11, kDensity = 7800;

/// The lowest in-plane bending frequency (Hz) of each circumferential order n = 2..6 of the free
/// casing ring: a mode is in-plane when its axial displacements hold under 1 % of its squared norm,
/// and its order is the largest DFT component of the inner face's radial displacement.
std::map<int, double> inPlaneFrequencies(HexFormulation formulation, int around) {
  CasingGeometry g;
  g.radius = kRadius;
  g.axialRange = {-0.03, 0.03};
  const Mesh mesh = makeCasingMesh(g, kThickness, {1, around, 3});
  Material mat{kDensity, kYoung, 0.3};
  mat.formulation = formulation;
  const FullModel ring = assembleHexModel("ring", mesh, mat, {}, Teuchos::DefaultComm<int>::getComm());
  const int count = 40;
  const EigenResult e = denseLowestEigenpairs(*ring.K, *ring.M, count, "the free ring");
  const std::vector<int> inner = ring.mesh.nodeSet("inner", "the ring");
  std::map<int, double> found;
  for (int k = 6; k < count; ++k) {  // past the six rigid-body modes
    const std::vector<double> u = nodalValues(ring, *e.vectors->getVector(k));
    double axial = 0, all = 0;
    for (std::size_t i = 0; i < u.size(); ++i) {
      all += u[i] * u[i];
      if (i % 3 == 2) axial += u[i] * u[i];
    }
    if (axial > 0.01 * all) continue;
    int order = 0;
    double best = 0;
    for (int n = 0; n <= 12; ++n) {
      double c = 0, s = 0;
      for (int node : inner) {
        const auto& x = ring.mesh.coords[node];
        const double theta = std::atan2(x[1], x[0]);
        const double ur = (u[3 * node] * x[0] + u[3 * node + 1] * x[1]) / std::hypot(x[0], x[1]);
        c += ur * std::cos(n * theta);
        s += ur * std::sin(n * theta);
      }
      if (c * c + s * s > best) {
        best = c * c + s * s;
        order = n;
      }
    }
    if (order >= 2 && order <= 6 && !found.count(order)) found[order] = std::sqrt(e.lambda[k]) / (2 * M_PI);
  }
  return found;
}

double thinRing(int n) {
  const double R = kRadius + kThickness / 2, IoverA = kThickness * kThickness / 12;
  const double n2 = n * n;
  return std::sqrt(kYoung * IoverA * n2 * (n2 - 1) * (n2 - 1) / (kDensity * std::pow(R, 4) * (n2 + 1))) / (2 * M_PI);
}

}  // namespace

TEST(FreeRing, IncompatibleModesMeetTheThinRingFormula) {
  const auto inc = inPlaneFrequencies(HexFormulation::IncompatibleModes, 144);
  const auto full = inPlaneFrequencies(HexFormulation::FullIntegration, 72);
  for (int n = 2; n <= 6; ++n) {
    ASSERT_TRUE(inc.count(n)) << "no in-plane mode of order " << n << " among the lowest 40";
    ASSERT_TRUE(full.count(n)) << "no in-plane mode of order " << n << " among the lowest 40 (trilinear)";
    const double f = thinRing(n);
    std::printf("n = %d: thin ring %.3f Hz, incompatible modes %.3f Hz (%+.3f %%), trilinear %.3f Hz (%+.1f %%)\n", n,
                f, inc.at(n), 100 * (inc.at(n) / f - 1), full.at(n), 100 * (full.at(n) / f - 1));
    EXPECT_NEAR(inc.at(n), f, 0.02 * f) << "n = " << n;
    EXPECT_GT(full.at(n), 1.5 * f) << "n = " << n;  // the locking: one element through 8 mm, 26 mm around
  }
}
