#pragma once
// Contact laws as the deck names them ('Contact->Method'): an interface and a registry keyed by that
// name. A law owns its deck keys (getValidParameters(), merged into the Contact list of the schema),
// makes the enforcement that runs at every step (Epaphe_ContactEnforcement.hpp), says how Coulomb
// friction and an abradable coating attach to it, and answers what the rest of Epaphe asks of it before
// a run: the stiffness it adds to the stable-step estimate, the springs the energy monitor may bound,
// whether it closes the gaps exactly (the massless boundary needs it), and its own refusals.
//
// The built-in laws, registered before any other:
//   Lagrange  forward-increment multipliers (eqs. 2.30-2.33), ForwardIncrementLagrange
//   Penalty   lambda = k_p (-g*) (eq. 2.34), PenaltyContact
// A program adds its own with registerContactLaw() before it reads a deck; no file of Epaphe changes
// (docs/developer/extending.md). The enforcement is called once per step (or per add pass) on the
// whole active set, so a law keeps its per-node work inside its own kernels.
#include <memory>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

namespace epaphe {

class ContactEnforcement;
class CoatingContact;
struct CoatingViews;

/// What a law's enforcement is built for.
struct ContactLawSetup {
  int numNodes = 0;       ///< contact nodes: work arrays are sized once for all of them
  double timeStep = 0.0;  ///< h (friction: the turning surfaces' motion over a step)
};

/// A contact law as the deck names it (see the file's opening comment): its keys, the enforcement it
/// makes and its answers to the checks made before a run.
class ContactLaw {
public:
  virtual ~ContactLaw() = default;
  /// The deck's name of the law ('Contact->Method').
  virtual std::string name() const = 0;
  /// One phrase for the documentation of 'Method' (what the law does, with its equation).
  virtual std::string description() const = 0;
  /// Its own keys in the Contact list, with defaults, documentation and validators. Keys must not
  /// clash with another law's, friction's or the detection's.
  virtual Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const = 0;
  /// The frictionless enforcement. `contact`: the Contact list, every key present (defaults filled).
  virtual std::unique_ptr<ContactEnforcement> make(const Teuchos::ParameterList& contact,
                                                   const ContactLawSetup& setup) const = 0;
  /// True when the law closes the gaps exactly: the operator then adds the nodes that the others'
  /// correction makes penetrate, and the massless boundary accepts it.
  virtual bool closesGaps() const = 0;

  /// Coulomb friction ('Friction coefficient' > 0) wraps the law when it supports it.
  virtual bool supportsFriction() const { return false; }
  /// The law with friction mu > 0 (`warm`: 'Warm friction start'); called only when supportsFriction().
  virtual std::unique_ptr<ContactEnforcement> withFriction(std::unique_ptr<ContactEnforcement> law, double mu,
                                                           bool warm, const Teuchos::ParameterList& contact,
                                                           const ContactLawSetup& setup) const;
  /// A surface with an abradable coating wraps the law (CoatingContact) when it supports it.
  virtual bool supportsCoatings() const { return false; }
  /// The coating law on top of `law` (which solves the coating's rows); called only when supportsCoatings().
  virtual std::unique_ptr<CoatingContact> withCoating(std::unique_ptr<ContactEnforcement> law, const CoatingViews& coat,
                                                      const Teuchos::ParameterList& contact,
                                                      const ContactLawSetup& setup) const;

  /// The stiffness counted on every contact DOF in the stable-step estimate (0: none).
  virtual double stableStepStiffness(const Teuchos::ParameterList& /*contact*/) const { return 0.0; }
  /// The key that lowers that stiffness, named when the time step is unstable ("": none).
  virtual std::string stiffnessKey() const { return ""; }
  /// The stiffness k of the springs its forces are, lambda = k (-g*), so that the bodies' energy
  /// cannot exceed what they were given (the energy monitor's bound); 0: the law promises no such bound.
  virtual double springStiffness(const Teuchos::ParameterList& /*contact*/) const { return 0.0; }
  /// Refusals of its values the schema cannot state, before anything is built (--check). `origin`:
  /// the deck's name for the messages.
  virtual void check(const Teuchos::ParameterList& /*contact*/, const std::string& /*origin*/) const {}
};

/// Adds a law to the registry (a program does it before it reads a deck). A name already registered,
/// or a key another law or the Contact list already holds, is refused.
void registerContactLaw(std::shared_ptr<const ContactLaw> law);
/// The registered law of that name (refused with the registered names when there is none).
const ContactLaw& contactLaw(const std::string& name);
/// The registered laws' names, the built-in ones first.
std::vector<std::string> contactLawNames();
/// Counts the registrations (the deck schema is rebuilt when it changes).
int contactLawRevision();

/// The deck's Contact list: Method (the registered laws), every law's keys, friction's and the detection's.
Teuchos::RCP<const Teuchos::ParameterList> contactValidParameters();

}  // namespace epaphe
