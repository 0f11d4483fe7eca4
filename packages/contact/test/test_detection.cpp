// Contact detection (Epaphe_ContactDetection.hpp): any number of surfaces in one fused kernel, and
// the skipping of nodes certified out of contact, checked against projecting every node.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ContactDetection.hpp"
#include "TestSurfaces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

using namespace epaphe;

namespace {

/// The plane through `o` spanned by a and b (4 x 4 grid over [-2, 2]^2 in (a, b)), normal
/// orientation * (a x b).
std::unique_ptr<BSplineSurface> plane(const char* name, const double o[3], const double a[3], const double b[3],
                                      int orientation) {
  std::vector<double> g;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double s = -2.0 + 4.0 * i / 3.0, t = -2.0 + 4.0 * j / 3.0;
      for (int d = 0; d < 3; ++d) g.push_back(o[d] + s * a[d] + t * b[d]);
    }
  SurfaceOptions opt;
  opt.closureU = opt.closureV = Closure::Open;
  opt.orientation = orientation;
  return std::make_unique<BSplineSurface>(name, 4, 4, g, opt);
}

/// A closed cylinder of radius r about z, z in [-1, 1], normal inwards (nodes inside it).
std::unique_ptr<BSplineSurface> cylinder(double r) {
  const int nu = 24, nv = 5;
  std::vector<double> g;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double th = 2 * M_PI * i / nu;
      g.insert(g.end(), {r * std::cos(th), r * std::sin(th), -1.0 + 2.0 * j / (nv - 1)});
    }
  SurfaceOptions opt;
  opt.closureU = Closure::Periodic;
  opt.closureV = Closure::Open;
  opt.orientation = -1;
  return std::make_unique<BSplineSurface>("cylinder", nu, nv, g, opt);
}

/// Nodes 0..n-1 with DOFs 3k..3k+2 at the given reference positions.
std::vector<int> dofsOf(int n) {
  std::vector<int> d(3 * static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = static_cast<int>(i);
  return d;
}

}  // namespace

TEST(ContactDetection, CountsTheProjectionsOfEachNodeOnItsOwnSurfacesOnly) {
  // A stage's copies of a surface are each for one instance's nodes (onlyBlock): a node is projected on
  // its own copy and on the shared surfaces, and the projections counted (the step's bound, the work a
  // detection expects) are those, not every node on every surface.
  const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
  const double o1[3] = {0, 0, -1}, o2[3] = {0, 0, 1}, o3[3] = {1, 0, 0};
  auto floor = plane("floor", o1, ex, ey, 1), ceiling = plane("ceiling", o2, ex, ey, -1),
       wall = plane("wall", o3, ey, ez, -1);
  std::vector<ContactSurface> all(3);
  all[0].surface = floor.get();
  all[0].onlyBlock = 0;
  all[1].surface = ceiling.get();
  all[1].onlyBlock = 1;
  all[2].surface = wall.get();
  const std::vector<double> X = {0.1, 0.2, -0.7, 0.3, -0.1, 0.8, 0.0, -0.6, 0.05};
  ContactDetection d(dofsOf(3), X, all, {}, {0, 0, 1});
  DenseVector q("q", 9);
  d.detect(q, 0.0, true);
  EXPECT_EQ(d.lastProjected(), 3);
  EXPECT_EQ(d.lastProjections(), 2 + 2 + 2);  // each node: its block's copy and the wall (not 3 x 3)
  EXPECT_EQ(d.projectionsUnskipped(), 6);
  EXPECT_EQ(d.views().selected(1), 2);  // node 1 (block 0): the wall, 0.7 away; the ceiling, 0.2 away, is block 1's
}

TEST(ContactDetection, SelectsTheNearestOfAnyNumberOfSurfaces) {
  // Four surfaces around the nodes: floor z = -1 (normal +z), ceiling z = 1 (normal -z), wall
  // x = 1 (normal -x) and a wall y = -1 turned by 30 degrees about z (normal +y before turning).
  const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
  const double o1[3] = {0, 0, -1}, o2[3] = {0, 0, 1}, o3[3] = {1, 0, 0}, o4[3] = {0, -1, 0};
  auto floor = plane("floor", o1, ex, ey, 1), ceiling = plane("ceiling", o2, ex, ey, -1),
       wall = plane("wall", o3, ey, ez, -1), turned = plane("turned", o4, ex, ez, -1);
  std::vector<ContactSurface> all(4);
  all[0].surface = floor.get();
  all[1].surface = ceiling.get();
  all[2].surface = wall.get();
  all[3].surface = turned.get();
  all[3].phase = M_PI / 6;
  const std::vector<double> X = {0.1, 0.2,  -0.7, 0.3, -0.1, 0.8,  0.85, 0.0, 0.0,
                                 0.0, -0.6, 0.05, 0.2, 0.3,  -1.2, -0.4, 0.1, 0.3};
  const int nc = 6;
  ContactDetection together(dofsOf(nc), X, all, {});
  DenseVector q("q", 3 * nc);
  together.detect(q, 0.0, true);
  EXPECT_EQ(together.numSurfaces(), 4);
  EXPECT_EQ(together.lastProjected(), nc);
  const auto& v = together.views();
  for (int k = 0; k < nc; ++k) {
    double best = 1e300;
    int which = -1;
    for (int s = 0; s < 4; ++s) {  // each surface alone
      ContactDetection alone(dofsOf(nc), X, {all[s]}, {});
      alone.detect(q, 0.0, true);
      const double g = alone.views().gap(k);
      if (alone.views().selected(k) == 0 && g < best) {
        best = g;
        which = s;
      }
    }
    EXPECT_EQ(v.selected(k), which) << "node " << k;
    EXPECT_NEAR(v.gap(k), best, 1e-12) << "node " << k;
  }
  // by hand: node 0 is 0.3 above the floor, node 1 0.2 below the ceiling, node 2 0.15 from the
  // wall, node 4 0.2 through the floor
  EXPECT_NEAR(v.gap(0), 0.3, 1e-12);
  EXPECT_NEAR(v.gap(1), 0.2, 1e-12);
  EXPECT_NEAR(v.gap(2), 0.15, 1e-12);
  EXPECT_NEAR(v.gap(4), -0.2, 1e-12);
  EXPECT_EQ(v.selected(4), 0);
}

TEST(ContactDetection, SkippingChangesNoGapOfANodeInContactAndBoundsTheOthers) {
  // 40 nodes flying through a cylinder of radius 1 (normal inwards) and against a floor z = -1
  // tilting about x at 2 rad/s, over 400 steps: with and without skipping, every projected node's
  // gap agrees to round-off, a skipped node's bound lies below its true gap, and the set of
  // penetrating nodes is the same at every step.
  auto cyl = cylinder(1.0);
  const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, o[3] = {0, 0, -0.9};
  auto floor = plane("floor", o, ex, ey, 1);
  std::vector<ContactSurface> surfaces(2);
  surfaces[0].surface = cyl.get();
  surfaces[1].surface = floor.get();
  surfaces[1].omega = 2.0;
  surfaces[1].axis = {1.0, 0.0, 0.0};
  const int nc = 40, steps = 400;
  std::vector<double> X(3 * nc), V(3 * nc);
  for (int k = 0; k < nc; ++k) {
    const double th = 2 * M_PI * k / nc, r = 0.2 + 0.6 * ((k * 7) % 10) / 10.0;
    X[3 * k] = r * std::cos(th);
    X[3 * k + 1] = r * std::sin(th);
    X[3 * k + 2] = 0.5 * std::sin(3.0 * k);
    V[3 * k] = 0.9 * std::cos(th + 0.3 * k);  // outwards, some fast, some slow
    V[3 * k + 1] = 0.9 * std::sin(th + 0.3 * k);
    V[3 * k + 2] = -0.4 * std::cos(1.7 * k);
  }
  DetectionOptions on, off;
  off.skipDistant = false;
  ContactDetection skipping(dofsOf(nc), X, surfaces, on), every(dofsOf(nc), X, surfaces, off);
  DenseVector q("q", 3 * nc);
  const double h = 2e-3;
  long projected = 0, skippedTotal = 0, contacts = 0;
  for (int n = 1; n <= steps; ++n) {
    for (int i = 0; i < 3 * nc; ++i) q(i) = n * h * V[i];
    skipping.detect(q, n * h, n % 100 == 0);  // every 100th step: an output step
    every.detect(q, n * h, false);
    EXPECT_EQ(every.lastProjected(), nc);
    projected += skipping.lastProjected();
    const auto& a = skipping.views();
    const auto& b = every.views();
    for (int k = 0; k < nc; ++k) {
      const bool inB = b.selected(k) >= 0 && b.gap(k) < 0.0;
      contacts += inB;
      if (a.skip.skipped(k)) {
        ++skippedTotal;
        ASSERT_GE(b.selected(k), 0) << "step " << n << " node " << k;
        EXPECT_GT(a.skip.bound(k), 0.0);
        EXPECT_LE(a.skip.bound(k), b.gap(k) + 1e-12) << "step " << n << " node " << k << ": the bound is no bound";
        EXPECT_FALSE(inB);
        continue;
      }
      ASSERT_EQ(a.selected(k), b.selected(k)) << "step " << n << " node " << k;
      if (b.selected(k) < 0) continue;
      EXPECT_NEAR(a.gap(k), b.gap(k), 1e-12) << "step " << n << " node " << k;
      for (int d = 0; d < 3; ++d) EXPECT_NEAR(a.normal(k, d), b.normal(k, d), 1e-10);
    }
  }
  // the scene must exercise both: contacts and skipped projections
  EXPECT_GT(contacts, 100);
  EXPECT_GT(skippedTotal, steps * nc / 4);
  EXPECT_EQ(projected + skippedTotal, static_cast<long>(steps) * nc);
  std::printf("skipping: %ld of %d projections skipped, %ld node-steps in contact\n", skippedTotal, steps * nc,
              contacts);
}

// refine() projects the flagged nodes; a node is skipped only with room for twice the last
// correction's move of it (SkipViews::correctionMove): nearer, the correction would send it to
// refine(), a projection on its own.
TEST(ContactDetection, RefineProjectsTheFlaggedNodesAndSkipLeavesRoomForTheCorrection) {
  const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, o[3] = {0, 0, 0};
  auto floor = plane("floor", o, ex, ey, 1);
  std::vector<ContactSurface> surfaces(1);
  surfaces[0].surface = floor.get();
  const std::vector<double> X = {0, 0, 0.5, 0.5, 0, 0.8};
  ContactDetection d(dofsOf(2), X, surfaces, {});
  DenseVector q("q", 6);
  d.detect(q, 0.0, false);
  EXPECT_EQ(d.lastProjected(), 2);  // first step: nothing to skip from
  q(2) = -0.1;                      // node 0 moves down by 0.1: 0.5 - 0.1 > 0, still skipped
  d.detect(q, 1e-3, false);
  EXPECT_EQ(d.lastProjected(), 0);
  EXPECT_EQ(d.views().skip.skipped(0), 1);
  EXPECT_NEAR(d.views().skip.bound(0), 0.4, 1e-14);  // the last gap less the motion since
  EXPECT_NEAR(d.views().gap(0), 0.5, 1e-14);         // the last projection's
  d.views().skip.refine(0) = 1;
  EXPECT_EQ(d.refine(), 1);
  EXPECT_EQ(d.views().skip.skipped(0), 0);
  EXPECT_EQ(d.views().skip.skipped(1), 1);
  EXPECT_NEAR(d.views().gap(0), 0.4, 1e-14);
  d.views().skip.correctionMove(0) = 0.3;
  d.reset();  // forgets the moves with the rest
  EXPECT_EQ(d.views().skip.correctionMove(0), 0.0);
  d.detect(q, 2e-3, false);
  EXPECT_EQ(d.lastProjected(), 2);
  d.views().skip.correctionMove(0) = 0.3;  // node 0 moved 0.3 by the last correction, node 1 not
  q(2) = -0.2;                             // node 0's bound: 0.4 - 0.1 = 0.3 < 2 x 0.3: projected
  d.detect(q, 3e-3, false);
  EXPECT_EQ(d.lastProjected(), 1);
  EXPECT_EQ(d.views().skip.skipped(0), 0);
  EXPECT_EQ(d.views().skip.skipped(1), 1);
  EXPECT_NEAR(d.views().gap(0), 0.3, 1e-14);
  d.views().skip.correctionMove(0) = 0.1;  // bound 0.3 > 2 x 0.1: skipped
  d.detect(q, 4e-3, false);
  EXPECT_EQ(d.lastProjected(), 0);
  EXPECT_EQ(d.views().skip.skipped(0), 1);
  EXPECT_NEAR(d.views().skip.bound(0), 0.3, 1e-14);
}

// Warm start moved on by the foot point's rate: a node at rest inside a cylinder turning 0.3 patch
// per step (so the foot point crosses the closed seam 1.25 times in 100 steps) converges in at most
// 2 Newton iterations from the third step on (from last step's foot point alone, 3: the step's
// travel, then its quadratic remainder, then the stop), and finds the same foot point, gap and
// normal as a cold start from the nearest grid node.
TEST(ContactDetection, WarmStartFollowsATurningSurfaceAcrossItsSeam) {
  auto cyl = cylinder(1.0);
  std::vector<ContactSurface> surfaces(1);
  surfaces[0].surface = cyl.get();
  const double h = 1e-3, patch = 2 * M_PI / 24;
  surfaces[0].omega = 0.3 * patch / h;
  const std::vector<double> X = {0.95 * std::cos(0.1), 0.95 * std::sin(0.1), 0.2};
  DetectionOptions opt;
  opt.skipDistant = false;
  ContactDetection warm(dofsOf(1), X, surfaces, opt), cold(dofsOf(1), X, surfaces, opt);
  DenseVector q("q", 3);
  const std::vector<double> none = {std::nan(""), std::nan("")};
  int worst = 0, wraps = 0;
  double uLast = 0;
  for (int n = 1; n <= 100; ++n) {
    cold.setWarmStarts(none);
    warm.detect(q, n * h, false);
    cold.detect(q, n * h, false);
    const auto& a = warm.views();
    const auto& b = cold.views();
    if (n >= 3) worst = std::max(worst, a.iterations(0));
    if (n > 1 && std::fabs(a.foot(0, 0) - uLast) > 12.0) ++wraps;  // through the seam u = 0 = 24
    uLast = a.foot(0, 0);
    EXPECT_NEAR(a.foot(0, 0), b.foot(0, 0), 1e-9) << "step " << n;
    EXPECT_NEAR(a.gap(0), b.gap(0), 1e-13) << "step " << n;
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(a.normal(0, d), b.normal(0, d), 1e-12) << "step " << n;
  }
  EXPECT_EQ(wraps, 2) << "the foot point should cross the seam twice (at u = 0.08 - 0.3 n)";
  EXPECT_LE(worst, 2);
  std::printf("warm start on a turning cylinder: at most %d Newton iterations per step\n", worst);
}

// A casing out of round, rho(phi) = R - c (1 - cos 2 phi) / 2 (two lobes, slope at most c), closed
// around the z axis at five axial stations: radialTurnRate bounds its motion per radian turned by
// its slope, at least c and not above 1.5 c (its sampled maximum raised by half), whatever the
// frame; surfaces that are not radial graphs about the axis get +infinity (the radius then serves).
TEST(ContactDetection, RadialTurnRateIsTheCasingsSlope) {
  const double R = 0.3, c = 3.56e-4;
  const int nu = 120, nv = 5;
  auto casing = [&](const std::array<double, 3>& shift) {
    std::vector<double> g;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        const double phi = 2 * M_PI * i / nu, rho = R - c * (1 - std::cos(2 * phi)) / 2;
        g.insert(g.end(),
                 {shift[0] + rho * std::cos(phi), shift[1] + rho * std::sin(phi), shift[2] - 0.03 + 0.015 * j});
      }
    SurfaceOptions o;
    o.closureU = Closure::Periodic;
    o.closureV = Closure::Open;
    return BSplineSurface("casing", nu, nv, g, o);
  };
  const std::array<double, 3> z{0, 0, 1}, origin{0, 0, 0}, shift{0.5, -0.2, 1.0};
  const double rate = radialTurnRate(casing(origin), z, origin);
  EXPECT_GE(rate, c);
  EXPECT_LE(rate, 1.5 * c * 1.01);
  EXPECT_NEAR(radialTurnRate(casing(shift), z, shift), rate, 1e-9 * rate);  // about its own axis
  // about an axis it is not round about, or one it does not close around at constant z: none
  EXPECT_TRUE(std::isinf(radialTurnRate(casing(shift), z, origin)));
  EXPECT_TRUE(std::isinf(radialTurnRate(casing(origin), {1, 0, 0}, origin)));
  EXPECT_TRUE(std::isinf(radialTurnRate(test::floorPlane(), z, origin)));
}
