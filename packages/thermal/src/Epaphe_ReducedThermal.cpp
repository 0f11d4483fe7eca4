#include "Epaphe_ReducedThermal.hpp"

#include "Epaphe_Error.hpp"

#include <algorithm>
#include <cmath>

namespace epaphe {

double ReducedThermalModel::temperature(int node, const std::vector<double>& eta) const {
  const int m = numModes();
  const double* row = basis.data() + static_cast<std::size_t>(node) * m;
  double theta = 0;
  for (int i = 0; i < m; ++i) theta += row[i] * eta[i];
  return referenceTemperature + theta;
}

ThermalIntegrator::ThermalIntegrator(const ReducedThermalModel& model)
    : model_(model),
      eta_(static_cast<std::size_t>(model.numModes()), 0.0),
      force_(eta_.size(), 0.0),
      window_(model.heatedNodes.size(), 0.0) {}

void ThermalIntegrator::addHeat(const double* power, double dt) {
  for (std::size_t k = 0; power != nullptr && k < window_.size(); ++k) {
    window_[k] += power[k] * dt;
    received_ += power[k] * dt;
  }
  windowTime_ += dt;
}

void ThermalIntegrator::advanceWindow() {
  if (windowTime_ <= 0) return;
  const double h = windowTime_;
  for (double& e : window_) e /= h;  // the mean power, eq. 60: Q_window = (1 / H) sum Q_n dt
  windowTime_ = 0;
  integrate(h, window_.data());  // its heat was counted by addHeat
  for (double& e : window_) e = 0;
}

void ThermalIntegrator::advance(double h, const double* power) {
  if (power)
    for (std::size_t k = 0; k < model_.heatedNodes.size(); ++k) received_ += power[k] * h;
  integrate(h, power);
}

std::vector<double> ThermalIntegrator::state() const {
  std::vector<double> s = {time_, windowTime_, received_};
  s.insert(s.end(), eta_.begin(), eta_.end());
  s.insert(s.end(), window_.begin(), window_.end());
  return s;
}

void ThermalIntegrator::setState(const std::vector<double>& s, const std::string& what) {
  EPAPHE_REQUIRE(s.size() == 3 + eta_.size() + window_.size(),
                 what << ": the thermal model of '" << model_.name << "' has " << s.size() << " state values, "
                      << 3 + eta_.size() + window_.size() << " expected (" << eta_.size() << " modes, "
                      << window_.size() << " heated nodes); run the deck anew");
  time_ = s[0];
  windowTime_ = s[1];
  received_ = s[2];
  std::copy(s.begin() + 3, s.begin() + 3 + static_cast<std::ptrdiff_t>(eta_.size()), eta_.begin());
  std::copy(s.begin() + 3 + static_cast<std::ptrdiff_t>(eta_.size()), s.end(), window_.begin());
  // the factors of eq. 59 are recomputed at the next window, from its length: the same bits
}

void ThermalIntegrator::integrate(double h, const double* power) {
  const int m = model_.numModes();
  const std::size_t nh = model_.heatedNodes.size();
  for (int i = 0; i < m; ++i) force_[i] = model_.ambientLoad[i];
  if (power)
    for (std::size_t k = 0; k < nh; ++k) {
      if (power[k] == 0) continue;
      const double* row = model_.heatedRows.data() + k * m;
      for (int i = 0; i < m; ++i) force_[i] += row[i] * power[k];
    }
  if (h != step_) {  // the windows have one length but the last: the factors are computed once
    decay_.resize(static_cast<std::size_t>(m));
    gain_.resize(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i) {
      const double lh = model_.rate[i] * h;
      decay_[i] = std::exp(-lh);
      // (1 - exp(-x)) / x -> 1 - x/2 as x -> 0 (a mode of zero rate: an insulated body's mean)
      gain_[i] = std::abs(lh) < 1e-8 ? h * (1 - lh / 2) : -std::expm1(-lh) / model_.rate[i];
    }
    step_ = h;
  }
  // eq. 59: eta_i(t + h) = exp(-lambda_i h) eta_i(t) + (1 - exp(-lambda_i h)) / lambda_i f_i
  for (int i = 0; i < m; ++i) eta_[i] = decay_[i] * eta_[i] + gain_[i] * force_[i];
  time_ += h;
}

}  // namespace epaphe
