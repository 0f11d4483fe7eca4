// epaphe-modes: reduction convergence for a deck body, like thesis Table 5.1. The body's full model
// (built in or imported) is reduced by the deck's 'Reduction->Method' (Craig-Bampton, Guyan, Massless
// boundary) with each number of modes given, and the first frequencies of each reduced model are set
// against the full model's (Anasazi).
//
//   epaphe-modes DECK.xml --modes N1,N2,... [--body NAME] [--count K] [--csv FILE] [--threads N]
//
// A body with 'Rotation->Speed' is taken at that speed (Epaphe_ModelAtSpeed.hpp; epaphe-campbell
// covers a speed range). The deck's reduction settings are used (retained node set, linear solver); --count defaults to
// the body's 'Frequency check' (10 when 0). Prints the table of frequencies and relative errors
// and, with --csv, writes one line per (modes, mode): modes,mode,full_hz,reduced_hz,relative_error,
// reduction_seconds. Exit code 1 on an error, 2 for a wrong command line.
#include "Epaphe_BodyModel.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ModelAtSpeed.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_Runtime.hpp"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {
const char* usage =
    "usage: epaphe-modes DECK.xml --modes N1,N2,... [--body NAME] [--count K] [--csv FILE] [--threads N]\n";

std::vector<int> parseList(const std::string& s) {
  std::vector<int> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    int v = -1;
    try {
      v = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || v < 0)
      throw epaphe::Error("--modes '" + s + "': '" + item +
                          "' is not a mode count >= 0; "
                          "write e.g. --modes 0,5,10,20");
    out.push_back(v);
  }
  if (out.empty()) throw epaphe::Error("--modes is empty; write e.g. --modes 0,5,10,20");
  return out;
}
}  // namespace

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  std::string deckPath, body, csv, modesText;
  int count = -1, threads = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--modes" && i + 1 < argc)
      modesText = argv[++i];
    else if (a == "--body" && i + 1 < argc)
      body = argv[++i];
    else if (a == "--count" && i + 1 < argc)
      count = std::atoi(argv[++i]);
    else if (a == "--csv" && i + 1 < argc)
      csv = argv[++i];
    else if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (a == "--help" || a == "-h") {
      if (rt.rank() == 0) std::cout << usage;
      return 0;
    } else if (!a.empty() && a[0] != '-' && deckPath.empty())
      deckPath = a;
    else {
      if (rt.rank() == 0) std::cerr << "epaphe-modes: unknown argument '" << a << "'\n" << usage;
      return 2;
    }
  }
  if (deckPath.empty() || modesText.empty()) {
    if (rt.rank() == 0) std::cerr << "epaphe-modes: a deck and --modes are needed\n" << usage;
    return 2;
  }
  try {
    const std::vector<int> modes = parseList(modesText);
    epaphe::Deck deck = epaphe::readDeck(deckPath);
    rt.initializeKokkos(threads);
    const auto& bodies = deck.params->sublist("Bodies");
    EPAPHE_REQUIRE(bodies.numParams() > 0, deckPath << ": 'Epaphe->Bodies' is empty");
    if (body.empty()) body = bodies.name(bodies.begin());
    EPAPHE_REQUIRE(bodies.isSublist(body),
                   deckPath << ": no body '" << body << "' in 'Epaphe->Bodies'; --body names one of them");
    const auto& bp = bodies.sublist(body);
    const auto& rp = bp.sublist("Reduction");
    std::string retained = rp.get<std::string>("Retained node set");
    if (retained.empty()) retained = bp.get<std::string>("Contact node set");
    EPAPHE_REQUIRE(!retained.empty(), deckPath << ": body '" << body << "' has neither 'Reduction->Retained node set' "
                                               << "nor 'Contact node set'; name the nodes to retain");
    if (count < 0) count = rp.get<int>("Frequency check") > 0 ? rp.get<int>("Frequency check") : 10;
    EPAPHE_REQUIRE(count >= 1, "--count " << count << ": give 1 or more frequencies to compare");

    epaphe::Stopwatch sw;
    epaphe::FullModel full = epaphe::buildBodyModel(body, bp, deckPath, rt.comm());
    rt.out() << "[" << body << "] full model: " << full.numNodes() << " nodes, " << full.numFree << " free DOFs ("
             << epaphe::formatDuration(sw.seconds()) << ")\n";
    // a rotating body: its model at 'Rotation->Speed' (Epaphe_ModelAtSpeed.hpp)
    const epaphe::RotationOptions rotation =
        epaphe::rotationOptions(bp.sublist("Rotation"), deckPath + ": body '" + body + "', Rotation");
    if (rotation.speed != 0) {
      EPAPHE_REQUIRE(full.material.has_value(), deckPath << ": body '" << body
                                                         << "', Rotation->Speed = " << rotation.speed
                                                         << " rad/s: an imported model cannot be built at speed");
      full = epaphe::modelAtSpeed(full, rotation, nullptr);
      rt.out() << "[" << body << "] at " << rotation.speed << " rad/s\n";
    }
    const std::vector<int> retainedNodes =
        full.mesh.nodeSet(retained, deckPath + ": body '" + body + "', retained set");
    const std::string method = rp.get<std::string>("Method");
    const auto reduction = epaphe::reductionMethod(rp);
    auto* modal = dynamic_cast<epaphe::ModalReduction*>(reduction.get());
    EPAPHE_REQUIRE(modal != nullptr && reduction->retainsNodes(),
                   deckPath << ": body '" << body << "', 'Reduction->Method' = '" << method
                            << "' keeps the full model: "
                               "it has no modes to vary; its frequency check is in epaphe-run's summary");
    const epaphe::CraigBamptonOptions base = modal->options();
    std::vector<std::vector<double>> reduced;
    std::vector<double> seconds;
    std::vector<int> sizes;
    std::vector<double> f;  // the full model's: Craig-Bampton computes them through its K_CC factor
    double checkSeconds = 0;
    for (std::size_t k = 0; k < modes.size(); ++k) {  // the deck's reduction method, with each mode count
      modal->options() = base;
      modal->options().modes = modes[k];
      modal->options().checkFrequencies = k + 1 == modes.size() ? std::min(count, full.numFree - 1) : 0;
      epaphe::ReductionReport rep;
      const epaphe::ReducedModel red = reduction->reduce(full, retainedNodes, &rep);
      reduced.push_back(epaphe::reducedFrequencies(red));
      seconds.push_back(rep.seconds);
      sizes.push_back(red.size);
      f = red.fullFrequencies;
      checkSeconds = rep.checkSeconds;
    }
    // Otherwise (massless boundary, a free body): a shift-invert solve of its own, its shift placed
    // by the richest reduction's frequencies (Rayleigh-Ritz upper bounds).
    if (static_cast<int>(f.size()) < std::min(count, full.numFree - 1)) {
      sw.restart();
      f = epaphe::fullModelFrequencies(full, std::min(count, full.numFree - 1), base.solver, base.iterativeTolerance,
                                       reduced.back());
      checkSeconds = sw.seconds();
    }
    rt.out() << "[" << body << "] " << f.size() << " full-model frequencies (" << epaphe::formatDuration(checkSeconds)
             << ")\n";
    for (auto& fr : reduced) fr.resize(std::min(fr.size(), f.size()));
    std::ostream& out = rt.out();
    out << "\n"
        << method << " convergence of body '" << body << "' (" << retainedNodes.size() << " retained nodes), relative "
        << "error of the reduced frequencies against the full model's\n\n";
    out << std::setw(6) << "mode" << std::setw(14) << "full (Hz)";
    for (std::size_t k = 0; k < modes.size(); ++k)
      out << std::setw(14) << ((method == "Massless boundary" ? "MB " : "C-B ") + std::to_string(modes[k]));
    out << "\n";
    for (std::size_t i = 0; i < f.size(); ++i) {
      out << std::setw(6) << i + 1 << std::setw(14) << std::setprecision(7) << f[i];
      for (std::size_t k = 0; k < modes.size(); ++k) {
        std::ostringstream cell;
        if (i < reduced[k].size())
          cell << std::setprecision(4) << 100 * (reduced[k][i] - f[i]) / f[i] << " %";
        else
          cell << "-";
        out << std::setw(14) << cell.str();
      }
      out << "\n";
    }
    out << std::setw(20) << "reduced DOFs";
    for (int s : sizes) out << std::setw(14) << s;
    out << "\n" << std::setw(20) << "reduction (s)";
    for (double s : seconds) out << std::setw(14) << std::setprecision(3) << s;
    out << "\n";
    if (!csv.empty() && rt.rank() == 0) {
      std::ofstream c(csv);
      EPAPHE_REQUIRE(c, "--csv " << csv << ": cannot write the file; check the directory");
      c << "modes,mode,full_hz,reduced_hz,relative_error,reduction_seconds\n" << std::setprecision(17);
      for (std::size_t k = 0; k < modes.size(); ++k)
        for (std::size_t i = 0; i < reduced[k].size(); ++i)
          c << modes[k] << "," << i + 1 << "," << f[i] << "," << reduced[k][i] << "," << (reduced[k][i] - f[i]) / f[i]
            << "," << seconds[k] << "\n";
      out << "\nwritten " << csv << "\n";
    }
    return 0;
  } catch (const std::exception& e) {
    if (rt.rank() == 0 || rt.size() == 1) std::cerr << "epaphe-modes: error: " << e.what() << "\n";
    return 1;
  }
}
