// Reductions of the clamped steel bar: Craig-Bampton's frequencies are upper bounds of the full
// model's (Rayleigh-Ritz) that fall towards them as modes are added, Guyan is Craig-Bampton without
// modes, and the full model's frequencies do not depend on where the shift-invert shift is placed
// (the reduced model's bound, or the old -1e-4 max K_ii/M_ii): only the cost does.
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ReducedModel.hpp"

#include "TestBar.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace epaphe;

TEST(Reduction, CraigBamptonBoundsTheFullFrequenciesAndConvergesWithModes) {
  const FullModel bar = test::bar(12, true);
  const auto tip = bar.mesh.nodeSet("x+", "test");
  const auto full = fullModelFrequencies(bar, 6);
  double previous = 1e300;
  for (int modes : {0, 4, 12}) {
    CraigBamptonOptions o;
    o.modes = modes;
    const ReducedModel r = craigBampton(bar, tip, o);
    EXPECT_EQ(r.kind, modes == 0 ? ReductionKind::Guyan : ReductionKind::CraigBampton);
    const auto f = reducedFrequencies(r);
    ASSERT_GE(f.size(), full.size());
    double worst = 0;
    for (std::size_t i = 0; i < full.size(); ++i) {
      EXPECT_GE(f[i], full[i] * (1 - 1e-10)) << "mode " << i + 1 << " with " << modes << " modes";
      worst = std::max(worst, (f[i] - full[i]) / full[i]);
    }
    EXPECT_LT(worst, previous) << modes << " modes do not improve on fewer";
    previous = worst;
  }
}

TEST(Reduction, TheFullFrequenciesDoNotDependOnTheShift) {
  const FullModel bar = test::bar(12, true);
  CraigBamptonOptions o;
  o.modes = 8;
  const auto bounds = reducedFrequencies(craigBampton(bar, bar.mesh.nodeSet("x+", "test"), o));
  const auto oldShift = fullModelFrequencies(bar, 6);
  const auto boundShift = fullModelFrequencies(bar, 6, LinearSolver::Mumps, 1e-12, bounds);
  ASSERT_EQ(oldShift.size(), boundShift.size());
  for (std::size_t i = 0; i < oldShift.size(); ++i)  // Anasazi's tolerance 1e-10 on the residual
    EXPECT_NEAR(boundShift[i], oldShift[i], 1e-8 * oldShift[i]) << "mode " << i + 1;
}

// The frequency check through the reduction's own K_CC factor (the Schur complement of K, no
// second factorization) gives the full model's frequencies: the same as a factor of the whole K,
// on 1 rank and distributed, for Craig-Bampton and Guyan. A free body (K singular) gets none, so
// that the caller falls back to a shifted factor.
TEST(Reduction, TheFrequencyCheckThroughTheCondensationIsTheFullModels) {
  const FullModel bar = test::bar(12, true);
  const auto full = fullModelFrequencies(bar, 8);
  for (int modes : {0, 6}) {
    CraigBamptonOptions o;
    o.modes = modes;
    o.checkFrequencies = 8;
    ReductionReport rep;
    const ReducedModel r = craigBampton(bar, bar.mesh.nodeSet("x+", "test"), o, &rep);
    ASSERT_EQ(r.fullFrequencies.size(), full.size()) << modes << " modes";
    for (std::size_t i = 0; i < full.size(); ++i)  // tolerances 1e-6 (the check) and 1e-10: ~1e-11 on f
      EXPECT_NEAR(r.fullFrequencies[i], full[i], 1e-9 * full[i]) << "mode " << i + 1 << ", " << modes << " modes";
    EXPECT_GT(rep.checkSeconds, 0.0);
  }
  const FullModel free = test::bar(12, false);
  CraigBamptonOptions o;
  o.modes = 4;
  o.checkFrequencies = 8;
  EXPECT_TRUE(craigBampton(free, free.mesh.nodeSet("x+", "test"), o).fullFrequencies.empty());
}
