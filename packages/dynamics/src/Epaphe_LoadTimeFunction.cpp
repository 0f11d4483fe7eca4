#include "Epaphe_LoadTimeFunction.hpp"

#include "Epaphe_Error.hpp"

#include <algorithm>
#include <cmath>

namespace epaphe {

const std::vector<std::string>& loadTimeKindNames() {
  static const std::vector<std::string> names{"Constant", "Harmonic", "Table", "Ramp"};
  return names;
}

LoadTimeFunction LoadTimeFunction::constant() {
  return LoadTimeFunction();
}

LoadTimeFunction LoadTimeFunction::harmonic(double frequency, double phase) {
  EPAPHE_REQUIRE(std::isfinite(frequency) && frequency > 0,
                 "a harmonic load's frequency is " << frequency << " Hz; it must be finite and > 0");
  EPAPHE_REQUIRE(std::isfinite(phase), "a harmonic load's phase is " << phase << " rad; it must be finite");
  LoadTimeFunction g;
  g.kind_ = LoadTimeKind::Harmonic;
  g.frequency_ = frequency;
  g.phase_ = phase;
  return g;
}

LoadTimeFunction LoadTimeFunction::table(const std::vector<double>& times, const std::vector<double>& values,
                                         const std::string& what) {
  EPAPHE_REQUIRE(!times.empty() && times.size() == values.size(),
                 what << ": " << times.size() << " times and " << values.size()
                      << " values; give at least one point and as many values as times");
  for (std::size_t i = 0; i < times.size(); ++i) {
    EPAPHE_REQUIRE(std::isfinite(times[i]) && std::isfinite(values[i]), what << ": point " << i + 1 << " is ("
                                                                             << times[i] << " s, " << values[i]
                                                                             << "); give finite values");
    EPAPHE_REQUIRE(i == 0 || times[i] > times[i - 1], what << ": time " << i + 1 << " (" << times[i]
                                                           << " s) does not follow time " << i << " (" << times[i - 1]
                                                           << " s); the times must increase strictly");
  }
  LoadTimeFunction g;
  g.kind_ = LoadTimeKind::Table;
  g.times_ = times;
  g.values_ = values;
  return g;
}

LoadTimeFunction LoadTimeFunction::ramp(double duration) {
  EPAPHE_REQUIRE(std::isfinite(duration) && duration > 0,
                 "a ramp load's duration is " << duration << " s; it must be finite and > 0");
  LoadTimeFunction g;
  g.kind_ = LoadTimeKind::Ramp;
  g.duration_ = duration;
  return g;
}

double LoadTimeFunction::largest() const {
  if (kind_ != LoadTimeKind::Table) return 1.0;
  double m = 0;
  for (double v : values_) m = std::max(m, std::abs(v));
  return m;
}

double LoadTimeFunction::operator()(double t) const {
  switch (kind_) {
    case LoadTimeKind::Constant:
      return 1.0;
    case LoadTimeKind::Harmonic:
      return std::cos(2.0 * M_PI * frequency_ * t + phase_);  // eq. 65
    case LoadTimeKind::Ramp:
      return std::min(t / duration_, 1.0);
    case LoadTimeKind::Table: {
      if (t <= times_.front()) return values_.front();
      if (t >= times_.back()) return values_.back();
      const std::size_t i =
          static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
      const double w = (t - times_[i - 1]) / (times_[i] - times_[i - 1]);
      return (1.0 - w) * values_[i - 1] + w * values_[i];
    }
  }
  return 0.0;
}

}  // namespace epaphe
