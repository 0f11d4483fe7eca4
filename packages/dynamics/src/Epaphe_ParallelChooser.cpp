#include "Epaphe_ParallelChooser.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <Kokkos_Core.hpp>

#include <sched.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace epaphe {

ParallelChoice::ParallelChoice(Options options, std::function<bool()> crowded)
    : o_(options), crowded_(std::move(crowded)) {
  EPAPHE_REQUIRE(o_.blockSteps >= 1 && o_.blockSeconds >= 0 && o_.pairs >= 1 && o_.holdFactor > 0,
                 "parallel choice: blocks of " << o_.blockSteps << " steps and " << o_.blockSeconds << " s, "
                                               << o_.pairs << " pairs, hold factor " << o_.holdFactor
                                               << "; give >= 1, >= 0, >= 1 and > 0");
  perStep_.assign(2 * static_cast<std::size_t>(o_.pairs), 0.0);
}

bool ParallelChoice::stepStarts(double now) {
  if (!probing_ && !looking_ && now >= holdUntil_) {  // the load may have changed
    looking_ = static_cast<bool>(crowded_);
    looks_ = 0;
    probing_ = !looking_;
    block_ = inBlock_ = 0;  // (warmed_ is false: the last probe's last block ended)
  }
  if (looking_) {  // before a probe, up to kLooks steps on the calling thread, each a look at the machine
    if (!crowded_()) {
      looking_ = false;
      probing_ = true;
    } else if (++looks_ == kLooks) {  // taken at every look: the calling thread without a probe
      looking_ = false;
      chosen_ = false;
      ++crowdedSkips_;
      holdUntil_ = now + 2 * o_.pairs * o_.blockSeconds;
    }
  }
  if (probing_) {
    if (block_ == 0 && inBlock_ == 0 && !warmed_) probeStart_ = now;
    parallel_ = block_ % 2 == 0;
  } else {
    parallel_ = !looking_ && chosen_;
  }
  ++steps_;
  if (parallel_) ++parallelSteps_;
  return parallel_;
}

void ParallelChoice::stepEnds(double now) {
  if (!probing_) return;
  if (!warmed_) {  // the block's first step ended: its timed steps start now
    warmed_ = true;
    blockStart_ = now;
    return;
  }
  if (++inBlock_ < o_.blockSteps || now - blockStart_ < o_.blockSeconds) return;
  perStep_[static_cast<std::size_t>(block_)] = (now - blockStart_) / inBlock_;
  inBlock_ = 0;
  warmed_ = false;
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
    : threshold_(threshold),
      choice_(options, [team = Kokkos::DefaultHostExecutionSpace().concurrency()] { return crowded(team); }) {}

namespace {

/// Threads of other processes running or ready to run: /proc/loadavg's running count less this
/// process's own threads in state R (/proc/self/task/*/stat); -1 where /proc cannot tell.
int othersRunning() {
  std::ifstream la("/proc/loadavg");
  double l1, l5, l15;
  std::string running;
  if (!(la >> l1 >> l5 >> l15 >> running) || running.find('/') == std::string::npos) return -1;
  int all = 0;
  try {
    all = std::stoi(running.substr(0, running.find('/')));
  } catch (const std::exception&) {
    return -1;
  }
  int own = 0;
  std::error_code ec;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    std::ifstream st(task.path() / "stat");
    std::string line;
    std::getline(st, line);
    const std::size_t close = line.rfind(')');  // "tid (name) S ...": the name may hold spaces
    if (close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'R') ++own;
  }
  if (ec) return -1;
  return all - own;
}

}  // namespace

bool ParallelChooser::crowded(int team) {
  cpu_set_t set;
  if (team < 2 || sched_getaffinity(0, sizeof set, &set) != 0) return false;
  const int others = othersRunning();
  return others >= 0 && CPU_COUNT(&set) - others < team;
}

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
  char line[320];
  std::snprintf(
      line, sizeof line,
      "threads: the loops on the team on %.1f %% of the steps (%d of %d probes chose it; last team/alone time %.3g; "
      "%d probes skipped: other processes held the cores)",
      c.steps() ? 100.0 * c.parallelSteps() / c.steps() : 0.0, c.parallelChoices(), c.probes(), c.lastRatio(),
      c.crowdedSkips());
  return line;
}

}  // namespace epaphe
