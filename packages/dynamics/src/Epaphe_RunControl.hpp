#pragma once
// Loop observers that control a run from outside: stops on SIGINT/SIGTERM or after a given number
// of steps (the run's checkpoint observer then writes a checkpoint), and progress lines.
#include "Epaphe_ExplicitLoop.hpp"

#include <string>

namespace epaphe {

/// Stops the loop at the end of a step when SIGINT or SIGTERM arrived (after catchStopSignals())
/// or once `stopAfterSteps` steps are done (counted from step 0; < 0: never). The last step never
/// stops: the run is then complete.
class StopControl : public LoopObserver {
public:
  /// `continueHint`: how to continue, appended to the reason ("continue with ...").
  StopControl(long long stopAfterSteps, std::string continueHint)
      : stopAfter_(stopAfterSteps), hint_(std::move(continueHint)) {}
  /// Installs handlers for SIGINT and SIGTERM that only set a flag the observer reads.
  static void catchStopSignals();
  /// The signal that stopped the loop (0: none).
  int signal() const { return signal_; }
  /// Requests the stop (with the reason and how to continue) when a signal arrived or the step count is reached.
  void endStep(ExplicitLoop& loop) override;

private:
  long long stopAfter_;
  std::string hint_;
  int signal_ = 0;
};

/// "t = ... (..%)  ... steps/s  ... left  active contacts .." every `interval` seconds of wall
/// time (looked at every 256 steps), on the loop's stream.
class ProgressReport : public LoopObserver {
public:
  /// A progress line every `interval` seconds of wall time (<= 0: never).
  explicit ProgressReport(double interval) : interval_(interval) {}
  /// Starts the interval's clock.
  void beginRun(ExplicitLoop&) override { since_.restart(); }
  /// Prints the progress line when the interval has passed (every 256 steps at most).
  void endStep(ExplicitLoop& loop) override;

private:
  double interval_;
  Stopwatch since_;
};

}  // namespace epaphe
