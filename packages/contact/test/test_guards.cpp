// Run guards (Epaphe_ContactGuards.hpp) on point masses against the plane z = 0 over [-2, 2]^2, a
// 4 x 4 grid: its smallest patch is L = 4/3, and every gap is the node's z.
#include "Epaphe_ContactGuards.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestSurfaces.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

using namespace epaphe;

namespace {

constexpr double kL = 4.0 / 3.0;  // the floor's grid spacing
constexpr double kH = 1e-3;       // time step (s)

struct Scene {
  BSplineSurface floor = test::floorPlane();
  std::vector<double> z;  // initial heights of the nodes
  double x0 = -1.0;       // x of the first node (the others 0.5 apart)
  explicit Scene(std::vector<double> heights, double first = -1.0) : z(std::move(heights)), x0(first) {}
  SurfaceContact make() {
    ContactNodes nodes;
    for (std::size_t k = 0; k < z.size(); ++k) {
      const int dof[3] = {int(3 * k), int(3 * k + 1), int(3 * k + 2)};
      const double x[3] = {x0 + 0.5 * double(k), 0.1, z[k]};
      nodes.add(int(10 + k), 0, dof, x);
    }
    DenseVector d("F", 3 * z.size());
    Kokkos::deep_copy(d, 2e-4);
    ContactOptions o;
    o.timeStep = kH;
    return SurfaceContact(nodes, {ContactSurface{&floor, nullptr, -1, {}, {}}}, {ContactBlock{0, int(3 * z.size())}}, o,
                          Flexibility::diagonal(d));
  }
};

GuardOptions gentle(double ramp) {
  GuardOptions o;
  o.initialPenetration = InitialPenetration::ResolveGently;
  o.rampTime = ramp;
  return o;
}

}  // namespace

TEST(ContactGuards, TheBoundIsTheSmallestPatch) {
  Scene s({0.5});
  const SurfaceContact c = s.make();
  EXPECT_NEAR(ContactGuards::motionBound(c), kL, 1e-14);
  EXPECT_EQ(c.detection().smallestPatchSurface(), 0);
}

TEST(ContactGuards, AnInitialSpeedThatCrossesAPatchPerStepIsRefused) {
  Scene s({0.5});
  const SurfaceContact c = s.make();
  const ContactGuards g({}, {"Bar"}, "deck.xml");
  std::vector<std::string> warnings;
  EXPECT_NO_THROW(g.checkInitialVelocities(c, {0.99 * kL / kH}, kH, warnings));
  try {
    g.checkInitialVelocities(c, {1.01 * kL / kH}, kH, warnings);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("deck.xml: body 'Bar'"), std::string::npos) << m;
    EXPECT_NE(m.find("tunnelling"), std::string::npos) << m;
    EXPECT_NE(m.find("'floor'"), std::string::npos) << m;
  }
  EXPECT_TRUE(warnings.empty());
  GuardOptions allow;
  allow.allowLargeMotion = true;
  const ContactGuards a(allow, {"Bar"}, "deck.xml");
  EXPECT_NO_THROW(a.checkInitialVelocities(c, {1e3 * kL / kH}, kH, warnings));
  EXPECT_EQ(warnings.size(), 1u);
}

TEST(ContactGuards, AStepMovingANodeFartherThanAPatchIsReported) {
  Scene s({0.5, 0.5, 0.5});
  const SurfaceContact c = s.make();
  const ContactGuards g({}, {"Bar"}, "deck.xml");
  DenseVector q0("q0", 9), q1("q1", 9);
  q1(4) = 0.9 * kL;  // node 1, along y
  EXPECT_EQ(g.checkStep(c, q1, q0, 0.0, kH), "");
  q1(7) = -0.8 * kL;  // node 2: |(0, 0.8, 0.8)| L > L
  q1(8) = 0.8 * kL;
  const std::string m = g.checkStep(c, q1, q0, 0.0, kH);
  EXPECT_NE(m.find("contact node 12 of body 'Bar' moved"), std::string::npos) << m;
  EXPECT_NE(m.find("tunnelling"), std::string::npos) << m;
  EXPECT_NE(m.find("Use a smaller 'Time->Time step'"), std::string::npos) << m;
}

// A node that moves more than a patch while pressed on the surface is not tunnelling: the message
// says so and advises no step (the run's diagnosis tells why its motion diverges).
TEST(ContactGuards, AFastNodeInContactIsNotCalledTunnelling) {
  Scene s({0.5, 0.5, -0.01});  // node 12 inside the floor
  SurfaceContact c = s.make();
  const ContactGuards g({}, {"Bar"}, "deck.xml");
  DenseVector q0("q0", 9), q1("q1", 9);
  CostSplit cost;
  c.correct(q0, cost);
  ASSERT_GT(c.force()(2), 0.0);
  q1(7) = -0.8 * kL;  // node 12: |(0, 0.8, 0.8)| L > L
  q1(8) = 0.8 * kL;
  const std::string m = g.checkStep(c, q1, q0, 0.0, kH);
  EXPECT_NE(m.find("contact node 12 of body 'Bar' moved"), std::string::npos) << m;
  EXPECT_NE(m.find("while pressed on surface 'floor'"), std::string::npos) << m;
  EXPECT_EQ(m.find("tunnelling"), std::string::npos) << m;
  EXPECT_EQ(m.find("Time step"), std::string::npos) << m;
}

TEST(ContactGuards, BodiesThatStartInsideASurfaceAreRefusedWithTheDeepestNode) {
  Scene s({0.2, -0.01, 0.0, -0.03, 1e-9 * kL});
  SurfaceContact c = s.make();
  const ContactGuards g({}, {"Bar"}, "deck.xml");
  DenseVector q0("q0", 15);
  CostSplit cost;
  try {
    g.checkInitialPenetration(c, q0, kH, cost);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("2 contact node(s) lie inside a surface"), std::string::npos) << m;  // a touch is not one
    EXPECT_NE(m.find("node 13 of body 'Bar' at (0.5, 0.1, -0.03) m, is 0.03 m inside surface 'floor'"),
              std::string::npos)
        << m;
  }
  Scene t({0.2, 0.0, -1e-7 * kL});  // touching, and within the tolerance 1e-6 L
  SurfaceContact ct = t.make();
  const PenetrationReport r = g.checkInitialPenetration(ct, DenseVector("q0", 9), kH, cost);
  EXPECT_EQ(r.count, 0);
  EXPECT_EQ(r.facing, 3);
  Scene far({-0.5, 0.2}, 1000.0);  // placed in mm in a deck in m: over no surface, so no penetration either
  SurfaceContact cf = far.make();
  const PenetrationReport rf = g.checkInitialPenetration(cf, DenseVector("q0", 6), kH, cost);
  EXPECT_EQ(rf.facing, 0);
  EXPECT_EQ(rf.count, 0);
}

TEST(ContactGuards, APenetrationResolvedGentlyIsPushedOutAlongTheRamp) {
  // A node 1 cm inside the floor, held still (q* = q at each step): after the Lagrange correction
  // at time t its effective gap z + 0.01 (1 - t/T) is closed, so z(t) = -0.01 (1 - t/T) exactly,
  // and z = 0 from t = T on. The other node, above the floor, is untouched.
  const double T = 10 * kH;
  Scene s({-0.01, 0.3});
  SurfaceContact c = s.make();
  const ContactGuards g(gentle(T), {"Bar"}, "deck.xml");
  DenseVector q("q", 6);
  CostSplit cost;
  const PenetrationReport r = g.checkInitialPenetration(c, q, kH, cost);
  ASSERT_EQ(r.count, 1);
  EXPECT_NEAR(r.deepest, 0.01, 1e-12);
  for (int n = 1; n <= 15; ++n) {
    const double t = n * kH;
    c.setTime(t);
    c.correct(q, cost);
    Kokkos::fence();
    const double expected = t < T ? -0.01 * (1 - t / T) : 0.0;
    EXPECT_NEAR(-0.01 + q(2), expected, 1e-12) << "step " << n;
    EXPECT_EQ(q(5), 0.0);
  }
  // the default ramp is 100 steps
  Scene d({-0.01});
  SurfaceContact cd = d.make();
  const ContactGuards g0(gentle(0.0), {"Bar"}, "deck.xml");
  DenseVector q1("q1", 3);
  g0.checkInitialPenetration(cd, q1, kH, cost);
  cd.setTime(50 * kH);
  cd.correct(q1, cost);
  Kokkos::fence();
  EXPECT_NEAR(-0.01 + q1(2), -0.005, 1e-12);
}

TEST(ContactGuards, TheDeckKeysAreDeclaredAndRead) {
  const auto pl = ContactDetection::getValidParameters();
  Teuchos::ParameterList deck = *pl;
  deck.set("Initial penetration", std::string("Resolve gently"));
  deck.set("Penetration ramp time", 2e-3);
  deck.set("Allow large motion per step", true);
  const GuardOptions o = guardOptions(deck);
  EXPECT_EQ(o.initialPenetration, InitialPenetration::ResolveGently);
  EXPECT_EQ(o.rampTime, 2e-3);
  EXPECT_TRUE(o.allowLargeMotion);
  EXPECT_THROW(ContactGuards(gentle(-1.0), {}, "deck.xml"), Error);
}
