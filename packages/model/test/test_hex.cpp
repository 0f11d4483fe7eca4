#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_HexElement.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <cmath>

using namespace epaphe;

namespace {
// A distorted hexahedron (no face parallel to another).
const double X[8][3] = {{0, 0, 0},       {1.1, 0.1, 0},     {1.2, 0.9, 0.1}, {-0.1, 1.0, 0},
                        {0.1, -0.1, 1.0}, {1.0, 0.0, 1.2},  {1.1, 1.1, 0.9}, {0.0, 0.9, 1.1}};
const Material steel{7800, 2.1e11, 0.3};
}  // namespace

TEST(Hex8, RigidBodyMotionsAreStressFree) {
  double K[576], M[576];
  hex8StiffnessMass(X, steel, K, M);
  // 3 translations and 3 infinitesimal rotations
  for (int mode = 0; mode < 6; ++mode) {
    double u[24];
    for (int a = 0; a < 8; ++a) {
      const double* x = X[a];
      double r[3] = {0, 0, 0};
      if (mode < 3) r[mode] = 1;
      else if (mode == 3) { r[1] = -x[2]; r[2] = x[1]; }
      else if (mode == 4) { r[0] = x[2]; r[2] = -x[0]; }
      else { r[0] = -x[1]; r[1] = x[0]; }
      for (int d = 0; d < 3; ++d) u[3 * a + d] = r[d];
    }
    double fmax = 0;
    for (int i = 0; i < 24; ++i) {
      double f = 0;
      for (int j = 0; j < 24; ++j) f += K[i * 24 + j] * u[j];
      fmax = std::max(fmax, std::abs(f));
    }
    EXPECT_LT(fmax, 1e-4 * steel.young * 1e-6) << "mode " << mode;
  }
}

TEST(Hex8, ConsistentMassIsTotalMassAndSymmetric) {
  double K[576], M[576];
  const double cube[8][3] = {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}, {0, 0, 4}, {2, 0, 4}, {2, 3, 4}, {0, 3, 4}};
  hex8StiffnessMass(cube, steel, K, M);
  for (int d = 0; d < 3; ++d) {
    double m = 0;
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) m += M[(3 * a + d) * 24 + 3 * b + d];
    EXPECT_NEAR(m, steel.density * 24, 1e-9 * steel.density * 24);
  }
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j) {
      EXPECT_NEAR(K[i * 24 + j], K[j * 24 + i], 1e-6 * std::abs(K[i * 24 + i]));
      EXPECT_NEAR(M[i * 24 + j], M[j * 24 + i], 1e-12 * M[i * 24 + i]);
    }
}

TEST(Hex8, UniaxialStressOnCubeMatchesHooke) {
  // Unit cube, nu = 0, stretch u_x = eps * x: reaction on the x = 1 face is E * eps * area.
  double K[576], M[576];
  const double cube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const Material mat{1000, 1e9, 0.0};
  hex8StiffnessMass(cube, mat, K, M);
  const double eps = 1e-3;
  double u[24] = {};
  for (int a = 0; a < 8; ++a) u[3 * a] = eps * cube[a][0];
  double fx = 0;
  for (int a : {1, 2, 5, 6})
    for (int j = 0; j < 24; ++j) fx += K[(3 * a) * 24 + j] * u[j];
  EXPECT_NEAR(fx, mat.young * eps * 1.0, 1e-9 * mat.young * eps);
}

TEST(Hex8, InvertedElementIsAnError) {
  double K[576], M[576];
  double bad[8][3];
  for (int a = 0; a < 8; ++a)
    for (int d = 0; d < 3; ++d) bad[a][d] = X[a][d];
  std::swap(bad[1], bad[3]);
  std::swap(bad[5], bad[7]);
  EXPECT_THROW(hex8StiffnessMass(bad, steel, K, M), Error);
}

TEST(Mesh, BoxNodeSets) {
  const Mesh m = makeBoxMesh({0, 0, 0}, {1, 2, 3}, {4, 2, 3});
  EXPECT_EQ(m.numNodes(), 5 * 3 * 4);
  EXPECT_EQ(m.hexes.size(), 4u * 2 * 3);
  EXPECT_EQ(m.nodeSet("x+", "test").size(), 3u * 4);
  EXPECT_EQ(m.nodeSet("z-", "test").size(), 5u * 3);
  for (int n : m.nodeSet("x+", "test")) EXPECT_DOUBLE_EQ(m.coords[n][0], 1.0);
  EXPECT_THROW(m.nodeSet("tip", "test"), Error);
  // unions: disjoint faces, and faces sharing an edge of 4 nodes
  EXPECT_EQ(m.nodeSet("x+, x-", "test").size(), 2u * 12);
  EXPECT_EQ(m.nodeSet("x+,y-", "test").size(), 12u + 20u - 4u);  // 5 x 4 nodes on y-, 4 on the shared edge
  EXPECT_THROW(m.nodeSet("x+, tip", "test"), Error);
}

TEST(FullModel, MassAndFreeFreeFrequencies) {
  // Free-free bar, nu = 0: 6 rigid-body modes, then bending and the first axial mode c/(2L).
  const Mesh mesh = makeBoxMesh({0, 0, 0}, {0.2, 0.02, 0.02}, {40, 1, 1});
  const Material mat{8000, 2e11, 0.0};
  FullModel full = assembleHexModel("bar", mesh, mat, {}, Teuchos::DefaultComm<int>::getComm());
  EXPECT_NEAR(rigidMass(full, 0), 8000 * 0.2 * 4e-4, 1e-9);
  const ReducedModel r = unreducedModel(full);
  const auto f = denseFrequencies(r.K, r.M, r.size);
  for (int i = 0; i < 6; ++i) EXPECT_LT(f[i], 1.0) << "rigid mode " << i << " at " << f[i] << " Hz";
  // The first axial mode of a free-free bar: c / (2 L) = 12500 Hz; FE with 40 elements within 0.5 %.
  bool found = false;
  for (double x : f) found = found || std::abs(x - 12500.0) < 0.005 * 12500.0;
  EXPECT_TRUE(found);
}

TEST(Mesh, RingSegment) {
  // The chapter-4 ring: radii 0.15..0.18 m, 90 degrees, 0.1 m wide.
  const Mesh m = makeRingSegmentMesh({0.2, 0, 0}, 0.15, 0.03, {135, 225}, {-0.05, 0.05}, {2, 12, 3});
  EXPECT_EQ(m.numNodes(), 3 * 13 * 4);
  EXPECT_EQ(m.hexes.size(), 2u * 12 * 3);
  EXPECT_EQ(m.nodeSet("end-, end+", "test").size(), 2u * 3 * 4);
  const NodeGrid& g = m.nodeGrids.at("outer");
  ASSERT_EQ(g.nu * g.nv, static_cast<int>(g.nodes.size()));
  for (int n : g.nodes) {
    const double dx = m.coords[n][0] - 0.2, dy = m.coords[n][1];
    EXPECT_NEAR(std::hypot(dx, dy), 0.18, 1e-14);
  }
  // Every hexahedron is right-handed (assembly would refuse one that is not), and the assembled
  // mass is rho times the volume of the ring, within the error of its faceted arcs (12 facets).
  const Material mat{7800, 2.1e11, 0.3};
  const FullModel full = assembleHexModel("ring", m, mat, {}, Teuchos::DefaultComm<int>::getComm());
  const double exact = 7800 * 0.5 * (0.18 * 0.18 - 0.15 * 0.15) * (M_PI / 2) * 0.1;
  EXPECT_NEAR(rigidMass(full, 0), exact, 0.01 * exact);
  EXPECT_THROW(makeRingSegmentMesh({0, 0, 0}, 0.15, 0.03, {10, 5}, {0, 1}, {1, 1, 1}), Error);
}
