#include "Epaphe_EnergyMonitor.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace epaphe {

EnergyMonitor::EnergyMonitor(const ExplicitLoop& loop, const EnergyMonitorOptions& options) : opt_(options) {
  double loadScale = 0;
  for (std::size_t b = 0; b < loop.bodies().size(); ++b) {
    e0_.push_back(
        loop.bodies()[b].integrator->halfStepEnergy(loop.part(loop.previous(), b), loop.part(loop.current(), b)));
    energyRef_ += std::abs(e0_.back());
    loadScale += loop.bodies()[b].integrator->loadEnergyScale();
  }
  // A body that starts at rest under loads that start from zero has no energy yet: the loads' own
  // scale (eq. 67) keeps the round-off of the first steps' work (a preloaded contact's) from reading as
  // a relative error of 1. 0 without loads: the reference is then the initial energy alone.
  energyRef_ = std::max(std::max(energyRef_, loadScale), 1e-300);
}

void EnergyMonitor::afterCorrect(ExplicitLoop& loop) {
  if (opt_.penaltyStiffness > 0 && loop.step() == 0 && loop.contact()) {  // springs of initial penetrations
    const auto f0 = loop.contact()->forces();
    for (std::size_t k = 0; k < f0.extent(0); ++k) springEnergy0_ += f0(k) * f0(k) / (2 * opt_.penaltyStiffness);
  }
  if (!measures(loop)) return;
  ScopedPhase phase(loop.cost(), "output");
  const LoopAccumulators& acc = loop.accumulators();
  EnergySnapshot s;
  s.time = loop.time();
  s.step = loop.step();
  s.contactWork = acc.contactWork;
  for (std::size_t b = 0; b < loop.bodies().size(); ++b) {
    const CentralDifference& cd = *loop.bodies()[b].integrator;
    const CentralDifference::EnergyTerms e =
        cd.energies(loop.part(loop.current(), b), loop.part(loop.next(), b), loop.velocity(b));
    s.kinetic += e.kinetic;
    s.total += e.total;
    s.strain += e.strain;
    s.externalWork += acc.externalWork[b];
    s.damping += acc.damping[b];
    s.initial += e0_[b];
  }
  for (double w : acc.driveWork) s.driveWork += w;
  s.heatTerm = acc.heatTerm();
  if (s.heatTerm) {
    // eq. 63 (docs/theory/heat.md): E + D + Q - W_n - W_s - W_ext - W_drive = E_0, the friction's share of the
    // contact work W_c = W_n + W_s - Q taken out as the heat Q it made
    s.frictionHeat = acc.frictionHeat;
    s.normalWork = acc.normalWork;
    s.counterfaceWork = acc.counterfaceWork;
    s.balance = (s.total + s.damping + s.frictionHeat - s.normalWork - s.counterfaceWork - s.externalWork -
                 s.driveWork - s.initial) /
                std::max(energyRef_, std::abs(s.total));
  } else {
    s.balance = (s.total + s.damping - s.contactWork - s.externalWork - s.driveWork - s.initial) /
                std::max(energyRef_, std::abs(s.total));
  }
  last_ = s;
  recent_.push_back(s);
  if (recent_.size() > 32) recent_.pop_front();
  pending_ = true;
}

// The checks come at the end of the step, after the observers that follow this one recorded the
// measured step: a run stopped by them keeps its last record.
void EnergyMonitor::endStep(ExplicitLoop& loop) {
  if (!pending_) return;
  pending_ = false;
  const EnergySnapshot& s = last_;
  LoopAccumulators& acc = loop.accumulators();
  acc.maxBalanceError = std::max(acc.maxBalanceError, std::abs(s.balance));
  if (!std::isfinite(s.total)) {
    std::ostringstream os;
    os << "the solution is no longer finite at t = " << s.time << " s (step " << s.step
       << "): the time step is probably too large for the contact stiffness";
    loop.fail(os.str());
  }
  if (opt_.penaltyStiffness > 0) {
    const double given = s.initial + s.externalWork - s.damping + springEnergy0_;
    if (s.total > given + 1e-3 * std::max(std::abs(given), energyRef_)) {
      std::ostringstream os;
      os << "the energy of the bodies grew to " << s.total << " J at t = " << s.time << " s, more than the " << given
         << " J they were given (initial, external work, initial penalty springs): the penalty contact is "
            "unstable at this time step (the penalty on the predicted gap is stable for h^2 kp / m below "
            "4/3); use a smaller 'Penalty stiffness' or 'Time step'";
      loop.fail(os.str());
    }
  }
  if (std::abs(s.balance) > opt_.tolerance) {
    std::ostringstream os;
    os << "energy balance error " << s.balance << " at t = " << s.time
       << " s exceeds 'Output->Energy balance tolerance' = " << opt_.tolerance << " (total " << s.total
       << " J, contact work " << s.contactWork << " J, damping " << s.damping << " J, initial " << s.initial << " J";
    if (s.heatTerm)
      os << ", friction heat " << s.frictionHeat << " J, normal work " << s.normalWork << " J, counterface work "
         << s.counterfaceWork << " J";
    os << ")";
    loop.fail(os.str());
  }
}

}  // namespace epaphe

namespace epaphe {

std::string EnergyGrowth::source() const {
  const double gain = e1 - e0;
  if (contactWork >= 0.5 * gain) return "contact work";
  if (externalWork >= 0.5 * gain) return "external work";
  return "the integrator";
}

EnergyGrowth EnergyMonitor::growth() const {
  EnergyGrowth g;
  if (recent_.empty()) return g;
  auto energy = [](const EnergySnapshot& s) { return s.kinetic + s.strain; };
  // the rise: from the kept record of least positive energy to the last, which must be the largest
  std::size_t first = recent_.size() - 1;
  bool largest = true;
  for (std::size_t i = 0; i + 1 < recent_.size(); ++i) {
    const double e = energy(recent_[i]);
    largest = largest && !(e > energy(recent_.back()));
    if (e > 0 && (first == recent_.size() - 1 || e < energy(recent_[first]))) first = i;
  }
  const EnergySnapshot &a = recent_[first], &b = recent_.back();
  g.records = static_cast<int>(recent_.size() - first);
  g.t0 = a.time;
  g.t1 = b.time;
  g.e0 = energy(a);
  g.e1 = energy(b);
  g.contactWork = b.contactWork - a.contactWork;
  g.externalWork = b.externalWork - a.externalWork;
  g.damping = b.damping - a.damping;
  g.total = b.total - a.total;
  g.balance = b.balance;
  const bool finite = std::isfinite(g.e1) && std::isfinite(b.total);
  // the current rate: over the last 4 records of the rise (its start may not grow exponentially)
  const EnergySnapshot& c = recent_[std::max(first, recent_.size() - 4)];
  if (g.records >= 2 && energy(c) > 0 && finite && g.e1 > energy(c))
    g.efolding = (g.t1 - c.time) / std::log(g.e1 / energy(c));
  g.unbounded = !finite || (largest && g.records >= 4 && g.e0 > 0 && g.e1 >= M_E * g.e0);
  return g;
}

}  // namespace epaphe
