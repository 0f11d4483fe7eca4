#pragma once
// Errors meant for users: what was wrong, where (file, line, key, node), the value seen,
// and what to do about it.
#include <sstream>
#include <stdexcept>
#include <string>

namespace epaphe {

/// An error meant for the user: the message says what was wrong, where, the value seen and how to fix it.
class Error : public std::runtime_error {
public:
  /// The whole message, as printed to the user.
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Builds a message with operator<< and throws epaphe::Error.
///   throw_error() << "deck " << file << ": 'Time step' = " << h << " must be > 0";
class ErrorBuilder {
public:
  template <class T>
  /// Appends `v` to the message (anything an std::ostream prints).
  ErrorBuilder& operator<<(const T& v) {
    os_ << v;
    return *this;
  }
  /// Throws the Error with the message built so far.
  [[noreturn]] void raise() const { throw Error(os_.str()); }
  /// The message built so far.
  std::string str() const { return os_.str(); }

private:
  std::ostringstream os_;
};

}  // namespace epaphe

/// EPAPHE_REQUIRE(condition, message stream): throws epaphe::Error with the message when false.
#define EPAPHE_REQUIRE(cond, msg)  \
  do {                             \
    if (!(cond)) {                 \
      ::epaphe::ErrorBuilder eb__; \
      eb__ << msg;                 \
      eb__.raise();                \
    }                              \
  } while (0)
