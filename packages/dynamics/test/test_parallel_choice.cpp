// The parallel/serial choice of the explicit step's loops (Epaphe_ParallelChooser.hpp), on a clock of
// the test's own: a step's cost in each mode is given, the choice must find the cheaper one, hold it,
// and probe again; and the chunked sums of Epaphe_Parallel.hpp give the same bits serial and parallel.
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_ParallelChooser.hpp"

#include <gtest/gtest.h>

#include <sched.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>

namespace epaphe {
namespace {

/// Runs `steps` steps on a clock where a step costs `parallel(n)` or `serial(n)` seconds (n: the
/// step's index); returns the total time.
double runSteps(ParallelChoice& c, long steps, const std::function<double(long)>& parallel,
                const std::function<double(long)>& serial) {
  double now = 0;
  for (long n = 0; n < steps; ++n) {
    now += c.stepStarts(now) ? parallel(n) : serial(n);
    c.stepEnds(now);
  }
  return now;
}

/// Blocks of 32 timed steps whatever they last (the tests below count steps), the default pairs (15),
/// hold 20x the probe.
ParallelChoice::Options bySteps() {
  ParallelChoice::Options o;
  o.blockSteps = 32;
  o.blockSeconds = 0;
  return o;
}

TEST(ParallelChoice, RunsTheFasterModeAndProbesAgain) {
  const ParallelChoice::Options o = bySteps();
  for (const bool parallelFaster : {true, false}) {
    ParallelChoice c(o);
    const double fast = 1e-5, slow = 1.7e-5;
    const auto par = [&](long) { return parallelFaster ? fast : slow; };
    const auto ser = [&](long) { return parallelFaster ? slow : fast; };
    const double total = runSteps(c, 100000, par, ser);
    EXPECT_GE(c.probes(), 2) << "a probe after each hold";
    EXPECT_EQ(c.parallelChoices(), parallelFaster ? c.probes() : 0);
    EXPECT_NEAR(c.lastRatio(), parallelFaster ? fast / slow : slow / fast, 1e-9);
    // the slower mode runs in half of each probe: 15 x 33 steps of every 15 x 33 + 20 x (the probe's
    // 2 x 15 x 33 steps)
    const double slowShare =
        parallelFaster ? 1.0 - double(c.parallelSteps()) / c.steps() : double(c.parallelSteps()) / c.steps();
    EXPECT_LT(slowShare, 0.03) << "slow steps " << slowShare;
    EXPECT_LT(total, 1.03 * 100000 * fast + 0.03 * 100000 * (slow - fast));
  }
}

TEST(ParallelChoice, FollowsAChangeOfLoad) {
  // the parallel loops pay for the first half of the run and cost twice the serial ones after it (another
  // process takes a core): the probes after the change choose the calling thread
  ParallelChoice c(bySteps());
  const long steps = 200000;
  const auto par = [&](long n) { return n < steps / 2 ? 1e-5 : 4e-5; };
  const auto ser = [&](long) { return 2e-5; };
  double now = runSteps(c, steps / 2, par, ser);  // the clock goes on from there
  EXPECT_EQ(c.parallelChoices(), c.probes());
  const int before = c.probes();
  const long parallelBefore = c.parallelSteps();
  for (long n = steps / 2; n < steps; ++n) {
    now += c.stepStarts(now) ? par(n) : ser(n);
    c.stepEnds(now);
  }
  EXPECT_GT(c.probes(), before);
  EXPECT_NEAR(c.lastRatio(), 2.0, 1e-6);
  EXPECT_LT(double(c.parallelSteps() - parallelBefore) / (steps / 2), 0.1);
}

/// The first probe's verdict when step `slowStep` costs 200 times its mode's cost.
bool firstVerdict(double parallelCost, double serialCost, long slowStep) {
  ParallelChoice c(bySteps());
  double now = 0;
  for (long n = 0; c.probes() == 0; ++n) {
    now += (c.stepStarts(now) ? parallelCost : serialCost) * (n == slowStep ? 200 : 1);
    c.stepEnds(now);
  }
  return c.parallelChoices() == 1;
}

TEST(ParallelChoice, OneSlowBlockDoesNotDecide) {
  // a probe's blocks: steps 0-32 parallel (0 not timed), 33-65 serial (33 not timed)... One step slowed
  // 200x (a checkpoint, an interrupt) makes its pair's ratio point the wrong way; the median of the
  // pairs' ratios does not follow it
  EXPECT_TRUE(firstVerdict(1e-5, 2e-5, -1));
  EXPECT_TRUE(firstVerdict(1e-5, 2e-5, 1));  // in the first parallel block
  EXPECT_FALSE(firstVerdict(2e-5, 1e-5, -1));
  EXPECT_FALSE(firstVerdict(2e-5, 1e-5, 40));  // in the first serial block
}

TEST(ParallelChoice, BlocksLastLongEnoughToTime) {
  // the default blocks: a first step not timed, then at least 1 step and 2 ms. Steps of 10 us (a
  // blade): 200 timed steps a block; steps of 20 ms: 1; the verdict compares the time per step either way
  const ParallelChoice::Options o;
  for (const double step : {1e-5, 2e-2}) {
    ParallelChoice c;
    double now = 0;
    long n = 0;
    for (; c.probes() == 0; ++n) {
      now += c.stepStarts(now) ? step : 1.5 * step;
      c.stepEnds(now);
    }
    EXPECT_EQ(c.parallelChoices(), 1);
    EXPECT_NEAR(c.lastRatio(), 1 / 1.5, 1e-6);
    auto timed = [&](double cost) { return std::max(1L, static_cast<long>(std::ceil(o.blockSeconds / cost - 1e-9))); };
    const long expected = o.pairs * (2 + timed(step) + timed(1.5 * step));
    EXPECT_GE(n, expected - o.pairs) << "step " << step;  // (a sum of step costs may reach 2 ms a step early...)
    EXPECT_LE(n, expected + o.pairs) << "step " << step;  // (...or late)
  }
}

TEST(ParallelChoice, TheFirstStepOfABlockIsNotTimed) {
  // a change of mode costs the step after it (the team wakes, data moves between the cores' caches):
  // 20x a parallel step into the team, 5x a serial one out of it. Blocks of 4 steps timed whole
  // would find the team at (20 + 3) / 4 = 5.75 parallel steps a step against (5 + 3 x 1.3) / 4 = 2.2,
  // and choose the calling thread; without their first steps the blocks compare 1 to 1.3
  ParallelChoice::Options o = bySteps();
  o.blockSteps = 3;
  ParallelChoice c(o);
  const double par = 1e-5, ser = 1.3e-5;
  double now = 0;
  bool last = false;
  for (long n = 0; c.probes() == 0; ++n) {
    const bool p = c.stepStarts(now);
    now += p ? (p != last && n > 0 ? 20 * par : par) : (p != last ? 5 * par : ser);
    last = p;
    c.stepEnds(now);
  }
  EXPECT_EQ(c.parallelChoices(), 1);
  EXPECT_NEAR(c.lastRatio(), par / ser, 1e-9);
  EXPECT_EQ(c.steps(), 2 * o.pairs * (1 + o.blockSteps));
}

TEST(ParallelChoice, CrowdedCoresSkipTheProbe) {
  // the team's steps cost 3 times the calling thread's (another process holds a core). With `crowded`
  // saying so, no step runs on the team; once the cores are free again, the next look lets a probe run
  // and choose the team, which is then faster
  bool taken = true;
  int looks = 0;
  ParallelChoice::Options o = bySteps();
  o.blockSeconds = 1e-3;  // (a look every 2 x 15 pairs x 1 ms)
  ParallelChoice c(o, [&] {
    ++looks;
    return taken;
  });
  const long steps = 20000;
  const auto par = [&](long) { return taken ? 3e-5 : 1e-5; };
  const auto ser = [&](long) { return 2e-5; };
  double now = runSteps(c, steps, par, ser);
  EXPECT_EQ(c.parallelSteps(), 0);
  EXPECT_EQ(c.probes(), 0);
  EXPECT_GT(c.crowdedSkips(), 10);
  EXPECT_EQ(looks, 3 * c.crowdedSkips()) << "three looks before each skipped probe";
  EXPECT_NEAR(now, steps * 2e-5, 1e-12);
  taken = false;
  for (long n = 0; n < steps; ++n) {
    now += c.stepStarts(now) ? par(n) : ser(n);
    c.stepEnds(now);
  }
  EXPECT_GE(c.probes(), 1);
  EXPECT_EQ(c.parallelChoices(), c.probes());
  EXPECT_GT(c.parallelSteps(), steps / 2);
}

TEST(ParallelChoice, FreeCoresLetTheProbeDecide) {
  // `crowded` saying no changes nothing: the same verdicts and counts as without it
  for (const bool parallelFaster : {true, false}) {
    ParallelChoice with(bySteps(), [] { return false; }), without(bySteps());
    const auto par = [&](long) { return parallelFaster ? 1e-5 : 2e-5; };
    const auto ser = [&](long) { return parallelFaster ? 2e-5 : 1e-5; };
    EXPECT_EQ(runSteps(with, 50000, par, ser), runSteps(without, 50000, par, ser));
    EXPECT_EQ(with.parallelSteps(), without.parallelSteps());
    EXPECT_EQ(with.probes(), without.probes());
    EXPECT_EQ(with.crowdedSkips(), 0);
  }
}

TEST(ParallelChooser, LooksAtTheMachine) {
  // this process's own running thread is not counted as another's: with 1 thread wanted nothing is
  // crowded, and a team larger than the machine's cores always is
  EXPECT_FALSE(ParallelChooser::crowded(1));
  cpu_set_t set;
  ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  EXPECT_TRUE(ParallelChooser::crowded(CPU_COUNT(&set) + 1));
}

TEST(ParallelChoice, RefusesNonsense) {
  ParallelChoice::Options o;
  o.blockSteps = 0;
  EXPECT_THROW(ParallelChoice{o}, Error);
}

TEST(ChunkedSums, SameBitsSerialAndParallel) {
  // 10,007 terms of mixed magnitude: a running sum and a two-halves sum differ in their last bits; the
  // chunked reduce gives one value whichever path runs
  const long n = 10007;
  Kokkos::View<double*> x("x", n), y("y", n);
  for (long i = 0; i < n; ++i) {
    x(i) = std::sin(0.37 * i) * std::pow(10.0, (i % 13) - 6);
    y(i) = std::cos(1.3 * i);
  }
  setSerialWorkNs(LONG_MAX);
  const double serial = dot(x, y);
  setSerialWorkNs(0);
  const double parallel = dot(x, y);
  setSerialWorkNs(kDefaultSerialWorkNs);
  EXPECT_EQ(serial, parallel);
  double running = 0;
  for (long i = 0; i < n; ++i) running += x(i) * y(i);
  EXPECT_NEAR(serial, running, 1e-12 * std::abs(running) + 1e-18);
}

}  // namespace
}  // namespace epaphe
