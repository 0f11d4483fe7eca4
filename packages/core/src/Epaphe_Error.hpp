#pragma once
// Errors meant for users: what was wrong, where (file, line, key, node), the value seen,
// and what to do about it.
#include <sstream>
#include <stdexcept>
#include <string>

namespace epaphe {

class Error : public std::runtime_error {
public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

/// Builds a message with operator<< and throws epaphe::Error.
///   throw_error() << "deck " << file << ": 'Time step' = " << h << " must be > 0";
class ErrorBuilder {
public:
  template <class T>
  ErrorBuilder& operator<<(const T& v) {
    os_ << v;
    return *this;
  }
  [[noreturn]] void raise() const { throw Error(os_.str()); }
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
