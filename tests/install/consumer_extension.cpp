// Extends an installed Epaphe from outside, as docs/developer/extending.md says: its own contact law
// (a Hertz law, lambda = k (-g*)^(3/2), registered under 'Contact->Method' = "Hertz" with its own key
// 'Hertz stiffness') and its own observer (the peak total contact force, enabled from the deck's
// 'Observers->Peak force' and writing its result to the HDF5 output), plus an observer it hands to the
// run itself (Simulation::addObserver). It runs the deck given (custom-law.xml: the bar of V1 hitting a
// wall) and checks that the law made the forces of the run and that both observers were called at
// every step.
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_ContactLaw.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_ForwardIncrementLagrange.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_RunObserver.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_Simulation.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

namespace {

// What the law did over the run: calls with active nodes, and the largest total force it produced.
long long lawCalls = 0;
double lawPeak = 0.0;

/// lambda_k = k (-g*_k)^(3/2) along n_k, from the predicted gap (explicit, as the penalty law).
class HertzEnforcement final : public epaphe::ContactEnforcement {
public:
  explicit HertzEnforcement(double k) : k_(k) {}
  const char* name() const override { return "Hertz"; }
  void enforce(const epaphe::ContactStepViews& v, std::vector<int>& active, const epaphe::DenseVector&,
               const epaphe::DenseVector*) override {
    epaphe::normalDirections(v);  // c_k = n_k
    const int nc = static_cast<int>(v.force.extent(0));
    for (int k = 0; k < nc; ++k) v.force(k) = 0.0;
    double total = 0.0;
    for (int k : active) {
      v.force(k) = k_ * std::pow(-v.gap(k), 1.5);
      total += v.force(k);
    }
    if (!active.empty()) ++lawCalls;
    lawPeak = std::max(lawPeak, total);
  }
  bool closesGaps() const override { return false; }

private:
  double k_;
};

class HertzLaw final : public epaphe::ContactLaw {
public:
  std::string name() const override { return "Hertz"; }
  std::string description() const override { return "lambda = k * penetration^(3/2)"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Hertz"));
    epaphe::deck::addDouble(*pl, "Hertz stiffness", 3e11, "k (N/m^1.5) of the Hertz law", 1e-300);
    return pl;
  }
  std::unique_ptr<epaphe::ContactEnforcement> make(const Teuchos::ParameterList& contact,
                                                   const epaphe::ContactLawSetup&) const override {
    return std::make_unique<HertzEnforcement>(contact.get<double>("Hertz stiffness"));
  }
  bool closesGaps() const override { return false; }
};

/// The peak of the total contact force over the run, written to <Group> as attributes at the end.
class PeakForce final : public epaphe::RunObserver {
public:
  PeakForce(epaphe::io::Hdf5File& file, std::string group) : file_(file), group_(std::move(group)) {}
  void endStep(epaphe::ExplicitLoop& loop) override {
    ++steps_;
    peak_ = std::max(peak_, loop.totalContactForce());
  }
  void endRun(epaphe::ExplicitLoop&) override {
    file_.setAttribute(group_, "peak_total_force", peak_);
    file_.setAttribute(group_, "steps", steps_);
  }
  std::vector<std::string> summary() const override {
    std::ostringstream os;
    os << "peak force observer: " << steps_ << " steps, peak total contact force " << peak_ << " N";
    return {os.str()};
  }

private:
  epaphe::io::Hdf5File& file_;
  std::string group_;
  long long steps_ = 0;
  double peak_ = 0.0;
};

class PeakForceKind final : public epaphe::ObserverKind {
public:
  std::string name() const override { return "Peak force"; }
  std::string description() const override { return "The peak total contact force of the run"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Peak force"));
    epaphe::deck::addString(*pl, "Group", "/peak_force", "HDF5 group of its attributes");
    return pl;
  }
  std::unique_ptr<epaphe::RunObserver> make(const Teuchos::ParameterList& params,
                                            const epaphe::ObserverContext& context) const override {
    return std::make_unique<PeakForce>(context.file, params.get<std::string>("Group"));
  }
};

/// Handed to the run by the program: counts the steps.
class StepCounter final : public epaphe::RunObserver {
public:
  void endStep(epaphe::ExplicitLoop&) override { ++steps; }
  long long steps = 0;
};

}  // namespace

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  if (argc < 3) {
    std::cerr << "usage: consumer_extension DECK OUTPUT.h5\n";
    return 2;
  }
  epaphe::registerContactLaw(std::make_shared<HertzLaw>());
  epaphe::registerObserver(std::make_shared<PeakForceKind>());
  bool ok = true;
  try {
    const epaphe::Deck deck = epaphe::readDeck(argv[1]);  // validated against the schema with "Hertz"
    rt.initializeKokkos(1);
    StepCounter counter;
    epaphe::RunSummary summary;
    {
      epaphe::Simulation sim(deck, rt, argv[2]);
      sim.addObserver(&counter);
      sim.setup();
      summary = sim.run();
      sim.printSummary(std::cout);
    }
    epaphe::io::Hdf5File out(argv[2], epaphe::io::Hdf5File::Mode::ReadOnly);
    const double observed = out.doubleAttribute("/peak_force", "peak_total_force");
    const long long observedSteps = out.intAttribute("/peak_force", "steps");
    std::cout << "Hertz law: " << lawCalls << " steps with contact, peak total force " << lawPeak
              << " N; peak force observer: " << observedSteps << " steps, " << observed
              << " N; step counter: " << counter.steps << " of " << summary.steps << " steps\n";
    // the run completed, with the law's forces: contact over many steps, its peak the run's peak
    ok = ok && summary.status == "complete";
    ok = ok && lawCalls > 100 && lawPeak > 0.0 && std::abs(observed - lawPeak) <= 1e-12 * lawPeak;
    // whatever the law, the elastic bar (0.64 kg at 100 m/s) rebounds: the impulse is 2 m v = 128 N s
    // (V1; within 2 %), and the peak is of the order of its impact force rho c A v = 1.6 MN (within 50 %:
    // the Hertz spring is softer than the bar's end and rings)
    ok = ok && std::abs(summary.totals.impulse - 128.0) < 0.02 * 128.0;
    ok = ok && std::abs(lawPeak - 1.6e6) < 0.5 * 1.6e6;
    // both observers saw every step
    ok = ok && observedSteps == summary.steps && counter.steps == summary.steps && summary.steps > 0;
  } catch (const std::exception& e) {
    std::cerr << "consumer_extension: " << e.what() << "\n";
    ok = false;
  }
  std::cout << (ok ? "consumer_extension OK" : "consumer_extension FAILED") << "\n";
  return ok ? 0 : 1;
}
