#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_HexElement.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

using namespace epaphe;

namespace {
// A distorted hexahedron (no face parallel to another).
const double X[8][3] = {{0, 0, 0},        {1.1, 0.1, 0},   {1.2, 0.9, 0.1}, {-0.1, 1.0, 0},
                        {0.1, -0.1, 1.0}, {1.0, 0.0, 1.2}, {1.1, 1.1, 0.9}, {0.0, 0.9, 1.1}};
const Material steel{7800, 2.1e11, 0.3};
/// The sign (-1 or 1) of node a's natural coordinate d (the element's node order, C3D8 / VTK).
int kCornerSign(int a, int d) {
  const int s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  return s[a][d];
}
/// max_i |(K u)_i| of a 24 x 24 element stiffness (row-major) and a nodal displacement
double largestForce(const double* K, const double* u) {
  double fmax = 0;
  for (int i = 0; i < 24; ++i) {
    double f = 0;
    for (int j = 0; j < 24; ++j) f += K[i * 24 + j] * u[j];
    fmax = std::max(fmax, std::abs(f));
  }
  return fmax;
}
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
      if (mode < 3)
        r[mode] = 1;
      else if (mode == 3) {
        r[1] = -x[2];
        r[2] = x[1];
      } else if (mode == 4) {
        r[0] = x[2];
        r[2] = -x[0];
      } else {
        r[0] = -x[1];
        r[1] = x[0];
      }
      for (int d = 0; d < 3; ++d) u[3 * a + d] = r[d];
    }
    EXPECT_LT(largestForce(K, u), 1e-4 * steel.young * 1e-6) << "mode " << mode;
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

namespace {
double energy(const double* K, const double* u) {
  double e = 0;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j) e += 0.5 * u[i] * K[i * 24 + j] * u[j];
  return e;
}
}  // namespace

TEST(Hex8Incompatible, RigidBodyMotionsAreStressFreeAndKIsSymmetric) {
  Material inc = steel;
  inc.formulation = HexFormulation::IncompatibleModes;
  double K[576], M[576], Mfull[576], Kfull[576];
  hex8StiffnessMass(X, inc, K, M);
  hex8StiffnessMass(X, steel, Kfull, Mfull);
  for (int i = 0; i < 576; ++i) EXPECT_EQ(M[i], Mfull[i]);  // the mass is the trilinear one
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j) EXPECT_EQ(K[i * 24 + j], K[j * 24 + i]);
  for (int mode = 0; mode < 6; ++mode) {
    double u[24];
    for (int a = 0; a < 8; ++a) {
      const double* x = X[a];
      const double r[6][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, -x[2], x[1]}, {x[2], 0, -x[0]}, {-x[1], x[0], 0}};
      for (int d = 0; d < 3; ++d) u[3 * a + d] = r[mode][d];
    }
    EXPECT_LT(largestForce(K, u), 1e-4 * steel.young * 1e-6) << "mode " << mode;
  }
}

// The patch test on a distorted element: under a linear displacement (a constant strain) the
// incompatible modes stay at rest (Taylor's det J_0 / det J scaling: int B_a dV = 0), so the nodal
// forces are the trilinear element's. Without the scaling they are not on this shape.
TEST(Hex8Incompatible, ConstantStrainPassesThePatchTest) {
  Material inc = steel;
  inc.formulation = HexFormulation::IncompatibleModes;
  double K[576], M[576], Kfull[576];
  hex8StiffnessMass(X, inc, K, M);
  hex8StiffnessMass(X, steel, Kfull, M);
  const double A[3][3] = {{1e-3, 2e-4, -3e-4}, {5e-4, -7e-4, 1e-4}, {-2e-4, 3e-4, 6e-4}};
  double u[24];
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i) u[3 * a + i] = A[i][0] * X[a][0] + A[i][1] * X[a][1] + A[i][2] * X[a][2];
  double scale = 0, diff = 0;
  for (int i = 0; i < 24; ++i) {
    double f = 0, g = 0;
    for (int j = 0; j < 24; ++j) {
      f += K[i * 24 + j] * u[j];
      g += Kfull[i * 24 + j] * u[j];
    }
    scale = std::max(scale, std::abs(g));
    diff = std::max(diff, std::abs(f - g));
  }
  EXPECT_LT(diff, 1e-10 * scale);
}

// Pure bending of a brick L x b x c (nu = 0): u_x = -kappa x z, u_z = kappa x^2 / 2 is the exact
// field, of energy E kappa^2 b L c^3 / 24. The incompatible element holds it exactly (its x^2 is the
// mode 1 - xi^2); the trilinear element adds parasitic shear and is stiffer by 1 + (L/c)^2 / 2 here.
TEST(Hex8Incompatible, PureBendingOfABrickIsExact) {
  const double L = 0.05, b = 0.01, c = 0.008, kappa = 0.3;
  double brick[8][3];
  for (int a = 0; a < 8; ++a) {
    brick[a][0] = kCornerSign(a, 0) > 0 ? L : 0;
    brick[a][1] = kCornerSign(a, 1) > 0 ? b : 0;
    brick[a][2] = kCornerSign(a, 2) * c / 2;
  }
  Material mat{1000, 1e9, 0.0};
  double u[24];
  for (int a = 0; a < 8; ++a) {
    const double x = brick[a][0], z = brick[a][2];
    u[3 * a] = -kappa * x * z;
    u[3 * a + 1] = 0;
    u[3 * a + 2] = kappa * x * x / 2;
  }
  const double exact = mat.young * kappa * kappa * b * L * c * c * c / 24;
  double K[576], M[576];
  hex8StiffnessMass(brick, mat, K, M);
  const double full = energy(K, u);
  mat.formulation = HexFormulation::IncompatibleModes;
  hex8StiffnessMass(brick, mat, K, M);
  EXPECT_NEAR(energy(K, u), exact, 1e-10 * exact);
  EXPECT_GT(full, 2 * exact);  // the locking the formulation removes: 1 + (L/c)^2 / 2 = 20.5 exact
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

TEST(Mesh, CasingIsClosedAroundTheAxisAndFollowsTheClearanceLaw) {
  // The casing of inputs/blade-flexible-casing.xml, coarser: a 5-degree cone with the 2- and
  // 6-lobe Harmonics law, 2 elements through 1 cm, 12 around, 3 along z.
  CasingGeometry g;
  g.radius = 0.3;
  g.axialPosition = 0.01;
  g.coneAngle = 5;
  g.axialRange = {-0.03, 0.03};
  g.law = ClearanceLaw::Harmonics;
  g.clearance = 5e-5;
  g.orders = {2, 6};
  g.amplitudesFirst = {1e-4, 0};
  g.amplitudesLast = {0, 1e-4};
  const int nr = 2, nt = 12, nz = 3;
  const double t = 0.01;
  const Mesh m = makeCasingMesh(g, t, {nr, nt, nz});
  // The seam is merged: nt node layers around the axis, not nt + 1; every node is used, none twice.
  EXPECT_EQ(m.numNodes(), (nr + 1) * nt * (nz + 1));
  EXPECT_EQ(m.hexes.size(), std::size_t(nr) * nt * nz);
  std::vector<int> uses(m.coords.size(), 0);
  for (const auto& h : m.hexes)
    for (int n : h) ++uses[n];
  for (int n = 0; n < m.numNodes(); ++n) EXPECT_GT(uses[n], 0) << "node " << n;
  double closest = 1e300;
  for (int a = 0; a < m.numNodes(); ++a)
    for (int b = a + 1; b < m.numNodes(); ++b)
      closest = std::min(closest, std::hypot(m.coords[a][0] - m.coords[b][0], m.coords[a][1] - m.coords[b][1],
                                             m.coords[a][2] - m.coords[b][2]));
  EXPECT_GT(closest, 1e-3);
  EXPECT_EQ(m.nodeSet("inner", "test").size(), std::size_t(nt) * (nz + 1));
  EXPECT_EQ(m.nodeSet("outer", "test").size(), std::size_t(nt) * (nz + 1));
  EXPECT_EQ(m.nodeSet("front, back", "test").size(), 2u * (nr + 1) * nt);
  // Inner nodes on the cone plus the law, written out here: gap = c - A2(z) cos 2 theta - A6(z) cos 6 theta.
  auto law = [&](double th, double z) {
    const double w = (z + 0.03) / 0.06;
    return 0.3 + (z - 0.01) * std::tan(5 * M_PI / 180) + 5e-5 - 1e-4 * (1 - w) * std::cos(2 * th) -
           1e-4 * w * std::cos(6 * th);
  };
  for (const char* face : {"inner", "outer"})
    for (int n : m.nodeSet(face, "test")) {
      const auto& x = m.coords[n];
      const double expected = law(std::atan2(x[1], x[0]), x[2]) + (face[0] == 'o' ? t : 0.0);
      EXPECT_NEAR(std::hypot(x[0], x[1]), expected, 1e-15) << face << " node " << n;
    }
  for (int n : m.nodeSet("front", "test")) EXPECT_DOUBLE_EQ(m.coords[n][2], -0.03);
  for (int n : m.nodeSet("back", "test")) EXPECT_DOUBLE_EQ(m.coords[n][2], 0.03);
  // The inner grid runs once around and repeats its first row: a B-spline through it is periodic
  // along u (the repeated row dropped), open along z, with its normal towards the axis (out of
  // the body, where a blade is).
  const NodeGrid& gi = m.nodeGrids.at("inner");
  ASSERT_EQ(gi.nu, nt + 1);
  ASSERT_EQ(gi.nv, nz + 1);
  for (int j = 0; j < gi.nv; ++j) EXPECT_EQ(gi.nodes[nt * gi.nv + j], gi.nodes[j]);
  std::set<int> distinct(gi.nodes.begin(), gi.nodes.end());
  EXPECT_EQ(distinct.size(), std::size_t(nt) * (nz + 1));
  EXPECT_EQ(m.nodeGrids.count("front") + m.nodeGrids.count("back") + m.nodeGrids.count("outer"), 3u);
  std::vector<double> pts;
  for (int n : gi.nodes) pts.insert(pts.end(), m.coords[n].begin(), m.coords[n].end());
  const BSplineSurface inner("inner", gi.nu, gi.nv, pts);
  EXPECT_TRUE(inner.periodicU());
  EXPECT_FALSE(inner.periodicV());
  EXPECT_EQ(inner.nu(), nt);
  const HostSurfaceView sv = inner.hostView();
  for (double u : {0.3, 5.5, 11.7}) {
    double S[3], Su[3], Sv[3], Suu[3], Suv[3], Svv[3], n[3];
    evaluate(sv, u, 1.5, S, Su, Sv, Suu, Suv, Svv);
    unitNormal(sv, Su, Sv, n);
    EXPECT_LT((n[0] * S[0] + n[1] * S[1]) / std::hypot(S[0], S[1]), -0.99) << "u = " << u;
  }
  // Assembled (assembly refuses a left-handed hexahedron): the mass of a cylindrical wall, within
  // the error of its 48 facets.
  CasingGeometry c;
  c.radius = 0.3;
  c.axialRange = {0.0, 0.06};
  const FullModel full =
      assembleHexModel("casing", makeCasingMesh(c, t, {1, 48, 2}), steel, {}, Teuchos::DefaultComm<int>::getComm());
  const double exact = 7800 * M_PI * (0.31 * 0.31 - 0.3 * 0.3) * 0.06;
  EXPECT_NEAR(rigidMass(full, 0), exact, 0.005 * exact);
  // Fewer than 4 elements around, or a law that crosses the axis, are refused.
  EXPECT_THROW(makeCasingMesh(g, t, {1, 3, 3}), Error);
  CasingGeometry deep = g;
  deep.clearance = -0.5;
  EXPECT_THROW(makeCasingMesh(deep, t, {1, 12, 3}), Error);
}

namespace {
/// Smallest determinant of the trilinear map's Jacobian over the 8 corners of every hexahedron
/// (the triple product of the three edges leaving each corner, in the element's own frame), over
/// the largest: a right-handed, non-degenerate mesh has it > 0 everywhere, corners included.
double smallestCornerJacobian(const Mesh& m) {
  // the three neighbours of corner a along xi, eta, zeta (VTK order), as a right-handed triple
  static const int nb[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7}, {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};
  double lo = 1e300, hi = 0;
  for (const auto& e : m.hexes)
    for (int a = 0; a < 8; ++a) {
      double d[3][3];
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) d[k][c] = m.coords[e[nb[a][k]]][c] - m.coords[e[a]][c];
      const double det = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                         d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                         d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
      lo = std::min(lo, det);
      hi = std::max(hi, det);
    }
  return lo / hi;
}
}  // namespace

TEST(Mesh, SphereVolumeConvergesJacobiansPositiveNodeSets) {
  const std::array<double, 3> c{0.1, -0.2, 0.3};
  const double R = 0.01, exact = 4.0 / 3.0 * M_PI * R * R * R;
  const Material unit{1.0, 2.1e11, 0.3};  // density 1: the rigid mass is the volume
  for (double grading : {1.0, 0.3}) {
    double previous = 1e300;
    for (int n : {4, 8, 16}) {
      const Mesh m = makeSphereMesh(c, R, {n, n, n}, grading);
      ASSERT_EQ(m.numNodes(), (n + 1) * (n + 1) * (n + 1));
      // every hexahedron right-handed at all its corners (and so the assembly accepts it)
      EXPECT_GT(smallestCornerJacobian(m), 0.0) << "n = " << n << ", grading " << grading;
      const FullModel full = assembleHexModel("ball", m, unit, {}, Teuchos::DefaultComm<int>::getComm());
      const double err = std::abs(rigidMass(full, 0) - exact) / exact;
      // bilinear faces on a sphere: the volume error is O(h^2), so it falls by about 4 per halving
      // (measured 6.5, 1.7, 0.42 % ungraded); at least 3 is asked
      EXPECT_LT(err, previous / 3.0) << "n = " << n << ", grading " << grading;
      previous = err;
      if (n == 16) {  // measured 0.42 % uniform, 0.97 % graded (its equator elements are 2.4 times larger)
        EXPECT_LT(err, grading == 1.0 ? 0.006 : 0.013) << "grading " << grading;
      }
      // the six caps: on the sphere, (n + 1)^2 nodes each, the lower one below z = -R / sqrt(3);
      // each cap's node grid has S_u x S_v pointing out of the ball
      for (const char* cap : {"x-", "x+", "y-", "y+", "z-", "z+"}) {
        const auto& set = m.nodeSet(cap, "test");
        EXPECT_EQ(set.size(), std::size_t(n + 1) * (n + 1)) << cap;
        for (int node : set)
          EXPECT_NEAR(std::hypot(m.coords[node][0] - c[0], m.coords[node][1] - c[1], m.coords[node][2] - c[2]), R,
                      1e-14)
              << cap << " node " << node;
        const NodeGrid& g = m.nodeGrids.at(cap);
        ASSERT_EQ(g.nu, n + 1);
        ASSERT_EQ(g.nv, n + 1);
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            const auto& p = m.coords[g.nodes[i * g.nv + j]];
            const auto& pu = m.coords[g.nodes[(i + 1) * g.nv + j]];
            const auto& pv = m.coords[g.nodes[i * g.nv + j + 1]];
            const double u[3] = {pu[0] - p[0], pu[1] - p[1], pu[2] - p[2]},
                         v[3] = {pv[0] - p[0], pv[1] - p[1], pv[2] - p[2]};
            const double nrm[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
            EXPECT_GT(nrm[0] * (p[0] - c[0]) + nrm[1] * (p[1] - c[1]) + nrm[2] * (p[2] - c[2]), 0.0) << cap;
          }
      }
      for (int node : m.nodeSet("z-", "test")) EXPECT_LT(m.coords[node][2] - c[2], -R / std::sqrt(3.0) + 1e-15);
      // every node of the ball is on one of the caps or strictly inside
      EXPECT_EQ(m.nodeSet("x-, x+, y-, y+, z-, z+", "test").size(), std::size_t(6 * n * n + 2));
      const auto& pole = m.nodeSet("z-pole", "test");
      ASSERT_EQ(pole.size(), 1u);
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(m.coords[pole[0]][d], c[d] + (d == 2 ? -R : 0.0), 1e-15);
    }
  }
  // Grading refines the lower pole: its first element is about g times as deep (0.32 here).
  const Mesh uniform = makeSphereMesh(c, R, {16, 16, 16}, 1.0), graded = makeSphereMesh(c, R, {16, 16, 16}, 0.3);
  const int pole = 8 + 17 * 8, above = pole + 17 * 17;
  EXPECT_LT(graded.coords[above][2] - graded.coords[pole][2],
            0.6 * (uniform.coords[above][2] - uniform.coords[pole][2]));
  // an odd count across the axis (no pole node) and a grading outside [0.02, 1] are refused
  EXPECT_THROW(makeSphereMesh(c, R, {5, 6, 6}, 1.0), Error);
  EXPECT_THROW(makeSphereMesh(c, R, {6, 6, 6}, 0.01), Error);
  EXPECT_THROW(makeSphereMesh(c, -R, {6, 6, 6}, 1.0), Error);
}
