// What one contact step costs in Kokkos parallel regions, allocations and deep copies, counted by
// Kokkos Tools callbacks (KernelCounter), on a rigid-surface Lagrange step and a friction step.
// The budgets are the structure's: the step allocates nothing, and launches a bounded number of
// regions whatever the number of nodes. With the default serial threshold, a step of a few nodes
// launches none (its loops run on the calling thread: 2 threads are never slower than 1).
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestSurfaces.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

using namespace epaphe;

using test::floorPlane;

namespace {

constexpr int kNodes = 12, kN = 3 * kNodes;

/// 12 nodes on a 4 x 3 grid at z = 0.01, with a dense coupled flexibility (diagonal 1e-3 plus a
/// small symmetric coupling between every pair of DOFs).
struct Scene {
  BSplineSurface floor = floorPlane();
  ContactNodes nodes;
  DenseMatrix F{"F", kN, kN};
  Scene() {
    for (int k = 0; k < kNodes; ++k) {
      const int dof[3] = {3 * k, 3 * k + 1, 3 * k + 2};
      const double x[3] = {-0.6 + 0.4 * (k % 4), -0.4 + 0.4 * (k / 4), 0.01};
      nodes.add(k, 0, dof, x);
    }
    for (int i = 0; i < kN; ++i)
      for (int j = 0; j < kN; ++j) F(i, j) = i == j ? 1e-3 : 1e-5 / (1.0 + (i - j) * (i - j));
  }
  SurfaceContact make(double mu, bool coated = false) {
    ContactOptions o;
    o.set("Friction coefficient", mu);
    o.timeStep = 1e-3;
    ContactSurface s{&floor, nullptr, -1, {}, {}};
    if (coated) {  // 5 mm of coating that the pushed nodes load into its plastic range
      s.coating.thickness = 5e-3;
      s.coating.youngsModulus = 1e3;
      s.coating.yieldStress = 1.0;
      s.coating.hardeningModulus = 1e2;
      s.coating.elements[0] = s.coating.elements[1] = 8;
    }
    return SurfaceContact(nodes, {s}, {ContactBlock{0, kN}}, o, Flexibility(F));
  }
};

struct Counts {
  std::int64_t launches, allocations, deepCopies;
};

/// One step: half the nodes pushed 2e-3 through the floor and every node moved sideways.
Counts step(SurfaceContact& c, DenseVector& q, DenseVector& qn, int n) {
  for (int k = 0; k < kNodes; ++k) {
    qn(3 * k) = 1e-4 * n;
    q(3 * k) = 1e-4 * (n + 1);
    q(3 * k + 1) = 0.0;
    q(3 * k + 2) = k % 2 ? -0.012 : 0.0;
  }
  CostSplit cost;
  KernelCounter counter;
  c.correct(q, qn, cost);
  Kokkos::fence();
  return {counter.launches(), counter.allocations(), counter.deepCopies()};
}

}  // namespace

TEST(StepBudget, LagrangeAndFrictionStepsAllocateNothingAndLaunchABoundedNumberOfRegions) {
  Scene scene;
  const long saved = serialWorkNs();
  setSerialWorkNs(0);  // every loop a Kokkos kernel: count what the structure launches
  for (double mu : {0.0, 0.3}) {
    SurfaceContact c = scene.make(mu);
    DenseVector q("q", kN), qn("qn", kN);
    step(c, q, qn, 0);  // warm-up
    const Counts k = step(c, q, qn, 1);
    EXPECT_EQ(c.numActive(), kNodes / 2);
    std::printf(
        "%s step, %d of %d nodes active: %lld parallel regions, %lld allocations, %lld deep copies "
        "(friction passes %d)\n",
        mu > 0 ? "friction" : "Lagrange", c.numActive(), kNodes, static_cast<long long>(k.launches),
        static_cast<long long>(k.allocations), static_cast<long long>(k.deepCopies), c.lastFrictionPasses());
    EXPECT_EQ(k.allocations, 0) << "the step allocates";
    // Budgets (measured at the time of writing: 9 regions frictionless, 14 with one friction pass):
    // a change of structure that adds launches must say so here.
    const std::int64_t budget = mu > 0 ? 12 + 4 * c.lastFrictionPasses() : 10;
    EXPECT_LE(k.launches, budget);
  }
  {  // with an abradable coating: its branch passes and the commit, nothing allocated
    SurfaceContact c = scene.make(0.0, true);
    DenseVector q("q", kN), qn("qn", kN);
    step(c, q, qn, 0);
    const Counts k = step(c, q, qn, 1);
    const int passes = c.coating()->lastBranchPasses();
    std::printf(
        "coated Lagrange step, %d active: %lld parallel regions, %lld allocations (branch passes %d), wear "
        "%.3g m\n",
        c.numActive(), static_cast<long long>(k.launches), static_cast<long long>(k.allocations), passes,
        c.coatingViews().wear(c.detection().views().element(1)));
    EXPECT_EQ(c.numActive(), kNodes / 2);
    EXPECT_GT(c.coatingViews().wear(c.detection().views().element(1)), 0.0);  // plastic: the law ran
    EXPECT_EQ(k.allocations, 0) << "the coated step allocates";
    // per branch pass: rows, the Lagrange solve (directions, matrix), penetrations, classification; then
    // the first guess and the commit (measured: 31 regions in 4 passes)
    EXPECT_LE(k.launches, 10 + 5 * passes + 3);
  }
  setSerialWorkNs(saved);
  {  // default threshold: a 12-node step runs its loops on the calling thread
    SurfaceContact c = scene.make(0.3);
    DenseVector q("q", kN), qn("qn", kN);
    step(c, q, qn, 0);
    const Counts k = step(c, q, qn, 1);
    EXPECT_EQ(k.allocations, 0);
    EXPECT_EQ(k.launches, 0) << "a small step should run serially";
  }
}
