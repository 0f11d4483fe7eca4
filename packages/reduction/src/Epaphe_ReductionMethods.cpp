// The built-in reduction methods (Epaphe_ReductionMethod.hpp): Craig-Bampton, Guyan, None, Full, lumped
// mass and Massless boundary, registered under their deck names.
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ReductionMethod.hpp"
#include "Epaphe_Runtime.hpp"

#include <algorithm>
#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// The entry of a Reduction key that several methods share, with its one documentation.
void reductionKey(ParameterList& pl, const std::string& key) {
  if (key == "Fixed-interface modes")
    deck::addInt(pl, key, 20,
                 "Modes kept: Craig-Bampton's fixed-interface modes, or for Massless "
                 "boundary the body's elastic normal modes with the retained nodes free",
                 0, 100000);
  else if (key == "Candidate modes")
    deck::addInt(pl, key, 0,
                 "Massless boundary: compute this many of the lowest elastic modes and keep "
                 "the 'Fixed-interface modes' of them that a load along 'Load direction' on every "
                 "retained node excites most (their generalized force, Kammer & Triller's effective "
                 "mass); 0: the lowest modes, as many as kept",
                 0, 100000);
  else if (key == "Eigensolver")
    deck::addEnum(
        pl, key, "Anasazi", {"Anasazi", "LAPACK dense"}, {0, 1},
        "Massless boundary: Anasazi (block Krylov-Schur, shift-invert through the factor: the lowest modes of "
        "any model) or LAPACK dense (every mode at once by dsygvd on the dense K and M: models of at most "
        "6000 DOFs; with 'Candidate modes', the whole spectrum to choose from for the cost of a few Anasazi "
        "pairs)");
  else if (key == "Load direction")
    deck::addDoubleArray(pl, key, {0, 0, 0},
                         "Massless boundary with 'Candidate modes': the direction of the "
                         "load the contact puts on the retained nodes, e.g. a wall's normal");
  else if (key == "Linear solver")
    deck::addEnum(
        pl, key, "MUMPS", {"MUMPS", "KLU2", "Belos CG"},
        {int(LinearSolver::Mumps), int(LinearSolver::Klu2), int(LinearSolver::BelosCg)},
        "Solver of K_CC for the constraint modes and inside Anasazi's shift-invert: MUMPS or KLU2 (Amesos2 "
        "direct; KLU2 one MPI rank only), or Belos CG (Belos block conjugate gradients, Jacobi-preconditioned, "
        "no factor stored: less memory, usually slower; see 'Iterative tolerance')");
  else if (key == "Iterative tolerance")
    deck::addDouble(pl, key, 1e-12, "Belos CG: relative residual at which a solve stops", 1e-300, 1e-2);
  else if (key == "Frequency check")
    deck::addInt(pl, key, 10,
                 "Compare this many frequencies of the reduced model with the full "
                 "model's (Anasazi); 0: skip",
                 0, 1000);
  else
    throw Error("reductionKey: no shared Reduction key '" + key + "'");
}

Teuchos::RCP<const ParameterList> keysOf(std::initializer_list<const char*> keys) {
  auto pl = Teuchos::rcp(new ParameterList("Reduction"));
  for (const char* k : keys) reductionKey(*pl, k);
  return pl;
}

/// The part of the reduced-model cache key the built-in methods' parameters make.
std::string keyText(const ParameterList& rp) {
  std::string load;
  for (double x : deck::getDoubles(rp, "Load direction")) load += std::to_string(x) + " ";
  return "\nmodes=" + std::to_string(rp.get<int>("Fixed-interface modes")) +
         "\ncheck=" + std::to_string(rp.get<int>("Frequency check")) +
         "\nsolver=" + rp.get<std::string>("Linear solver") +
         "\ntolerance=" + std::to_string(rp.get<double>("Iterative tolerance")) +
         "\ncandidates=" + std::to_string(rp.get<int>("Candidate modes")) +
         "\neigensolver=" + rp.get<std::string>("Eigensolver") + "\nload=" + load;
}

/// 'Candidate modes' selects a massless boundary's modes; the other methods refuse it.
void refuseCandidates(const ReductionMeshFacts& f) {
  const ParameterList& rp = *f.reduction;
  const int candidates = rp.get<int>("Candidate modes");
  EPAPHE_REQUIRE(candidates <= 0,
                 f.context << ": '" << deck::pathOf(rp, "Candidate modes") << "' = " << candidates
                           << " selects modes for a Massless boundary only; remove it, or set 'Method' to Massless "
                              "boundary");
}

/// A held body's rigid translations are not motions of a Craig-Bampton or Guyan model: no gravity.
void refuseHeldGravity(const ReductionMeshFacts& f) {
  const auto& g = f.gravity;
  if (f.clampedSet.empty()) return;
  for (int d = 0; d < 3; ++d)
    EPAPHE_REQUIRE(g[d] == 0, f.context << ", 'Gravity' = {" << g[0] << ", " << g[1] << ", " << g[2]
                                        << "}: a rigid translation along "
                                        << "xyz"[d] << " is not a motion of its "
                                        << f.reduction->get<std::string>("Method")
                                        << " model (its rigid translations are held): "
                                        << "the body is held by 'Clamped node set' = '" << f.clampedSet
                                        << "', so M t is not its weight T^T M e; use 'Full, lumped mass' (weight "
                                           "exact with clamps), or remove the key");
}

/// The frequency check from what the reduction computed through its factor (Craig-Bampton and Guyan:
/// CraigBamptonOptions::checkFrequencies), else by Anasazi on the full model, the shift placed by the
/// reduced model's frequencies (Rayleigh-Ritz upper bounds; a lumped model's own, close estimates):
/// a shift far below the lowest modes costs minutes on a fine mesh.
FrequencyCheck solvedFrequencyCheck(const FullModel& full, const ReducedModel& model, const CraigBamptonOptions& o,
                                    int count, const ReductionReport& report) {
  FrequencyCheck c;
  Stopwatch sw;
  count = std::min(count, full.numFree - 1);
  if (static_cast<int>(model.fullFrequencies.size()) >= count && !model.sparse()) {
    c.full.assign(model.fullFrequencies.begin(), model.fullFrequencies.begin() + count);
    c.throughReduction = true;
    c.seconds = report.checkSeconds;
    return c;
  }
  if (model.sparse())  // the lumped model's own frequencies, against the consistent model's
    c.lumped = fullModelFrequencies(withLumpedMass(full), count, o.solver, o.iterativeTolerance);
  c.full = fullModelFrequencies(full, count, o.solver, o.iterativeTolerance,
                                model.sparse() ? c.lumped : reducedFrequencies(model));
  c.seconds = sw.seconds();
  return c;
}

/// The built-in methods: their options from the deck's keys, their part of the cache key.
class BuiltInReduction : public ModalReduction {
public:
  void setParameters(const ParameterList& rp) override {
    options_ = craigBamptonOptions(rp, guyan());
    keyText_ = keyText(rp);
  }
  std::string cacheKeyText() const override { return keyText_; }
  FrequencyCheck frequencyCheck(const FullModel& full, const ReducedModel& model, int count,
                                const ReductionReport& report) const override {
    return solvedFrequencyCheck(full, model, options_, count, report);
  }

protected:
  virtual bool guyan() const { return false; }
  /// The log line of a method that keeps retained nodes and modes.
  std::string reducedLine(const ReducedModel& m, const ReductionReport& r, int ranks) const {
    std::ostringstream os;
    os << m.method() << ": " << r.retainedDofs << " retained DOFs + " << options_.modes << " modes = " << m.size
       << " reduced DOFs in " << formatDuration(r.seconds) << " on " << ranks << " rank(s) (factor "
       << formatDuration(r.factorSeconds) << ", constraint modes " << formatDuration(r.constraintSeconds)
       << ", eigenmodes " << formatDuration(r.eigenSeconds) << ")";
    return os.str();
  }

private:
  std::string keyText_;
};

class CraigBamptonMethod : public BuiltInReduction {
public:
  std::string name() const override { return "Craig-Bampton"; }
  std::string documentation() const override { return "fixed-interface modes and constraint modes (eq. 2.12)"; }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    return keysOf({"Fixed-interface modes", "Linear solver", "Iterative tolerance", "Frequency check"});
  }
  ReducedModel reduce(const FullModel& full, const std::vector<int>& retained, ReductionReport* report) const override {
    return craigBampton(full, retained, options_, report);
  }
  std::string describe(const ReducedModel& m, const ReductionReport& r, int ranks) const override {
    return reducedLine(m, r, ranks);
  }
  void checkMesh(const ReductionMeshFacts& f) const override {
    const int condensed = f.freeDofs - f.retainedDofs, modes = options_.modes;
    EPAPHE_REQUIRE(modes <= condensed, f.context << ": " << modes << " fixed-interface modes asked but only "
                                                 << condensed << " condensed DOFs exist (" << f.freeDofs << " free, "
                                                 << f.retainedDofs << " retained); set '"
                                                 << deck::pathOf(*f.reduction, "Fixed-interface modes")
                                                 << "' <= " << condensed);
    refuseCandidates(f);
    refuseHeldGravity(f);
  }
  bool hasParametricModel() const override { return true; }
  bool projectsCoriolis() const override { return true; }
  SpeedParametricModel parametricModel(SpeedSampleSource& source, const std::vector<int>& retained,
                                       const std::vector<double>& speeds, ReductionReport* report) const override {
    return parametricCraigBampton(source, retained, options_, speeds, report);
  }
  int parametricModes() const override { return options_.modes; }
};

class GuyanMethod : public CraigBamptonMethod {
public:
  std::string name() const override { return "Guyan"; }
  std::string documentation() const override { return "static condensation, Craig-Bampton without modes (eq. 2.11)"; }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    return keysOf({"Linear solver", "Iterative tolerance", "Frequency check"});
  }
  ReducedModel reduce(const FullModel& full, const std::vector<int>& retained, ReductionReport* report) const override {
    CraigBamptonOptions o = options_;
    o.modes = 0;
    return craigBampton(full, retained, o, report);
  }
  void checkMesh(const ReductionMeshFacts& f) const override {
    refuseCandidates(f);
    refuseHeldGravity(f);
  }

protected:
  bool guyan() const override { return true; }
};

class UnreducedMethod : public BuiltInReduction {
public:
  std::string name() const override { return "None"; }
  std::string documentation() const override { return "the full model, dense: small models only"; }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    return keysOf({"Linear solver", "Iterative tolerance", "Frequency check"});
  }
  ReducedModel reduce(const FullModel& full, const std::vector<int>&, ReductionReport*) const override {
    return unreducedModel(full);
  }
  bool retainsNodes() const override { return false; }
  bool projectsCoriolis() const override { return true; }
  void checkMesh(const ReductionMeshFacts& f) const override { refuseCandidates(f); }
};

class LumpedMethod : public UnreducedMethod {
public:
  std::string name() const override { return "Full, lumped mass"; }
  std::string documentation() const override {
    return "no reduction: K kept sparse, M lumped to its diagonal by HRZ scaling, a step is one sparse product and "
           "the contact flexibility is diagonal; cheaper than a dense reduced model once the retained interface is "
           "large, see docs/user/models.md; damping: none or Rayleigh with Beta = 0; 'Fixed-interface modes', "
           "'Retained node set' and the cache are unused; 'Frequency check' compares the lumped model's frequencies "
           "with the consistent-mass model's";
  }
  ReducedModel reduce(const FullModel& full, const std::vector<int>&, ReductionReport*) const override {
    return sparseModel(withLumpedMass(full));
  }
  bool cacheable() const override { return false; }
  bool projectsCoriolis() const override { return false; }
  bool diagonalMass() const override { return true; }
  std::string describe(const ReducedModel& m, const ReductionReport&, int) const override {
    return "full model kept: K sparse (" + std::to_string(m.sparseK.values.size()) +
           " entries), mass lumped to its diagonal (HRZ)";
  }
};

class MasslessBoundaryMethod : public BuiltInReduction {
public:
  std::string name() const override { return "Massless boundary"; }
  std::string documentation() const override {
    return "MacNeal's residual flexibility: the body's own lowest normal modes with the retained nodes free, plus "
           "the static response to the contact forces; the retained DOFs carry no mass, so the stable step is set "
           "by the last kept mode, not by the boundary; a body without clamps keeps its 6 rigid-body modes besides "
           "and its static part is the inertia-relief flexibility; an initial velocity is projected onto the "
           "modes, exactly for a free body, and the log says the kinetic energy a held body loses; Lagrange "
           "contact only";
  }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    return keysOf({"Fixed-interface modes", "Candidate modes", "Eigensolver", "Load direction", "Linear solver",
                   "Iterative tolerance", "Frequency check"});
  }
  ReducedModel reduce(const FullModel& full, const std::vector<int>& retained, ReductionReport* report) const override {
    return masslessBoundary(full, retained, options_, report);
  }
  std::string describe(const ReducedModel& m, const ReductionReport& r, int ranks) const override {
    return reducedLine(m, r, ranks);
  }
  /// Its modes are the full model's lowest (retained nodes free), from the reduction's own solve; its
  /// reduced model has no other frequency (the boundary carries no mass) to compare.
  FrequencyCheck frequencyCheck(const FullModel& full, const ReducedModel& model, int count,
                                const ReductionReport& report) const override {
    count = std::min(count, full.numFree - 1);
    if (static_cast<int>(model.fullFrequencies.size()) >= count)
      return solvedFrequencyCheck(full, model, options_, count, report);
    FrequencyCheck c;
    const auto& f = model.modeFrequencies;
    c.full.assign(f.begin(), f.begin() + std::min<std::ptrdiff_t>(count, static_cast<std::ptrdiff_t>(f.size())));
    c.reused = true;
    return c;
  }
  std::string penaltyContactProblem() const override {
    return "a penalty force computed from the predicted gap would ignore the boundary's static residual "
           "flexibility (its nodes have no mass to lag behind the force); use 'Lagrange', or 'Craig-Bampton' for "
           "penalty contact";
  }
  void checkMesh(const ReductionMeshFacts& f) const override {
    const ParameterList& rp = *f.reduction;
    const int rigid = f.clampedSet.empty() ? 6 : 0;  // a free body keeps its rigid-body modes too
    const int modes = options_.modes, candidates = options_.candidates;
    EPAPHE_REQUIRE(f.retainedDofs + modes + rigid <= f.freeDofs,
                   f.context << ": " << f.retainedDofs << " retained DOFs and " << modes << " modes"
                             << (rigid ? " (and the free body's 6 rigid-body modes)" : "") << " exceed the model's "
                             << f.freeDofs << " free DOFs; keep fewer modes");
    if (candidates <= 0) return;
    const std::string key = deck::pathOf(rp, "Candidate modes");
    EPAPHE_REQUIRE(candidates >= modes, f.context << ": '" << key << "' = " << candidates << " is fewer than the "
                                                  << modes << " 'Fixed-interface modes' kept");
    EPAPHE_REQUIRE(f.retainedDofs + candidates + rigid <= f.freeDofs,
                   f.context << ": " << candidates << " candidate modes and " << f.retainedDofs
                             << " retained DOFs exceed the model's " << f.freeDofs
                             << " free DOFs; ask fewer 'Candidate modes'");
    const auto d = options_.loadDirection;
    EPAPHE_REQUIRE(d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0,
                   f.context << ": '" << key << "' = " << candidates << " needs the direction "
                             << "of the contact's load: set '" << deck::pathOf(rp, "Load direction")
                             << "', e.g. {1, 0, 0}");
  }
  bool hasParametricModel() const override { return true; }
  void checkSpeedRange(const ParameterList& bp, const std::string& ctx) const override {
    EPAPHE_REQUIRE(!bp.get<std::string>("Clamped node set").empty(),
                   ctx << "->Speed range: a massless-boundary model over a speed range needs a held body; name a "
                       << "'Clamped node set' (a free body has rigid-body modes the parametric model does not keep)");
    EPAPHE_REQUIRE(options_.candidates <= options_.modes,
                   ctx << "->Speed range: a massless-boundary model over a speed range keeps the lowest modes; "
                       << "remove 'Reduction->Candidate modes' (" << options_.candidates << ")");
  }
  SpeedParametricModel parametricModel(SpeedSampleSource& source, const std::vector<int>& retained,
                                       const std::vector<double>& speeds, ReductionReport* report) const override {
    return parametricMasslessBoundary(source, retained, options_, speeds, report);
  }
  int parametricModes() const override { return options_.modes; }
};

}  // namespace

CraigBamptonOptions craigBamptonOptions(const ParameterList& rp, bool guyan) {
  CraigBamptonOptions o;
  o.modes = guyan ? 0 : rp.get<int>("Fixed-interface modes");
  o.solver = deck::getEnum<LinearSolver>(rp, "Linear solver");
  o.iterativeTolerance = rp.get<double>("Iterative tolerance");
  o.checkFrequencies = rp.get<int>("Frequency check");
  o.candidates = rp.get<int>("Candidate modes");
  o.denseEigen = rp.get<std::string>("Eigensolver") == "LAPACK dense";
  const auto d = deck::getDoubles(rp, "Load direction");
  for (std::size_t i = 0; i < 3 && i < d.size(); ++i) o.loadDirection[i] = d[i];
  return o;
}

void registerBuiltInReductions(const std::function<void(const std::string&, ReductionRegistry::Factory)>& add) {
  add("Craig-Bampton", [] { return std::make_unique<CraigBamptonMethod>(); });
  add("Guyan", [] { return std::make_unique<GuyanMethod>(); });
  add("None", [] { return std::make_unique<UnreducedMethod>(); });
  add("Full, lumped mass", [] { return std::make_unique<LumpedMethod>(); });
  add("Massless boundary", [] { return std::make_unique<MasslessBoundaryMethod>(); });
}

}  // namespace epaphe
