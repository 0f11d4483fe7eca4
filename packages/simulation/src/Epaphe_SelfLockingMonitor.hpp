#pragma once
// The self-locking check of the sliding contact nodes over a run (docs/theory/divergence.md, eqs.
// (48)-(50)). The friction law checks each sliding node at each step (CoulombFriction); this observer
// keeps, over the run, the least quasi-static margin and the least margin of the correction's own
// Delassus block, with their node and time, and the first node and time where either holds (margin
// <= 0). Simulation writes them into the run summary and the output's /run attributes.
//
// The quasi-static margin needs the static compliance S_a = (K^{-1})_aa of each contact node's body
// at the node's DOFs (staticContactCompliance): exact for the massless boundary and for Craig-Bampton,
// Guyan or an unreduced dense model (their static response is exact at the retained DOFs); not
// formed for a full body with lumped mass (sparse K) or a free body (singular K): their nodes get
// the correction's margin only.
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <string>
#include <vector>

namespace epaphe {

/// 9 entries per node of `nodes` (row-major 3 x 3, x y z): (K^{-1}) of `rom` at the node's DOFs,
/// or NaN when the model has no static compliance to offer (see above).
std::vector<double> staticContactCompliance(const ReducedModel& rom, const std::vector<int>& nodes);

/// One margin over the run: least value, its contact node (-1: never checked) and time (t_{n+1}).
struct LockRecord {
  double margin = 1.0;  ///< the least margin (1: none checked)
  int node = -1;        ///< its contact node (-1: never checked)
  double time = -1.0;   ///< its time t_{n+1} (s; -1: never checked)
};

/// The self-locking check over a run, as a loop observer (see the file's opening comment).
class SelfLockingMonitor : public LoopObserver {
public:
  /// `contact`: the loop's contact (null: none); `h`: the time step (a correction at step n sets the
  /// forces at t_{n+1}).
  SelfLockingMonitor(const SurfaceContact* contact, double h) : contact_(contact), h_(h) {}
  /// Keeps the step's least margins and first locks (from the friction law's check).
  void afterCorrect(ExplicitLoop& loop) override;
  /// Quasi-static (eq. (50)) and correction (eq. (48)) margins: least over the run, and first lock.
  const LockRecord& least() const { return least_; }
  /// The least margin of the correction's Delassus block over the run (eq. (48)).
  const LockRecord& leastStep() const { return leastStep_; }
  /// The first lock of the quasi-static margin (margin <= 0; node -1: none).
  const LockRecord& firstLock() const { return first_; }
  /// The first lock of the correction's margin (node -1: none).
  const LockRecord& firstStepLock() const { return firstStep_; }
  long long checks() const { return checks_; }  ///< sliding nodes checked (node-steps)

private:
  const SurfaceContact* contact_;
  double h_;
  LockRecord least_, leastStep_, first_, firstStep_;
  long long checks_ = 0;
};

}  // namespace epaphe
