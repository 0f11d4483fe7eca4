#include "Epaphe_RunObserver.hpp"

#include "Epaphe_Error.hpp"

namespace epaphe {

std::vector<std::unique_ptr<RunObserver>> makeDeckObservers(const Teuchos::ParameterList& epaphe,
                                                            const ObserverContext& context) {
  std::vector<std::unique_ptr<RunObserver>> made;
  if (!epaphe.isSublist("Observers")) return made;
  const Teuchos::ParameterList& list = epaphe.sublist("Observers");
  for (const auto& kind : observerKinds()) {
    if (!list.isSublist(kind->name())) continue;
    const Teuchos::ParameterList& pl = list.sublist(kind->name());
    if (!pl.get<bool>("Enabled")) continue;
    made.push_back(kind->make(pl, context));
    EPAPHE_REQUIRE(made.back() != nullptr, "observer '" << kind->name() << "': its kind made no observer");
  }
  return made;
}

}  // namespace epaphe
