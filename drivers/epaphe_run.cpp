// epaphe-run: runs one deck.
//
//   epaphe-run DECK.xml [--threads N] [--output FILE] [--check] [--restart FILE.h5]
//   epaphe-run --print-parameters
//
// --check validates the deck and stops; --print-parameters prints every valid parameter with its
// type, default, allowed values and documentation. --restart continues the run stored in FILE.h5
// (an output of the same deck) from its last checkpoint, appending to it. SIGINT and SIGTERM stop
// the run at the end of the current step with a checkpoint and the status "stopped: interrupted by
// ..."; the exit code is then 128 + the signal (130, 143). Errors go to stderr on rank 0 as one
// message, and the exit code is 1 (2 for a wrong command line; 3 after --stop-after-steps N, a
// testing option that stops like SIGTERM after N steps).
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_Simulation.hpp"
#include "Epaphe_Version.hpp"

#include <cstring>
#include <iostream>
#include <string>

namespace {
const char* usage =
    "usage: epaphe-run DECK.xml [--threads N] [--output FILE] [--check] [--restart FILE.h5]\n"
    "       epaphe-run --print-parameters\n";
}

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  std::string deckPath, output;
  int threads = -1;
  bool check = false;
  std::string restart;
  long long stopAfter = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--print-parameters") {
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
    if (check) {
      rt.out() << deckPath << ": valid\n";
      return 0;
    }
    rt.initializeKokkos(threads >= 0 ? threads : deck.params->sublist("Run").get<int>("Threads"));
    rt.out() << "Epaphe " << epaphe::version << ": " << deckPath << " on " << rt.threads() << " thread(s), "
             << rt.size() << " MPI rank(s)\n";
    int code = 0;
    {
      epaphe::Simulation sim(deck, rt, output);
      if (!restart.empty()) sim.setRestart(restart);
      sim.setStopAfterSteps(stopAfter);
      sim.setup();
      epaphe::Simulation::catchSignals();  // from here on, SIGINT/SIGTERM stop with a checkpoint
      const epaphe::RunSummary& s = sim.run();
      sim.printSummary(rt.out());
      if (s.stopSignal != 0) code = 128 + s.stopSignal;
      else if (s.stoppedEarly) code = 3;
    }
    return code;
  } catch (const std::exception& e) {
    // Only rank 0 speaks, unless the error happened on another rank alone.
    if (rt.rank() == 0 || rt.size() == 1) std::cerr << "epaphe-run: error: " << e.what() << "\n";
    return 1;
  }
}
