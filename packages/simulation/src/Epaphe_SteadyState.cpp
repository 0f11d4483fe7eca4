#include "Epaphe_SteadyState.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_SceneCheck.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;

SteadyStateOptions steadyStateOptions(const ParameterList& P, const std::string& origin) {
  SteadyStateOptions o;
  if (!P.isSublist("Steady state")) return o;
  const ParameterList& sp = P.sublist("Steady state");
  o.enabled = sp.get<bool>("Enabled");
  if (!o.enabled) return o;
  const ParameterList& bl = P.sublist("Bodies");
  o.body = sp.get<std::string>("Body");
  if (o.body.empty()) {
    EPAPHE_REQUIRE(bl.numParams() == 1, origin << ": '" << deck::pathOf(sp, "Body") << "' is empty and the deck has "
                                               << bl.numParams() << " bodies; name the body to watch");
    o.body = bl.name(bl.begin());
  }
  EPAPHE_REQUIRE(bl.isSublist(o.body), origin << ": '" << deck::pathOf(sp, "Body") << "' = '" << o.body
                                              << "' is not a body of the deck; name one of 'Bodies'");
  o.nodeSet = sp.get<std::string>("Node set");
  EPAPHE_REQUIRE(!o.nodeSet.empty(), origin << ": '" << deck::pathOf(sp, "Node set")
                                            << "' is empty; name the node set whose motion is watched");
  const auto d = deck::getVec3(sp, "Direction", origin);
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  EPAPHE_REQUIRE(len > 0 && std::isfinite(len), origin << ": '" << deck::pathOf(sp, "Direction") << "' = {" << d[0]
                                                       << ", " << d[1] << ", " << d[2]
                                                       << "} has no length; give the direction of the watched motion");
  for (int k = 0; k < 3; ++k) o.direction[k] = d[k] / len;
  o.frequency = sp.get<double>("Frequency");
  if (o.frequency == 0) {  // the first Harmonic load of the deck
    for (auto it = bl.begin(); it != bl.end() && o.frequency == 0; ++it)
      for (const BodyLoad& load : bodyLoads(bl.sublist(bl.name(it)), origin))
        if (load.g.kind() == LoadTimeKind::Harmonic) {
          o.frequency = load.g.frequency();
          break;
        }
    EPAPHE_REQUIRE(o.frequency > 0, origin << ": '" << deck::pathOf(sp, "Frequency")
                                           << "' = 0 and no body has a Harmonic load: give the drive's frequency (Hz)");
  }
  const double h = P.sublist("Time").get<double>("Time step");
  const double steps = 1.0 / (o.frequency * h);
  o.stepsPerPeriod = std::llround(steps);
  EPAPHE_REQUIRE(o.stepsPerPeriod >= 4 && std::abs(steps - static_cast<double>(o.stepsPerPeriod)) <= 1e-6 * steps,
                 origin << ": 'Steady state' at " << o.frequency << " Hz: a drive period is 1/(nu h) = " << steps
                        << " steps of 'Time->Time step' = " << h
                        << " s, not a whole number (at least 4); choose the step h = 1/(nu N) for a whole N, e.g. "
                        << 1.0 / (o.frequency * std::max(4.0, std::ceil(steps))) << " s");
  o.tolerance = sp.get<double>("Tolerance");
  o.longestPattern = sp.get<int>("Longest pattern");
  o.window = sp.get<int>("Window");
  o.harmonics = sp.get<int>("Harmonics");
  o.stop = sp.get<bool>("Stop");
  return o;
}

SteadyStateMonitor::SteadyStateMonitor(const SteadyStateOptions& options, const SceneBody& body, std::size_t bodyIndex,
                                       double h)
    : opt_(options), body_(bodyIndex), h_(h), omega_(2 * M_PI * options.frequency) {
  const std::vector<int> nodes = body.rom->nodeSet(opt_.nodeSet, "'Steady state->Node set'");
  nodes_ = static_cast<int>(nodes.size());
  recovery_ = NodeRecovery(*body.rom, nodes, "epaphe::steady::R");
  u_ = DenseVector("epaphe::steady::u", recovery_.rows());
  sums_.assign(static_cast<std::size_t>(opt_.harmonics) + 1, 0.0);
  criterion_ = std::numeric_limits<double>::infinity();
}

void SteadyStateMonitor::afterCorrect(ExplicitLoop& loop) {
  const long long s = loop.step() + 1;  // the sample x_{n+1} at t_{n+1} = s h
  const long long N = opt_.stepsPerPeriod;
  if (inPeriod_ < 0) {
    if ((s - 1) % N != 0) return;  // a period starts at s = j N + 1
    inPeriod_ = 0;
    std::fill(sums_.begin(), sums_.end(), 0.0);
  }
  recovery_.apply(loop.part(loop.next(), body_), u_);
  fence();
  const double* u = u_.data();
  double x = 0;
  for (int i = 0; i < nodes_; ++i)
    for (int d = 0; d < 3; ++d) x += opt_.direction[d] * u[3 * i + d];
  x /= nodes_;
  const double t = static_cast<double>(s) * h_;
  sums_[0] += x;
  for (std::size_t k = 1; k < sums_.size(); ++k)
    sums_[k] += x * std::exp(std::complex<double>(0.0, -static_cast<double>(k) * omega_ * t));
  if (++inPeriod_ < N) return;
  // a whole period: a_0 = mean, a_k = (2/N) sum x e^{-i k omega t}
  std::vector<std::complex<double>> a(sums_.size());
  a[0] = sums_[0] / static_cast<double>(N);
  for (std::size_t k = 1; k < a.size(); ++k) a[k] = 2.0 * sums_[k] / static_cast<double>(N);
  a_.push_front(std::move(a));
  const std::size_t keep = static_cast<std::size_t>(2 * opt_.longestPattern + opt_.window);
  if (a_.size() > keep) a_.pop_back();
  ++periods_;
  inPeriod_ = 0;
  std::fill(sums_.begin(), sums_.end(), 0.0);
  if (steady_) return;
  // eq. (70): the smallest p with max_{j < p + W} |a1_j - a1_{j+p}| <= eps |a1_0|
  const double ref = std::abs(a_[0][1]);
  double best = std::numeric_limits<double>::infinity();
  int bestP = 1;
  for (int p = 1; p <= opt_.longestPattern; ++p) {
    const std::size_t n = static_cast<std::size_t>(p + opt_.window);
    if (n + static_cast<std::size_t>(p) > a_.size()) break;
    double c = 0;
    for (std::size_t j = 0; j < n; ++j) c = std::max(c, std::abs(a_[j][1] - a_[j + p][1]));
    c = ref > 0 ? c / ref : (c > 0 ? std::numeric_limits<double>::infinity() : 0.0);
    if (c < best) {
      best = c;
      bestP = p;
    }
    if (c <= opt_.tolerance) {
      best = c;
      bestP = p;
      steady_ = true;
      steadyTime_ = t;
      break;
    }
  }
  criterion_ = best;
  pattern_ = bestP;
  if (steady_ && opt_.stop) {
    std::ostringstream os;
    os << "steady state at t = " << t << " s (" << periods_ << " periods of " << opt_.frequency << " Hz)";
    loop.requestStop(os.str());
  }
}

std::vector<std::complex<double>> SteadyStateMonitor::harmonics() const {
  std::vector<std::complex<double>> mean(static_cast<std::size_t>(opt_.harmonics) + 1, 0.0);
  const std::size_t p = std::min<std::size_t>(static_cast<std::size_t>(pattern_), a_.size());
  for (std::size_t j = 0; j < p; ++j)
    for (std::size_t k = 0; k < mean.size(); ++k) mean[k] += a_[j][k] / static_cast<double>(p);
  return mean;
}

void SteadyStateMonitor::write(io::Hdf5File& file) const {
  const std::vector<std::complex<double>> a = harmonics();
  std::vector<double> reim, amplitude, phase;
  for (const auto& z : a) {
    reim.push_back(z.real());
    reim.push_back(z.imag());
    amplitude.push_back(std::abs(z));
    phase.push_back(std::arg(z));
  }
  file.writeDoubles("/steady_state/harmonics", {a.size(), 2}, reim.data());
  file.writeDoubles("/steady_state/amplitude", amplitude);
  file.writeDoubles("/steady_state/phase", phase);
  file.setAttribute("/steady_state", "steady", static_cast<long long>(steady_ ? 1 : 0));
  file.setAttribute("/steady_state", "time", steadyTime_);
  file.setAttribute("/steady_state", "periods", periods_);
  file.setAttribute("/steady_state", "pattern", static_cast<long long>(pattern_));
  file.setAttribute("/steady_state", "criterion", criterion_);
  file.setAttribute("/steady_state", "frequency", opt_.frequency);
  file.setAttribute("/steady_state", "tolerance", opt_.tolerance);
}

std::string SteadyStateMonitor::summary() const {
  std::ostringstream os;
  const auto a = harmonics();
  if (steady_)
    os << "steady state at t = " << steadyTime_ << " s after " << periods_ << " periods of " << opt_.frequency
       << " Hz (repeating every " << pattern_ << ", to " << criterion_ << "): first harmonic " << std::abs(a[1])
       << " m, phase " << std::arg(a[1]) << " rad";
  else
    os << "not steady after " << periods_ << " periods of " << opt_.frequency << " Hz (best pattern " << pattern_
       << ", criterion " << criterion_ << " > " << opt_.tolerance << ")";
  return os.str();
}

}  // namespace epaphe
