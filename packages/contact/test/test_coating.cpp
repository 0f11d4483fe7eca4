// The abradable coating (Epaphe_AbradableCoating.hpp, Epaphe_CoatingContact.hpp) on one point mass
// over the coated plane z = 0: 4 x 4 elements of 1 m^2 each on [-2, 2]^2, t = 1 cm, E = 1 MPa,
// sigma_Y = 1 kPa, H = 0.2 MPa, so k_e = A E / t = 1e8 N/m, the yield force 1 kN at delta_y = 10 um,
// and the plastic slope k_t = A E H / (t (E + H)). Expected values are the closed forms of linear
// isotropic hardening in 1-D, written here independently of the code's return mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_SurfaceContact.hpp"
#include "TestSurfaces.hpp"

using namespace epaphe;

namespace {

constexpr double kT = 0.01, kE = 1e6, kSY = 1e3, kH = 2e5, kArea = 1.0;
constexpr double kKe = kArea * kE / kT;                     // elastic slope (N/m)
constexpr double kKt = kArea * kE * kH / (kT * (kE + kH));  // plastic slope: E_t = E H / (E + H)
constexpr double kDy = kSY * kT / kE;                       // yield compression

CoatingMaterial material(double t = kT, double sY = kSY) {
  CoatingMaterial m;
  m.thickness = t;
  m.youngsModulus = kE;
  m.yieldStress = sY;
  m.hardeningModulus = kH;
  m.elements[0] = m.elements[1] = 4;
  return m;
}

/// One point mass (flexibility f per DOF) over the coated floor at (0.3, 0.3): element (2, 2).
struct Node {
  BSplineSurface floor = test::floorPlane();
  SurfaceContact make(const std::string& method, double f, const CoatingMaterial& m, double kp = 1e12) {
    ContactNodes nodes;
    const int dof[3] = {0, 1, 2};
    const double x[3] = {0.3, 0.3, 0.0};
    nodes.add(0, 0, dof, x);
    ContactSurface s{&floor, nullptr, -1, {}, {}};
    s.coating = m;
    ContactOptions o;
    o.set("Method", method);
    o.set("Penalty stiffness", kp);
    o.timeStep = 1e-3;
    DenseVector d("F", 3);
    Kokkos::deep_copy(d, f);
    return SurfaceContact(nodes, {s}, {ContactBlock{0, 3}}, o, Flexibility::diagonal(d));
  }
};

/// The node at height z (the coating's unworn front is at z = t): corrects and returns the force.
double pressTo(SurfaceContact& c, double z, double* corrected = nullptr) {
  DenseVector q("q", 3);
  q(2) = z;
  CostSplit cost;
  c.correct(q, cost);
  if (corrected) *corrected = q(2);
  return c.force()(0);
}

double wear(const SurfaceContact& c) {
  const CoatingViews& v = c.coatingViews();
  return v.wear(v.grid(0, 2) + 2 * 4 + 2);
}

}  // namespace

TEST(Coating, TheElementsTileTheSurfaceAndTheirAreasSumToIt) {
  Node n;
  SurfaceContact c = n.make("Penalty", 1e-9, material());
  const CoatingViews& v = c.coatingViews();
  ASSERT_EQ(v.numElements(), 16);
  for (int e = 0; e < 16; ++e) EXPECT_NEAR(v.area(e), 1.0, 1e-12) << e;
  pressTo(c, 1.0);  // far above: the node's element is found anyway
  EXPECT_EQ(c.detection().views().element(0), 10);
  EXPECT_NEAR(c.gap()(0), 1.0 - kT, 1e-12);  // the gap is to the coating's front
}

// Penalty computes the element's force at the imposed (predicted) compression: the force against
// compression is the analytic elastic-plastic curve, loading, unloading and reloading.
TEST(Coating, PenaltyForceFollowsTheElasticPlasticCurveWithHardening) {
  Node n;
  SurfaceContact c = n.make("Penalty", 1e-12, material());
  auto force = [&](double delta) { return pressTo(c, kT - delta); };
  // elastic loading: slope k_e up to the yield point
  EXPECT_NEAR(force(0.5 * kDy), kKe * 0.5 * kDy, 1e-9 * kSY);
  EXPECT_NEAR(force(kDy), kArea * kSY, 1e-9 * kSY);  // the yield point
  EXPECT_EQ(wear(c), 0.0);
  // plastic loading: slope k_t
  const double d1 = 3 * kDy, d2 = 5 * kDy;
  const double f1 = force(d1), f2 = force(d2);
  EXPECT_NEAR(f1, kArea * kSY + kKt * (d1 - kDy), 1e-9 * f1);
  EXPECT_NEAR(f2, kArea * kSY + kKt * (d2 - kDy), 1e-9 * f2);
  EXPECT_NEAR((f2 - f1) / (d2 - d1), kKt, 1e-6 * kKt);
  // residual shortening after d2: the elastic part f2 / k_e comes back
  const double residual = d2 - f2 / kKe;
  EXPECT_NEAR(wear(c), residual, 1e-12 * kT);
  // unloading: slope k_e from (d2, f2), zero force at the residual shortening and below
  const double d3 = 0.5 * (d2 + residual);
  EXPECT_NEAR(force(d3), f2 - kKe * (d2 - d3), 1e-9 * f2);
  EXPECT_EQ(force(0.9 * residual), 0.0);
  EXPECT_NEAR(wear(c), residual, 1e-12 * kT);  // unloading leaves the wear
  // reloading: elastic up to the hardened yield force f2, then on the plastic line again
  EXPECT_NEAR(force(d2 - 0.1 * f2 / kKe), 0.9 * f2, 1e-9 * f2);
  const double d4 = 8 * kDy;
  EXPECT_NEAR(force(d4), kArea * kSY + kKt * (d4 - kDy), 1e-9 * kSY);
  EXPECT_NEAR(wear(c), d4 - force(d4) / kKe, 1e-12 * kT);
  // the plastic dissipation: the yield force integrated over the shortening, from 0 to u_p
  const double up = wear(c), expected = kArea * (kSY * up + kH * up * up / (2 * kT));
  EXPECT_NEAR(c.coating()->plasticDissipation(), expected, 1e-9 * expected);
}

// Lagrange solves the node's correction with the element's law in it: after the correction, the
// force equals the law's force at the node's final compression, on each branch, and a node driven
// through the whole thickness ends on the rigid surface behind it.
TEST(Coating, LagrangeForceIsTheLawsForceAtTheCorrectedCompression) {
  const double f = 1e-7;  // the node's flexibility (m/N): a correction of 0.1 um per N
  for (const double depth : {0.5 * kDy, 2e-4, 3e-3, 5e-2}) {
    Node n;
    SurfaceContact c = n.make("Lagrange", f, material());
    double z = 0.0;
    const double lambda = pressTo(c, kT - depth, &z);
    const double delta = kT - z;                                     // the element's compression after the correction
    EXPECT_NEAR(z - (kT - depth), f * lambda, 1e-12 * kT) << depth;  // the correction moved it by F lambda
    if (delta < kT * (1 - 1e-12)) {
      const double law = delta <= kDy ? kKe * delta : kArea * kSY + kKt * (delta - kDy);
      EXPECT_NEAR(lambda, law, 1e-9 * law) << "depth " << depth;
    } else {  // crushed: on the surface, the force at least the crushed element's
      EXPECT_NEAR(z, 0.0, 1e-12) << depth;
      EXPECT_GE(lambda, kArea * kSY + kKt * (kT - kDy));
    }
    // the residual shortening: the compression less its elastic part (element force / k_e)
    const double element = delta < kT * (1 - 1e-12) ? lambda : kArea * kSY + kKt * (kT - kDy);
    EXPECT_NEAR(wear(c), std::max(0.0, std::min(delta, kT) - element / kKe), 1e-9 * kT) << depth;
  }
}

// Thickness 0: the rigid law exactly (same force, same correction, bit for bit).
TEST(Coating, ZeroThicknessIsTheRigidSurface) {
  for (const std::string m : {"Lagrange", "Penalty"}) {
    Node a, b;
    SurfaceContact coated = a.make(m, 1e-7, material(0.0), 1e8);
    SurfaceContact rigid = b.make(m, 1e-7, CoatingMaterial{}, 1e8);
    ASSERT_EQ(rigid.coating(), nullptr);
    for (const double z : {1e-3, -1e-5, -2e-4, 5e-5}) {
      double zc = 0, zr = 0;
      EXPECT_EQ(pressTo(coated, z, &zc), pressTo(rigid, z, &zr)) << z;
      EXPECT_EQ(zc, zr) << z;
    }
    EXPECT_EQ(wear(coated), 0.0);
  }
}

// An infinite yield stress: the elastic coating, i.e. the penalty law of stiffness k_e against the
// coating's front.
TEST(Coating, InfiniteYieldIsAnElasticSpringOfTheElementsStiffness) {
  Node a;
  SurfaceContact coated = a.make("Penalty", 1e-9, material(kT, 1e300));
  for (const double delta : {1e-5, 1e-3, 5e-3, 1e-3, 2e-6}) {
    const double force = pressTo(coated, kT - delta);
    EXPECT_NEAR(force, kKe * delta, 1e-12 * kKe * delta) << delta;
  }
  EXPECT_EQ(wear(coated), 0.0);
  EXPECT_EQ(coated.coating()->plasticDissipation(), 0.0);
  EXPECT_NEAR(coated.coating()->elasticEnergy(), 0.5 * kKe * 2e-6 * 2e-6, 1e-9 * kKe * 4e-12);
}
