#pragma once
// The registry of the kinds of observer a deck can ask for (Epaphe_RunObserver.hpp says what an
// observer of a run is): 'Observers-><name>' with 'Enabled' = true makes one for the run from the
// list's other keys. Apart from the observers themselves (HDF5, the loop), so that the deck schema
// can list the kinds' keys.
#include <memory>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

namespace epaphe {

class RunObserver;
struct ObserverContext;

/// A kind of observer the deck can ask for (see the file's opening comment): its name, documentation and
/// keys, and the observer it makes.
class ObserverKind {
public:
  virtual ~ObserverKind() = default;
  /// Its sublist's name in 'Observers'.
  virtual std::string name() const = 0;
  /// The sublist's documentation.
  virtual std::string description() const = 0;
  /// Its keys ('Enabled' is added by the schema).
  virtual Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const = 0;
  /// The observer, from its validated sublist.
  virtual std::unique_ptr<RunObserver> make(const Teuchos::ParameterList& params,
                                            const ObserverContext& context) const = 0;
};

/// Adds a kind to the registry (a program does it before it reads a deck); a name registered already
/// is refused.
void registerObserver(std::shared_ptr<const ObserverKind> kind);
/// The registered kinds, in the order of registration.
std::vector<std::shared_ptr<const ObserverKind>> observerKinds();
/// Counts the registrations (the deck schema is rebuilt when it changes).
int observerRevision();
/// The deck's Observers list: one sublist per registered kind, with 'Enabled' and its keys.
void addObserverParameters(Teuchos::ParameterList& epaphe);

}  // namespace epaphe
