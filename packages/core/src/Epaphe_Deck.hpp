#pragma once
// Decks are Teuchos XML parameter lists, validated before anything runs.
//
// Every configurable component offers a `validParameters()` list built with the add* helpers
// below: each entry carries its documentation, default and validator (range, or the list of
// allowed strings that become enums at parse time). `validateAndSetDefaults` walks a user deck
// against it: an unknown key is an error naming the key and the closest valid one; a wrong type
// or an out-of-range value names the value and the allowed range. A valid sublist named "*"
// is a template for sublists of any name (one per body, per surface, ...).
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>

#include <iosfwd>
#include <limits>
#include <array>
#include <string>
#include <vector>

/// Deck reading and validation: Teuchos XML parameter lists, the add* helpers that declare parameters
/// with their documentation, default and validator, and the typed getters.
namespace epaphe::deck {

/// Parses an XML deck file. Missing or unreadable file and malformed XML raise epaphe::Error
/// naming the file (and the parser's line when it gives one).
Teuchos::RCP<Teuchos::ParameterList> readXmlFile(const std::string& path);
/// Same, from text; `origin` names the source in messages.
Teuchos::RCP<Teuchos::ParameterList> readXmlString(const std::string& xml, const std::string& origin);

/// Validates `user` against `valid` recursively, fills in defaults and attaches validators, so
/// that getEnum() works on the result. `origin` names the deck in messages; `text`, when given,
/// lets messages cite the line of the offending key.
void validateAndSetDefaults(Teuchos::ParameterList& user, const Teuchos::ParameterList& valid,
                            const std::string& origin, const std::string& text = "");

/// The candidate closest to `key` (case-insensitive Levenshtein), or "" when none is close.
std::string nearest(const std::string& key, const std::vector<std::string>& candidates);

/// Prints every valid parameter with its type, default, allowed values and documentation.
void printDocumentation(std::ostream& os, const Teuchos::ParameterList& valid, int indent = 0);

// ---- declaring parameters ---------------------------------------------------------------------
/// Infinity, the default bounds of addDouble().
constexpr double inf = std::numeric_limits<double>::infinity();
/// Declares a double parameter: default `def`, documentation `doc`, valid in [min, max].
void addDouble(Teuchos::ParameterList& pl, const std::string& name, double def, const std::string& doc,
               double min = -inf, double max = inf);
/// Declares an int parameter: default `def`, documentation `doc`, valid in [min, max].
void addInt(Teuchos::ParameterList& pl, const std::string& name, int def, const std::string& doc,
            int min = std::numeric_limits<int>::min(), int max = std::numeric_limits<int>::max());
/// Declares a bool parameter with its default and documentation.
void addBool(Teuchos::ParameterList& pl, const std::string& name, bool def, const std::string& doc);
/// Declares a string parameter (any value) with its default and documentation.
void addString(Teuchos::ParameterList& pl, const std::string& name, const std::string& def, const std::string& doc);
/// Declares an Array(double) parameter with its default and documentation.
void addDoubleArray(Teuchos::ParameterList& pl, const std::string& name, const std::vector<double>& def,
                    const std::string& doc);
/// Declares an Array(int) parameter with its default and documentation.
void addIntArray(Teuchos::ParameterList& pl, const std::string& name, const std::vector<int>& def,
                 const std::string& doc);
/// Declares an Array(string) parameter with its default and documentation.
void addStringArray(Teuchos::ParameterList& pl, const std::string& name, const std::vector<std::string>& def,
                    const std::string& doc);
/// A string chosen among `names`, stored as the integral value of the matching `values`.
void addEnum(Teuchos::ParameterList& pl, const std::string& name, const std::string& def,
             const std::vector<std::string>& names, const std::vector<int>& values, const std::string& doc);

/// The enum value of a validated string entry.
template <class E>
E getEnum(const Teuchos::ParameterList& pl, const std::string& name) {
  return static_cast<E>(Teuchos::getIntegralValue<int>(pl, name));
}
/// A validated Array(double) entry as a std::vector.
std::vector<double> getDoubles(const Teuchos::ParameterList& pl, const std::string& name);
/// A point or vector {x, y, z}: exactly 3 finite values, else an error naming `origin` (the deck)
/// and the key's path.
std::array<double, 3> getVec3(const Teuchos::ParameterList& pl, const std::string& name, const std::string& origin);
/// A validated Array(int) entry as a std::vector.
std::vector<int> getInts(const Teuchos::ParameterList& pl, const std::string& name);
/// A validated Array(string) entry as a std::vector.
std::vector<std::string> getStrings(const Teuchos::ParameterList& pl, const std::string& name);

/// "Epaphe->Time->Time step" style path of a (sub)list entry, for messages.
std::string pathOf(const Teuchos::ParameterList& pl, const std::string& name);

}  // namespace epaphe::deck
