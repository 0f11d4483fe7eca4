// epaphe-campbell: the frequencies of a rotating deck body against its speed, from its parametric
// reduced model over 'Rotation->Speed range' (Epaphe_SpeedParametricModel.hpp), beside the full
// model's at the sample speeds and half-way between them, and the interpolation's error there
// against a direct reduction at that speed. The data of `epaphe-rotor campbell` (which draws the
// diagram, the engine orders and their crossings). A CalculiX model at speed ('Rotation->Imported
// speeds'): the full model at its imported speeds only, with no direct reduction between them.
//
//   epaphe-campbell DECK.xml --output FILE.h5 [--body NAME] [--speeds N] [--count K] [--threads N]
//
// --speeds: points of the curves over the range (default 41); --count: frequencies per speed
// (default: the body's 'Frequency check', 10 when 0). FILE.h5 holds
//   /speeds (N), /frequencies (N x K, Hz: the reduced model a run at that speed uses),
//   /growth (N, m: the largest static displacement of the contact node set),
//   /full/speeds (M), /full/frequencies (M x K: the full model at speed, Anasazi),
//   /direct/speeds (M'), /direct/frequencies (M' x K: a direct Craig-Bampton reduction at that speed),
//   /direct/growth (M'), /parametric/frequencies (M' x K: the parametric model there), and attributes
//   body, modes, samples, parametric_seconds, rest_reduction_seconds (the faster of two reductions at rest).
// Exit code 1 on an error, 2 for a wrong command line.
#include "Epaphe_BodyModel.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_ImportedSpeedSource.hpp"
#include "Epaphe_ModelAtSpeed.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SpeedParametricModel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {
const char* usage =
    "usage: epaphe-campbell DECK.xml --output FILE.h5 [--body NAME] [--speeds N] [--count K] [--threads N]\n";

/// The largest |u| over `nodes` of a nodal displacement (3 per node).
double largest(const std::vector<double>& u, const std::vector<int>& nodes) {
  double m = 0;
  for (int n : nodes) {
    const double* v = &u[3 * static_cast<std::size_t>(n)];
    m = std::max(m, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  return m;
}

void writeTable(epaphe::io::Hdf5File& f, const std::string& path, const std::vector<std::vector<double>>& rows,
                int count) {
  std::vector<double> flat;
  for (const auto& r : rows)
    for (int i = 0; i < count; ++i) flat.push_back(i < static_cast<int>(r.size()) ? r[i] : std::nan(""));
  f.writeDoubles(path, {rows.size(), static_cast<std::uint64_t>(count)}, flat.data());
}
}  // namespace

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  std::string deckPath, body, output;
  int points = 41, count = -1, threads = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--output" && i + 1 < argc)
      output = argv[++i];
    else if (a == "--body" && i + 1 < argc)
      body = argv[++i];
    else if (a == "--speeds" && i + 1 < argc)
      points = std::atoi(argv[++i]);
    else if (a == "--count" && i + 1 < argc)
      count = std::atoi(argv[++i]);
    else if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (a == "--help" || a == "-h") {
      if (rt.rank() == 0) std::cout << usage;
      return 0;
    } else if (!a.empty() && a[0] != '-' && deckPath.empty())
      deckPath = a;
    else {
      if (rt.rank() == 0) std::cerr << "epaphe-campbell: unknown argument '" << a << "'\n" << usage;
      return 2;
    }
  }
  if (deckPath.empty() || output.empty() || points < 2) {
    if (rt.rank() == 0) std::cerr << "epaphe-campbell: a deck, --output and --speeds >= 2 are needed\n" << usage;
    return 2;
  }
  try {
    epaphe::Deck deck = epaphe::readDeck(deckPath);
    rt.initializeKokkos(threads);
    const auto& bodies = deck.params->sublist("Bodies");
    EPAPHE_REQUIRE(bodies.numParams() > 0, deckPath << ": 'Epaphe->Bodies' is empty");
    if (body.empty()) body = bodies.name(bodies.begin());
    EPAPHE_REQUIRE(bodies.isSublist(body),
                   deckPath << ": no body '" << body << "' in 'Epaphe->Bodies'; --body names one of them");
    const auto& bp = bodies.sublist(body);
    const auto& rp = bp.sublist("Reduction");
    const auto& rotp = bp.sublist("Rotation");
    const std::string ctx = deckPath + ": body '" + body + "'";
    const auto range = epaphe::deck::getDoubles(rotp, "Speed range");
    EPAPHE_REQUIRE(range.size() == 2 && range[0] >= 0 && range[1] > range[0],
                   ctx << ": a Campbell diagram needs 'Rotation->Speed range' = {minimum, maximum} (rad/s)");
    // an imported model: CalculiX jobs at its imported speeds (the samples; no full model between them)
    const epaphe::ImportedSpeeds imported = epaphe::importedSpeeds(body, bp, deckPath);
    EPAPHE_REQUIRE(epaphe::hasBuiltInMesh(bp) || !imported.empty(),
                   ctx << ": the model is imported; Epaphe builds a body at speed from the elements of its built-in "
                          "meshes, or from CalculiX matrices at speed ('Rotation->Imported speeds', 'Imported jobs')");
    std::string retained = rp.get<std::string>("Retained node set");
    if (retained.empty()) retained = bp.get<std::string>("Contact node set");
    EPAPHE_REQUIRE(!retained.empty(), ctx << " has neither 'Reduction->Retained node set' nor 'Contact node set'");
    if (count < 0) count = rp.get<int>("Frequency check") > 0 ? rp.get<int>("Frequency check") : 10;
    const epaphe::RotationOptions rotation = epaphe::rotationOptions(rotp, ctx + ", Rotation");
    const auto reduction = epaphe::reductionMethod(rp);  // the options of a Craig-Bampton-like method
    const auto* modal = dynamic_cast<const epaphe::ModalReduction*>(reduction.get());
    const epaphe::CraigBamptonOptions co = modal ? modal->options() : epaphe::craigBamptonOptions(rp, false);
    std::ostream& out = rt.out();

    epaphe::FullModel restStorage;
    const auto source = epaphe::bodySpeedSource(body, bp, deckPath, rt.comm(), rotation, restStorage);
    const epaphe::FullModel& rest = source->reference();
    const auto retainedNodes = rest.mesh.nodeSet(retained, ctx + ", retained set");
    const std::string contactSet = bp.get<std::string>("Contact node set");
    const auto contact = rest.mesh.nodeSet(contactSet.empty() ? retained : contactSet, ctx + ", contact set");
    // one reduction at rest, the unit of the parametric model's cost: the faster of two, the first one
    // paying the process's first factorization and eigensolve (up to 2x on the deck's 528-DOF blade)
    epaphe::Stopwatch sw;
    double restSeconds = 0;
    for (int k = 0; k < 2; ++k) {
      sw.restart();
      epaphe::craigBampton(rest, retainedNodes, co);
      restSeconds = k == 0 ? sw.seconds() : std::min(restSeconds, sw.seconds());
    }
    sw.restart();
    const auto samples =
        imported.empty() ? epaphe::sampleSpeeds(range[0], range[1], rotp.get<int>("Sample speeds")) : imported.speeds;
    epaphe::ReductionReport cost;
    const epaphe::SpeedParametricModel pm = epaphe::parametricCraigBampton(*source, retainedNodes, co, samples, &cost);
    const double parametricSeconds = sw.seconds();
    out << "[" << body << "] parametric model: " << samples.size() << " samples, common basis of " << pm.base.size
        << " DOFs, built in " << epaphe::formatDuration(parametricSeconds) << " = " << std::setprecision(3)
        << parametricSeconds / restSeconds << " x one Craig-Bampton reduction at rest ("
        << epaphe::formatDuration(restSeconds) << "): static states " << epaphe::formatDuration(cost.staticSeconds)
        << ", reductions at the samples "
        << epaphe::formatDuration(cost.factorSeconds + cost.constraintSeconds + cost.eigenSeconds)
        << ", common basis and projections " << epaphe::formatDuration(cost.projectSeconds) << "\n";

    if (!pm.base.coriolis.empty())
      out << "[" << body << "] the curves keep the Coriolis terms (the whirls of M q'' + Omega G_r q' + K q = 0); "
          << "the full model's points and the direct reductions do not\n";
    // The curves: the model each run at that speed uses.
    std::vector<double> speeds, growth;
    std::vector<std::vector<double>> freq;
    for (int k = 0; k < points; ++k) {
      const double w = range[0] + (range[1] - range[0]) * k / (points - 1);
      const epaphe::ReducedModel r = pm.at(w, co.modes, ctx);
      // with 'Rotation->Coriolis' the run's model whirls: M q'' + Omega G_r q' + K q = 0
      auto f = r.coriolis.empty() ? epaphe::reducedFrequencies(r)
                                  : epaphe::gyroscopicFrequencies(r.K, r.M, r.coriolis, w, r.size);
      f.resize(std::min<std::size_t>(f.size(), static_cast<std::size_t>(count)));
      speeds.push_back(w);
      freq.push_back(f);
      growth.push_back(largest(r.staticDisplacement, contact));
    }

    // The full model at the samples and half-way between them; the direct reduction half-way.
    std::vector<double> fullSpeeds, directSpeeds, directGrowth;
    std::vector<std::vector<double>> fullFreq, directFreq, paramFreq;
    for (std::size_t s = 0; s < samples.size(); ++s)
      for (int half = 0; half < (s + 1 < samples.size() && imported.empty() ? 2 : 1); ++half) {
        const double w =
            half == 0 ? samples[s] : std::sqrt(0.5 * (samples[s] * samples[s] + samples[s + 1] * samples[s + 1]));
        epaphe::RotationOptions o = rotation;
        o.speed = w;
        o.staticState = pm.staticState;  // the parametric model's samples' static state
        epaphe::SpeedReport sr;
        const epaphe::FullModel at =
            !imported.empty() ? source->sample(w).model : (w == 0 ? rest : epaphe::modelAtSpeed(rest, o, &sr));
        const epaphe::ReducedModel direct = epaphe::craigBampton(at, retainedNodes, co);
        fullSpeeds.push_back(w);
        fullFreq.push_back(epaphe::fullModelFrequencies(at, count, co.solver, co.iterativeTolerance,
                                                        epaphe::reducedFrequencies(direct)));
        if (half == 1) {
          auto fd = epaphe::reducedFrequencies(direct), fp = epaphe::reducedFrequencies(pm.at(w, co.modes, ctx));
          fd.resize(std::min<std::size_t>(fd.size(), static_cast<std::size_t>(count)));
          fp.resize(fd.size());
          directSpeeds.push_back(w);
          directFreq.push_back(fd);
          paramFreq.push_back(fp);
          directGrowth.push_back(largest(sr.staticDisplacement, contact));
          double worst = 0;
          for (std::size_t i = 0; i < fd.size(); ++i) worst = std::max(worst, std::abs(fp[i] / fd[i] - 1));
          const double g = largest(pm.staticDisplacementAt(w), contact);
          out << "[" << body << "] between samples, " << w << " rad/s: parametric against direct reduction, largest "
              << "frequency difference " << std::setprecision(3) << 100 * worst << " %, contact set's static "
              << "displacement " << g << " m against " << directGrowth.back() << " m ("
              << 100 * (g / directGrowth.back() - 1) << " %)\n";
        }
      }
    out << "\n"
        << std::setw(12) << "speed" << std::setw(6) << "mode" << std::setw(14) << "full (Hz)" << std::setw(14)
        << "reduced (Hz)" << std::setw(12) << "difference\n";
    for (std::size_t s = 0; s < fullSpeeds.size(); ++s) {
      const auto fr = epaphe::reducedFrequencies(pm.at(fullSpeeds[s], co.modes, ctx));
      for (std::size_t i = 0; i < fullFreq[s].size(); ++i)
        out << std::setw(12) << std::setprecision(6) << fullSpeeds[s] << std::setw(6) << i + 1 << std::setw(14)
            << std::setprecision(7) << fullFreq[s][i] << std::setw(14) << fr[i] << std::setw(11) << std::setprecision(3)
            << 100 * (fr[i] / fullFreq[s][i] - 1) << " %\n";
    }
    if (rt.rank() == 0) {
      epaphe::io::Hdf5File f(output, epaphe::io::Hdf5File::Mode::Create);
      f.setAttribute("/", "body", body);
      f.setAttribute("/", "modes", static_cast<long long>(co.modes));
      f.setAttribute("/", "parametric_seconds", parametricSeconds);
      f.setAttribute("/", "rest_reduction_seconds", restSeconds);
      f.writeDoubles("/samples", samples);
      f.writeDoubles("/speeds", speeds);
      writeTable(f, "/frequencies", freq, count);
      f.writeDoubles("/growth", growth);
      f.writeDoubles("/full/speeds", fullSpeeds);
      writeTable(f, "/full/frequencies", fullFreq, count);
      f.writeDoubles("/direct/speeds", directSpeeds);
      writeTable(f, "/direct/frequencies", directFreq, count);
      writeTable(f, "/parametric/frequencies", paramFreq, count);
      f.writeDoubles("/direct/growth", directGrowth);
      f.close();
      out << "\nwritten " << output << "\n";
    }
    return 0;
  } catch (const std::exception& e) {
    if (rt.rank() == 0 || rt.size() == 1) std::cerr << "epaphe-campbell: error: " << e.what() << "\n";
    return 1;
  }
}
