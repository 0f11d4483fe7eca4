#include "Epaphe_ContactLaw.hpp"

#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_ContactDetection.hpp"
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_CoulombFriction.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ForwardIncrementLagrange.hpp"

#include <mutex>

namespace epaphe {

std::unique_ptr<ContactEnforcement> ContactLaw::withFriction(std::unique_ptr<ContactEnforcement>, double, bool,
                                                             const Teuchos::ParameterList&,
                                                             const ContactLawSetup&) const {
  return nullptr;  // supportsFriction() is false
}

std::unique_ptr<CoatingContact> ContactLaw::withCoating(std::unique_ptr<ContactEnforcement>, const CoatingViews&,
                                                        const Teuchos::ParameterList&, const ContactLawSetup&) const {
  return nullptr;  // supportsCoatings() is false
}

namespace {

/// Forward-increment Lagrange multipliers: the gaps close exactly; friction and coatings solve rows.
class LagrangeLaw final : public ContactLaw {
public:
  std::string name() const override { return "Lagrange"; }
  std::string description() const override { return "forward-increment multipliers (eqs. 2.30-2.33)"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    return ForwardIncrementLagrange::getValidParameters();
  }
  std::unique_ptr<ContactEnforcement> make(const Teuchos::ParameterList& contact,
                                           const ContactLawSetup& s) const override {
    return std::make_unique<ForwardIncrementLagrange>(contact.get<bool>("Lump contact matrix"), s.numNodes);
  }
  bool closesGaps() const override { return true; }
  bool supportsFriction() const override { return true; }
  std::unique_ptr<ContactEnforcement> withFriction(std::unique_ptr<ContactEnforcement> law, double mu, bool warm,
                                                   const Teuchos::ParameterList&,
                                                   const ContactLawSetup& s) const override {
    return std::make_unique<CoulombFriction>(mu, false, 0.0, s.timeStep, s.numNodes, std::move(law), warm);
  }
  bool supportsCoatings() const override { return true; }
  std::unique_ptr<CoatingContact> withCoating(std::unique_ptr<ContactEnforcement> law, const CoatingViews& coat,
                                              const Teuchos::ParameterList&, const ContactLawSetup& s) const override {
    return std::make_unique<CoatingContact>(std::move(law), false, 0.0, coat, s.numNodes);
  }
};

/// Penalty: a known force k_p (-g*) per node; friction and coatings take it as the known normal force.
class PenaltyLaw final : public ContactLaw {
public:
  std::string name() const override { return "Penalty"; }
  std::string description() const override { return "lambda = kp * penetration (eq. 2.34)"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    return PenaltyContact::getValidParameters();
  }
  std::unique_ptr<ContactEnforcement> make(const Teuchos::ParameterList& contact,
                                           const ContactLawSetup&) const override {
    return std::make_unique<PenaltyContact>(kp(contact));
  }
  bool closesGaps() const override { return false; }
  bool supportsFriction() const override { return true; }
  std::unique_ptr<ContactEnforcement> withFriction(std::unique_ptr<ContactEnforcement> law, double mu, bool warm,
                                                   const Teuchos::ParameterList& contact,
                                                   const ContactLawSetup& s) const override {
    return std::make_unique<CoulombFriction>(mu, true, kp(contact), s.timeStep, s.numNodes, std::move(law), warm);
  }
  bool supportsCoatings() const override { return true; }
  std::unique_ptr<CoatingContact> withCoating(std::unique_ptr<ContactEnforcement> law, const CoatingViews& coat,
                                              const Teuchos::ParameterList& contact,
                                              const ContactLawSetup& s) const override {
    return std::make_unique<CoatingContact>(std::move(law), true, kp(contact), coat, s.numNodes);
  }
  // The penalty acts on the predicted gap (forward increment, eq. 2.28 with lambda = kp (-g*)): for a
  // mass m on a spring kp alone, u_{n+1} = (1 - a)(2 u_n - u_{n-1}), a = h^2 kp / m, whose roots stay
  // in the unit circle for a <= 4/3, a third of the 4 of an ordinary spring (h omega <= 2). So each
  // penalty spring counts three times in the estimate.
  double stableStepStiffness(const Teuchos::ParameterList& contact) const override { return 3.0 * kp(contact); }
  std::string stiffnessKey() const override { return "Penalty stiffness"; }
  double springStiffness(const Teuchos::ParameterList& contact) const override { return kp(contact); }

private:
  static double kp(const Teuchos::ParameterList& contact) { return contact.get<double>("Penalty stiffness"); }
};

struct Registry {
  Registry() : laws{std::make_shared<LagrangeLaw>(), std::make_shared<PenaltyLaw>()} {}  // the built-in laws
  std::mutex mutex;
  std::vector<std::shared_ptr<const ContactLaw>> laws;
  int revision = 0;
};

Registry& registry() {
  static Registry r;
  return r;
}

/// The Contact list's keys that are not a law's: friction's and the detection's.
Teuchos::RCP<Teuchos::ParameterList> sharedContactKeys() {
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Contact"));
  pl->setParameters(*ContactDetection::getValidParameters());
  pl->setParameters(*CoulombFriction::getValidParameters());
  return pl;
}

}  // namespace

void registerContactLaw(std::shared_ptr<const ContactLaw> law) {
  EPAPHE_REQUIRE(law != nullptr, "contact: registerContactLaw() was given no law");
  const std::string name = law->name();
  const auto keys = law->getValidParameters();
  EPAPHE_REQUIRE(!name.empty() && !keys.is_null(), "contact: a contact law needs a name and a parameter list");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  auto taken = sharedContactKeys();
  for (const auto& other : r.laws) {
    EPAPHE_REQUIRE(other->name() != name, "contact: a contact law named '" << name << "' is registered already");
    taken->setParameters(*other->getValidParameters());
  }
  for (auto it = keys->begin(); it != keys->end(); ++it)
    EPAPHE_REQUIRE(!taken->isParameter(keys->name(it)) && keys->name(it) != "Method",
                   "contact: the law '" << name << "' declares the key '" << keys->name(it)
                                        << "', which the Contact list holds already; rename it");
  r.laws.push_back(std::move(law));
  ++r.revision;
}

const ContactLaw& contactLaw(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::string names;
  for (const auto& law : r.laws) {
    if (law->name() == name) return *law;
    names += (names.empty() ? "'" : ", '") + law->name() + "'";
  }
  throw Error("contact: no contact law named '" + name + "'; the registered ones are " + names);
}

std::vector<std::string> contactLawNames() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& law : r.laws) names.push_back(law->name());
  return names;
}

int contactLawRevision() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.revision;
}

Teuchos::RCP<const Teuchos::ParameterList> contactValidParameters() {
  std::vector<std::shared_ptr<const ContactLaw>> laws;
  {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    laws = r.laws;
  }
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Contact"));
  std::vector<std::string> names;
  std::vector<int> values;
  std::string doc;
  for (const auto& law : laws) {
    values.push_back(static_cast<int>(names.size()));
    names.push_back(law->name());
    doc += (doc.empty() ? "" : "; ") + law->name() + ": " + law->description();
  }
  deck::addEnum(*pl, "Method", "Lagrange", names, values, doc);
  pl->setParameters(*ContactDetection::getValidParameters());
  for (const auto& law : laws) pl->setParameters(*law->getValidParameters());
  pl->setParameters(*CoulombFriction::getValidParameters());
  return pl;
}

}  // namespace epaphe
