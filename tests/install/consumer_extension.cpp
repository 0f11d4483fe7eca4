// Extends an installed Epaphe from outside, as docs/developer/extending.md says, at its four extension
// points: its own contact law (a Hertz law, lambda = k (-g*)^(3/2), registered under 'Contact->Method' =
// "Hertz" with its own key 'Hertz stiffness'), its own reduction method ("Consumer reduction":
// Craig-Bampton with its own key 'Consumer modes'), its own importer ("Consumer bar": a bar of Epaphe's
// hexahedra from its own keys 'Consumer length' and 'Consumer elements') and its own observer (the peak
// total contact force, enabled from the deck's 'Observers->Peak force' and writing its result to the HDF5
// output), plus an observer it hands to the run itself (Simulation::addObserver). It runs the deck given
// (custom-law.xml: the bar of V1 hitting a wall, made by those) and checks that the law made the forces of
// the run, that the importer and the reduction method built the model, and that both observers were called
// at every step.
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_ContactLaw.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_ForwardIncrementLagrange.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ModelImporter.hpp"
#include "Epaphe_ReductionMethod.hpp"
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

// What the reduction method and the importer did: models reduced, models built.
int reductions = 0, imports = 0;

/// Craig-Bampton under a name of its own, its mode count from its own key 'Consumer modes'.
class ConsumerReduction final : public epaphe::ModalReduction {
public:
  std::string name() const override { return "Consumer reduction"; }
  std::string documentation() const override { return "Craig-Bampton with 'Consumer modes' modes"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Reduction"));
    epaphe::deck::addInt(*pl, "Consumer modes", 20, "Consumer reduction: fixed-interface modes kept", 0, 100000);
    return pl;
  }
  void setParameters(const Teuchos::ParameterList& rp) override {
    options_ = epaphe::craigBamptonOptions(rp, false);  // the shared solver keys, as Craig-Bampton reads them
    options_.modes = rp.get<int>("Consumer modes");
  }
  std::string cacheKeyText() const override { return "\nconsumer modes=" + std::to_string(options_.modes); }
  bool cacheable() const override { return false; }
  epaphe::ReducedModel reduce(const epaphe::FullModel& full, const std::vector<int>& retained,
                              epaphe::ReductionReport* report) const override {
    ++reductions;
    return epaphe::craigBampton(full, retained, options_, report);
  }
  std::string modelName(const epaphe::ReducedModel&) const override { return name(); }
};

/// A bar along x of Epaphe's hexahedra (the Box mesh's node sets: x+, x-, ...).
class ConsumerBar final : public epaphe::ModelImporter {
public:
  std::string name() const override { return "Consumer bar"; }
  std::string documentation() const override { return "a bar along x, 20 x 20 mm"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Mesh"));
    epaphe::deck::addDouble(*pl, "Consumer length", 0.2, "Consumer bar: length along x (m)", 1e-300);
    epaphe::deck::addInt(*pl, "Consumer elements", 10, "Consumer bar: hexahedra along x", 1, 100000);
    return pl;
  }
  bool builtInMesh() const override { return true; }
  epaphe::Mesh mesh(const epaphe::ImportRequest& r) const override {
    return epaphe::makeBoxMesh({0, 0, 0}, {r.mesh().get<double>("Consumer length"), 0.02, 0.02},
                               {r.mesh().get<int>("Consumer elements"), 1, 1});
  }
  epaphe::FullModel build(const epaphe::ImportRequest& r,
                          const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const override {
    ++imports;
    const Teuchos::ParameterList& mp = r.bodyParams->sublist("Material");
    epaphe::Material mat;
    mat.density = mp.get<double>("Density");
    mat.young = mp.get<double>("Young's modulus");
    mat.poisson = mp.get<double>("Poisson's ratio");
    return epaphe::assembleHexModel(r.body, mesh(r), mat, {}, comm);
  }
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
  epaphe::ReductionRegistry::add("Consumer reduction", [] { return std::make_unique<ConsumerReduction>(); });
  epaphe::ImporterRegistry::add("Consumer bar", [] { return std::make_unique<ConsumerBar>(); });
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
              << " N; step counter: " << counter.steps << " of " << summary.steps << " steps; " << imports
              << " model(s) imported, " << reductions << " reduced by the consumer's method; the history's "
              << "reduction attribute: " << out.stringAttribute("/bodies/Bar", "reduction") << "\n";
    // the run completed, with the law's forces: contact over many steps, its peak the run's peak
    ok = ok && summary.status == "complete";
    ok = ok && lawCalls > 100 && lawPeak > 0.0 && std::abs(observed - lawPeak) <= 1e-12 * lawPeak;
    // whatever the law, the elastic bar (0.64 kg at 100 m/s) rebounds: the impulse is 2 m v = 128 N s
    // (V1; within 2 %), and the peak is of the order of its impact force rho c A v = 1.6 MN (within 50 %:
    // the Hertz spring is softer than the bar's end and rings)
    ok = ok && std::abs(summary.totals.impulse - 128.0) < 0.02 * 128.0;
    ok = ok && std::abs(lawPeak - 1.6e6) < 0.5 * 1.6e6;
    // the consumer's importer built the bar and its method reduced it, under its name
    ok = ok && imports == 1 && reductions == 1 &&
         out.stringAttribute("/bodies/Bar", "reduction") == "Consumer reduction";
    // both observers saw every step
    ok = ok && observedSteps == summary.steps && counter.steps == summary.steps && summary.steps > 0;
  } catch (const std::exception& e) {
    std::cerr << "consumer_extension: " << e.what() << "\n";
    ok = false;
  }
  std::cout << (ok ? "consumer_extension OK" : "consumer_extension FAILED") << "\n";
  return ok ? 0 : 1;
}
