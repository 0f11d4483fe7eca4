#include "Epaphe_ReductionMethod.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Registry.hpp"
#include "Epaphe_Runtime.hpp"

#include <algorithm>
#include <mutex>

namespace epaphe {

// Epaphe_ReductionMethods.cpp
void registerBuiltInReductions(const std::function<void(const std::string&, ReductionRegistry::Factory)>& add);

namespace {

/// The registry, the built-in methods first.
NamedFactories<ReductionRegistry::Factory>& registry() {
  static NamedFactories<ReductionRegistry::Factory> r("reduction method");
  static std::once_flag builtIns;
  std::call_once(builtIns, [] {
    registerBuiltInReductions([](const std::string& n, ReductionRegistry::Factory f) { r.add(n, std::move(f)); });
  });
  return r;
}

}  // namespace

void ReductionRegistry::add(const std::string& name, Factory factory) {
  registry().add(name, std::move(factory));
}

std::unique_ptr<ReductionMethod> ReductionRegistry::make(const std::string& name, const std::string& context) {
  return registry().find(name, context)();
}

std::vector<std::string> ReductionRegistry::names() {
  return registry().names();
}

int ReductionRegistry::version() {
  return registry().version();
}

std::unique_ptr<ReductionMethod> reductionMethod(const Teuchos::ParameterList& rp) {
  auto m = ReductionRegistry::make(rp.get<std::string>("Method"), deck::pathOf(rp, "Method"));
  m->setParameters(rp);
  return m;
}

std::string ReductionMethod::describe(const ReducedModel&, const ReductionReport&, int) const {
  return "";
}

FrequencyCheck ReductionMethod::frequencyCheck(const FullModel& full, const ReducedModel& model, int count,
                                               const ReductionReport&) const {
  FrequencyCheck c;
  Stopwatch sw;
  count = std::min(count, full.numFree - 1);
  c.full = fullModelFrequencies(full, count, LinearSolver::Mumps, 1e-12,
                                model.sparse() ? std::vector<double>{} : reducedFrequencies(model));
  c.seconds = sw.seconds();
  return c;
}

void ReductionMethod::checkMesh(const ReductionMeshFacts&) const {}

void ReductionMethod::checkSpeedRange(const Teuchos::ParameterList&, const std::string&) const {}

SpeedParametricModel ReductionMethod::parametricModel(SpeedSampleSource&, const std::vector<int>&,
                                                      const std::vector<double>&, ReductionReport*) const {
  throw Error("reduction method '" + name() + "' has no parametric model over a speed range");
}

}  // namespace epaphe
