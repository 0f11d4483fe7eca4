#pragma once
// The explicit loop as a component: the central difference of every body (thesis eqs. 2.2-2.3),
// the contact's detection and correction of all bodies at once (eqs. 2.28-2.36), the energy
// accumulators, and observers called at fixed hook points in the manner of Tempus' app actions.
// Output, checkpoints, monitors, progress and signals are observers; a Trilinos application drives
// the loop step by step (advance()) or to its end (run()) and adds its own.
//
// One step n (t_n = n h), in order:
//   beginStep      q_{n-1}, q_n hold the state
//   predict        q* = A q_n + B q_{n-1} + P f per body (eq. 2.2)                  -> afterPredict
//   correct        contact on q* (eqs. 2.28-2.36), q_{n+1}; run guards; energy increments
//                  (contact work, damping, external work) and the contact statistics -> afterCorrect
//                  (the step's records: q_{n-1}, q_n, q_{n+1} and velocity(b) = v_n are available)
//   finish         q_{n-1} <- q_n <- q_{n+1} (three buffers rotate, nothing is copied) -> endStep
//                  (stepsDone() = n + 1; checkpoints, stop requests, progress)
// then, once, endRun; or, when an observer calls fail(), failed() on every observer and an Error.
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_ContactCorrector.hpp"
#include "Epaphe_Runtime.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace epaphe {

/// A body of the loop: its integrator and its block [offset, offset + size) of the system
/// coordinates (all bodies' reduced coordinates, stacked).
struct LoopBody {
  std::string name;
  const CentralDifference* integrator = nullptr;
  int offset = 0, size = 0;
  bool driven = false;  ///< its speed follows a law (Epaphe_RunUp.hpp): the loop keeps its drive work
};

/// What the loop sums over the run: everything a checkpoint must keep to continue it exactly.
struct LoopAccumulators {
  double contactWork = 0;  ///< J, sum of the contact work increments
  ///@{
  double firstContact = -1, lastContact = -1;  ///< s, steps with a positive total contact force
  ///@}
  ///@{
  double impulse = 0, maxForce = 0;  ///< N s, N
  ///@}
  double maxBalanceError = 0;  ///< the energy monitor's largest |balance error|
  ///@{
  std::vector<double> damping, externalWork;  ///< J, per body
  ///@}
  std::vector<double> driveWork;   ///< J, per body when a body is driven, else empty
  long long largeMotionSteps = 0;  ///< steps the guards let through (allowed by the deck)

  /// The values a checkpoint stores, in the order of names() (time first).
  std::vector<double> values(double time) const;
  static std::vector<std::string> names(const std::vector<LoopBody>& bodies);
  /// Restores from values(); `what` names the source for errors.
  void restore(const std::vector<double>& values, const std::string& what);
};

class ExplicitLoop;

/// Hook points of the loop; every method does nothing unless overridden.
class LoopObserver {
public:
  virtual ~LoopObserver() = default;
  virtual void beginRun(ExplicitLoop&) {}
  virtual void beginStep(ExplicitLoop&) {}
  virtual void afterPredict(ExplicitLoop&) {}
  virtual void afterCorrect(ExplicitLoop&) {}
  virtual void endStep(ExplicitLoop&) {}
  virtual void endRun(ExplicitLoop&) {}
  /// The run stops on an error (`why`); called before the loop throws it.
  virtual void failed(ExplicitLoop&, const std::string& /*why*/) {}
};

class ExplicitLoop {
public:
  /// `contact` may be null (no contact); it works on the system coordinates of all bodies (the
  /// contact package's GuardedContact: SurfaceContact and its run guards). `cost` receives the
  /// phases' wall times (integration, contact and projection inside the contact, energy, and what
  /// observers add).
  ExplicitLoop(std::vector<LoopBody> bodies, double h, long long numSteps, ContactCorrector* contact, CostSplit& cost,
               std::ostream& out);

  /// Observers are called in the order they were added; the loop does not own them.
  void addObserver(LoopObserver* observer) { observers_.push_back(observer); }

  /// Starts at step `first` (a restart) instead of 0; before run() or the first advance().
  void setFirstStep(long long first);
  /// Runs the steps left; returns true when all ran, false when an observer asked to stop.
  bool run();
  /// Runs one step; returns false once the loop is finished (all steps run, or stopped).
  bool advance();

  // ---- state, for observers and drivers ------------------------------------------------------
  double timeStep() const { return h_; }
  long long numSteps() const { return numSteps_; }
  long long firstStep() const { return firstStep_; }
  /// The step running (n, t_n = n h); after the rotation (endStep) stepsDone() = n + 1.
  long long step() const { return n_; }
  double time() const { return static_cast<double>(n_) * h_; }
  long long stepsDone() const { return done_; }
  bool lastStep() const { return n_ == numSteps_ - 1; }
  const std::vector<LoopBody>& bodies() const { return bodies_; }
  /// System coordinates: before the rotation q_{n-1}, q_n, q_{n+1}; after it (endStep) previous()
  /// is q_n and current() q_{n+1}. The views alias the loop's buffers: copy what must outlive the hook.
  const DenseVector& previous() const { return Q_[iPrev_]; }
  const DenseVector& current() const { return Q_[iCur_]; }
  const DenseVector& next() const { return Q_[iNext_]; }
  /// Body b's block of a system vector (an unmanaged view, no allocation).
  DenseVector part(const DenseVector& system, std::size_t b) const {
    return DenseVector(system.data() + bodies_[b].offset, bodies_[b].size);
  }
  /// v_n = (q_{n+1} - q_{n-1}) / 2h of body b, in afterCorrect; computed once per step on demand.
  const DenseVector& velocity(std::size_t b);
  /// The sum of the contact forces of the step and the active nodes (0 without contact).
  double totalContactForce() const { return totalForce_; }
  int activeContacts() const { return active_; }
  ContactCorrector* contact() const { return contact_; }
  CostSplit& cost() { return cost_; }
  std::ostream& out() { return out_; }
  LoopAccumulators& accumulators() { return acc_; }
  const LoopAccumulators& accumulators() const { return acc_; }
  /// Wall time of the loop so far (s).
  double seconds() const { return watch_.seconds(); }

  // ---- control, for observers ------------------------------------------------------------------
  /// Stop after this step's endStep hooks (checkpoints see stopRequested()).
  void requestStop(const std::string& reason) {
    if (!stop_) stopReason_ = reason;
    stop_ = true;
  }
  bool stopRequested() const { return stop_; }
  const std::string& stopReason() const { return stopReason_; }
  /// Stops the run on an error: failed(why) on every observer, then throws Error(why).
  [[noreturn]] void fail(const std::string& why);

private:
  void notify(void (LoopObserver::*hook)(ExplicitLoop&));
  std::vector<LoopBody> bodies_;
  double h_;
  long long numSteps_, firstStep_ = 0, n_ = 0, done_ = 0;
  ContactCorrector* contact_;
  CostSplit& cost_;
  std::ostream& out_;
  std::vector<LoopObserver*> observers_;
  DenseVector Q_[3];
  int iPrev_ = 0, iCur_ = 1, iNext_ = 2;
  std::vector<DenseVector> v_;
  std::vector<bool> vReady_;
  LoopAccumulators acc_;
  double totalForce_ = 0;
  int active_ = 0;
  bool started_ = false, stop_ = false;
  std::string stopReason_;
  Stopwatch watch_;
};

}  // namespace epaphe
