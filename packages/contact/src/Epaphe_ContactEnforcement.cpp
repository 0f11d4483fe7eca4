#include "Epaphe_ContactEnforcement.hpp"

#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_Error.hpp"

#include <cmath>

namespace epaphe {

Kokkos::View<int*> ContactStepViews::upload(const std::vector<int>& list) const {
  EPAPHE_REQUIRE(list.size() <= active.extent(0),
                 "contact: " << list.size() << " active nodes, room for " << active.extent(0));
  const auto a = Kokkos::subview(active, Kokkos::make_pair(0, static_cast<int>(list.size())));
  for (std::size_t i = 0; i < list.size(); ++i) a(i) = list[i];  // host-accessible (ContactDetection)
  return a;
}

Teuchos::ParameterList ContactOptions::complete() const {
  Teuchos::ParameterList all = *contactValidParameters();
  all.setParameters(contact);  // the keys set over the defaults
  return all;
}

std::string ContactOptions::method() const {
  return contact.isParameter("Method") ? contact.get<std::string>("Method") : std::string("Lagrange");
}

std::unique_ptr<ContactEnforcement> makeContactEnforcement(const ContactOptions& o, int numNodes,
                                                           const CoatingViews* coat, CoatingContact** coating) {
  const Teuchos::ParameterList cp = o.complete();
  const ContactLaw& law = contactLaw(o.method());
  const ContactLawSetup setup{numNodes, o.timeStep};
  const double mu = cp.get<double>("Friction coefficient");
  EPAPHE_REQUIRE(std::isfinite(mu) && mu >= 0.0,
                 "contact: friction coefficient mu = " << mu << "; it must be a finite value >= 0 (0: frictionless)");
  std::unique_ptr<ContactEnforcement> e = law.make(cp, setup);
  if (mu > 0.0) {
    EPAPHE_REQUIRE(law.supportsFriction(), "contact: the law '" << law.name() << "' has no Coulomb friction (mu = "
                                                                << mu << "); set 'Friction coefficient' = 0");
    e = law.withFriction(std::move(e), mu, cp.get<bool>("Warm friction start"), cp, setup);
  }
  if (coating) *coating = nullptr;
  if (coat && coat->any()) {  // nodes facing a coated surface follow its element law; the deck's law solves its rows
    EPAPHE_REQUIRE(law.supportsCoatings(), "contact: the law '" << law.name()
                                                                << "' takes no abradable coating; remove the "
                                                                   "surfaces' 'Coating' elements");
    auto c = law.withCoating(std::move(e), *coat, cp, setup);
    if (coating) *coating = c.get();
    e = std::move(c);
  }
  return e;
}

ContactOptions contactOptions(const Teuchos::ParameterList& cp, double h) {
  ContactOptions o;
  o.contact = cp;
  o.timeStep = h;
  return o;
}

}  // namespace epaphe
