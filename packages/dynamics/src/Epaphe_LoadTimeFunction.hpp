#pragma once
// The time function g(t) of an external load f(t) = g(t) f_0 (docs/theory/forced-response.md, eq. 65):
//
//   Constant   g = 1
//   Harmonic   g = cos(2 pi nu t + phi)                 (nu > 0 Hz, phi rad)
//   Table      g = piecewise linear through (t_i, g_i), held at g_0 before t_0 and at the last value after
//   Ramp       g = min(t / T, 1)                        (T > 0 s)
//
// Plain data, no deck: the simulation package reads the deck's 'Loads' and builds these; the
// central difference evaluates them once per step (Epaphe_CentralDifference.hpp).
#include <string>
#include <vector>

namespace epaphe {

/// The kinds of a load's time function; the deck's 'Time function' values, in this order.
enum class LoadTimeKind { Constant, Harmonic, Table, Ramp };

/// The deck's names of the kinds, in LoadTimeKind's order: "Constant", "Harmonic", "Table", "Ramp".
const std::vector<std::string>& loadTimeKindNames();

/// g(t) of one load (eq. 65): the factor its reduced force f_0 is multiplied by at time t.
class LoadTimeFunction {
public:
  /// g = 1.
  static LoadTimeFunction constant();
  /// g = cos(2 pi frequency t + phase); `frequency` (Hz) finite and > 0, `phase` (rad) finite.
  static LoadTimeFunction harmonic(double frequency, double phase);
  /// g piecewise linear through (times[i], values[i]); times strictly increasing, at least one point,
  /// as many values as times, all finite. `what` names the table in an error.
  static LoadTimeFunction table(const std::vector<double>& times, const std::vector<double>& values,
                                const std::string& what);
  /// g = min(t / duration, 1); `duration` (s) finite and > 0.
  static LoadTimeFunction ramp(double duration);

  /// g(t), t in s.
  double operator()(double t) const;
  /// max |g| over all times: 1, or a table's largest |value|.
  double largest() const;
  /// The kind.
  LoadTimeKind kind() const { return kind_; }
  /// The harmonic's frequency (Hz; 0 for the other kinds).
  double frequency() const { return frequency_; }

private:
  LoadTimeKind kind_ = LoadTimeKind::Constant;
  double frequency_ = 0, phase_ = 0, duration_ = 0;
  std::vector<double> times_, values_;
};

}  // namespace epaphe
