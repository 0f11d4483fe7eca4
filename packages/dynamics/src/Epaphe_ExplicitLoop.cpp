#include "Epaphe_ExplicitLoop.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <algorithm>

namespace epaphe {

std::vector<double> LoopAccumulators::values(double time) const {
  std::vector<double> v = {time, contactWork, firstContact, lastContact, impulse, maxForce, maxBalanceError};
  for (std::size_t b = 0; b < damping.size(); ++b) {
    v.push_back(damping[b]);
    v.push_back(externalWork[b]);
  }
  v.insert(v.end(), driveWork.begin(), driveWork.end());
  if (heatTerm()) {
    v.insert(v.end(), {frictionHeat, normalWork, counterfaceWork, coatingHeat});
    v.insert(v.end(), heatReceived.begin(), heatReceived.end());
  }
  return v;
}

std::vector<std::string> LoopAccumulators::names(const std::vector<LoopBody>& bodies, bool heat) {
  std::vector<std::string> v = {"time",    "contact_work", "first_contact",    "last_contact",
                                "impulse", "max_force",    "max_balance_error"};
  for (const auto& b : bodies) {
    v.push_back(b.name + "/damping");
    v.push_back(b.name + "/external_work");
  }
  if (std::any_of(bodies.begin(), bodies.end(), [](const LoopBody& b) { return b.driven; }))
    for (const auto& b : bodies) v.push_back(b.name + "/drive_work");
  if (heat) {
    v.insert(v.end(), {"friction_heat", "normal_work", "counterface_work", "coating_heat"});
    for (const auto& b : bodies) v.push_back(b.name + "/heat");
  }
  return v;
}

void LoopAccumulators::restore(const std::vector<double>& v, const std::string& what) {
  const std::size_t heatValues = heatTerm() ? 4 + heatReceived.size() : 0;
  const std::size_t expected = 7 + 2 * damping.size() + driveWork.size() + heatValues;
  EPAPHE_REQUIRE(v.size() == expected, what << " has " << v.size() << " values, " << expected << " expected");
  contactWork = v[1];
  firstContact = v[2];
  lastContact = v[3];
  impulse = v[4];
  maxForce = v[5];
  maxBalanceError = v[6];
  for (std::size_t b = 0; b < damping.size(); ++b) {
    damping[b] = v[7 + 2 * b];
    externalWork[b] = v[8 + 2 * b];
  }
  for (std::size_t b = 0; b < driveWork.size(); ++b) driveWork[b] = v[7 + 2 * damping.size() + b];
  if (heatTerm()) {
    const std::size_t h = 7 + 2 * damping.size() + driveWork.size();
    frictionHeat = v[h];
    normalWork = v[h + 1];
    counterfaceWork = v[h + 2];
    coatingHeat = v[h + 3];
    for (std::size_t b = 0; b < heatReceived.size(); ++b) heatReceived[b] = v[h + 4 + b];
  }
}

ExplicitLoop::ExplicitLoop(std::vector<LoopBody> bodies, double h, long long numSteps, ContactCorrector* contact,
                           CostSplit& cost, std::ostream& out)
    : bodies_(std::move(bodies)), h_(h), numSteps_(numSteps), contact_(contact), cost_(cost), out_(out) {
  EPAPHE_REQUIRE(h > 0 && numSteps > 0,
                 "ExplicitLoop: time step " << h << " s and " << numSteps << " steps; both must be positive");
  int size = 0;
  for (const auto& b : bodies_) {
    EPAPHE_REQUIRE(b.integrator && b.offset == size && b.size > 0,
                   "ExplicitLoop: body '" << b.name << "' has no integrator or is not the next block (offset "
                                          << b.offset << ", expected " << size << ")");
    size += b.size;
    v_.emplace_back("epaphe::loop::v", b.size);
  }
  for (int i = 0; i < 3; ++i) Q_[i] = DenseVector("epaphe::system::q" + std::to_string(i), size);
  if (contact_ &&
      std::any_of(bodies_.begin(), bodies_.end(), [](const LoopBody& b) { return b.integrator->wantsContactForce(); }))
    contactForce_ = DenseVector("epaphe::system::contact_force", size);
  vReady_.assign(bodies_.size(), false);
  acc_.damping.assign(bodies_.size(), 0.0);
  acc_.externalWork.assign(bodies_.size(), 0.0);
  if (std::any_of(bodies_.begin(), bodies_.end(), [](const LoopBody& b) { return b.driven; }))
    acc_.driveWork.assign(bodies_.size(), 0.0);
}

void ExplicitLoop::setFirstStep(long long first) {
  EPAPHE_REQUIRE(!started_, "ExplicitLoop::setFirstStep after the loop started");
  EPAPHE_REQUIRE(first >= 0 && first <= numSteps_,
                 "ExplicitLoop: first step " << first << " outside [0, " << numSteps_ << "]");
  firstStep_ = n_ = done_ = first;
}

void ExplicitLoop::notify(void (LoopObserver::*hook)(ExplicitLoop&)) {
  for (LoopObserver* o : observers_) (o->*hook)(*this);
}

void ExplicitLoop::fail(const std::string& why) {
  for (LoopObserver* o : observers_) o->failed(*this, why);
  throw Error(why);
}

const DenseVector& ExplicitLoop::velocity(std::size_t b) {
  if (!vReady_[b]) {  // v_n = (q_{n+1} - q_{n-1}) / 2h
    copy(v_[b], part(Q_[iNext_], b));
    epaphe::axpby(-0.5 / h_, part(Q_[iPrev_], b), 0.5 / h_, v_[b]);
    vReady_[b] = true;
  }
  return v_[b];
}

bool ExplicitLoop::run() {
  while (advance()) {
  }
  return !stop_;
}

bool ExplicitLoop::advance() {
  if (!started_) {
    started_ = true;
    watch_.restart();
    notify(&LoopObserver::beginRun);
  }
  if (stop_ || n_ >= numSteps_) return false;
  const double t = time();
  std::fill(vReady_.begin(), vReady_.end(), false);
  notify(&LoopObserver::beginStep);
  {
    ScopedPhase phase(cost_, "integration");
    for (std::size_t b = 0; b < bodies_.size(); ++b)
      bodies_[b].integrator->predict(part(Q_[iCur_], b), part(Q_[iPrev_], b), part(Q_[iNext_], b),
                                     t);  // eq. 2.2, the loads at t_n (eq. 67)
  }
  notify(&LoopObserver::afterPredict);
  totalForce_ = 0;
  active_ = 0;
  if (contact_) {
    // eqs. 2.28-2.36 on all bodies at once (eq. 2.33), friction from the motion q_n -> q*
    contact_->correct(t + h_, Q_[iNext_], Q_[iCur_], cost_);
    if (const std::string large = contact_->checkStep(Q_[iNext_], Q_[iCur_], t, h_); !large.empty()) {
      if (!contact_->largeMotionAllowed()) fail(large);
      if (acc_.largeMotionSteps++ == 0) out_ << "warning: " << large << " (further such steps are counted)\n";
    }
    if (contactForce_.extent(0) > 0) {
      ScopedPhase phase(cost_, "integration");  // a massless boundary's residual force (setContactForce)
      contact_->generalizedForce(contactForce_);
      for (std::size_t b = 0; b < bodies_.size(); ++b)
        bodies_[b].integrator->setContactForce(part(Q_[iNext_], b), part(contactForce_, b));
    }
  }
  {
    ScopedPhase phase(cost_, "energy");  // one phase for the step's work and dissipation increments
    if (contact_) {
      acc_.contactWork += contact_->workIncrement(Q_[iNext_], Q_[iPrev_]);
      totalForce_ = contact_->totalForce();
      active_ = contact_->numActive();
    }
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      acc_.damping[b] += bodies_[b].integrator->dampingIncrement(part(Q_[iNext_], b), part(Q_[iPrev_], b));
      acc_.externalWork[b] += bodies_[b].integrator->externalWorkIncrement(part(Q_[iNext_], b), part(Q_[iPrev_], b));
    }
  }
  if (totalForce_ > 0) {
    if (acc_.firstContact < 0) acc_.firstContact = t;
    acc_.lastContact = t;
    acc_.impulse += totalForce_ * h_;
    acc_.maxForce = std::max(acc_.maxForce, totalForce_);
  }
  notify(&LoopObserver::afterCorrect);
  // q_{n-1} <- q_n <- q_{n+1}
  const int oldPrev = iPrev_;
  iPrev_ = iCur_;
  iCur_ = iNext_;
  iNext_ = oldPrev;
  done_ = n_ + 1;
  notify(&LoopObserver::endStep);
  n_ = done_;
  if (n_ >= numSteps_ || stop_) {
    notify(&LoopObserver::endRun);
    return false;
  }
  return true;
}

}  // namespace epaphe
