#pragma once
// A rotation speed that follows a law in time (a run-up or run-down, Batailly et al. with a
// time-dependent angular speed): constant, or a linear ramp from `start` rad/s at `t0` to `end` rad/s
// at `t1`, constant before and after. The angle is the speed's integral from t = 0:
//
//   theta(t) = w0 t                                              t <= t0
//            = w0 t + (w1 - w0) (t - t0)^2 / (2 (t1 - t0))       t0 < t < t1
//            = w0 t + (w1 - w0) ((t1 - t0) / 2 + (t - t1))       t >= t1
//
// scaled by `scale` (a surface that turns at -Omega around a blade turning at +Omega: scale = -1).
#include <algorithm>
#include <cmath>

namespace epaphe {

/// A rotation speed in time: constant, or a linear ramp between two speeds, times `scale` (see the file's
/// opening comment for the angle).
struct SpeedLaw {
  bool ramp = false;  ///< false: constant at `start`
  ///@{
  double start = 0, end = 0;  ///< rad/s
  ///@}
  ///@{
  double t0 = 0, t1 = 0;  ///< s, t1 > t0 for a ramp
  ///@}
  double scale = 1;  ///< factor on the speed and the angle (-1: the opposite sense)

  /// The speed at time `t` (s), rad/s: `scale` times the constant or ramp speed.
  double speed(double t) const {
    if (!ramp || t <= t0) return scale * start;
    if (t >= t1) return scale * end;
    return scale * (start + (end - start) * (t - t0) / (t1 - t0));
  }
  /// The angle turned from t = 0 to `t` (rad): the integral of speed().
  double angle(double t) const {
    double a = start * t;
    if (ramp && t > t0) {
      const double s = std::min(t, t1) - t0;
      a += (end - start) * (s * s / (2 * (t1 - t0)) + std::max(t - t1, 0.0));
    }
    return scale * a;
  }
  /// The largest |speed| over the run.
  double fastest() const { return std::abs(scale) * std::max(std::abs(start), ramp ? std::abs(end) : 0.0); }
  /// The same law with `scale` multiplied by `factor`.
  SpeedLaw scaled(double factor) const {
    SpeedLaw l = *this;
    l.scale *= factor;
    return l;
  }
};

}  // namespace epaphe
