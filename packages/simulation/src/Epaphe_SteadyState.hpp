#pragma once
// The steady state of a driven run (docs/theory/forced-response.md, eq. (70)): the deck's 'Steady state'
// list watches x(t) = d . (the mean displacement of a node set), takes its harmonics over each drive
// period of N = 1/(nu h) steps (a whole number: the DFT is then exact for a periodic x),
//
//   a_k = (2/N) sum_{s in the period} x_s exp(-i k omega t_s)   (k >= 1),   a_0 = (1/N) sum x_s,
//
// so that x ~ a_0 + sum_k Re(a_k exp(i k omega t)), and calls the run steady when the first harmonic
// repeats after p <= P periods: max_{j < p + W} |a1_j - a1_{j+p}| <= eps |a1_0| (j periods before the
// last). A linear response repeats every period; with friction the stops fall on the step grid and the
// discrete motion may repeat only after a few periods. The run then stops (with 'Stop'), and the
// harmonics averaged over the last p periods go to /steady_state of the output. A restart starts the
// detection again from the restart's first whole period.
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_SceneBody.hpp"

#include <Teuchos_ParameterList.hpp>

#include <array>
#include <complex>
#include <deque>
#include <string>
#include <vector>

namespace epaphe {

/// The deck's 'Steady state' list, checked (steadyStateOptions).
struct SteadyStateOptions {
  bool enabled = false;               ///< 'Enabled'
  std::string body;                   ///< the watched body ('Body'; the only body when empty)
  std::string nodeSet;                ///< 'Node set': x is the mean displacement of its nodes
  std::array<double, 3> direction{};  ///< 'Direction' d, unit
  double frequency = 0;               ///< the drive's frequency nu (Hz): 'Frequency', or the first Harmonic load's
  long long stepsPerPeriod = 0;       ///< N = 1/(nu h)
  double tolerance = 1e-6;            ///< 'Tolerance' eps
  int longestPattern = 10;            ///< 'Longest pattern' P (periods)
  int window = 4;                     ///< 'Window' W (periods)
  int harmonics = 3;                  ///< 'Harmonics': a_1 .. a_H kept
  bool stop = true;                   ///< 'Stop': end the run once steady
};

/// The 'Steady state' list of deck `P` (its Time step and loads), checked: a node set and a direction,
/// a drive frequency (the key or a Harmonic load), a whole number of steps per period. `origin` names
/// the deck in errors.
SteadyStateOptions steadyStateOptions(const Teuchos::ParameterList& P, const std::string& origin);

/// The detection of eq. (70) over a run (see the file's opening comment).
class SteadyStateMonitor : public LoopObserver {
public:
  /// Watches `body` (index `bodyIndex` of the loop) with `options`; `h` the time step (s).
  SteadyStateMonitor(const SteadyStateOptions& options, const SceneBody& body, std::size_t bodyIndex, double h);
  /// Samples x_{n+1} at t_{n+1}; at the end of a period, the criterion (and the stop).
  void afterCorrect(ExplicitLoop& loop) override;
  /// True once the criterion held.
  bool steady() const { return steady_; }
  /// The pattern p (periods) of the last check (the best one when not steady).
  int pattern() const { return pattern_; }
  /// The criterion's value at the last check (max relative change over the pattern; inf before 2 checks).
  double criterion() const { return criterion_; }
  /// Whole periods taken.
  long long periods() const { return periods_; }
  /// The time the run became steady (s; -1: not steady).
  double steadyTime() const { return steadyTime_; }
  /// a_0 .. a_H averaged over the last p periods (a_0 real).
  std::vector<std::complex<double>> harmonics() const;
  /// /steady_state: attributes (steady, time, periods, pattern, criterion, frequency) and the datasets
  /// harmonics (H+1 x 2: real and imaginary parts), amplitude and phase (rad) of x ~ sum |a_k| cos(k omega t +
  /// arg a_k).
  void write(io::Hdf5File& file) const;
  /// One line for the run's summary.
  std::string summary() const;

private:
  SteadyStateOptions opt_;
  std::size_t body_;
  double h_, omega_;
  NodeRecovery recovery_;
  DenseVector u_;
  int nodes_;
  std::vector<std::complex<double>> sums_;           // this period's sums, k = 0 .. H
  long long inPeriod_ = -1;                          // samples taken in this period (-1: waiting for one to start)
  std::deque<std::vector<std::complex<double>>> a_;  // each whole period's a_0 .. a_H, the last first
  bool steady_ = false;
  int pattern_ = 1;
  double criterion_ = 0, steadyTime_ = -1;
  long long periods_ = 0;
};

}  // namespace epaphe
