#include "Epaphe_SpeedSampleSource.hpp"

namespace epaphe {

SpeedSample BuiltInSpeedSource::sample(double speed) {
  RotationOptions o = common_;
  o.speed = speed;
  if (!first_ && speed > 0 && previousSpeed_ > 0 && common_.staticState == StaticState::StressStiffened) {
    const double q = (speed / previousSpeed_) * (speed / previousSpeed_);
    o.initialState = previousState_;
    for (double& v : o.initialState) v *= q;
  }
  SpeedReport sr;
  SpeedSample s;
  s.model = speed == 0 ? rest_ : modelAtSpeed(rest_, terms(), o, &sr);
  s.staticDisplacement = speed == 0 ? std::vector<double>(rest_.eq.size(), 0.0) : sr.staticDisplacement;
  s.seconds = sr.seconds;
  if (first_ && common_.staticState == StaticState::Automatic)
    common_.staticState = sr.stiffened ? StaticState::StressStiffened : StaticState::Linear;
  first_ = false;
  previousSpeed_ = speed;
  previousState_ = s.staticDisplacement;
  s.report = std::move(sr);
  return s;
}

}  // namespace epaphe
