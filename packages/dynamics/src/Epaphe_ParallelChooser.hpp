#pragma once
// Chooses, while a run runs, whether the explicit step's loops run on the thread team or all on the
// calling thread, by timing both on the run itself.
//
// Why: whether a parallel region pays depends on the machine's load as much as on the work. On an
// idle 2-core machine the stage scene's step is 1.7x faster on 2 threads; with one other busy
// process three threads share two cores, a thread of the team is descheduled for a time slice
// while its partner waits at the join, and the same step is slower on 2 threads than on 1. A fixed
// choice is wrong in one of the two cases.
//
// How: a probe runs short blocks of steps alternately with the loops parallel (the configured
// serialWorkNs threshold) and serial (every loop on the calling thread), `pairs` of each. A block's
// first step is not timed (it pays for the mode's change: the data the other mode's threads left in
// their caches), then the block lasts at least `blockSteps` steps and `blockSeconds` of wall time
// (2 ms: about 5 steps of a stage, some 250 of a blade). Each pair's ratio of wall times per step
// compares the two modes on neighbouring steps. They must be near: a contact's work moves with the
// motion (the stage's active nodes go from 0 to 32 and back within 50-70 steps), and blocks of many
// such periods would compare steps of different work. The median of the pairs' ratios decides (the
// pairs on the work's rise and on its fall), so that a block slowed by a checkpoint or an interrupt
// does not. The faster mode then holds until the wall time since the probe is `holdFactor` times the
// probe's own, and a new probe starts (the load may have changed). The slower mode's share of a run
// is at most about 1 / (2 holdFactor) of its steps.
//
// A probe's team blocks are what the adaptive run pays for its choice, and they cost most when the
// answer is plain: beside a busy process a team step on a 2-core machine is 2-3 times slower, and half
// of a probe's steps are the team's. So before a probe, the
// chooser looks at the machine (ParallelChoice's `crowded`) at the start of up to 3 steps run on the
// calling thread: when at every look other processes' threads ready to run leave fewer free cores than
// the team has threads (Linux: /proc/loadavg's running threads less this process's own), the calling
// thread's mode is kept without a probe, and the machine looked at again after a probe's least length.
// One look that finds the cores free, or /proc that cannot tell, lets the probe decide as above.
//
// Switching changes no result: the step's loops write per item and reduce() sums in fixed chunks in
// index order (Epaphe_Parallel.hpp), so a run gives the same bits in either mode.
#include "Epaphe_ExplicitLoop.hpp"

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace epaphe {

/// The choice itself, apart from the loop and the clock (unit-tested with a clock of its own).
class ParallelChoice {
public:
  /// How a probe runs and how long its verdict holds.
  struct Options {
    int blockSteps = 1;           ///< a probe's block: at least this many timed steps...
    double blockSeconds = 0.002;  ///< ...and this much wall time (s), after its first step (not timed)
    int pairs = 15;               ///< blocks of each mode in a probe
    double holdFactor = 20;       ///< the chosen mode holds for this many times the probe's wall time
  };
  /// With the default options.
  ParallelChoice() : ParallelChoice(Options{}) {}
  /// Throws epaphe::Error on options out of range (blocks of no step, no pair, no hold). `crowded`
  /// (optional), one look at the machine, is asked at the start of up to 3 steps before a probe, run
  /// on the calling thread: true at all of them (other processes hold the cores the team needs) keeps
  /// the calling thread's mode without a probe until 2 pairs x blockSeconds later.
  explicit ParallelChoice(Options options, std::function<bool()> crowded = {});

  /// A step starts at wall time `now` (s); returns true when it must run its loops in parallel.
  bool stepStarts(double now);
  /// The step that started last ends at wall time `now` (s).
  void stepEnds(double now);

  /// Steps run with parallel loops, and in all.
  ///@{
  long long parallelSteps() const { return parallelSteps_; }
  long long steps() const { return steps_; }
  ///@}
  /// Probes completed, and how many of them chose the parallel loops.
  ///@{
  int probes() const { return probes_; }
  int parallelChoices() const { return parallelChoices_; }
  ///@}
  /// The median parallel/serial wall-time ratio of the last probe (0 before the first).
  double lastRatio() const { return lastRatio_; }
  /// Probes not run because every look found the cores taken.
  int crowdedSkips() const { return crowdedSkips_; }

private:
  Options o_;
  bool probing_ = false, parallel_ = true, chosen_ = true;
  bool warmed_ = false;          // the block's first step (not timed) has run
  int block_ = 0, inBlock_ = 0;  // block of the probe (even: parallel), timed steps done in it
  double blockStart_ = 0, probeStart_ = 0, holdUntil_ = 0;
  std::vector<double> perStep_;  // the probe's blocks' wall times
  long long parallelSteps_ = 0, steps_ = 0;
  int probes_ = 0, parallelChoices_ = 0;
  double lastRatio_ = 0;
  static constexpr int kLooks = 3;
  std::function<bool()> crowded_;
  bool looking_ = false;
  int looks_ = 0, crowdedSkips_ = 0;
};

/// The loop observer that applies ParallelChoice: sets serialWorkNs() before each step (the
/// configured threshold, or every loop serial), restores the configured threshold at the end.
class ParallelChooser : public LoopObserver {
public:
  /// `threshold`: the serialWorkNs() of parallel mode (the configured one).
  explicit ParallelChooser(long threshold, ParallelChoice::Options options = {});
  /// One look at the machine: true when other processes' threads ready to run leave fewer free cores
  /// than `team` threads (Linux /proc; false where it cannot tell).
  static bool crowded(int team);
  void beginStep(ExplicitLoop&) override;
  void endStep(ExplicitLoop&) override;
  void endRun(ExplicitLoop&) override;
  void failed(ExplicitLoop&, const std::string&) override;

  /// The choice and its counts so far.
  const ParallelChoice& choice() const { return choice_; }
  /// One line for the run summary: the share of steps with parallel loops and the probes' verdicts.
  std::string summary() const;

private:
  double now() const;
  long threshold_;
  ParallelChoice choice_;
  std::chrono::steady_clock::time_point origin_ = std::chrono::steady_clock::now();
};

}  // namespace epaphe
