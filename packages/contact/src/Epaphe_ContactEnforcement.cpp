#include "Epaphe_ContactEnforcement.hpp"

#include "Epaphe_ContactDetection.hpp"
#include "Epaphe_CoulombFriction.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ForwardIncrementLagrange.hpp"

#include <cmath>

namespace epaphe {

Kokkos::View<int*> ContactStepViews::upload(const std::vector<int>& list) const {
  EPAPHE_REQUIRE(list.size() <= active.extent(0),
                 "contact: " << list.size() << " active nodes, room for " << active.extent(0));
  const auto a = Kokkos::subview(active, Kokkos::make_pair(0, static_cast<int>(list.size())));
  for (std::size_t i = 0; i < list.size(); ++i) a(i) = list[i];  // host-accessible (ContactDetection)
  return a;
}

std::unique_ptr<ContactEnforcement> makeContactEnforcement(const ContactOptions& o, int numNodes) {
  EPAPHE_REQUIRE(
      std::isfinite(o.friction) && o.friction >= 0.0,
      "contact: friction coefficient mu = " << o.friction << "; it must be a finite value >= 0 (0: frictionless)");
  std::unique_ptr<ContactEnforcement> normal;
  if (o.method == ContactMethod::Penalty)
    normal = std::make_unique<PenaltyContact>(o.penaltyStiffness);
  else
    normal = std::make_unique<ForwardIncrementLagrange>(o.lumped, numNodes);
  if (o.friction == 0.0) return normal;
  return std::make_unique<CoulombFriction>(o.friction, o.method == ContactMethod::Penalty, o.penaltyStiffness,
                                           o.timeStep, numNodes, std::move(normal), o.warmFriction);
}

Teuchos::RCP<const Teuchos::ParameterList> contactValidParameters() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Contact"));
  deck::addEnum(*pl, "Method", "Lagrange", {"Lagrange", "Penalty"},
                {int(ContactMethod::Lagrange), int(ContactMethod::Penalty)},
                "Lagrange: forward-increment multipliers (eqs. 2.30-2.33); Penalty: lambda = kp * penetration "
                "(eq. 2.34)");
  pl->setParameters(*PenaltyContact::getValidParameters());
  pl->setParameters(*ContactDetection::getValidParameters());
  pl->setParameters(*ForwardIncrementLagrange::getValidParameters());
  pl->setParameters(*CoulombFriction::getValidParameters());
  return pl;
}

ContactOptions contactOptions(const Teuchos::ParameterList& cp, double h) {
  ContactOptions o;
  o.method = deck::getEnum<ContactMethod>(cp, "Method");
  o.penaltyStiffness = cp.get<double>("Penalty stiffness");
  o.nrTolerance = cp.get<double>("Newton tolerance");
  o.nrMaxIterations = cp.get<int>("Newton max iterations");
  o.lumped = cp.get<bool>("Lump contact matrix");
  o.friction = cp.get<double>("Friction coefficient");
  o.edgeTolerance = cp.get<double>("Edge tolerance");
  o.skipDistant = cp.get<bool>("Skip distant nodes");
  o.warmFriction = cp.get<bool>("Warm friction start");
  o.timeStep = h;
  return o;
}

}  // namespace epaphe
