#include "Epaphe_BodyHeat.hpp"

#include "Epaphe_BodyModel.hpp"
#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SurfaceContact.hpp"
#include "Epaphe_ThermalGrowth.hpp"
#include "Epaphe_ThermalReduction.hpp"

#include <algorithm>
#include <cmath>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// What a body's thermal model and its growth take of its material (eq. 76): a built-in mesh the
/// Material's density, E and nu and 'Thermal->Expansion coefficient'; a CalculiX import its input's
/// *DENSITY, *ELASTIC and *EXPANSION, else the deck's ('Material->Density', 'Thermal->Young's modulus',
/// 'Thermal->Poisson's ratio', 'Thermal->Expansion coefficient'). A value given both ways must agree.
struct BodyThermalMaterial {
  double density = 0;
  Material elastic;    // E, nu of the growth (when alpha > 0)
  double alpha = 0;    // 0: no growth
  std::string origin;  // where they come from, for the setup line
};

BodyThermalMaterial bodyThermalMaterial(const ParameterList& bp, const std::string& body, const std::string& deckPath,
                                        const std::string& ctx) {
  const ParameterList& th = bp.sublist("Thermal");
  BodyThermalMaterial m;
  const double deckE = th.get<double>("Young's modulus"), deckNu = th.get<double>("Poisson's ratio");
  const double deckAlpha = th.get<double>("Expansion coefficient");
  if (!hasCalculixMesh(bp)) {
    EPAPHE_REQUIRE(deckE == 0.0 && deckNu == -1.0,
                   ctx << ": 'Thermal->Young's modulus' = " << deckE << " and 'Thermal->Poisson's ratio' = " << deckNu
                       << " are for models imported from CalculiX; a built-in mesh's growth takes the Material's: "
                          "set 'Material->Young's modulus' and 'Material->Poisson's ratio' instead");
    m.density = bp.sublist("Material").get<double>("Density");
    m.elastic.young = bp.sublist("Material").get<double>("Young's modulus");
    m.elastic.poisson = bp.sublist("Material").get<double>("Poisson's ratio");
    m.alpha = deckAlpha;
    m.origin = "the deck's Material";
    return m;
  }
  const CalculixMaterial cm = importedMaterial(body, bp, deckPath);
  EPAPHE_REQUIRE(cm.problem.empty(),
                 ctx << ": 'Thermal' on a CalculiX import reads the input's material, and " << cm.problem);
  if (std::isnan(cm.density)) {
    m.density = bp.sublist("Material").get<double>("Density");
  } else {
    EPAPHE_REQUIRE(cm.density > 0, cm.densityWhere << ": *DENSITY = " << cm.density << " kg/m^3 (body '" << body
                                                   << "' of " << deckPath
                                                   << "); the thermal model's heat capacity needs a density > 0");
    m.density = cm.density;
  }
  if (!std::isnan(cm.expansion)) {
    EPAPHE_REQUIRE(cm.expansion >= 0, cm.expansionWhere << ": *EXPANSION = " << cm.expansion << " 1/K (body '" << body
                                                        << "' of " << deckPath << "); give alpha >= 0");
    EPAPHE_REQUIRE(deckAlpha == 0.0 || deckAlpha == cm.expansion,
                   ctx << ": 'Thermal->Expansion coefficient' = " << deckAlpha << " and " << cm.expansionWhere
                       << " *EXPANSION = " << cm.expansion << " differ; give alpha once (remove the deck's key)");
    m.alpha = cm.expansion;
  } else {
    m.alpha = deckAlpha;
  }
  m.origin = "the CalculiX input's material";
  if (m.alpha == 0.0) return m;
  if (!std::isnan(cm.young)) {
    EPAPHE_REQUIRE(deckE == 0.0 && deckNu == -1.0,
                   ctx << ": 'Thermal->Young's modulus' = " << deckE << " and 'Thermal->Poisson's ratio' = " << deckNu
                       << " are given, and " << cm.elasticWhere << " *ELASTIC gives E = " << cm.young
                       << ", nu = " << cm.poisson << "; give them once (remove the deck's keys)");
    EPAPHE_REQUIRE(cm.young > 0 && cm.poisson > -1 && cm.poisson < 0.5,
                   cm.elasticWhere << ": *ELASTIC gives E = " << cm.young << " Pa, nu = " << cm.poisson << " (body '"
                                   << body << "' of " << deckPath
                                   << "); the thermal growth needs E > 0 and -1 < nu < 0.5");
    m.elastic.young = cm.young;
    m.elastic.poisson = cm.poisson;
    return m;
  }
  EPAPHE_REQUIRE(deckE > 0 && deckNu > -1.0,
                 ctx << ": the thermal growth (alpha = " << m.alpha << " 1/K) of a CalculiX import needs E and nu, "
                     << "and its input has no *ELASTIC while 'Thermal->Young's modulus' = " << deckE
                     << " and 'Thermal->Poisson's ratio' = " << deckNu
                     << "; add *ELASTIC to the input or set both keys (E > 0, -1 < nu < 0.5)");
  m.elastic.young = deckE;
  m.elastic.poisson = deckNu;
  m.origin = "the deck's 'Thermal' keys";
  return m;
}

ThermalDefinition thermalDefinition(const ParameterList& bp, const Mesh& mesh, double density, const std::string& ctx) {
  const ParameterList& th = bp.sublist("Thermal");
  ThermalDefinition def;
  def.material = {th.get<double>("Conductivity"), th.get<double>("Specific heat"), density};
  checkThermalMaterial(def.material, (ctx + ", 'Thermal' (its density: 'Material->Density')").c_str());
  def.referenceTemperature = th.get<double>("Reference temperature");
  const std::string fixedSet = th.get<std::string>("Fixed temperature node set");
  if (!fixedSet.empty()) def.fixedNodes = mesh.nodeSet(fixedSet, ctx + ", 'Thermal->Fixed temperature node set'");
  const std::string convSet = th.get<std::string>("Convection node set");
  const double h = th.get<double>("Convection coefficient");
  EPAPHE_REQUIRE(convSet.empty() == (h == 0.0), ctx << ": 'Thermal->Convection node set' = '" << convSet
                                                    << "' and 'Thermal->Convection coefficient' = " << h
                                                    << ": give both (a face set and h > 0) or neither");
  if (!convSet.empty())
    def.convection.push_back(
        {mesh.nodeSet(convSet, ctx + ", 'Thermal->Convection node set'"), h, th.get<double>("Ambient temperature")});
  EPAPHE_REQUIRE(!def.fixedNodes.empty() || !def.convection.empty(),
                 ctx << ": the thermal model is insulated (no 'Thermal->Fixed temperature node set', no "
                        "'Thermal->Convection node set'), so the heat of rubbing has no steady state; give one");
  return def;
}

double partitionOf(const ParameterList& bp, double density) {
  const ParameterList& th = bp.sublist("Thermal");
  if (const double p = th.get<double>("Heat partition"); p >= 0.0) return p;
  const double eb =
      ThermalMaterial{th.get<double>("Conductivity"), th.get<double>("Specific heat"), density}.effusivity();
  return eb / (eb + th.get<double>("Counterface effusivity"));
}

}  // namespace

void checkThermal(const ParameterList& bp, const Mesh& mesh, const std::string& ctx, const std::string& body,
                  const std::string& deckPath) {
  if (!hasThermalModel(bp)) return;
  const BodyThermalMaterial material = bodyThermalMaterial(bp, body, deckPath, ctx);
  EPAPHE_REQUIRE(!bp.get<std::string>("Contact node set").empty(),
                 ctx << ": 'Thermal' heats the body at its contact nodes, and it has no 'Contact node set'");
  const double p = bp.sublist("Thermal").get<double>("Heat partition");
  EPAPHE_REQUIRE(p == -1.0 || p >= 0.0, ctx << ": 'Thermal->Heat partition' = " << p
                                            << "; give a share in [0, 1], or -1 for the effusivities'");
  const ThermalDefinition def = thermalDefinition(bp, mesh, material.density, ctx);
  if (!def.convection.empty()) {
    const auto areas = faceAreas(mesh, def.convection[0].nodes);
    EPAPHE_REQUIRE(std::any_of(areas.begin(), areas.end(), [](double a) { return a > 0; }),
                   ctx << ": 'Thermal->Convection node set' = '"
                       << bp.sublist("Thermal").get<std::string>("Convection node set")
                       << "' holds no face of an element (a face needs all its corners in the set, an imported mesh's "
                          "a boundary face); name a face's node set");
  }
  std::vector<char> fixed(static_cast<std::size_t>(mesh.numNodes()), 0);
  for (int n : def.fixedNodes) fixed[n] = 1;
  for (int n : mesh.nodeSet(bp.get<std::string>("Contact node set"), ctx + ", 'Contact node set'"))
    EPAPHE_REQUIRE(!fixed[n], ctx << ": contact node " << mesh.nodeId(n)
                                  << " is in 'Thermal->Fixed temperature node set' = '"
                                  << bp.sublist("Thermal").get<std::string>("Fixed temperature node set")
                                  << "': the heat of rubbing enters there, so it cannot be held at the reference "
                                     "temperature; hold another face");
}

std::vector<std::unique_ptr<BodyHeat>> buildBodyHeats(const ParameterList& P, const std::string& origin,
                                                      const std::vector<std::unique_ptr<SceneBody>>& bodies,
                                                      const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                                      std::ostream& out) {
  std::vector<std::unique_ptr<BodyHeat>> heats;
  const ParameterList& bl = P.sublist("Bodies");
  for (std::size_t ib = 0; ib < bodies.size(); ++ib) {
    const SceneBody& b = *bodies[ib];
    const ParameterList& bp = bl.sublist(b.deckName);
    if (!hasThermalModel(bp)) continue;
    const std::string ctx = origin + ": body '" + b.name + "'";
    const BodyThermalMaterial material = bodyThermalMaterial(bp, b.name, origin, ctx);
    Mesh mesh = buildThermalMesh(b.name, bp, origin);
    const ThermalDefinition def = thermalDefinition(bp, mesh, material.density, ctx);
    const ThermalFullModel full = assembleThermalModel(b.name, std::move(mesh), def, comm);
    ThermalReductionOptions opt;
    opt.modes = bp.sublist("Thermal").get<int>("Modes");
    opt.solver = comm->getSize() == 1 ? LinearSolver::Klu2 : LinearSolver::Mumps;
    auto heat = std::make_unique<BodyHeat>();
    heat->body = static_cast<int>(ib);
    heat->model = reduceThermal(full, b.contactNodes, opt);
    heat->integrator = std::make_unique<ThermalIntegrator>(heat->model);
    heat->partition = partitionOf(bp, material.density);
    heat->subSteps = bp.sublist("Thermal").get<int>("Sub-steps");
    heat->contactBegin = b.contactBegin;
    heat->contactEnd = b.contactEnd;
    heat->expansion = material.alpha;
    if (heat->expansion > 0) {
      // eq. 61: G = K^{-1} F at the contact nodes, from the body's full mechanical model (its clamps
      // hold it; built once, at setup); an imported model's elements and material, eq. 76
      const FullModel mech = buildBodyModel(b.name, bp, origin, comm);
      heat->growth = mech.material ? thermalGrowth(mech, heat->expansion, heat->model, b.contactNodes, opt.solver)
                                   : thermalGrowth(mech, material.elastic, heat->expansion, heat->model, b.contactNodes,
                                                   opt.solver);
    }
    out << "body '" << b.name << "': thermal model of " << full.numFree << " free nodes reduced to "
        << heat->model.numModes() << " (slowest time constant " << 1.0 / heat->model.rate.front()
        << " s), heat partition " << heat->partition << ", thermal step " << heat->subSteps << " mechanical steps"
        << (heat->expansion > 0 ? ", thermal growth of the contact nodes" : "")
        << (hasCalculixMesh(bp) ? " (imported mesh, material from " + material.origin + ")" : "") << "\n";
    heats.push_back(std::move(heat));
  }
  return heats;
}

struct HeatOutput::Record {
  std::string group;
  io::Series time, temperature, maxTemperature, frictionHeat, heat;
  std::unique_ptr<io::Series> growth;       // with thermal growth
  std::unique_ptr<io::Series> coatingHeat;  // with a coating
  Record(io::Hdf5File& file, const std::string& g, std::uint64_t nodes, bool grows, bool coated)
      : group(g),
        time(file, g + "/time", {}),
        temperature(file, g + "/temperature", {nodes}),
        maxTemperature(file, g + "/max_temperature", {}),
        frictionHeat(file, g + "/friction_heat", {}),
        heat(file, g + "/heat", {}) {
    if (grows) growth = std::make_unique<io::Series>(file, g + "/growth", std::vector<std::uint64_t>{3 * nodes});
    if (coated) coatingHeat = std::make_unique<io::Series>(file, g + "/coating_heat", std::vector<std::uint64_t>{});
  }
};

class HeatOutput::Sources : public LoopObserver {
public:
  explicit Sources(HeatOutput& out) : out_(out) {}
  void afterCorrect(ExplicitLoop& loop) override { out_.measure(loop); }

private:
  HeatOutput& out_;
};

HeatOutput::HeatOutput(io::Hdf5File& file, std::vector<std::unique_ptr<BodyHeat>> heats, SurfaceContact& contact,
                       const std::vector<std::unique_ptr<SceneBody>>& bodies, long long every,
                       std::vector<double> restX)
    : heats_(std::move(heats)),
      contact_(contact),
      every_(every),
      restX_(std::move(restX)),
      X_(restX_),
      heat_(static_cast<std::size_t>(contact.numNodes()), 0.0),
      power_(heat_.size(), 0.0),
      normalWork_(heat_.size(), 0.0),
      counterfaceWork_(heat_.size(), 0.0),
      coatingHeat_(contact.coating() ? heat_.size() : 0, 0.0),
      made_(heats_.size(), 0.0),
      coatingMadeBy_(heats_.size(), 0.0) {
  sources_ = std::make_unique<Sources>(*this);
  for (const auto& h : heats_) {
    const SceneBody& b = *bodies[h->body];
    const std::string group = "/thermal/" + b.name;
    records_.push_back(
        std::make_unique<Record>(file, group, b.contactNodes.size(), !h->growth.empty(), contact.coating() != nullptr));
    std::vector<double> labels;
    for (int n : b.contactNodes) labels.push_back(n);
    file.writeDoubles(group + "/nodes", labels);
    file.setAttribute(group, "partition", h->partition);
    file.setAttribute(group, "modes", h->model.numModes());
    file.writeDoubles(group + "/rates", h->model.rate);
    file.setAttribute(group, "sub_steps", h->subSteps);
    file.setAttribute(group, "reference_temperature", h->model.referenceTemperature);
    file.setAttribute(group, "expansion_coefficient", h->expansion);
  }
}

HeatOutput::~HeatOutput() = default;

LoopObserver* HeatOutput::sources() {
  return sources_.get();
}

void HeatOutput::measure(ExplicitLoop& loop) {
  ScopedPhase phase(loop.cost(), "thermal");  // the thermal update's share of the step, in the run's cost split
  rubbing_ = contact_.numActive() > 0;        // else no node made heat: the window only grows longer
  if (!rubbing_) return;
  contact_.frictionHeatByNode(loop.next(), loop.previous(), loop.timeStep(), heat_.data(), normalWork_.data(),
                              counterfaceWork_.data());
  // eq. 63: the step's Q, W_n and W_s over every contact node, and each thermal body's share p Q_b
  LoopAccumulators& acc = loop.accumulators();
  for (std::size_t k = 0; k < heat_.size(); ++k) {
    acc.frictionHeat += heat_[k];
    acc.normalWork += normalWork_[k];
    acc.counterfaceWork += counterfaceWork_[k];
  }
  if (const CoatingContact* coating = contact_.coating()) {
    // eq. 64: the plastic dissipation each node made over the step
    const auto made = Kokkos::create_mirror_view(coating->dissipationByNode());
    Kokkos::deep_copy(made, coating->dissipationByNode());
    for (std::size_t k = 0; k < coatingHeat_.size(); ++k) {
      coatingHeat_[k] = made(k);
      acc.coatingHeat += coatingHeat_[k];
    }
  }
  for (std::size_t i = 0; i < heats_.size(); ++i) {
    const BodyHeat& b = *heats_[i];
    double made = 0, plastic = 0;
    for (int k = b.contactBegin; k < b.contactEnd; ++k) made += heat_[k];
    if (!coatingHeat_.empty()) {
      for (int k = b.contactBegin; k < b.contactEnd; ++k) plastic += coatingHeat_[k];
      coatingMadeBy_[i] += plastic;
    }
    made_[i] += made;
    acc.heatReceived[b.body] += b.partition * (made + plastic);
  }
}

void HeatOutput::afterCorrect(ExplicitLoop& loop) {
  ScopedPhase phase(loop.cost(), "thermal");
  const double h = loop.timeStep();
  const long long step = loop.stepsDone() + 1;  // this step, once finished
  bool grown = false;
  for (std::size_t i = 0; i < heats_.size(); ++i) {
    BodyHeat& b = *heats_[i];
    if (rubbing_) {  // P_a = p (Q_a + D_a) / h: the friction heat and the coating's dissipation at node a (eq. 64)
      for (int k = b.contactBegin; k < b.contactEnd; ++k) power_[k - b.contactBegin] = b.partition * heat_[k] / h;
      if (!coatingHeat_.empty())
        for (int k = b.contactBegin; k < b.contactEnd; ++k)
          power_[k - b.contactBegin] += b.partition * coatingHeat_[k] / h;
    }
    b.integrator->addHeat(rubbing_ ? power_.data() : nullptr, h);
    if (step % b.subSteps == 0) {
      b.integrator->advanceWindow();
      if (!b.growth.empty()) {
        grow(b);
        grown = true;
      }
    }
  }
  if (grown) contact_.setReferencePositions(X_);
}

void HeatOutput::grow(const BodyHeat& b) {
  // X_a = X_a,0 + sum_i G[a, i] eta_i at the body's contact nodes (eq. 61)
  const std::vector<double>& eta = b.integrator->coordinates();
  const std::size_t m = eta.size();
  for (int k = b.contactBegin; k < b.contactEnd; ++k)
    for (int d = 0; d < 3; ++d) {
      const std::size_t row = 3 * static_cast<std::size_t>(k - b.contactBegin) + d;
      double u = 0;
      for (std::size_t i = 0; i < m; ++i) u += b.growth[row * m + i] * eta[i];
      X_[3 * static_cast<std::size_t>(k) + d] = restX_[3 * static_cast<std::size_t>(k) + d] + u;
    }
}

std::vector<io::Series*> HeatOutput::series() {
  std::vector<io::Series*> out;
  for (const auto& r : records_) {
    for (io::Series* x : {&r->time, &r->temperature, &r->maxTemperature, &r->frictionHeat, &r->heat}) out.push_back(x);
    if (r->growth) out.push_back(r->growth.get());
    if (r->coatingHeat) out.push_back(r->coatingHeat.get());
  }
  return out;
}

std::vector<double> HeatOutput::state() const {
  std::vector<double> s;
  for (std::size_t i = 0; i < heats_.size(); ++i) {
    const std::vector<double> b = heats_[i]->integrator->state();
    s.push_back(static_cast<double>(b.size()));
    s.insert(s.end(), b.begin(), b.end());
    s.push_back(made_[i]);
    s.push_back(coatingMadeBy_[i]);
  }
  return s;
}

void HeatOutput::setState(const std::vector<double>& s, const std::string& what) {
  std::size_t at = 0;
  bool grows = false;
  for (std::size_t i = 0; i < heats_.size(); ++i) {
    BodyHeat& b = *heats_[i];
    EPAPHE_REQUIRE(at < s.size() && at + 3 + static_cast<std::size_t>(s[at]) <= s.size(),
                   what << ": the thermal state ends before body " << i << "'s; run the deck anew");
    const std::size_t n = static_cast<std::size_t>(s[at]);
    b.integrator->setState(std::vector<double>(s.begin() + at + 1, s.begin() + at + 1 + n), what);
    made_[i] = s[at + 1 + n];
    coatingMadeBy_[i] = s[at + 2 + n];
    at += 3 + n;
    if (!b.growth.empty()) {
      grow(b);  // X_0 + G eta: the positions the last thermal step set (eta = 0 before it: X_0)
      grows = true;
    }
  }
  EPAPHE_REQUIRE(at == s.size(), what << ": the thermal state has " << s.size() << " values, " << at << " expected");
  if (grows) contact_.setReferencePositions(X_);
}

void HeatOutput::endStep(ExplicitLoop& loop) {
  if (loop.stepsDone() % every_ == 0) record(loop);
}

void HeatOutput::endRun(ExplicitLoop& loop) {
  if (loop.stepsDone() % every_ != 0) record(loop);
}

void HeatOutput::record(ExplicitLoop& loop) {
  ScopedPhase phase(loop.cost(), "thermal");
  for (std::size_t i = 0; i < heats_.size(); ++i) {
    const BodyHeat& b = *heats_[i];
    Record& r = *records_[i];
    const double t = static_cast<double>(loop.stepsDone()) * loop.timeStep();
    r.time.append(&t);
    std::vector<double> T;
    for (int n : b.model.heatedNodes) T.push_back(b.integrator->temperature(n));
    r.temperature.append(T);
    double hottest = -1e300;
    for (int n = 0; n < b.model.numNodes; ++n) hottest = std::max(hottest, b.integrator->temperature(n));
    r.maxTemperature.append(&hottest);
    r.frictionHeat.append(&made_[i]);
    if (r.coatingHeat) r.coatingHeat->append(&coatingMadeBy_[i]);
    const double received = b.integrator->heatReceived();
    r.heat.append(&received);
    if (r.growth) {
      std::vector<double> u;
      for (int k = b.contactBegin; k < b.contactEnd; ++k)
        for (int d = 0; d < 3; ++d)
          u.push_back(X_[3 * static_cast<std::size_t>(k) + d] - restX_[3 * static_cast<std::size_t>(k) + d]);
      r.growth->append(u);
    }
  }
}

}  // namespace epaphe
