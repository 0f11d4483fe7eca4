// epaphe-run: runs one deck.
//
//   epaphe-run DECK.xml [--threads N] [--output FILE] [--check]
//   epaphe-run --print-parameters
//
// --check validates the deck and stops; --print-parameters prints every valid parameter with its
// type, default, allowed values and documentation. Errors go to stderr on rank 0 as one message,
// and the exit code is 1 (2 for a wrong command line).
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
    "usage: epaphe-run DECK.xml [--threads N] [--output FILE] [--check]\n"
    "       epaphe-run --print-parameters\n";
}

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  std::string deckPath, output;
  int threads = -1;
  bool check = false;
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
  try {
    epaphe::Deck deck = epaphe::readDeck(deckPath);
    if (check) {
      rt.out() << deckPath << ": valid\n";
      return 0;
    }
    rt.initializeKokkos(threads >= 0 ? threads : deck.params->sublist("Run").get<int>("Threads"));
    rt.out() << "Epaphe " << epaphe::version << ": " << deckPath << " on " << rt.threads() << " thread(s), "
             << rt.size() << " MPI rank(s)\n";
    {
      epaphe::Simulation sim(deck, rt, output);
      sim.setup();
      sim.run();
      sim.printSummary(rt.out());
    }
    return 0;
  } catch (const std::exception& e) {
    // Only rank 0 speaks, unless the error happened on another rank alone.
    if (rt.rank() == 0 || rt.size() == 1) std::cerr << "epaphe-run: error: " << e.what() << "\n";
    return 1;
  }
}
