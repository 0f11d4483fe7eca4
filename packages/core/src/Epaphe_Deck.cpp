#include "Epaphe_Deck.hpp"

#include "Epaphe_Error.hpp"

#include <Teuchos_Array.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <regex>
#include <cctype>
#include <cerrno>
#include <limits>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace epaphe::deck {
namespace {

using Teuchos::ParameterEntry;
using Teuchos::ParameterList;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::size_t levenshtein(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string typeName(const ParameterEntry& e) {
  if (e.isList()) return "ParameterList";
  if (e.isType<double>()) return "double";
  if (e.isType<int>()) return "int";
  if (e.isType<bool>()) return "bool";
  if (e.isType<std::string>()) return "string";
  if (e.isType<Teuchos::Array<double>>()) return "Array(double)";
  if (e.isType<Teuchos::Array<int>>()) return "Array(int)";
  if (e.isType<Teuchos::Array<std::string>>()) return "Array(string)";
  return e.getAny(false).typeName();
}

std::string valueText(const ParameterEntry& e) {
  if (e.isList()) return "(list)";
  std::ostringstream os;
  os << e.getAny(false);
  return os.str();
}

/// Line of `name="key"` in the deck text, or 0.
int lineOf(const std::string& text, const std::string& key) {
  if (text.empty()) return 0;
  const std::string pat = "name=\"" + key + "\"";
  std::size_t pos = text.find(pat);
  if (pos == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

std::string where(const std::string& origin, const std::string& text, const ParameterList& pl, const std::string& key) {
  std::ostringstream os;
  os << origin;
  if (int l = lineOf(text, key)) os << ":" << l;
  os << ": '" << pathOf(pl, key) << "'";
  return os.str();
}

std::vector<std::string> keysOf(const ParameterList& pl) {
  std::vector<std::string> keys;
  for (auto it = pl.begin(); it != pl.end(); ++it) keys.push_back(pl.name(it));
  return keys;
}

std::string joined(const std::vector<std::string>& v) {
  std::ostringstream os;
  for (std::size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << "'" << v[i] << "'";
  return os.str();
}

void checkEntry(ParameterList& user, const std::string& key, const ParameterEntry& validEntry,
                const std::string& origin, const std::string& text) {
  ParameterEntry& e = user.getEntry(key);
  const std::string expected = typeName(validEntry);
  // Integers are welcome where doubles are expected.
  if (validEntry.isType<double>() && e.isType<int>()) {
    const double d = e.getValue<int>(nullptr);
    user.set(key, d);
  }
  if (validEntry.isType<Teuchos::Array<double>>() && e.isType<Teuchos::Array<int>>()) {
    const auto& a = e.getValue<Teuchos::Array<int>>(nullptr);
    user.set(key, Teuchos::Array<double>(a.begin(), a.end()));
  }
  ParameterEntry& f = user.getEntry(key);
  if (typeName(f) != expected) {
    ErrorBuilder eb;
    eb << where(origin, text, user, key) << " has type " << typeName(f) << " (value " << valueText(f) << "), expected "
       << expected << "; write it as <Parameter name=\"" << key << "\" type=\"" << expected << "\" value=\"...\"/>";
    eb.raise();
  }

  auto validator = validEntry.validator();
  if (validator.is_null()) return;
  if (auto dv = Teuchos::rcp_dynamic_cast<const Teuchos::EnhancedNumberValidator<double>>(validator); !dv.is_null()) {
    const double v = f.getValue<double>(nullptr);
    if (!(v >= dv->getMin() && v <= dv->getMax())) {
      ErrorBuilder eb;
      eb << where(origin, text, user, key) << " = " << std::setprecision(10) << v
         << " is out of range: allowed values are in [" << dv->getMin() << ", " << dv->getMax() << "]";
      eb.raise();
    }
  } else if (auto iv = Teuchos::rcp_dynamic_cast<const Teuchos::EnhancedNumberValidator<int>>(validator);
             !iv.is_null()) {
    const int v = f.getValue<int>(nullptr);
    if (v < iv->getMin() || v > iv->getMax()) {
      ErrorBuilder eb;
      eb << where(origin, text, user, key) << " = " << v << " is out of range: allowed values are in [" << iv->getMin()
         << ", " << iv->getMax() << "]";
      eb.raise();
    }
  } else if (auto sv =
                 Teuchos::rcp_dynamic_cast<const Teuchos::StringToIntegralParameterEntryValidator<int>>(validator);
             !sv.is_null()) {
    const std::string v = f.getValue<std::string>(nullptr);
    std::vector<std::string> allowed(sv->validStringValues()->begin(), sv->validStringValues()->end());
    if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
      ErrorBuilder eb;
      eb << where(origin, text, user, key) << " = '" << v << "' is not one of " << joined(allowed);
      const std::string near = nearest(v, allowed);
      if (!near.empty()) eb << "; did you mean '" << near << "'?";
      eb.raise();
    }
  }
  f.setValidator(validator);
}

void validateList(ParameterList& user, const ParameterList& valid, const std::string& origin, const std::string& text,
                  const std::string& path) {
  user.setName(path);  // messages cite "Epaphe->Time->Time step" whatever the parser called it
  const bool hasTemplate = valid.isSublist("*");
  // 1. Every user key must be known.
  for (const std::string& key : keysOf(user)) {
    if (valid.isParameter(key)) continue;
    if (hasTemplate && user.isSublist(key)) continue;
    std::vector<std::string> candidates;
    for (const std::string& k : keysOf(valid))
      if (k != "*") candidates.push_back(k);
    ErrorBuilder eb;
    eb << origin;
    if (int l = lineOf(text, key)) eb << ":" << l;
    eb << ": unknown parameter '" << key << "' in list '" << user.name() << "'";
    const std::string near = nearest(key, candidates);
    if (!near.empty())
      eb << "; did you mean '" << near << "'?";
    else
      eb << "; valid keys are " << joined(candidates);
    eb << " (run with --print-parameters for the documentation of every key)";
    eb.raise();
  }
  // 2. Defaults, types, ranges, validators; recurse into sublists.
  for (auto it = valid.begin(); it != valid.end(); ++it) {
    const std::string& key = valid.name(it);
    const ParameterEntry& ve = valid.entry(it);
    if (key == "*") continue;
    if (ve.isList()) {
      if (user.isParameter(key) && !user.isSublist(key)) {
        ErrorBuilder eb;
        eb << where(origin, text, user, key) << " must be a <ParameterList name=\"" << key << "\">, not a parameter";
        eb.raise();
      }
      validateList(user.sublist(key), valid.sublist(key), origin, text, path + "->" + key);
      continue;
    }
    if (!user.isParameter(key)) {
      user.setEntry(key, ParameterEntry(ve.getAny(false), false, false, ve.docString(), ve.validator()));
      continue;
    }
    if (user.isSublist(key)) {
      ErrorBuilder eb;
      eb << where(origin, text, user, key) << " is a list, but a parameter of type " << typeName(ve) << " is expected";
      eb.raise();
    }
    checkEntry(user, key, ve, origin, text);
  }
  if (hasTemplate) {
    for (const std::string& key : keysOf(user))
      if (user.isSublist(key) && !valid.isParameter(key))
        validateList(user.sublist(key), valid.sublist("*"), origin, text, path + "->" + key);
  }
}

/// Teuchos reads "1e-5x" as 1e-5 and "{nan, 0}" as {0, 0} without a word: check every numeric
/// value of the text strictly first (whole token a number, and finite).
void checkNumbers(const std::string& xml, const std::string& origin) {
  static const std::regex tag(R"(<Parameter\s[^>]*>)");
  static const std::regex attr(R"re((\w+)\s*=\s*(?:"([^"]*)"|'([^']*)'))re");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator(); ++it) {
    std::map<std::string, std::string> a;
    const std::string t = it->str();
    for (auto jt = std::sregex_iterator(t.begin(), t.end(), attr); jt != std::sregex_iterator(); ++jt)
      a[(*jt)[1]] = (*jt)[2].matched ? (*jt)[2].str() : (*jt)[3].str();
    const std::string& type = a["type"];
    const auto lineHere = [&] { return 1 + std::count(xml.begin(), xml.begin() + it->position(), '\n'); };
    if (type == "bool") {
      // Teuchos' own message would not name the parameter.
      const std::string v = lower(a["value"]);
      if (v != "true" && v != "false" && v != "yes" && v != "no" && v != "0" && v != "1") {
        ErrorBuilder eb;
        eb << origin << ":" << lineHere() << ": parameter '" << a["name"] << "' of type bool has value \"" << a["value"]
           << "\"; write true or false";
        eb.raise();
      }
      continue;
    }
    const bool isInt = type == "int" || type == "Array(int)";
    if (!(isInt || type == "double" || type == "Array(double)")) continue;
    std::string v = a["value"];
    const bool array = type.rfind("Array", 0) == 0;
    if (array) {
      const auto b = v.find('{'), e = v.rfind('}');
      if (b == std::string::npos || e == std::string::npos || e < b) {
        ErrorBuilder eb;
        eb << origin << ":" << 1 + std::count(xml.begin(), xml.begin() + it->position(), '\n') << ": parameter '"
           << a["name"] << "' of type " << type << " has value \"" << v << "\"; write it as {1, 2, 3}";
        eb.raise();
      }
      v = v.substr(b + 1, e - b - 1);
    }
    std::stringstream ss(v);
    std::string token;
    while (std::getline(ss, token, array ? ',' : '\0')) {
      const auto first = token.find_first_not_of(" \t\n");
      if (first == std::string::npos) {
        if (array) continue;
      }
      const std::string tk =
          first == std::string::npos ? "" : token.substr(first, token.find_last_not_of(" \t\n") - first + 1);
      char* end = nullptr;
      errno = 0;
      const double d = isInt ? double(std::strtoll(tk.c_str(), &end, 10)) : std::strtod(tk.c_str(), &end);
      const bool intRange =
          !isInt || (errno != ERANGE && d >= std::numeric_limits<int>::min() && d <= std::numeric_limits<int>::max());
      if (!tk.empty() && *end == '\0' && !intRange) {
        ErrorBuilder eb;
        eb << origin << ":" << lineHere() << ": parameter '" << a["name"] << "' of type " << type << " has value \""
           << a["value"] << "\": '" << tk << "' does not fit in an int (at most " << std::numeric_limits<int>::max()
           << ")";
        eb.raise();
      }
      if (tk.empty() || *end != '\0' || !std::isfinite(d)) {
        ErrorBuilder eb;
        eb << origin << ":" << 1 + std::count(xml.begin(), xml.begin() + it->position(), '\n') << ": parameter '"
           << a["name"] << "' of type " << type << " has value \"" << a["value"] << "\": '" << tk << "' is not "
           << (isInt ? "an integer" : "a finite number");
        eb.raise();
      }
    }
  }
}

}  // namespace

std::string pathOf(const Teuchos::ParameterList& pl, const std::string& name) {
  return pl.name() + "->" + name;
}

Teuchos::RCP<Teuchos::ParameterList> readXmlString(const std::string& xml, const std::string& origin) {
  checkNumbers(xml, origin);
  try {
    return Teuchos::getParametersFromXmlString(xml);
  } catch (const std::exception& e) {
    std::string what = e.what();
    // Keep the parser's own sentence; drop Teuchos' file/line of its source code.
    auto pos = what.rfind("\n\n");
    if (pos != std::string::npos) what = what.substr(pos + 2);
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    throw Error(origin + ": not a valid XML parameter list: " + what +
                " (a deck is <ParameterList name=\"Epaphe\"> ... </ParameterList>; see inputs/ for examples)");
  }
}

Teuchos::RCP<Teuchos::ParameterList> readXmlFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("deck '" + path + "' cannot be opened: check the path and its permissions");
  std::stringstream ss;
  ss << in.rdbuf();
  return readXmlString(ss.str(), path);
}

void validateAndSetDefaults(Teuchos::ParameterList& user, const Teuchos::ParameterList& valid,
                            const std::string& origin, const std::string& text) {
  validateList(user, valid, origin, text, valid.name());
}

std::string nearest(const std::string& key, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t bestD = std::string::npos;
  const std::string k = lower(key);
  for (const auto& c : candidates) {
    const std::size_t d = levenshtein(k, lower(c));
    if (d < bestD) {
      bestD = d;
      best = c;
    }
  }
  // Close enough: at most a third of the key's letters differ.
  if (best.empty() || bestD > std::max<std::size_t>(2, key.size() / 3)) return "";
  return best;
}

void printDocumentation(std::ostream& os, const Teuchos::ParameterList& valid, int indent) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  for (auto it = valid.begin(); it != valid.end(); ++it) {
    const std::string& key = valid.name(it);
    const ParameterEntry& e = valid.entry(it);
    if (e.isList()) {
      os << pad << "[" << (key == "*" ? std::string("<any name>") : key) << "]";
      const std::string doc = e.docString();
      if (!doc.empty()) os << "  " << doc;
      os << "\n";
      printDocumentation(os, valid.sublist(key), indent + 2);
      continue;
    }
    os << pad << key << " (" << typeName(e) << ", default " << valueText(e) << ")";
    auto v = e.validator();
    if (auto dv = Teuchos::rcp_dynamic_cast<const Teuchos::EnhancedNumberValidator<double>>(v); !dv.is_null())
      os << " in [" << dv->getMin() << ", " << dv->getMax() << "]";
    else if (auto iv = Teuchos::rcp_dynamic_cast<const Teuchos::EnhancedNumberValidator<int>>(v); !iv.is_null())
      os << " in [" << iv->getMin() << ", " << iv->getMax() << "]";
    else if (auto sv = Teuchos::rcp_dynamic_cast<const Teuchos::StringToIntegralParameterEntryValidator<int>>(v);
             !sv.is_null())
      os << " one of "
         << joined(std::vector<std::string>(sv->validStringValues()->begin(), sv->validStringValues()->end()));
    os << "\n" << pad << "    " << e.docString() << "\n";
  }
}

void addDouble(Teuchos::ParameterList& pl, const std::string& name, double def, const std::string& doc, double min,
               double max) {
  auto v = Teuchos::rcp(new Teuchos::EnhancedNumberValidator<double>(min, max));
  pl.set(name, def, doc, v);
}
void addInt(Teuchos::ParameterList& pl, const std::string& name, int def, const std::string& doc, int min, int max) {
  auto v = Teuchos::rcp(new Teuchos::EnhancedNumberValidator<int>(min, max));
  pl.set(name, def, doc, v);
}
void addBool(Teuchos::ParameterList& pl, const std::string& name, bool def, const std::string& doc) {
  pl.set(name, def, doc);
}
void addString(Teuchos::ParameterList& pl, const std::string& name, const std::string& def, const std::string& doc) {
  pl.set(name, def, doc);
}
void addDoubleArray(Teuchos::ParameterList& pl, const std::string& name, const std::vector<double>& def,
                    const std::string& doc) {
  pl.set(name, Teuchos::Array<double>(def.begin(), def.end()), doc);
}
void addIntArray(Teuchos::ParameterList& pl, const std::string& name, const std::vector<int>& def,
                 const std::string& doc) {
  pl.set(name, Teuchos::Array<int>(def.begin(), def.end()), doc);
}
void addStringArray(Teuchos::ParameterList& pl, const std::string& name, const std::vector<std::string>& def,
                    const std::string& doc) {
  pl.set(name, Teuchos::Array<std::string>(def.begin(), def.end()), doc);
}
void addEnum(Teuchos::ParameterList& pl, const std::string& name, const std::string& def,
             const std::vector<std::string>& names, const std::vector<int>& values, const std::string& doc) {
  Teuchos::setStringToIntegralParameter<int>(name, def, doc, Teuchos::Array<std::string>(names.begin(), names.end()),
                                             Teuchos::Array<int>(values.begin(), values.end()), &pl);
}

std::vector<double> getDoubles(const Teuchos::ParameterList& pl, const std::string& name) {
  const auto& a = pl.get<Teuchos::Array<double>>(name);
  return std::vector<double>(a.begin(), a.end());
}
std::array<double, 3> getVec3(const Teuchos::ParameterList& pl, const std::string& name, const std::string& origin) {
  const auto v = getDoubles(pl, name);
  EPAPHE_REQUIRE(v.size() == 3, origin << ": '" << pathOf(pl, name) << "' has " << v.size()
                                       << " values, 3 are expected, e.g. {0, 0, 0}");
  for (double x : v) EPAPHE_REQUIRE(std::isfinite(x), origin << ": '" << pathOf(pl, name) << "' holds " << x);
  return {v[0], v[1], v[2]};
}
std::vector<int> getInts(const Teuchos::ParameterList& pl, const std::string& name) {
  const auto& a = pl.get<Teuchos::Array<int>>(name);
  return std::vector<int>(a.begin(), a.end());
}
std::vector<std::string> getStrings(const Teuchos::ParameterList& pl, const std::string& name) {
  const auto& a = pl.get<Teuchos::Array<std::string>>(name);
  return std::vector<std::string>(a.begin(), a.end());
}

}  // namespace epaphe::deck
