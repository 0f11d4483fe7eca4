#include "Epaphe_ObserverKind.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"

#include <mutex>

namespace epaphe {

namespace {

struct Registry {
  std::mutex mutex;
  std::vector<std::shared_ptr<const ObserverKind>> kinds;
  int revision = 0;
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void registerObserver(std::shared_ptr<const ObserverKind> kind) {
  EPAPHE_REQUIRE(kind != nullptr && !kind->name().empty(), "registerObserver(): an observer kind needs a name");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& k : r.kinds)
    EPAPHE_REQUIRE(k->name() != kind->name(), "an observer kind named '" << kind->name() << "' is registered already");
  r.kinds.push_back(std::move(kind));
  ++r.revision;
}

std::vector<std::shared_ptr<const ObserverKind>> observerKinds() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.kinds;
}

int observerRevision() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.revision;
}

void addObserverParameters(Teuchos::ParameterList& epaphe) {
  auto& list = epaphe.sublist("Observers", false,
                              "Observers of the loop a program registered (registerObserver), one sublist each; "
                              "'Enabled' = true adds one to the run");
  for (const auto& kind : observerKinds()) {
    auto& pl = list.sublist(kind->name(), false, kind->description());
    deck::addBool(pl, "Enabled", false, "Add this observer to the run");
    pl.setParameters(*kind->getValidParameters());
  }
}

}  // namespace epaphe
