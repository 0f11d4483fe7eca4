#include "Epaphe_RunControl.hpp"

#include <csignal>
#include <signal.h>
#include <cstdio>
#include <sstream>

namespace epaphe {

namespace {

volatile std::sig_atomic_t stopSignal = 0;

extern "C" void onStopSignal(int sig) {
  stopSignal = sig;
}

const char* signalName(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

}  // namespace

void StopControl::catchStopSignals() {
  struct sigaction sa = {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // system calls in progress (HDF5 writes) go on
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void StopControl::endStep(ExplicitLoop& loop) {
  const long long done = loop.stepsDone();
  if (done >= loop.numSteps()) return;
  const int sig = stopSignal;
  if (sig == 0 && done != stopAfter_) return;
  std::ostringstream os;
  if (sig != 0)
    os << "interrupted by " << signalName(sig);
  else
    os << "stopped after " << done << " steps as asked (--stop-after-steps)";
  os << " at t = " << done * loop.timeStep() << " s (step " << done << " of " << loop.numSteps() << ")";
  if (!hint_.empty()) os << "; " << hint_;
  signal_ = sig;
  loop.requestStop(os.str());
}

void ProgressReport::endStep(ExplicitLoop& loop) {
  const long long n = loop.step();
  if (interval_ <= 0 || loop.stopRequested() || (n & 255) != 0 || since_.seconds() <= interval_) return;
  since_.restart();
  const double rate = (n + 1 - loop.firstStep()) / loop.seconds();
  char line[200];
  std::snprintf(line, sizeof line, "  t = %.4e s (%3.0f %%)  %.0f steps/s  %s left  active contacts %d\n", loop.time(),
                100.0 * (n + 1) / loop.numSteps(), rate, formatDuration((loop.numSteps() - n - 1) / rate).c_str(),
                loop.activeContacts());
  loop.out() << line << std::flush;
}

}  // namespace epaphe
