#pragma once
// The energy balance of a run as a loop observer (thesis section 2.2): at every output step the
// kinetic, strain and half-step total energies of the bodies, and the balance
//   (E_total + damping - contact work - external work - drive work - E_0) / max(E_ref, |E_total|),
// E_ref the sum of the bodies' initial |E_{1/2}|, the drive work that of a run-up (Epaphe_RunUp.hpp).
// With a heat term (LoopAccumulators::heatTerm(): a run with a thermal model), the contact work is split
// into what the contact supplies and the heat friction makes of it (docs/theory/heat.md, eq. 63):
//   (E_total + damping + friction heat - normal work - counterface work - external work - drive work - E_0) / ...
// the normal forces' work on the bodies and the counterface's work through friction (a turning casing's).
// The run stops (ExplicitLoop::fail) when the solution is no longer finite, when the balance error
// exceeds its tolerance, or, with penalty contact on still surfaces, when the bodies hold more energy
// than they were given.
#include "Epaphe_ExplicitLoop.hpp"

#include <deque>
#include <string>

namespace epaphe {

/// One energy record: the bodies' energies and the work done on them up to a step, and the balance error.
struct EnergySnapshot {
  double time = 0;     ///< t_n (s)
  long long step = 0;  ///< n
  ///@{
  double kinetic = 0, strain = 0, total = 0;  ///< J: sum over the bodies; total = E_{n+1/2}
  ///@}
  ///@{
  double contactWork = 0, externalWork = 0, damping = 0, initial = 0;  ///< J
  ///@}
  double driveWork = 0;  ///< J, a run-up's
  ///@{
  /// J, with a heat term (eq. 63 of docs/theory/heat.md; else 0): the heat friction made, the normal forces'
  /// work, the counterface's work through friction; contact work = normal + counterface work - friction heat
  double frictionHeat = 0, normalWork = 0, counterfaceWork = 0;
  ///@}
  bool heatTerm = false;  ///< the balance is eq. 63's
  double balance = 0;     ///< relative
};

/// How the bodies' energy E = kinetic + strain grew over the last records (EnergyMonitor::growth).
/// It grows without bound when, over the kept records, the last is the largest and at least e times
/// the least positive one, at least 4 records before it (the rise), or when it is no longer finite.
/// `efolding`: dt / ln(E1 / E) over the last 4 records of the rise (the current rate).
/// The energy came from the work of the contact forces, the external forces, or neither: the
/// integrator itself (its balance error, or the half-step energy E_{n+1/2} held while kinetic and
/// strain energies grow, which an unstable step does).
struct EnergyGrowth {
  bool unbounded = false;  ///< true when the energy grows without bound (see above)
  int records = 0;         ///< records of the rise
  ///@{
  double t0 = 0, t1 = 0;  ///< s
  ///@}
  ///@{
  double e0 = 0, e1 = 0;  ///< J, kinetic + strain
  ///@}
  double efolding = 0;  ///< s
  ///@{
  double contactWork = 0, externalWork = 0, damping = 0, total = 0;  ///< J, changes over the rise
  ///@}
  double balance = 0;  ///< relative balance error at the last record
  /// "contact work", "external work" or "the integrator"
  std::string source() const;
};

/// What the energy monitor measures and the tolerance it holds the balance to.
struct EnergyMonitorOptions {
  int every = 1;                ///< Output->Every: the steps measured (and the last)
  double tolerance = 1e-2;      ///< Output->Energy balance tolerance
  double penaltyStiffness = 0;  ///< > 0: check the penalty bound (penalty contact, no turning surface)
};

/// The energy balance of the run (the identity of Epaphe_CentralDifference.hpp): measures the bodies'
/// energies at the steps the history records, fails the run when the balance error exceeds the tolerance,
/// when the energy is no longer finite or, under penalty contact, when it grows beyond what was given.
class EnergyMonitor : public LoopObserver {
public:
  /// Takes E_0 from the loop's state now: construct it after the initial state is set and before
  /// a restart overwrites it.
  EnergyMonitor(const ExplicitLoop& loop, const EnergyMonitorOptions& options);

  /// True at the steps the monitor measures (and the history records).
  bool measures(const ExplicitLoop& loop) const { return loop.step() % opt_.every == 0 || loop.lastStep(); }
  /// The last measurement (valid from afterCorrect of a measured step).
  const EnergySnapshot& last() const { return last_; }
  /// How the energy grew over the last records this run measured (at most 32 are kept).
  EnergyGrowth growth() const;
  /// The energy the balance error is relative to: sum over the bodies of |E_0| (J).
  double reference() const { return energyRef_; }

  /// At a measured step: the energy record (last()), its balance error.
  void afterCorrect(ExplicitLoop& loop) override;
  /// The checks of the measured step: finite energy, the penalty bound, the balance tolerance.
  void endStep(ExplicitLoop& loop) override;

private:
  EnergyMonitorOptions opt_;
  std::vector<double> e0_;
  double energyRef_ = 0, springEnergy0_ = 0;
  EnergySnapshot last_;
  std::deque<EnergySnapshot> recent_;
  bool pending_ = false;
};

}  // namespace epaphe
