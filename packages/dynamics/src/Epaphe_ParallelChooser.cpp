#include "Epaphe_ParallelChooser.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <algorithm>
#include <climits>
#include <cstdio>

namespace epaphe {

ParallelChoice::ParallelChoice(Options options) : o_(options) {
  EPAPHE_REQUIRE(o_.blockSteps >= 1 && o_.blockSeconds >= 0 && o_.pairs >= 1 && o_.holdFactor > 0,
                 "parallel choice: blocks of " << o_.blockSteps << " steps and " << o_.blockSeconds << " s, "
                                               << o_.pairs << " pairs, hold factor " << o_.holdFactor
                                               << "; give >= 1, >= 0, >= 1 and > 0");
  perStep_.assign(2 * static_cast<std::size_t>(o_.pairs), 0.0);
}

bool ParallelChoice::stepStarts(double now) {
  if (!probing_ && now >= holdUntil_) {  // a new probe: the load may have changed
    probing_ = true;
    block_ = inBlock_ = 0;
  }
  if (probing_) {
    if (block_ == 0 && inBlock_ == 0) probeStart_ = now;
    if (inBlock_ == 0) blockStart_ = now;
    parallel_ = block_ % 2 == 0;
  } else {
    parallel_ = chosen_;
  }
  ++steps_;
  if (parallel_) ++parallelSteps_;
  return parallel_;
}

void ParallelChoice::stepEnds(double now) {
  if (!probing_ || ++inBlock_ < o_.blockSteps || now - blockStart_ < o_.blockSeconds) return;
  perStep_[static_cast<std::size_t>(block_)] = (now - blockStart_) / inBlock_;
  inBlock_ = 0;
  if (++block_ < 2 * o_.pairs) return;
  // the median over the pairs of (parallel block / the serial block after it)
  std::vector<double> ratio;
  for (int p = 0; p < o_.pairs; ++p) {
    const double s = perStep_[2 * static_cast<std::size_t>(p) + 1];
    ratio.push_back(s > 0 ? perStep_[2 * static_cast<std::size_t>(p)] / s : 1.0);
  }
  std::sort(ratio.begin(), ratio.end());
  const std::size_t m = ratio.size() / 2;
  lastRatio_ = ratio.size() % 2 ? ratio[m] : 0.5 * (ratio[m - 1] + ratio[m]);
  chosen_ = lastRatio_ < 1.0;
  ++probes_;
  if (chosen_) ++parallelChoices_;
  probing_ = false;
  holdUntil_ = now + o_.holdFactor * (now - probeStart_);
}

ParallelChooser::ParallelChooser(long threshold, ParallelChoice::Options options)
    : threshold_(threshold), choice_(options) {}

double ParallelChooser::now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - origin_).count();
}

void ParallelChooser::beginStep(ExplicitLoop&) {
  setSerialWorkNs(choice_.stepStarts(now()) ? threshold_ : LONG_MAX);
}

void ParallelChooser::endStep(ExplicitLoop&) {
  choice_.stepEnds(now());
}

void ParallelChooser::endRun(ExplicitLoop&) {
  setSerialWorkNs(threshold_);
}

void ParallelChooser::failed(ExplicitLoop&, const std::string&) {
  setSerialWorkNs(threshold_);
}

std::string ParallelChooser::summary() const {
  const ParallelChoice& c = choice_;
  char line[200];
  std::snprintf(
      line, sizeof line,
      "threads: the loops on the team on %.1f %% of the steps (%d of %d probes chose it; last team/alone time %.3g)",
      c.steps() ? 100.0 * c.parallelSteps() / c.steps() : 0.0, c.parallelChoices(), c.probes(), c.lastRatio());
  return line;
}

}  // namespace epaphe
