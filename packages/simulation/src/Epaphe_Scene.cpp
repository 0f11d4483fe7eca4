#include "Epaphe_Scene.hpp"

#include "Epaphe_BodyModel.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ImportedSpeedSource.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_ReducedModelCache.hpp"
#include "Epaphe_SceneCheck.hpp"
#include "Epaphe_SelfLockingMonitor.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// The rotation of a surface (thesis section 3.3), rigid or carried by a body: 'Rotation speed',
/// 'Initial angle', 'Rotation axis', 'Rotation center'.
/// The nodes a reduction keeps: 'Reduction->Retained node set', else the body's contact node set.
std::string retainedSetOf(const SceneBody& b, const ParameterList& rp) {
  const std::string given = rp.get<std::string>("Retained node set");
  return given.empty() ? b.contactSet : given;
}

void setRotation(ContactSurface& cs, const ParameterList& s, const SpeedLaw& law, const std::string& origin) {
  cs.omega = s.get<double>("Rotation speed");
  if (law.ramp && cs.omega != 0.0) cs.law = law.scaled(cs.omega > 0 ? 1.0 : -1.0);  // a run-up: checkScene
  cs.phase = s.get<double>("Initial angle") * M_PI / 180.0;
  cs.axis = deck::getVec3(s, "Rotation axis", origin);
  cs.center = deck::getVec3(s, "Rotation center", origin);
  EPAPHE_REQUIRE(cs.axis[0] != 0.0 || cs.axis[1] != 0.0 || cs.axis[2] != 0.0,
                 origin << ": '" << deck::pathOf(s, "Rotation axis")
                        << "' = {0, 0, 0}; give the axis direction, e.g. "
                           "{0, 0, 1}");
}

/// A copy of `tuned` with its stiffness times `factor` (a mistuned instance): K, a lumped full model's
/// sparse K, the massless boundary's residual flexibility (divided), and the frequencies times sqrt(factor).
std::shared_ptr<ReducedModel> scaledStiffness(const ReducedModel& tuned, double factor) {
  auto r = std::make_shared<ReducedModel>(tuned);
  for (double& v : r->K) v *= factor;
  for (double& v : r->sparseK.values) v *= factor;
  for (double& v : r->residualFlexibility) v /= factor;
  for (double& v : r->modeFrequencies) v *= std::sqrt(factor);
  for (double& v : r->fullFrequencies) v *= std::sqrt(factor);
  return r;
}

/// Rank 0 builds or loads; the result is broadcast so every rank holds the same reduced model.
void broadcast(ReducedModel& r, const Teuchos::Comm<int>& comm) {
  if (comm.getSize() == 1) return;
  auto bcastVec = [&](auto& v) {
    int n = static_cast<int>(v.size());
    Teuchos::broadcast(comm, 0, Teuchos::outArg(n));
    v.resize(static_cast<std::size_t>(n));
    if (n > 0) Teuchos::broadcast(comm, 0, n, v.data());
  };
  int header[3] = {r.size, r.numModes, static_cast<int>(r.kind)};
  Teuchos::broadcast(comm, 0, 3, header);
  r.size = header[0];
  r.numModes = header[1];
  r.kind = static_cast<ReductionKind>(header[2]);
  bcastVec(r.K);
  bcastVec(r.M);
  bcastVec(r.recovery);
  bcastVec(r.nodeDof);
  bcastVec(r.retainedNodes);
  bcastVec(r.modeFrequencies);
  bcastVec(r.fullFrequencies);
  bcastVec(r.boundaryModes);
  bcastVec(r.residualFlexibility);
  bcastVec(r.modalTranslation);
  Teuchos::broadcast(comm, 0, 3, r.translationMass.data());
  Teuchos::broadcast(comm, 0, Teuchos::outArg(r.speed));
  bcastVec(r.staticDisplacement);
  bcastVec(r.coriolis);
  std::vector<double> xyz;
  if (comm.getRank() == 0)
    for (const auto& c : r.coords) xyz.insert(xyz.end(), c.begin(), c.end());
  bcastVec(xyz);
  r.coords.resize(xyz.size() / 3);
  for (std::size_t i = 0; i < r.coords.size(); ++i) r.coords[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  // node sets: names as one text, then each set
  std::string names;
  for (const auto& kv : r.nodeSets) names += kv.first + "\n";
  std::vector<char> chars(names.begin(), names.end());
  bcastVec(chars);
  names.assign(chars.begin(), chars.end());
  std::map<std::string, std::vector<int>> sets;
  for (std::size_t b = 0, e; (e = names.find('\n', b)) != std::string::npos; b = e + 1) {
    const std::string name = names.substr(b, e - b);
    std::vector<int> nodes = comm.getRank() == 0 ? r.nodeSets[name] : std::vector<int>();
    bcastVec(nodes);
    sets[name] = nodes;
  }
  r.nodeSets = sets;
  // node grids: (nu, nv, nodes) per grid, in the order of the names
  std::string gnames;
  for (const auto& kv : r.nodeGrids) gnames += kv.first + "\n";
  std::vector<char> gchars(gnames.begin(), gnames.end());
  bcastVec(gchars);
  gnames.assign(gchars.begin(), gchars.end());
  std::map<std::string, NodeGrid> grids;
  for (std::size_t b = 0, e; (e = gnames.find('\n', b)) != std::string::npos; b = e + 1) {
    const std::string name = gnames.substr(b, e - b);
    std::vector<int> g;
    if (comm.getRank() == 0) {
      const NodeGrid& ng = r.nodeGrids[name];
      g.push_back(ng.nu);
      g.push_back(ng.nv);
      g.insert(g.end(), ng.nodes.begin(), ng.nodes.end());
    }
    bcastVec(g);
    grids[name] = NodeGrid{g.at(0), g.at(1), std::vector<int>(g.begin() + 2, g.end())};
  }
  r.nodeGrids = grids;
}

}  // namespace

Scene::Scene(const Deck& deck, const Runtime& runtime, std::string output, bool restarting)
    : deck_(deck), rt_(runtime), output_(std::move(output)), restarting_(restarting) {}

Scene::~Scene() = default;

void Scene::build() {
  Stopwatch watch;
  const ParameterList& P = *deck_.params;
  const std::string& origin = deck_.origin;

  // ---- bodies -------------------------------------------------------------------------------
  checkScene(deck_, output_, restarting_);  // everything that needs no reduced model, as --check
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& tp = P.sublist("Time");
  const double h = tp.get<double>("Time step");
  const DampingOptions damping = dampingOptions(tp, origin);
  const ParameterList& cp = P.sublist("Contact");
  const ContactOptions copt = contactOptions(cp, h);

  for (auto it = bl.begin(); it != bl.end(); ++it) {
    auto b = std::make_unique<Body>();
    b->name = b->deckName = bl.name(it);
    const ParameterList& bp = bl.sublist(b->name);
    b->contactSet = bp.get<std::string>("Contact node set");
    loadOrReduce(b.get(), bp);
    const int count = bp.sublist("Instances").get<int>("Count");
    if (count == 1) {
      setInitialState(b.get(), bp, h, damping);
      b->offset = systemSize_;
      systemSize_ += b->rom->size;
      bodies_.push_back(std::move(b));
      continue;
    }
    // a stage: N instances of the one reduced model (shared unless mistuned), each placed by its pose
    const std::vector<double> factors = instanceFactors(bp, origin + ": body '" + b->name + "'");  // checkScene
    std::shared_ptr<ReducedModel> tuned = b->rom;
    for (int k = 0; k < count; ++k) {
      auto inst = std::make_unique<Body>();
      inst->deckName = b->name;
      inst->name = b->name + "[" + std::to_string(k) + "]";
      inst->instance = k;
      inst->poseAngle = 2 * M_PI * k / count;
      inst->stiffnessFactor = factors[static_cast<std::size_t>(k)];
      inst->method = b->method;
      inst->fromCache = b->fromCache;
      inst->report = b->report;
      inst->contactSet = b->contactSet;
      inst->rom = inst->stiffnessFactor == 1 ? tuned : scaledStiffness(*tuned, inst->stiffnessFactor);
      inst->fullFrequencies = inst->rom->fullFrequencies;
      for (double f : b->reducedFrequencies) inst->reducedFrequencies.push_back(f * std::sqrt(inst->stiffnessFactor));
      setInitialState(inst.get(), bp, h, damping);
      inst->offset = systemSize_;
      systemSize_ += inst->rom->size;
      bodies_.push_back(std::move(inst));
    }
    int mistuned = 0;
    for (double f : factors) mistuned += f != 1;
    rt_.out() << "[" << b->name << "] " << count << " instances at 2 pi k / " << count << " about the engine axis, "
              << "one " << b->method << " model";
    if (mistuned > 0) {
      const auto [lo, hi] = std::minmax_element(factors.begin(), factors.end());
      rt_.out() << " (" << mistuned << " mistuned, stiffness factors " << *lo << " to " << *hi << ")";
    }
    rt_.out() << "\n";
  }

  const auto carriedDofs = setupSurfacesAndContact(copt);
  checkContactAtStart(cp, h);
  if (tp.get<std::string>("Initial state") == "Static equilibrium") staticEquilibrium(cp);
  checkStableSteps(carriedDofs, copt, damping);
  report_.timeStep = h;
  report_.criticalStep = 1e300;
  for (const auto& b : bodies_) report_.criticalStep = std::min(report_.criticalStep, b->stable.critical);
  report_.setupSeconds = watch.seconds();
}

/// The reduced-model cache key of a body: a hash of everything its reduced model depends on (the
/// model's text and imported files' content hashes, the clamps, the reduction's parameters, the
/// rotation). Reads the imported files: call it on rank 0.
std::string Scene::reducedModelKey(const Body& body, const ParameterList& bp) const {
  const ParameterList& rp = bp.sublist("Reduction");
  return contentKey(bodyModelKeyText(body.name, bp, deck_.origin) +
                    "clamped=" + bp.get<std::string>("Clamped node set") + "\nretained=" + retainedSetOf(body, rp) +
                    "\nmethod=" + rp.get<std::string>("Method") + reductionMethod(rp)->cacheKeyText() +
                    rotationKeyText(bp.sublist("Rotation")));
}

/// The body's reduced model: from its cache when the key (model files, mesh, reduction parameters)
/// matches, else built and reduced by its method (Epaphe_ReductionMethod.hpp), frequency-checked and cached.
void Scene::loadOrReduce(Body* b, const ParameterList& bp) {
  const std::string& origin = deck_.origin;
  std::ostream& out = rt_.out();
  const ParameterList& rp = bp.sublist("Reduction");
  const std::string ctx = origin + ": body '" + b->name + "'";
  bodyModelFiles(b->name, bp, origin);  // every rank checks the files exist before anything waits on rank 0
  const std::string cacheFile = cacheFileOf(rp, output_, b->name);
  const auto method = reductionMethod(rp);
  const bool useCache = rp.get<bool>("Cache") && method->cacheable();  // a lumped full model has nothing to reduce
  const std::string key = useCache && rt_.comm()->getRank() == 0 ? reducedModelKey(*b, bp) : std::string();

  const RotationOptions rotation = rotationOptions(bp.sublist("Rotation"), ctx + ", Rotation");
  if (!deck::getDoubles(bp.sublist("Rotation"), "Speed range").empty()) {
    // a rotating body over a speed range: its model at the speed, from the parametric model
    const SpeedParametricModel pm = parametricModel(b, bp, key, cacheFile, useCache, rotation);
    if (const SpeedLaw law = speedLawOf(bp.sublist("Rotation")); law.ramp) {
      // a run-up: the model at the start speed, and its stiffness over the range on that basis
      SpeedParametricModel::FixedBasis f = pm.onFixedBasis(law.start, method->parametricModes(), ctx);
      *b->rom = std::move(f.model);
      b->runUp = std::make_unique<RunUpModel>();
      b->runUp->law = law;
      b->runUp->maxSpeed = pm.maxSpeed();
      b->runUp->stiffness = std::move(f.stiffness);
      b->runUp->growth = pm.growth;
      for (const auto& c : pm.base.coords) b->runUp->restX.insert(b->runUp->restX.end(), c.begin(), c.end());
      out << "[" << b->name << "] run-up from " << law.start << " rad/s at " << law.t0 << " s to " << law.end
          << " rad/s at " << law.t1 << " s: the stiffness and static state follow the speed on the basis at "
          << law.start << " rad/s (refreshed every " << b->runUp->xiStep << " in (Omega/Omega_max)^2)\n";
    } else {
      *b->rom = pm.at(std::abs(rotation.speed), method->parametricModes(), ctx);
    }
    b->rom->speed = rotation.speed;
    b->method = method->modelName(*b->rom);
    out << "[" << b->name << "] " << b->method << " at " << rotation.speed << " rad/s from the parametric model ("
        << pm.base.size << " DOFs, samples";
    for (double w : pm.speeds) out << " " << w;
    out << " rad/s): " << b->rom->size << " reduced DOFs\n";
  } else {
    loadOrBuildReducedModel(b, bp, key, cacheFile, useCache, rotation);
    b->method = method->modelName(*b->rom);
  }
  if (b->fromCache)
    out << "[" << b->name << "] reduced model (" << b->method << ", " << b->rom->size << " DOFs) reused from "
        << cacheFile << "\n";
  b->fullFrequencies = b->rom->fullFrequencies;
  if (!b->rom->sparse()) b->reducedFrequencies = reducedFrequencies(*b->rom);
  if (!b->rom->coriolis.empty()) reportCoriolis(*b, out);
  if (!b->rom->staticDisplacement.empty()) reportGrowth(*b, bp, out);
}

/// The body's reduced model at rest or at its speed ('Rotation->Speed'): from its cache when the key
/// matches, else built (at speed: Epaphe_ModelAtSpeed.hpp), reduced by its method (reductionMethod),
/// frequency-checked and cached.
void Scene::loadOrBuildReducedModel(Body* b, const ParameterList& bp, const std::string& key,
                                    const std::string& cacheFile, bool useCache, const RotationOptions& rotation) {
  const std::string& origin = deck_.origin;
  auto comm = rt_.comm();
  std::ostream& out = rt_.out();
  const ParameterList& rp = bp.sublist("Reduction");
  const std::string ctx = origin + ": body '" + b->name + "'";
  const std::string retainedSet = retainedSetOf(*b, rp);
  const auto method = reductionMethod(rp);
  const int checkCount = rp.get<int>("Frequency check");
  int cached = 0;
  if (useCache && comm->getRank() == 0) cached = loadReducedModel(cacheFile, key, *b->rom) ? 1 : 0;
  Teuchos::broadcast(*comm, 0, Teuchos::outArg(cached));
  if (cached) {
    broadcast(*b->rom, *comm);
    b->rom->name = b->name;
    b->fromCache = true;
  } else {
    Stopwatch built;
    FullModel full = buildBodyModel(b->name, bp, origin, comm);
    out << "[" << b->name << "] full model: " << full.numNodes() << " nodes, " << full.numFree << " free DOFs, "
        << full.mesh.hexes.size() << " hexahedra, " << (hasBuiltInMesh(bp) ? "built" : "imported") << " in "
        << formatDuration(built.seconds()) << "\n";
    SpeedReport atSpeed;
    if (rotation.speed != 0) {  // checkScene refused a rotating imported model: Epaphe's elements at the speed
      SpeedSample sample = BuiltInSpeedSource(full, rotation).sample(rotation.speed);
      full = std::move(sample.model);
      atSpeed = std::move(sample.report);
      out << "[" << b->name << "] at " << rotation.speed << " rad/s: "
          << (atSpeed.stiffened ? "stress-stiffened (" + std::to_string(atSpeed.passes) + " passes)"
                                : std::string("linear"))
          << " static state and K_e + K_sigma - Omega^2 M_perp in " << formatDuration(atSpeed.seconds)
          << "; largest static displacement " << atSpeed.largestDisplacement << " m (node "
          << full.mesh.nodeId(atSpeed.largestNode) << "; linear state " << atSpeed.linearLargest << " m";
      if (atSpeed.passes > 0) out << ", the stress-stiffened one moves it by " << 100 * atSpeed.stiffenedChange << " %";
      out << "); Coriolis terms Omega ||G|| / sqrt(||K|| ||M||) = " << atSpeed.coriolisRatio
          << (rotation.coriolis ? " (kept)\n" : " (not kept)\n");
    }
    const bool retains = method->retainsNodes();
    EPAPHE_REQUIRE(!retains || !retainedSet.empty(), ctx << ": reduction " << rp.get<std::string>("Method")
                                                         << " needs a 'Retained node set' (or a 'Contact node set')");
    const auto retainedNodes =
        retains ? full.mesh.nodeSet(retainedSet, ctx + ", 'Reduction->Retained node set'") : std::vector<int>{};
    try {  // the reduction's errors name the body; add the deck
      *b->rom = method->reduce(full, retainedNodes, &b->report);
    } catch (const Error& e) {
      throw Error(origin + ": " + e.what());
    }
    b->rom->speed = rotation.speed;
    b->rom->staticDisplacement = std::move(atSpeed.staticDisplacement);
    if (rotation.coriolis && !atSpeed.coriolis.is_null())  // G_r = V^T G V (checkScene: a dense reduction)
      b->rom->coriolis = reducedCoriolis(*atSpeed.coriolis, full, b->rom->recovery, b->rom->size);
    if (const std::string line = method->describe(*b->rom, b->report, comm->getSize()); !line.empty())
      out << "[" << b->name << "] " << line << "\n";
    if (checkCount > 0) {
      const FrequencyCheck fc = method->frequencyCheck(full, *b->rom, checkCount, b->report);
      b->rom->fullFrequencies = fc.full;
      if (b->rom->sparse()) b->reducedFrequencies = fc.lumped;
      out << "[" << b->name << "] frequency check: the full model's lowest " << fc.full.size() << " frequencies "
          << (fc.reused
                  ? std::string("are the reduction's own modes")
                  : (fc.throughReduction ? "through the reduction's factor in " : "in ") + formatDuration(fc.seconds))
          << "\n";
    }
    if (useCache && comm->getRank() == 0) saveReducedModel(*b->rom, cacheFile, key);
  }
}

/// The parametric model of a body over its 'Rotation->Speed range': from the cache when the key
/// matches (the key leaves out the speed, so that a speed sweep reduces nothing per speed), else
/// built from direct reductions at the sample speeds and cached. On every rank.
SpeedParametricModel Scene::parametricModel(Body* b, const ParameterList& bp, const std::string& key,
                                            const std::string& cacheFile, bool useCache,
                                            const RotationOptions& rotation) {
  auto comm = rt_.comm();
  std::ostream& out = rt_.out();
  const ParameterList& rp = bp.sublist("Reduction");
  const ParameterList& rotp = bp.sublist("Rotation");
  SpeedParametricModel pm;
  int cached = 0;
  if (useCache && comm->getRank() == 0) cached = loadParametricModel(cacheFile, key, pm) ? 1 : 0;
  Teuchos::broadcast(*comm, 0, Teuchos::outArg(cached));
  if (cached) {
    broadcast(pm.base, *comm);
    int sizes[4] = {static_cast<int>(pm.speeds.size()), pm.boundarySize, static_cast<int>(pm.staticState),
                    static_cast<int>(pm.growth.size())};
    Teuchos::broadcast(*comm, 0, 4, sizes);
    pm.speeds.resize(static_cast<std::size_t>(sizes[0]));
    pm.boundarySize = sizes[1];
    pm.staticState = static_cast<StaticState>(sizes[2]);
    Teuchos::broadcast(*comm, 0, sizes[0], pm.speeds.data());
    pm.stiffness.resize(static_cast<std::size_t>(sizes[0] - 1));
    pm.growth.resize(static_cast<std::size_t>(sizes[3]));
    const std::size_t N = static_cast<std::size_t>(pm.base.size), rows = 3 * pm.base.coords.size();
    for (auto& c : pm.stiffness) {
      c.resize(N * N);
      Teuchos::broadcast(*comm, 0, static_cast<int>(c.size()), c.data());
    }
    for (auto& g : pm.growth) {
      g.resize(rows);
      Teuchos::broadcast(*comm, 0, static_cast<int>(g.size()), g.data());
    }
    b->fromCache = true;
    return pm;
  }
  Stopwatch built;
  const ImportedSpeeds imported = importedSpeeds(b->name, bp, deck_.origin);
  FullModel rest;
  const auto source = bodySpeedSource(b->name, bp, deck_.origin, comm, rotation, rest);
  const std::string retainedSet = retainedSetOf(*b, rp);
  const std::string ctx = deck_.origin + ": body '" + b->name + "'";
  EPAPHE_REQUIRE(!retainedSet.empty(), ctx << ": reduction " << rp.get<std::string>("Method")
                                           << " needs a 'Retained node set' (or a 'Contact node set')");
  const auto retainedNodes = source->reference().mesh.nodeSet(retainedSet, ctx + ", 'Reduction->Retained node set'");
  const auto range = deck::getDoubles(rotp, "Speed range");
  const auto speeds =
      imported.empty() ? sampleSpeeds(range[0], range[1], rotp.get<int>("Sample speeds")) : imported.speeds;
  try {
    pm = reductionMethod(rp)->parametricModel(*source, retainedNodes, speeds, &b->report);
  } catch (const Error& e) {
    throw Error(deck_.origin + ": " + e.what());
  }
  out << "[" << b->name << "] parametric model over " << range[0] << " to " << range[1] << " rad/s: " << speeds.size()
      << (pm.base.massless() ? " massless-boundary" : " Craig-Bampton") << " reductions and "
      << (imported.empty() ? (pm.staticState == StaticState::StressStiffened ? "stress-stiffened" : "linear")
                           : "CalculiX (imported)")
      << " static states, common basis of " << pm.base.size << " DOFs (" << pm.boundarySize << " retained), in "
      << formatDuration(built.seconds()) << "; the static state between samples by Galerkin on the basis, fitted by "
      << "a polynomial of degree " << pm.growth.size() - 1 << " in Omega^2 within " << pm.growthFitError
      << " of its largest displacement\n";
  if (useCache && comm->getRank() == 0) saveParametricModel(pm, cacheFile, key);
  return pm;
}

/// What the kept Coriolis terms do to the reduced model: its lowest frequencies with them (the whirls of
/// M q'' + Omega G_r q' + K q = 0) against those of (K, M), the largest relative change.
void Scene::reportCoriolis(const Body& b, std::ostream& out) const {
  const ReducedModel& r = *b.rom;
  if (r.size > 1000) {  // the first-order eigenproblem is 2n x 2n, dense: minutes past a few thousand
    out << "[" << b.name << "] Coriolis terms kept (Omega G_r, " << r.size << " x " << r.size
        << "); their effect on the frequencies is computed for models of 1000 DOFs or fewer\n";
    return;
  }
  const std::vector<double> g = gyroscopicFrequencies(r.K, r.M, r.coriolis, r.speed, r.size);
  const std::size_t count = std::min<std::size_t>({10, g.size(), b.reducedFrequencies.size()});
  double largest = 0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const double f0 = b.reducedFrequencies[k];
    const double change = f0 > 0 ? std::abs(g[k] / f0 - 1) : 0.0;
    if (change > largest) {
      largest = change;
      at = k;
    }
  }
  out << "[" << b.name << "] Coriolis terms kept (Omega G_r, " << r.size << " x " << r.size << "): the lowest " << count
      << " frequencies move by up to " << 100 * largest << " %";
  if (count > 0)
    out << " (mode " << at + 1 << ": " << b.reducedFrequencies[at] << " Hz without, " << g[at] << " Hz with)";
  out << "\n";
}

/// The static displacement at speed of the contact and watched node sets: its largest length and
/// its largest radial part (along P (x - x_0), away from the axis), the tip growth that closes a
/// casing's clearance.
void Scene::reportGrowth(const Body& b, const ParameterList& bp, std::ostream& out) const {
  const SpinAxis axis = rotationOptions(bp.sublist("Rotation"), deck_.origin).axis;
  const auto& a = axis.direction;
  std::vector<std::string> sets;
  if (!b.contactSet.empty()) sets.push_back(b.contactSet);
  for (const std::string& ws : deck::getStrings(bp, "Watched node sets")) sets.push_back(ws);
  for (const std::string& set : sets) {
    double largest = 0, radial = -1e300;
    for (int n : b.rom->nodeSet(set, deck_.origin + ": body '" + b.name + "'")) {
      const double* u = &b.rom->staticDisplacement[3 * static_cast<std::size_t>(n)];
      double r[3], along = 0;  // r = P (x - x_0) at rest, x = coords - u
      for (int d = 0; d < 3; ++d) r[d] = b.rom->coords[n][d] - u[d] - axis.point[d];
      for (int d = 0; d < 3; ++d) along += r[d] * a[d];
      double len = 0;
      for (int d = 0; d < 3; ++d) len += (r[d] - along * a[d]) * (r[d] - along * a[d]);
      len = std::sqrt(len);
      double growth = 0;
      for (int d = 0; d < 3; ++d) growth += (len > 0 ? (r[d] - along * a[d]) / len : 0.0) * u[d];
      largest = std::max(largest, std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
      radial = std::max(radial, growth);
    }
    out << "[" << b.name << "] at " << b.rom->speed << " rad/s, node set '" << set << "': static displacement up to "
        << largest << " m, radial growth up to " << radial << " m\n";
  }
}

/// Initial velocity, watched and contact node sets, the integrator and gravity of a reduced body.
void Scene::setInitialState(Body* b, const ParameterList& bp, double h, const DampingOptions& damping) {
  const std::string& origin = deck_.origin;
  const std::string ctx = origin + ": body '" + b->name + "'";
  // Initial velocity: uniform translation, exact in reduced coordinates (retained DOFs); a massless
  // boundary's projection onto the modes (rigidTranslation) is exact for a free body, and a held
  // one's keeps part of the field's kinetic energy: said here, measured.
  const auto v0 = deck::getVec3(bp, "Initial velocity", origin);
  b->v0.assign(static_cast<std::size_t>(b->rom->size), 0.0);
  b->speed = std::sqrt(v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]);
  for (int d = 0; d < 3; ++d) {
    const auto t = b->rom->rigidTranslation(d);
    for (int i = 0; i < b->rom->size; ++i) b->v0[i] += v0[d] * t[i];
  }
  if (b->rom->massless() && b->speed > 0) {
    double field = 0, kept = 0;  // 1/2 v^T M v of the uniform field (translations are M-orthogonal), 1/2 |eta'|^2
    for (int d = 0; d < 3; ++d) field += 0.5 * v0[d] * v0[d] * b->rom->translationMass[d];
    for (int k = 0; k < b->rom->numModes; ++k)
      kept += 0.5 * b->v0[b->rom->boundarySize() + k] * b->v0[b->rom->boundarySize() + k];
    rt_.out() << "[" << b->name << "] initial velocity projected onto the " << b->rom->numModes
              << " modes: kinetic energy " << kept << " J of the uniform field's " << field << " J ("
              << 100 * (1 - kept / field) << " % lost)\n";
  }
  for (const std::string& ws : deck::getStrings(bp, "Watched node sets"))
    b->watched.emplace_back(ws, b->rom->nodeSet(ws, ctx + ", 'Watched node sets'"));

  if (!b->contactSet.empty()) b->contactNodes = b->rom->nodeSet(b->contactSet, ctx + ", 'Contact node set'");
  b->integrator = std::make_unique<CentralDifference>(*b->rom, h, damping);

  // Gravity g: the consistent weight f = sum_d g_d T^T M e_d (e_d: every node translated by 1
  // along d), a constant force. When a rigid translation is a motion of the model, T t_d = e_d
  // (t_d = rigidTranslation(d)), so T^T M e_d = (T^T M T) t_d = M t_d, the vector of the momentum
  // p = (M t_d) . v below: exact for every reduction. With lumped mass M t_d is the free DOFs' nodal
  // masses, exact for a clamped body too. The initial acceleration is M^{-1} f = sum_d g_d t_d.
  const auto grav = deck::getVec3(bp, "Gravity", origin);
  b->a0.assign(static_cast<std::size_t>(b->rom->size), 0.0);
  if (grav[0] != 0 || grav[1] != 0 || grav[2] != 0) {
    const int n = b->rom->size;
    std::vector<double> f(static_cast<std::size_t>(n), 0.0);
    for (int d = 0; d < 3; ++d) {
      if (grav[d] == 0) continue;
      const auto t = b->rom->rigidTranslation(d);
      const auto Mt = b->rom->massTimes(t);
      if (!b->rom->sparse()) {
        // t_d is a rigid motion when its Rayleigh quotient t^T K t / t^T M t is round-off against the
        // largest eigenvalue (bounded below by max_i K_ii / M_ii); a clamped body's is at least its
        // lowest eigenvalue.
        double tKt = 0, tMt = 0, scale = 0;
        for (int j = 0; j < n; ++j) {
          tMt += t[j] * Mt[j];
          if (b->rom->m(j, j) > 0) scale = std::max(scale, b->rom->k(j, j) / b->rom->m(j, j));
          if (t[j] != 0)
            for (int i = 0; i < n; ++i) tKt += t[i] * b->rom->k(i, j) * t[j];
        }
        const double rayleigh = tMt > 0 ? tKt / tMt : 1e300;
        const std::string clamped = bp.get<std::string>("Clamped node set");
        EPAPHE_REQUIRE(
            rayleigh <= 1e-10 * scale,
            ctx << ", 'Gravity' = {" << grav[0] << ", " << grav[1] << ", " << grav[2] << "}: a rigid translation along "
                << "xyz"[d] << " is not a motion of its " << b->method << " model (t^T K t / t^T M t = " << rayleigh
                << " s^-2, against " << scale << " for its stiffest DOF): the body is held"
                << (clamped.empty() ? " by the imported model's boundary conditions"
                                    : " by 'Clamped node set' = '" + clamped + "'")
                << ", so M t is not its weight T^T M e; use 'Full, lumped mass' (weight exact "
                   "with clamps), or remove the key");
      }
      for (int i = 0; i < n; ++i) {
        f[i] += grav[d] * Mt[i];
        b->a0[i] += grav[d] * t[i];
      }
    }
    b->integrator->setConstantForce(f);
  }
  // Loads (eqs. 65-66): f_k = sum over the set's nodes i of R_i^T F_k, R_i the recovery rows of node i
  // (u_i = R_i q): the reduced force that does the nodal forces' virtual work on every motion of the
  // model. A full model with lumped mass (R = I) takes F_k on each free DOF of the set's nodes.
  for (const BodyLoad& load : bodyLoads(bp, origin)) {
    std::vector<double> f(static_cast<std::size_t>(b->rom->size), 0.0);
    if (!load.reducedDofs.empty()) {
      // on the model's coordinates directly: f_j = F_j (eq. 66 with R^T F given)
      for (std::size_t k = 0; k < load.reducedDofs.size(); ++k) {
        const int j = load.reducedDofs[k];
        EPAPHE_REQUIRE(j < b->rom->size, origin << ": '" << load.path << "->Reduced DOFs' holds " << j << ", but body '"
                                                << b->name << "' has " << b->rom->size << " coordinates (" << b->method
                                                << "): give indices from 0 to " << b->rom->size - 1);
        f[static_cast<std::size_t>(j)] += load.reducedForces[k];
      }
      b->integrator->addLoad(f, load.g);
      continue;
    }
    const std::vector<int> nodes = b->rom->nodeSet(load.nodeSet, origin + ": '" + load.path + "->Node set'");
    if (b->rom->sparse() || b->rom->recovery.empty()) {
      const std::vector<int> index = b->rom->recoveryIndex(nodes);
      for (std::size_t r = 0; r < index.size(); ++r)
        if (index[r] >= 0) f[static_cast<std::size_t>(index[r])] += load.force[r % 3];
    } else {
      for (int node : nodes)
        for (int d = 0; d < 3; ++d) {
          if (load.force[d] == 0) continue;
          const double* row = b->rom->recoveryRow(node, d);
          for (int i = 0; i < b->rom->size; ++i) f[static_cast<std::size_t>(i)] += row[i] * load.force[d];
        }
    }
    b->integrator->addLoad(f, load.g);
  }
  std::vector<int> watchedNodes;
  for (const auto& w : b->watched) watchedNodes.insert(watchedNodes.end(), w.second.begin(), w.second.end());
  b->recoveryWatched = NodeRecovery(*b->rom, watchedNodes, "epaphe::watched::R");
}

/// Refuses what would run to nonsense at t = 0 (ContactGuards): a step longer than a surface patch,
/// bodies that start inside a surface (or resolves them gently, as the deck says).
void Scene::checkContactAtStart(const ParameterList& cp, double h) {
  const std::string& origin = deck_.origin;
  std::ostream& out = rt_.out();
  if (!contact_) return;
  {
    std::vector<std::string> names;
    std::vector<double> speeds;
    for (const auto& b : bodies_) {
      names.push_back(b->name);
      speeds.push_back(b->speed);
    }
    guards_ = std::make_unique<ContactGuards>(guardOptions(cp), names, origin);
    corrector_ = std::make_unique<GuardedContact>(*contact_, *guards_);
    guards_->checkInitialVelocities(*contact_, speeds, h, report_.warnings);
    const DenseVector q0("epaphe::q0", static_cast<std::size_t>(systemSize_));
    CostSplit setupCost;
    const PenetrationReport pr = guards_->checkInitialPenetration(*contact_, q0, h, setupCost);
    if (pr.facing == 0)  // e.g. a surface placed in mm in a deck in m
      report_.warnings.push_back(
          "no contact node lies over any surface at t = 0 (every projection falls beyond an "
          "open edge): check the surfaces' positions, extents and units");
    report_.initialPenetrations = pr.count;
    report_.initialPenetrationDepth = pr.deepest;
    for (const auto& w : report_.warnings) out << "warning: " << w << "\n";
    if (pr.count > 0)
      out << "initial penetration: " << pr.count << " contact node(s), deepest " << pr.deepest
          << " m, resolved gently (Contact->Initial penetration)\n";
  }
}

/// 'Time->Initial state' = Static equilibrium (docs/theory/forced-response.md, eqs. 71-72): the contact
/// nodes that touch a surface at t = 0 (|g| within the guards' tolerance) are held where they are, stuck
/// (their three DOFs) or, with mu = 0, along the normal only, and the loads at t = 0 (with gravity) are
/// balanced by K q + C^T lambda = f, C q = 0 (eq. 71), solved densely. The surface's force on node k,
/// R_k = -lambda_k, must press (R_k . n_k > 0; else the preload opens the contact: refused) and lie in the
/// friction cone; a node whose tangential force exceeds mu N slides: its normal row alone, and mu N along
/// the tangential force it needed applied as a load, N from the solve again, until the set of sliding nodes
/// repeats (eq. 72).
void Scene::staticEquilibrium(const ParameterList& cp) {
  const std::string& origin = deck_.origin;
  std::ostream& out = rt_.out();
  const int n = systemSize_;
  EPAPHE_REQUIRE(contact_ != nullptr, origin << ": 'Time->Initial state' = Static equilibrium needs contact nodes "
                                                "('Contact node set') that touch a surface at t = 0");
  EPAPHE_REQUIRE(n <= 6000, origin << ": 'Time->Initial state' = Static equilibrium solves the bodies' " << n
                                   << " coordinates densely, at most 6000; reduce the bodies (Craig-Bampton or "
                                      "Massless boundary)");
  // K (block diagonal) and f at t = 0
  std::vector<double> K(static_cast<std::size_t>(n) * n, 0.0), f(static_cast<std::size_t>(n), 0.0);
  for (const auto& b : bodies_) {
    const int o = b->offset, m = b->rom->size;
    if (b->rom->sparse()) {
      const SparseRows& S = b->rom->sparseK;
      for (int i = 0; i < m; ++i)
        for (std::size_t e = S.rowStart[i]; e < S.rowStart[i + 1]; ++e)
          K[static_cast<std::size_t>(o + S.cols[e]) * n + (o + i)] = S.values[e];
    } else {
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) K[static_cast<std::size_t>(o + j) * n + (o + i)] = b->rom->k(i, j);
    }
    const std::vector<double> fb = b->integrator->forceAt(0.0);
    for (int i = 0; i < m; ++i) f[o + i] = fb[i];
  }
  // the touching nodes, their DOFs and normals
  CostSplit cost;
  const DenseVector zero("epaphe::q0", static_cast<std::size_t>(n));
  contact_->setTime(0.0);
  const auto warm = contact_->warmStarts();
  contact_->measureGaps(zero, cost);
  contact_->setWarmStarts(warm);
  const auto gap = contact_->gap();
  const auto surf = contact_->surfaceIndex();
  const DetectionViews& v = contact_->detection().views();
  auto dof = Kokkos::create_mirror_view(v.dof);
  Kokkos::deep_copy(dof, v.dof);
  auto nrm = Kokkos::create_mirror_view(v.normal);
  Kokkos::deep_copy(nrm, v.normal);
  const double tol = 1e-6 * contact_->detection().smallestPatch();
  const double mu = cp.get<double>("Friction coefficient");
  std::vector<int> held;
  for (int k = 0; k < contact_->numNodes(); ++k)
    if (surf(k) >= 0 && std::abs(gap(k)) <= tol) held.push_back(k);
  EPAPHE_REQUIRE(!held.empty(), origin << ": 'Time->Initial state' = Static equilibrium: no contact node touches a "
                                          "surface at t = 0 (within "
                                       << tol << " m); place the surfaces on the contact nodes, or start 'At rest'");
  std::vector<bool> sliding(held.size(), mu == 0.0);
  std::vector<std::array<double, 3>> slideDir(held.size(), {0, 0, 0});
  std::vector<double> normalForce(held.size(), 0.0);
  std::vector<double> q;
  int slides = 0;
  for (int pass = 0; pass < 50; ++pass) {
    // eq. 71: [K C^T; C 0] [q; lambda] = [f + friction of the sliding nodes; 0]
    std::vector<std::array<double, 3>> rows;  // per constraint row: its direction over the node's DOFs
    std::vector<int> rowNode;
    for (std::size_t a = 0; a < held.size(); ++a) {
      const int k = held[a];
      if (sliding[a]) {
        rows.push_back({nrm(k, 0), nrm(k, 1), nrm(k, 2)});
        rowNode.push_back(static_cast<int>(a));
      } else
        for (int d = 0; d < 3; ++d) {
          std::array<double, 3> e{0, 0, 0};
          e[d] = 1;
          rows.push_back(e);
          rowNode.push_back(static_cast<int>(a));
        }
    }
    const int m = static_cast<int>(rows.size()), N = n + m;
    std::vector<double> A(static_cast<std::size_t>(N) * N, 0.0), rhs(static_cast<std::size_t>(N), 0.0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) A[static_cast<std::size_t>(j) * N + i] = K[static_cast<std::size_t>(j) * n + i];
    for (int i = 0; i < n; ++i) rhs[i] = f[i];
    for (std::size_t a = 0; a < held.size(); ++a)
      if (sliding[a] && mu > 0)
        for (int d = 0; d < 3; ++d) rhs[dof(held[a], d)] += mu * normalForce[a] * slideDir[a][d];
    for (int r = 0; r < m; ++r)
      for (int d = 0; d < 3; ++d) {
        const int i = dof(held[rowNode[r]], d);
        A[static_cast<std::size_t>(n + r) * N + i] += rows[r][d];    // C^T
        A[static_cast<std::size_t>(i) * N + (n + r)] += rows[r][d];  // C
      }
    const std::vector<double> Ainv =
        generalInverse(A, N, origin + ": the static equilibrium of 'Time->Initial state'",
                       "the contact nodes that touch a surface must hold every body still: a body free to move "
                       "(no clamp, too few touching nodes) has no static equilibrium; start 'At rest'");
    std::vector<double> x(static_cast<std::size_t>(N), 0.0);
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) x[i] += Ainv[static_cast<std::size_t>(j) * N + i] * rhs[j];
    q.assign(x.begin(), x.begin() + n);
    // eq. 72: the surface's force on each held node, R = -C^T lambda; pressing, and in the cone
    std::vector<std::array<double, 3>> R(held.size(), {0, 0, 0});
    for (int r = 0; r < m; ++r)
      for (int d = 0; d < 3; ++d) R[rowNode[r]][d] -= rows[r][d] * x[n + r];
    bool changed = false;
    slides = 0;
    for (std::size_t a = 0; a < held.size(); ++a) {
      const int k = held[a];
      double Nk = 0;
      for (int d = 0; d < 3; ++d) Nk += R[a][d] * nrm(k, d);
      EPAPHE_REQUIRE(Nk > 0, origin << ": 'Time->Initial state' = Static equilibrium: the loads at t = 0 pull contact "
                                       "node "
                                    << contact_->nodes()[k] << " of body '" << bodies_[contact_->nodeBlocks()[k]]->name
                                    << "' off its surface (normal force " << Nk
                                    << " N): the preload opens the contact; press the node onto the surface "
                                       "(reverse the load), or start 'At rest'");
      normalForce[a] = Nk;
      if (sliding[a]) {
        ++slides;
        continue;
      }
      double T2 = 0;
      std::array<double, 3> T{};
      for (int d = 0; d < 3; ++d) {
        T[d] = R[a][d] - Nk * nrm(k, d);
        T2 += T[d] * T[d];
      }
      if (std::sqrt(T2) > mu * Nk) {  // outside the cone: it slides, friction mu N along the force it needed
        sliding[a] = true;
        for (int d = 0; d < 3; ++d) slideDir[a][d] = T[d] / std::sqrt(T2);
        changed = true;
        ++slides;
      }
    }
    if (!changed) break;
  }
  initialState_ = q;
  double largest = 0;
  for (double x : q) largest = std::max(largest, std::abs(x));
  out << "static equilibrium at t = 0 (Time->Initial state): " << held.size() << " contact node(s) held, "
      << held.size() - static_cast<std::size_t>(slides) << " stuck, " << slides << " sliding; largest |q_0| " << largest
      << "\n";
}

/// The stable step of each body (with the contact law's springs on its contact and carried surface DOFs)
/// against the deck's time step: an Error, or a warning with 'Allow unstable time step'.
void Scene::checkStableSteps(const std::vector<std::vector<int>>& carriedDofs, const ContactOptions& copt,
                             const DampingOptions& damping) {
  const std::string& origin = deck_.origin;
  std::ostream& out = rt_.out();
  const ParameterList& tp = deck_.params->sublist("Time");
  const double h = tp.get<double>("Time step");
  const ContactLaw& law = contactLaw(copt.method());
  // Stable step of each body, with the contact law's springs on its contact and surface DOFs.
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    Body* b = bodies_[ib].get();
    std::vector<int> contactDofs;
    for (int n : b->contactNodes)
      for (int d = 0; d < 3; ++d)
        if (b->rom->nodeDof[3 * n + d] >= 0) contactDofs.push_back(b->rom->nodeDof[3 * n + d]);
    contactDofs.insert(contactDofs.end(), carriedDofs[ib].begin(), carriedDofs[ib].end());
    // The stiffness the contact law adds on these DOFs (Penalty: 3 kp, see Epaphe_ContactLaw.cpp).
    const double kAdded = contact_ ? law.stableStepStiffness(copt.contact) : 0.0;
    b->stable = criticalTimeStep(*b->rom, contactDofs, kAdded, damping);
    if (b->runUp) {  // a run-up: the smallest critical step over the ramp's speeds (9 of them, even in xi)
      const RunUpModel& r = *b->runUp;
      ReducedModel at = *b->rom;
      const long long l0 = r.level(0.0), l1 = r.level(r.law.t1);
      for (int k = 0; k <= 8; ++k) {
        at.K = r.stiffnessAt(l0 + (l1 - l0) * k / 8);
        const StableStep s = criticalTimeStep(at, contactDofs, kAdded, damping);
        if (s.critical < b->stable.critical) b->stable = s;
      }
    }
    if (h > b->stable.critical) {
      std::ostringstream os;
      os << origin << ": 'Time->Time step' = " << h << " s exceeds the critical step " << b->stable.critical
         << " s of body '" << b->name << "' (highest frequency " << b->stable.omegaMax / (2 * M_PI) << " Hz"
         << (kAdded > 0 ? ", the " + law.name() + " law's springs included" : "")
         << "); the central difference would blow "
         << "up. Use 'Time step' <= " << 0.9 * b->stable.critical << " s";
      if (kAdded > 0 && !law.stiffnessKey().empty()) os << " or a smaller '" << law.stiffnessKey() << "'";
      if (!tp.get<bool>("Allow unstable time step")) throw Error(os.str() + ", or set 'Allow unstable time step'.");
      out << "warning: " << os.str() << "\n";
    }
  }
}

std::vector<std::vector<int>> Scene::setupSurfacesAndContact(const ContactOptions& copt) {
  const ParameterList& P = *deck_.params;
  const std::string& origin = deck_.origin;
  // ---- surfaces: rigid, or carried by a body and rebuilt from its moved grid nodes -------------
  const ParameterList& surfs = P.sublist("Surfaces");
  std::vector<ContactSurface> contactSurfaces;
  std::vector<std::vector<int>> carriedDofs(bodies_.size());
  for (auto it = surfs.begin(); it != surfs.end(); ++it) {
    const std::string name = surfs.name(it);
    const ParameterList& s = surfs.sublist(name);
    SurfaceOptions so;  // closed when the grid repeats its first row (an arc of 360 degrees)
    so.orientation = s.get<bool>("Flip normal") ? -1 : 1;
    so.id = static_cast<int>(surfaces_.size());
    const auto type = deck::getEnum<SurfaceType>(s, "Type");
    if (type == SurfaceType::BodyFace) {
      EPAPHE_REQUIRE(CoatingMaterial::fromParameters(s.sublist("Coating"), origin + ": " + deck::pathOf(s, "Coating"))
                             .elements[0] == 0,
                     origin << ": '" << deck::pathOf(s, "Coating")
                            << "': a coating is supported on rigid surfaces only "
                               "(a rigid casing behind it), not on a Body face; remove the Coating list");
      const std::string bodyName = s.get<std::string>("Body"), gridName = s.get<std::string>("Node grid");
      int ib = 0;  // checkScene: the body exists
      while (bodies_[static_cast<std::size_t>(ib)]->deckName != bodyName) ++ib;
      const Body& b = *bodies_[ib];  // checkScene: not an instanced body
      const auto git = b.rom->nodeGrids.find(gridName);
      if (git == b.rom->nodeGrids.end()) {
        ErrorBuilder eb;
        eb << origin << ": '" << deck::pathOf(s, "Node grid") << "' = '" << gridName << "' is not a node grid of body '"
           << bodyName << "'; ";
        if (b.rom->nodeGrids.empty())
          eb << "it has none (imported models have no node grid); carry the surface by a built-in mesh (Box: x-, x+, "
                "y-, y+, z-, z+; Ring segment and Casing: inner, outer, ...)";
        else
          eb << "it has:";
        for (const auto& [g, grid] : b.rom->nodeGrids) eb << " '" << g << "' (" << grid.nu << " x " << grid.nv << ")";
        eb.raise();
      }
      const NodeGrid& g = git->second;
      EPAPHE_REQUIRE(g.nu >= 4 && g.nv >= 4, origin << ": surface '" << name << "': node grid '" << gridName
                                                    << "' of body '" << bodyName << "' is " << g.nu << " x " << g.nv
                                                    << " nodes; a bicubic "
                                                       "surface needs at least 4 in each direction: refine the mesh");
      ContactSurface cs;
      cs.block = ib;
      const std::set<int> retained(b.rom->retainedNodes.begin(), b.rom->retainedNodes.end());
      int free = 0;
      for (int node : g.nodes) {
        const bool kept = b.rom->kind == ReductionKind::None || retained.count(node) > 0;
        EPAPHE_REQUIRE(kept, origin << ": surface '" << name << "': node " << node << " of grid '" << gridName
                                    << "' is not a retained node of body '" << bodyName
                                    << "'; add the grid's node set to "
                                       "its 'Reduction->Retained node set'");
        for (int d = 0; d < 3; ++d) {
          const int i = b.rom->nodeDof[3 * node + d];  // -1: clamped
          cs.gridDofs.push_back(i < 0 ? -1 : b.offset + i);
          cs.gridX.push_back(b.rom->coords[node][d]);
          if (i >= 0) {
            ++free;
            carriedDofs[ib].push_back(i);
          }
        }
      }
      EPAPHE_REQUIRE(free > 0, origin << ": surface '" << name << "': every node of grid '" << gridName
                                      << "' is clamped; use a rigid surface");
      surfaces_.push_back(std::make_unique<BSplineSurface>(name, g.nu, g.nv, cs.gridX, so));
      cs.surface = cs.moving = surfaces_.back().get();
      setRotation(cs, s, runUpOf(P), origin);
      surfaceCarried_.push_back(true);
      contactSurfaces.push_back(std::move(cs));
      continue;
    }
    const RigidGrid grid = rigidSurfaceGrid(s, origin);
    if (grid.towardsAxis) so.orientation = -so.orientation;
    surfaces_.push_back(std::make_unique<BSplineSurface>(name, grid.nu, grid.nv, grid.points, so));
    ContactSurface cs{surfaces_.back().get(), nullptr, -1, {}, {}};
    setRotation(cs, s, runUpOf(P), origin);
    cs.coating = CoatingMaterial::fromParameters(s.sublist("Coating"), origin + ": " + deck::pathOf(s, "Coating"));
    contactSurfaces.push_back(std::move(cs));
    surfaceCarried_.push_back(false);
  }

  for (auto& dofs : carriedDofs) {  // a closed grid repeats its first row
    std::sort(dofs.begin(), dofs.end());
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  }

  // ---- a stage: each instance sees its own copy of every surface, turned back by its pose --------
  if (std::any_of(bodies_.begin(), bodies_.end(), [](const auto& b) { return b->instance >= 0; })) {
    std::vector<ContactSurface> copies;
    for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
      const Body& b = *bodies_[ib];
      if (b.contactNodes.empty()) continue;  // checkScene: no contact nodes but the instances', no coating
      for (const ContactSurface& cs : contactSurfaces) {
        ContactSurface c = cs;
        c.phase -= b.poseAngle;  // the instance at angle theta_k sees the casing turned by -theta_k
        c.onlyBlock = static_cast<int>(ib);
        copies.push_back(std::move(c));
      }
    }
    contactSurfaces = std::move(copies);
  }

  // ---- contact: every body's contact nodes against every surface, one joint correction ----------
  ContactNodes nodes;
  std::vector<ContactBlock> blocks;
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    Body& b = *bodies_[ib];
    blocks.push_back(ContactBlock{b.offset, b.rom->size});
    b.contactBegin = static_cast<int>(nodes.labels.size());
    if (!contactSurfaces.empty())
      for (int node : b.contactNodes) {
        int dof[3];
        for (int d = 0; d < 3; ++d) {
          const int i = b.rom->nodeDof[3 * node + d];
          EPAPHE_REQUIRE(i >= 0, origin << ": body '" << b.name << "': contact node " << node << " (direction "
                                        << "xyz"[d]
                                        << ") is not a retained DOF of the reduced model; add it to the retained node "
                                           "set, and do not clamp contact nodes");
          dof[d] = b.offset + i;
        }
        nodes.add(node, static_cast<int>(ib), dof, b.rom->coords[node].data());
      }
    b.contactEnd = static_cast<int>(nodes.labels.size());
    if (b.runUp) {  // its growth and rest positions at its contact nodes only
      RunUpModel& r = *b.runUp;
      auto pick = [&](const std::vector<double>& all) {
        std::vector<double> v;
        if (!contactSurfaces.empty())
          for (int node : b.contactNodes) v.insert(v.end(), all.begin() + 3 * node, all.begin() + 3 * node + 3);
        return v;
      };
      for (auto& g : r.growth) g = pick(g);
      r.restX = pick(r.restX);
      r.contactBegin = b.contactBegin;
    }
  }
  if (nodes.labels.empty()) return carriedDofs;
  // the system flexibility: block diagonal, one block per body (dense, or diagonal for a full body)
  Flexibility flexibility;
  for (const auto& b : bodies_) flexibility.append(b->integrator->flexibility());
  contactX_ = nodes.X;
  contact_ = std::make_unique<SurfaceContact>(std::move(nodes), std::move(contactSurfaces), blocks, copt, flexibility);
  if (contact_->enforcement().frictional()) {  // the quasi-static self-locking check (Epaphe_SelfLockingMonitor.hpp)
    std::vector<double> S;
    for (const auto& b : bodies_) {
      const std::vector<double> Sb = staticContactCompliance(*b->rom, b->contactNodes);
      S.insert(S.end(), Sb.begin(), Sb.end());
    }
    contact_->setStaticCompliance(S);
  }
  return carriedDofs;
}

}  // namespace epaphe
