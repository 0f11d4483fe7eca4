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
  std::string name;                               ///< the body's name (checkpoint and output names)
  const CentralDifference* integrator = nullptr;  ///< its central difference (not owned)
  /// its block of the system coordinates: first index, size
  ///@{
  int offset = 0, size = 0;
  ///@}
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
  /// The heat term of the energy balance (docs/theory/heat.md, eq. 63), kept by an observer that runs before the
  /// energy monitor (a run with a thermal model: HeatOutput); empty otherwise. Per body, the share of the friction
  /// heat it received (J; 0 for a body without a thermal model): its share of the friction heat and of the
  /// coating's plastic dissipation made at its nodes (eq. 64).
  std::vector<double> heatReceived;
  ///@{
  /// J, with the heat term: the heat friction made at every contact node, the normal contact forces' work on the
  /// bodies, and the counterface's work through friction (a turning surface's; 0 on still ones)
  double frictionHeat = 0, normalWork = 0, counterfaceWork = 0;
  ///@}
  /// J, with the heat term: the coating's plastic dissipation that became heat (eq. 64; part of the normal work)
  double coatingHeat = 0;
  /// True when the energy balance has its heat term (heatReceived is then sized to the bodies).
  bool heatTerm() const { return !heatReceived.empty(); }

  /// The values a checkpoint stores, in the order of names() (time first).
  std::vector<double> values(double time) const;
  /// The names of values(), for `bodies`: time, contact work, contact times, impulse, peak force, balance
  /// error, then per body its damping and external work (and drive work when a body is driven), then with
  /// `heat` (the heat term) the friction heat, normal and counterface work, the coating's heat and each body's
  /// received heat.
  static std::vector<std::string> names(const std::vector<LoopBody>& bodies, bool heat = false);
  /// Restores from values(); `what` names the source for errors.
  void restore(const std::vector<double>& values, const std::string& what);
};

class ExplicitLoop;

/// Hook points of the loop; every method does nothing unless overridden.
class LoopObserver {
public:
  virtual ~LoopObserver() = default;
  /// Once, before the first step (after a restart, before the first step run).
  virtual void beginRun(ExplicitLoop&) {}
  /// Step n starts: previous() = q_{n-1}, current() = q_n.
  virtual void beginStep(ExplicitLoop&) {}
  /// After the predictor: next() holds q*.
  virtual void afterPredict(ExplicitLoop&) {}
  /// After the contact correction and the energy increments: next() = q_{n+1}, velocity(b) = v_n.
  virtual void afterCorrect(ExplicitLoop&) {}
  /// After the rotation: stepsDone() = n + 1; stop requests and checkpoints go here.
  virtual void endStep(ExplicitLoop&) {}
  /// Once, when the loop has run its last step or stopped.
  virtual void endRun(ExplicitLoop&) {}
  /// The run stops on an error (`why`); called before the loop throws it.
  virtual void failed(ExplicitLoop&, const std::string& /*why*/) {}
};

/// The explicit loop (see the file's opening comment): steps the bodies' central differences, the contact's
/// correction and the energy accumulators, and calls its observers at the hooks of LoopObserver.
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
  /// The time step h (s).
  double timeStep() const { return h_; }
  /// The number of steps of the run (t_end = numSteps h).
  long long numSteps() const { return numSteps_; }
  /// The first step run: 0, or the restart's (setFirstStep()).
  long long firstStep() const { return firstStep_; }
  /// The step running (n, t_n = n h); after the rotation (endStep) stepsDone() = n + 1.
  long long step() const { return n_; }
  /// t_n = n h (s) of the step running.
  double time() const { return static_cast<double>(n_) * h_; }
  /// The steps done, counted from step 0.
  long long stepsDone() const { return done_; }
  /// True during the last step of the run.
  bool lastStep() const { return n_ == numSteps_ - 1; }
  /// The bodies, in the order of the system coordinates.
  const std::vector<LoopBody>& bodies() const { return bodies_; }
  /// System coordinates: before the rotation q_{n-1}, q_n, q_{n+1}; after it (endStep) previous()
  /// is q_n and current() q_{n+1}. The views alias the loop's buffers: copy what must outlive the hook.
  const DenseVector& previous() const { return Q_[iPrev_]; }
  /// q_n before the rotation, q_{n+1} after it (see previous()).
  const DenseVector& current() const { return Q_[iCur_]; }
  /// q* after the predictor, q_{n+1} after the correction (before the rotation).
  const DenseVector& next() const { return Q_[iNext_]; }
  /// Body b's block of a system vector (an unmanaged view, no allocation).
  DenseVector part(const DenseVector& system, std::size_t b) const {
    return DenseVector(system.data() + bodies_[b].offset, bodies_[b].size);
  }
  /// v_n = (q_{n+1} - q_{n-1}) / 2h of body b, in afterCorrect; computed once per step on demand.
  const DenseVector& velocity(std::size_t b);
  /// The sum of the contact forces of the step and the active nodes (0 without contact).
  double totalContactForce() const { return totalForce_; }
  /// The number of active contact nodes of the step.
  int activeContacts() const { return active_; }
  /// The contact corrector (null without contact).
  ContactCorrector* contact() const { return contact_; }
  /// The cost split the phases' wall times go to.
  CostSplit& cost() { return cost_; }
  /// The stream of progress and messages (rank 0's).
  std::ostream& out() { return out_; }
  /// What the loop sums over the run.
  LoopAccumulators& accumulators() { return acc_; }
  /// What the loop sums over the run.
  const LoopAccumulators& accumulators() const { return acc_; }
  /// Wall time of the loop so far (s).
  double seconds() const { return watch_.seconds(); }

  // ---- control, for observers ------------------------------------------------------------------
  /// Stop after this step's endStep hooks (checkpoints see stopRequested()).
  void requestStop(const std::string& reason) {
    if (!stop_) stopReason_ = reason;
    stop_ = true;
  }
  /// True once an observer called requestStop().
  bool stopRequested() const { return stop_; }
  /// The reason given to the first requestStop().
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
  DenseVector contactForce_;  // the correction's G lambda, when a body's step reads it (else empty)
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
