// The online loop from an installed Epaphe with no Tpetra: it links Epaphe::dynamics (and through
// it contact, surface, modeldata, core) only. A mass on springs, built by hand as a reduced model,
// is driven step by step through epaphe::ExplicitLoop for one period, as a Trilinos application
// would: the application's own observer watches the discrete energy E_{n+1/2} after every
// correction (the central difference conserves it exactly, to round-off), Epaphe's EnergyMonitor
// checks the balance, and between steps the application reads the state: at half a period the
// mass is at -x0, after a period back at x0 (phase error (omega h)^2 / 24 per radian: 1.6e-6 of a
// period here).
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>

#include <cmath>
#include <iostream>

namespace {

/// The application's observer: the largest relative drift of E_{n+1/2} over the run.
class EnergyDrift : public epaphe::LoopObserver {
public:
  void afterCorrect(epaphe::ExplicitLoop& loop) override {
    const auto& cd = *loop.bodies()[0].integrator;
    const double e = cd.halfStepEnergy(loop.current(), loop.next());
    if (loop.step() == 0) e0_ = e;
    drift_ = std::max(drift_, std::abs(e - e0_) / e0_);
    ++calls_;
  }
  double drift() const { return drift_; }
  long long calls() const { return calls_; }

private:
  double e0_ = 0, drift_ = 0;
  long long calls_ = 0;
};

double displacement(const epaphe::ExplicitLoop& loop) {
  auto qh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), loop.current());
  return qh(0);
}

}  // namespace

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  bool ok = true;
  {
    const double m = 2.0, k = 800.0, omega = std::sqrt(k / m), period = 2 * M_PI / omega;
    const int steps = 1000;
    const double h = period / steps, x0 = 1e-3;
    epaphe::ReducedModel r;  // one node, mass m and stiffness k in each direction
    r.name = "oscillator";
    r.kind = epaphe::ReductionKind::None;
    r.size = 3;
    r.K.assign(9, 0.0);
    r.M.assign(9, 0.0);
    for (int i = 0; i < 3; ++i) {
      r.K[4 * i] = k;
      r.M[4 * i] = m;
    }
    r.nodeDof = {0, 1, 2};
    r.recovery = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    r.coords = {{0, 0, 0}};
    r.retainedNodes = {0};
    const epaphe::CentralDifference cd(r, h, epaphe::DampingOptions{});
    epaphe::CostSplit cost;
    epaphe::ExplicitLoop loop({{"oscillator", &cd, 0, 3}}, h, steps, nullptr, cost, std::cout);
    auto init = Kokkos::create_mirror_view(loop.current());
    init(0) = x0;
    Kokkos::deep_copy(loop.current(), init);           // q_0
    init(0) = x0 * (1 - 0.5 * h * h * omega * omega);  // q_{-1} = q_0 + h^2/2 a_0 (v_0 = 0)
    Kokkos::deep_copy(loop.previous(), init);
    EnergyDrift drift;
    epaphe::EnergyMonitor monitor(loop, {1, 1e-9, 0.0});
    loop.addObserver(&monitor);
    loop.addObserver(&drift);
    double half = 0;
    while (loop.advance())
      if (loop.stepsDone() == steps / 2) half = displacement(loop) / x0;
    const double back = displacement(loop) / x0;
    std::cout << "u/u0 after half a period " << half << ", after one period " << back << "; energy drift "
              << drift.drift() << " over " << drift.calls() << " steps; monitor balance " << monitor.last().balance
              << "\n";
    ok = std::abs(half + 1) < 1e-4 && std::abs(back - 1) < 1e-4 && drift.drift() < 1e-12 && drift.calls() == steps &&
         std::abs(monitor.last().balance) < 1e-12 && loop.stepsDone() == steps;
  }
  std::cout << (ok ? "online consumer OK" : "online consumer FAILED") << "\n";
  return ok ? 0 : 1;
}
