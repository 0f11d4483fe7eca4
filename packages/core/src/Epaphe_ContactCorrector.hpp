#pragma once
// The contact as the explicit loop sees it (Epaphe_ExplicitLoop.hpp): once per step, after the
// predictor has made q* (thesis eq. 2.2), detect contact and correct q* in place to q_{n+1} (eqs.
// 2.28-2.36), check the step's motion, and answer the loop's questions on energy (the contact work
// increment) and statistics (total force, active nodes).
//
// An interface of whole-step calls: the loop makes a few virtual calls per step and none per node;
// the per-node work stays in the implementation's kernels. It lives in core, the lowest package
// that both the loop (dynamics) and the contact (contact: GuardedContact, SurfaceContact with its
// run guards) use, so that neither includes the other.
#include "Epaphe_DenseTypes.hpp"
#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>

#include <string>
#include <vector>

namespace epaphe {

/// The contact as the explicit loop sees it: whole-step calls to detect and correct, check the step's
/// motion and report energy and statistics (see the file's opening comment).
class ContactCorrector {
public:
  virtual ~ContactCorrector() = default;
  /// Detects contact at the predicted coordinates `qPredicted` (q*, time t = t_{n+1}) and corrects
  /// them in place to q_{n+1}; `qCurrent` = q_n gives each node's motion over the step (friction).
  /// `cost` receives the phases' wall times.
  virtual void correct(double t, const DenseVector& qPredicted, const DenseVector& qCurrent, CostSplit& cost) = 0;
  /// After correct(): "" when the step's motion from `qCurrent` to `qNext` is within the run guards'
  /// bound, else a message for the user (t = t_n, h the step).
  virtual std::string checkStep(const DenseVector& qNext, const DenseVector& qCurrent, double t, double h) const = 0;
  /// True when the deck lets a step beyond the guards' bound go on (a warning, counted).
  virtual bool largeMotionAllowed() const = 0;
  /// The contact forces of the last correction on the system's coordinates, G lambda = sum_k D_k^T
  /// c_k lambda_k (eq. 2.33; q's layout), into `g`.
  virtual void generalizedForce(const DenseVector& g) const = 0;
  /// Work of the contact forces of the last correction over [t_{n-1}, t_{n+1}] / 2.
  virtual double workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const = 0;
  /// Sum of the normal forces of the last correction (N) and the number of active nodes.
  virtual double totalForce() const = 0;
  /// The number of active nodes of the last correction.
  virtual int numActive() const = 0;
  /// Per contact node, the normal force of the last correction (N, >= 0).
  virtual Kokkos::View<double*>::HostMirror forces() const = 0;
  /// The contact nodes' reference positions (3 per node): a body whose rest shape changes with its
  /// speed (a run-up) moves them between steps.
  virtual void setReferencePositions(const std::vector<double>& X) = 0;
};

}  // namespace epaphe
