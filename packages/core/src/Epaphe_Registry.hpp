#pragma once
// Factories keyed by the deck's name of what they make (a reduction method, an importer), in the
// order they were added: the registries of Epaphe's extension points (docs/developer/extending.md).
#include "Epaphe_Error.hpp"

#include <string>
#include <utility>
#include <vector>

namespace epaphe {

/// Factories of one kind, keyed by the name the deck uses, kept in the order they were added.
/// `Factory` is what makes one object (usually an std::function).
template <class Factory>
class NamedFactories {
public:
  /// `what` names the kind of thing made, for messages ("reduction method").
  explicit NamedFactories(std::string what) : what_(std::move(what)) {}

  /// Adds `factory` under `name`; an Error when the name is taken.
  void add(const std::string& name, Factory factory) {
    for (const auto& e : entries_)
      EPAPHE_REQUIRE(e.first != name, what_ << " '" << name << "' is registered twice; give it another name");
    entries_.emplace_back(name, std::move(factory));
    ++version_;
  }
  /// The factory of `name`; an Error names `context` and the registered names.
  const Factory& find(const std::string& name, const std::string& context) const {
    for (const auto& e : entries_)
      if (e.first == name) return e.second;
    ErrorBuilder eb;
    eb << context << ": no " << what_ << " '" << name << "'; the registered ones are:";
    for (const auto& e : entries_) eb << " '" << e.first << "'";
    eb.raise();
  }
  /// The registered names, in the order they were added.
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const auto& e : entries_) n.push_back(e.first);
    return n;
  }
  /// Changes with every add(), so that what is built from the names knows when to rebuild.
  int version() const { return version_; }

private:
  std::string what_;
  std::vector<std::pair<std::string, Factory>> entries_;
  int version_ = 0;
};

}  // namespace epaphe
