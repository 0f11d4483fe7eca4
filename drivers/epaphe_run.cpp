// epaphe-run: runs one deck.
//
//   epaphe-run DECK.xml [--threads N] [--output FILE] [--check] [--restart FILE.h5] [--kernel-times]
//   epaphe-run DECK.xml --speeds W1,W2,... [--revolutions R] [--threads N]
//   epaphe-run --print-parameters[=xml]
//
// --check validates the deck (its schema, then every check that needs no reduced model: the same
// messages as a run) and stops; --print-parameters prints every valid parameter with its
// type, default, allowed values and documentation (=xml: the same as a Teuchos XML parameter list
// with its validators, for programs). --restart continues the run stored in FILE.h5
// (an output of the same deck) from its last checkpoint, appending to it. SIGINT and SIGTERM stop
// the run at the end of the current step with a checkpoint and the status "stopped: interrupted by
// ..."; the exit code is then 128 + the signal (130, 143). Errors go to stderr on rank 0 as one
// message, and the exit code is 1 (2 for a wrong command line; 3 after --stop-after-steps N, a
// testing option that stops like SIGTERM after N steps). --kernel-times times the run's loop kernel
// by kernel (each forEach and reduce by its name, on the team or on the calling thread,
// Epaphe_Parallel.hpp) and prints them after the summary, the longest first: where a step's time
// goes, and which kernels two threads speed up.
//
// --speeds runs the deck once per rotation speed (rad/s; every turning surface takes it, with its
// own sign), the speeds dealt round-robin to the MPI ranks (mpirun -np P epaphe-run ...): each
// rank runs its decks alone, on its own communicator, and writes speed-<W>.h5 and
// speed-<W>.summary.txt in the working directory. --revolutions R sets each run's length. The
// exit code is 1 when any run failed (each failure is reported by the rank that ran it).
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SceneCheck.hpp"
#include "Epaphe_Simulation.hpp"
#include "Epaphe_Version.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {
const char* usage =
    "usage: epaphe-run DECK.xml [--threads N] [--output FILE] [--check] [--restart FILE.h5] [--kernel-times]\n"
    "       epaphe-run DECK.xml --speeds W1,W2,... [--revolutions R] [--threads N]\n"
    "       epaphe-run --print-parameters[=xml]\n";

/// "600,1000,1.4e3" -> {600, 1000, 1400}; false when an item is not a number.
bool parseList(const std::string& text, std::vector<double>& values) {
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') return false;
    values.push_back(v);
  }
  return !values.empty();
}

/// The kernels timed in a loop of `loopSeconds` (--kernel-times): one line each, the longest first.
void printKernelTimes(std::ostream& out, double loopSeconds) {
  const std::vector<epaphe::KernelTime> kernels = epaphe::kernelTimes();
  double total = 0;
  long launches = 0;
  for (const epaphe::KernelTime& k : kernels) {
    total += k.seconds;
    launches += k.launches;
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "kernels: %ld launches, %.1f ms of the loop's %.1f ms (the rest: code between them)\n", launches,
                1e3 * total, 1e3 * loopSeconds);
  out << line;
  std::snprintf(line, sizeof line, "  %-52s %9s %8s %10s %11s %7s\n", "kernel", "launches", "on team", "time (ms)",
                "us/launch", "% loop");
  out << line;
  for (const epaphe::KernelTime& k : kernels) {
    std::snprintf(line, sizeof line, "  %-52s %9ld %7.1f%% %10.2f %11.2f %6.1f%%\n", k.name.c_str(), k.launches,
                  100.0 * k.onTeam / k.launches, 1e3 * k.seconds, 1e6 * k.seconds / k.launches,
                  loopSeconds > 0 ? 100.0 * k.seconds / loopSeconds : 0.0);
    out << line;
  }
}

/// The speed sweep: this rank's share of `speeds`, each run alone. Returns the exit code.
int runSpeeds(epaphe::Runtime& rt, const epaphe::Deck& deck, const std::vector<double>& speeds, double revolutions) {
  const auto world = rt.worldComm();
  const int me = world->getRank(), ranks = world->getSize();
  rt.useOwnCommunicator();
  int code = 0;
  for (std::size_t k = me; k < speeds.size(); k += ranks) {
    std::ostringstream stem;
    stem << "speed-" << speeds[k];
    try {
      epaphe::Deck d = epaphe::deckAtSpeed(deck, speeds[k], revolutions, stem.str() + ".h5");
      epaphe::Simulation sim(d, rt, "");
      sim.setup();
      const epaphe::RunSummary& s = sim.run();
      std::ofstream summary(stem.str() + ".summary.txt");
      sim.printSummary(summary);
      std::ostringstream line;
      line << "epaphe-run: rank " << me << ": " << speeds[k] << " rad/s, " << s.steps << " steps, " << s.stepsPerSecond
           << " steps/s -> " << stem.str() << ".h5\n";
      std::cout << line.str() << std::flush;
    } catch (const std::exception& e) {
      std::cerr << "epaphe-run: error (rank " << me << ", " << speeds[k] << " rad/s): " << e.what() << "\n";
      code = 1;
    }
  }
  int worst = 0;
  Teuchos::reduceAll(*world, Teuchos::REDUCE_MAX, code, Teuchos::outArg(worst));
  return worst;
}
}  // namespace

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  std::string deckPath, output;
  int threads = -1;
  bool check = false, kernelTimes = false;
  std::string restart;
  long long stopAfter = -1;
  std::vector<double> speeds;
  double revolutions = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--print-parameters=xml") {
      // Machine-readable: the valid parameter list as Teuchos XML, with each entry's type, default,
      // docString and validator (ranges, enum values) -- what python/epaphe's schema reads.
      if (rt.rank() == 0) Teuchos::writeParameterListToXmlOStream(*epaphe::validDeckParameters(), std::cout);
      return 0;
    } else if (a == "--print-parameters") {
      if (rt.rank() == 0) {
        std::cout << "Epaphe " << epaphe::version << ": every deck parameter (lists in brackets)\n\n";
        epaphe::deck::printDocumentation(std::cout, *epaphe::validDeckParameters());
      }
      return 0;
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (a == "--output" && i + 1 < argc) {
      output = argv[++i];
    } else if (a == "--restart" && i + 1 < argc) {
      restart = argv[++i];
    } else if (a == "--stop-after-steps" && i + 1 < argc) {
      stopAfter = std::atoll(argv[++i]);
    } else if (a == "--speeds" && i + 1 < argc) {
      if (!parseList(argv[++i], speeds)) {
        if (rt.rank() == 0) std::cerr << "epaphe-run: --speeds " << argv[i] << ": give numbers separated by commas\n";
        return 2;
      }
    } else if (a == "--revolutions" && i + 1 < argc) {
      revolutions = std::atof(argv[++i]);
      if (!(revolutions > 0)) {
        if (rt.rank() == 0) std::cerr << "epaphe-run: --revolutions " << argv[i] << ": give a number > 0\n";
        return 2;
      }
    } else if (a == "--kernel-times") {
      kernelTimes = true;
    } else if (a == "--check") {
      check = true;
    } else if (a == "--help" || a == "-h") {
      if (rt.rank() == 0) std::cout << usage;
      return 0;
    } else if (!a.empty() && a[0] != '-' && deckPath.empty()) {
      deckPath = a;
    } else {
      if (rt.rank() == 0) std::cerr << "epaphe-run: unknown argument '" << a << "'\n" << usage;
      return 2;
    }
  }
  if (deckPath.empty()) {
    if (rt.rank() == 0) std::cerr << "epaphe-run: no deck given\n" << usage;
    return 2;
  }
  if (!restart.empty() && !output.empty() && output != restart) {
    if (rt.rank() == 0)
      std::cerr << "epaphe-run: --restart " << restart << " continues that file; drop --output " << output << "\n";
    return 2;
  }
  try {
    epaphe::Deck deck = epaphe::readDeck(deckPath);
    if (check) {  // everything a run checks before its reduction (Epaphe_SceneCheck.hpp)
      epaphe::checkScene(deck, output.empty() ? deck.params->sublist("Output").get<std::string>("File") : output,
                         !restart.empty());
      rt.out() << deckPath << ": valid\n";
      return 0;
    }
    rt.initializeKokkos(threads >= 0 ? threads : deck.params->sublist("Run").get<int>("Threads"));
    if (!speeds.empty()) {
      if (!restart.empty() || !output.empty() || stopAfter >= 0) {
        if (rt.rank() == 0)
          std::cerr
              << "epaphe-run: --speeds writes speed-<W>.h5 files; drop --output, --restart and --stop-after-steps\n";
        return 2;
      }
      return runSpeeds(rt, deck, speeds, revolutions);
    }
    rt.out() << "Epaphe " << epaphe::version << ": " << deckPath << " on " << rt.threads() << " thread(s), "
             << rt.size() << " MPI rank(s)\n";
    int code = 0;
    {
      epaphe::Simulation sim(deck, rt, output);
      if (!restart.empty()) sim.setRestart(restart);
      sim.setStopAfterSteps(stopAfter);
      sim.setup();
      epaphe::Simulation::catchSignals();  // from here on, SIGINT/SIGTERM stop with a checkpoint
      epaphe::timeKernels(kernelTimes);
      const epaphe::RunSummary& s = sim.run();
      epaphe::timeKernels(false);
      sim.printSummary(rt.out());
      if (kernelTimes) printKernelTimes(rt.out(), s.loopSeconds);
      if (s.stopSignal != 0)
        code = 128 + s.stopSignal;
      else if (s.stoppedEarly)
        code = 3;
    }
    return code;
  } catch (const std::exception& e) {
    // Only rank 0 speaks, unless the error happened on another rank alone.
    if (rt.rank() == 0 || rt.size() == 1) std::cerr << "epaphe-run: error: " << e.what() << "\n";
    return 1;
  }
}
