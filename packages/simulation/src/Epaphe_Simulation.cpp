#include "Epaphe_Simulation.hpp"

#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_BodyModel.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_ReducedModelCache.hpp"
#include "Epaphe_SceneCheck.hpp"
#include "Epaphe_Version.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

/// u = R q (eq. 2.5) at a list of nodes, 3 rows per node: dense rows of R for a reduced body; for a
/// full body (R = I), the index in q of each row's DOF (-1: clamped, u = 0).
struct NodeRecovery {
  DenseMatrix R;
  std::vector<int> index;

  NodeRecovery() = default;
  NodeRecovery(const ReducedModel& rom, const std::vector<int>& nodes, const std::string& label) {
    if (rom.sparse()) {
      index = rom.recoveryIndex(nodes);
      return;
    }
    R = DenseMatrix(label, 3 * nodes.size(), rom.size);
    auto Rh = Kokkos::create_mirror_view(R);
    for (std::size_t k = 0; k < nodes.size(); ++k)
      for (int d = 0; d < 3; ++d)
        for (int j = 0; j < rom.size; ++j) Rh(3 * k + d, j) = rom.recoveryRow(nodes[k], d)[j];
    Kokkos::deep_copy(R, Rh);
  }
  std::size_t rows() const { return R.extent(0) > 0 ? R.extent(0) : index.size(); }
  void apply(const DenseVector& q, const DenseVector& u) const {
    if (index.empty()) {  // u = R q: one BLAS dgemv on the host (no kernel launch for a few rows)
      const int m = static_cast<int>(R.extent(0)), n = static_cast<int>(R.extent(1));
      Teuchos::BLAS<int, double>().GEMV(Teuchos::NO_TRANS, m, n, 1.0, R.data(), m, q.data(), 1, 0.0, u.data(), 1);
      return;
    }
    auto uh = Kokkos::create_mirror_view(u);
    auto qh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), q);
    for (std::size_t i = 0; i < index.size(); ++i) uh(i) = index[i] >= 0 ? qh(index[i]) : 0.0;
    Kokkos::deep_copy(u, uh);
  }
  /// u = R q and w = R v in one pass over R ([u w] = R [q v], one dgemm): a record of many watched
  /// nodes reads R once, the memory traffic that bounds it.
  void apply(const DenseVector& q, const DenseVector& v, const DenseVector& u, const DenseVector& w) const {
    if (!index.empty()) {
      apply(q, u);
      apply(v, w);
      return;
    }
    const int m = static_cast<int>(R.extent(0)), n = static_cast<int>(R.extent(1));
    X.resize(2 * static_cast<std::size_t>(n));
    Y.resize(2 * static_cast<std::size_t>(m));
    std::copy(q.data(), q.data() + n, X.begin());
    std::copy(v.data(), v.data() + n, X.begin() + n);
    Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, m, 2, n, 1.0, R.data(), m, X.data(), n, 0.0,
                                      Y.data(), m);
    std::copy(Y.begin(), Y.begin() + m, u.data());
    std::copy(Y.begin() + m, Y.end(), w.data());
  }
  mutable std::vector<double> X, Y;  // [q v] and [u w], sized at the first record
};

}  // namespace

struct Simulation::Body {
  std::string name;
  ReducedModel rom;
  bool fromCache = false;
  ReductionReport report;
  std::vector<double> fullFrequencies, reducedFrequencies;
  std::vector<int> contactNodes;
  std::string contactSet;
  std::vector<double> v0;
  double speed = 0;  // |initial velocity| (m/s), for the run guards
  std::vector<double> a0;  // initial acceleration M^{-1} f of the constant force (gravity), reduced coordinates
  std::vector<std::pair<std::string, std::vector<int>>> watched;
  NodeRecovery recoveryWatched;  // the watched nodes, in order
  StableStep stable;
  std::unique_ptr<CentralDifference> integrator;
  int offset = 0;                        // its block of the system coordinates
  int contactBegin = 0, contactEnd = 0;  // its nodes in the contact order
};

namespace {

volatile std::sig_atomic_t stopSignal = 0;

extern "C" void onStopSignal(int sig) { stopSignal = sig; }

const char* signalName(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

/// |Rotation speed| of the fastest turning surface of the deck (rad/s), 0 when none turns.
double fastestRotation(const ParameterList& P) {
  double omega = 0;
  for (const auto& s : P.sublist("Surfaces"))
    omega = std::max(omega, std::abs(P.sublist("Surfaces").sublist(s.first).get<double>("Rotation speed")));
  return omega;
}

/// The rotation of a surface (thesis section 3.3), rigid or carried by a body: 'Rotation speed',
/// 'Initial angle', 'Rotation axis', 'Rotation center'.
void setRotation(ContactSurface& cs, const ParameterList& s, const std::string& origin) {
  cs.omega = s.get<double>("Rotation speed");
  cs.phase = s.get<double>("Initial angle") * M_PI / 180.0;
  cs.axis = deck::getVec3(s, "Rotation axis", origin);
  cs.center = deck::getVec3(s, "Rotation center", origin);
  EPAPHE_REQUIRE(cs.axis[0] != 0.0 || cs.axis[1] != 0.0 || cs.axis[2] != 0.0,
                 origin << ": '" << deck::pathOf(s, "Rotation axis") << "' = {0, 0, 0}; give the axis direction, e.g. "
                                                                        "{0, 0, 1}");
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

Simulation::Simulation(Deck deck, const Runtime& runtime, std::string outputOverride)
    : deck_(std::move(deck)), rt_(runtime) {
  output_ = outputOverride.empty() ? deck_.params->sublist("Output").get<std::string>("File") : outputOverride;
}

Simulation::~Simulation() = default;

void Simulation::setRestart(const std::string& file) {
  restart_ = file;
  output_ = file;
}

void Simulation::catchSignals() {
  struct sigaction sa = {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // system calls in progress (HDF5 writes) go on
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void Simulation::setup() {
  Stopwatch watch;
  const ParameterList& P = *deck_.params;
  const std::string& origin = deck_.origin;

  // ---- bodies -------------------------------------------------------------------------------
  checkScene(deck_, output_, !restart_.empty());  // everything that needs no reduced model, as --check
  const ParameterList& bl = P.sublist("Bodies");
  const ParameterList& tp = P.sublist("Time");
  const double h = tp.get<double>("Time step");
  const DampingOptions damping = dampingOptions(tp, origin);
  const ParameterList& cp = P.sublist("Contact");
  const ContactOptions copt = contactOptions(cp, h);

  for (auto it = bl.begin(); it != bl.end(); ++it) {
    auto b = std::make_unique<Body>();
    b->name = bl.name(it);
    const ParameterList& bp = bl.sublist(b->name);
    b->contactSet = bp.get<std::string>("Contact node set");
    loadOrReduce(b.get(), bp);
    setInitialState(b.get(), bp, h, damping);
    b->offset = systemSize_;
    systemSize_ += b->rom.size;
    bodies_.push_back(std::move(b));
  }

  const auto carriedDofs = setupSurfacesAndContact(copt);
  checkContactAtStart(cp, h);
  checkStableSteps(carriedDofs, copt, damping);
  summary_.timeStep = h;
  summary_.criticalStep = 1e300;
  for (const auto& b : bodies_) summary_.criticalStep = std::min(summary_.criticalStep, b->stable.critical);
  summary_.setupSeconds = watch.seconds();
}

/// The body's reduced model: from its cache when the key (model files, mesh, reduction parameters)
/// matches, else built and reduced by the factory (reduceBody), frequency-checked and cached.
void Simulation::loadOrReduce(Body* b, const ParameterList& bp) {
  const std::string& origin = deck_.origin;
  auto comm = rt_.comm();
  std::ostream& out = rt_.out();
  const ParameterList& rp = bp.sublist("Reduction");
  const std::string ctx = origin + ": body '" + b->name + "'";
  std::string retainedSet = rp.get<std::string>("Retained node set");
  if (retainedSet.empty()) retainedSet = b->contactSet;
  const auto method = deck::getEnum<ReductionMethod>(rp, "Method");
  const int checkCount = rp.get<int>("Frequency check");

    // Cache key: everything the reduced model depends on (imported files: their content hashes, on rank 0).
    bodyModelFiles(b->name, bp, origin);  // every rank checks the files exist before anything waits on rank 0
    std::string key;
    if (comm->getRank() == 0)
      key = contentKey(bodyModelKeyText(b->name, bp, origin) + "clamped=" + bp.get<std::string>("Clamped node set") +
                       "\nretained=" + retainedSet + "\nmethod=" + rp.get<std::string>("Method") +
                       "\nmodes=" + std::to_string(rp.get<int>("Fixed-interface modes")) +
                       "\ncheck=" + std::to_string(checkCount) + "\nsolver=" + rp.get<std::string>("Linear solver") +
                       "\ntolerance=" + std::to_string(rp.get<double>("Iterative tolerance")));
    const std::string cacheFile = cacheFileOf(rp, output_, b->name);
    const bool useCache = rp.get<bool>("Cache") && method != ReductionMethod::FullLumped;  // nothing to reduce

    int cached = 0;
    if (useCache && comm->getRank() == 0) cached = loadReducedModel(cacheFile, key, b->rom) ? 1 : 0;
    Teuchos::broadcast(*comm, 0, Teuchos::outArg(cached));
    if (cached) {
      broadcast(b->rom, *comm);
      b->rom.name = b->name;
      b->fromCache = true;
    } else {
      Stopwatch built;
      FullModel full = buildBodyModel(b->name, bp, origin, comm);
      out << "[" << b->name << "] full model: " << full.numNodes() << " nodes, " << full.numFree << " free DOFs, "
          << full.mesh.hexes.size() << " hexahedra, " << (hasBuiltInMesh(bp) ? "built" : "imported") << " in "
          << formatDuration(built.seconds()) << "\n";
      const CraigBamptonOptions cbo = reductionOptions(rp);
      const bool retains = method != ReductionMethod::None && method != ReductionMethod::FullLumped;
      EPAPHE_REQUIRE(!retains || !retainedSet.empty(), ctx << ": reduction " << rp.get<std::string>("Method")
                                                          << " needs a 'Retained node set' (or a 'Contact node set')");
      const auto retainedNodes = retains ? full.mesh.nodeSet(retainedSet, ctx + ", 'Reduction->Retained node set'")
                                         : std::vector<int>{};
      try {  // the reduction's errors name the body; add the deck
        b->rom = reduceBody(full, retainedNodes, rp, cbo, &b->report);
      } catch (const Error& e) {
        throw Error(origin + ": " + e.what());
      }
      if (b->rom.sparse())
        out << "[" << b->name << "] full model kept: K sparse (" << b->rom.sparseK.values.size()
            << " entries), mass lumped to its diagonal (HRZ)\n";
      else if (retains)
        out << "[" << b->name << "] " << b->rom.method() << ": " << b->report.retainedDofs << " retained DOFs + "
            << cbo.modes << " modes = " << b->rom.size << " reduced DOFs in " << formatDuration(b->report.seconds)
            << " on " << comm->getSize() << " rank(s) (factor " << formatDuration(b->report.factorSeconds)
            << ", constraint modes " << formatDuration(b->report.constraintSeconds) << ", eigenmodes "
            << formatDuration(b->report.eigenSeconds) << ")\n";
      if (checkCount > 0) {
        const FrequencyCheck fc = frequencyCheck(full, b->rom, cbo, checkCount);
        b->rom.fullFrequencies = fc.full;
        if (b->rom.sparse()) b->reducedFrequencies = fc.lumped;
        out << "[" << b->name << "] frequency check: the full model's lowest " << fc.full.size() << " frequencies "
            << (fc.reused ? std::string("are the reduction's own modes") : "in " + formatDuration(fc.seconds)) << "\n";
      }
      if (useCache && comm->getRank() == 0) saveReducedModel(b->rom, cacheFile, key);
    }
    if (b->fromCache) out << "[" << b->name << "] reduced model (" << b->rom.method() << ", " << b->rom.size
                          << " DOFs) reused from " << cacheFile << "\n";
    b->fullFrequencies = b->rom.fullFrequencies;
    if (!b->rom.sparse()) b->reducedFrequencies = reducedFrequencies(b->rom);
}

/// Initial velocity, watched and contact node sets, the integrator and gravity of a reduced body.
void Simulation::setInitialState(Body* b, const ParameterList& bp, double h, const DampingOptions& damping) {
  const std::string& origin = deck_.origin;
  const std::string ctx = origin + ": body '" + b->name + "'";
    // Initial velocity: uniform translation, exact in reduced coordinates (retained DOFs).
    const auto v0 = deck::getVec3(bp, "Initial velocity", origin);
    b->v0.assign(static_cast<std::size_t>(b->rom.size), 0.0);
    b->speed = std::sqrt(v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2]);
    for (int d = 0; d < 3; ++d) {
      const auto t = b->rom.rigidTranslation(d);
      for (int i = 0; i < b->rom.size; ++i) b->v0[i] += v0[d] * t[i];
    }
    for (const std::string& ws : deck::getStrings(bp, "Watched node sets"))
      b->watched.emplace_back(ws, b->rom.nodeSet(ws, ctx + ", 'Watched node sets'"));

    if (!b->contactSet.empty()) b->contactNodes = b->rom.nodeSet(b->contactSet, ctx + ", 'Contact node set'");
    b->integrator = std::make_unique<CentralDifference>(b->rom, h, damping);

    // Gravity g: the consistent weight f = sum_d g_d T^T M e_d (e_d: every node translated by 1
    // along d), a constant force. When a rigid translation is a motion of the model, T t_d = e_d
    // (t_d = rigidTranslation(d)), so T^T M e_d = (T^T M T) t_d = M t_d, the vector of the momentum
    // p = (M t_d) . v below: exact for every reduction. With lumped mass M t_d is the free DOFs' nodal
    // masses, exact for a clamped body too. The initial acceleration is M^{-1} f = sum_d g_d t_d.
    const auto grav = deck::getVec3(bp, "Gravity", origin);
    b->a0.assign(static_cast<std::size_t>(b->rom.size), 0.0);
    if (grav[0] != 0 || grav[1] != 0 || grav[2] != 0) {
      const int n = b->rom.size;
      std::vector<double> f(static_cast<std::size_t>(n), 0.0);
      for (int d = 0; d < 3; ++d) {
        if (grav[d] == 0) continue;
        const auto t = b->rom.rigidTranslation(d);
        const auto Mt = b->rom.massTimes(t);
        if (!b->rom.sparse()) {
          // t_d is a rigid motion when its Rayleigh quotient t^T K t / t^T M t is round-off against the
          // largest eigenvalue (bounded below by max_i K_ii / M_ii); a clamped body's is at least its
          // lowest eigenvalue.
          double tKt = 0, tMt = 0, scale = 0;
          for (int j = 0; j < n; ++j) {
            tMt += t[j] * Mt[j];
            if (b->rom.m(j, j) > 0) scale = std::max(scale, b->rom.k(j, j) / b->rom.m(j, j));
            if (t[j] != 0)
              for (int i = 0; i < n; ++i) tKt += t[i] * b->rom.k(i, j) * t[j];
          }
          const double rayleigh = tMt > 0 ? tKt / tMt : 1e300;
          const std::string clamped = bp.get<std::string>("Clamped node set");
          EPAPHE_REQUIRE(rayleigh <= 1e-10 * scale,
                         ctx << ", 'Gravity' = {" << grav[0] << ", " << grav[1] << ", " << grav[2]
                             << "}: a rigid translation along " << "xyz"[d] << " is not a motion of its "
                             << b->rom.method() << " model (t^T K t / t^T M t = " << rayleigh
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
    std::vector<int> watchedNodes;
    for (const auto& w : b->watched) watchedNodes.insert(watchedNodes.end(), w.second.begin(), w.second.end());
    b->recoveryWatched = NodeRecovery(b->rom, watchedNodes, "epaphe::watched::R");
}

/// Refuses what would run to nonsense at t = 0 (ContactGuards): a step longer than a surface patch,
/// bodies that start inside a surface (or resolves them gently, as the deck says).
void Simulation::checkContactAtStart(const ParameterList& cp, double h) {
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
    guards_->checkInitialVelocities(*contact_, speeds, h, summary_.warnings);
    const DenseVector q0("epaphe::q0", static_cast<std::size_t>(systemSize_));
    CostSplit setupCost;
    const PenetrationReport pr = guards_->checkInitialPenetration(*contact_, q0, h, setupCost);
    if (pr.facing == 0)  // e.g. a surface placed in mm in a deck in m
      summary_.warnings.push_back("no contact node lies over any surface at t = 0 (every projection falls beyond an "
                                  "open edge): check the surfaces' positions, extents and units");
    summary_.initialPenetrations = pr.count;
    summary_.initialPenetrationDepth = pr.deepest;
    for (const auto& w : summary_.warnings) out << "warning: " << w << "\n";
    if (pr.count > 0)
      out << "initial penetration: " << pr.count << " contact node(s), deepest " << pr.deepest
          << " m, resolved gently (Contact->Initial penetration)\n";
  }
}

/// The stable step of each body (with the penalty springs on its contact and carried surface DOFs)
/// against the deck's time step: an Error, or a warning with 'Allow unstable time step'.
void Simulation::checkStableSteps(const std::vector<std::vector<int>>& carriedDofs, const ContactOptions& copt,
                                  const DampingOptions& damping) {
  const std::string& origin = deck_.origin;
  std::ostream& out = rt_.out();
  const ParameterList& tp = deck_.params->sublist("Time");
  const double h = tp.get<double>("Time step");
  // Stable step of each body, with the penalty springs on its contact and surface DOFs.
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    Body* b = bodies_[ib].get();
    std::vector<int> contactDofs;
    for (int n : b->contactNodes)
      for (int d = 0; d < 3; ++d)
        if (b->rom.nodeDof[3 * n + d] >= 0) contactDofs.push_back(b->rom.nodeDof[3 * n + d]);
    contactDofs.insert(contactDofs.end(), carriedDofs[ib].begin(), carriedDofs[ib].end());
    // The penalty acts on the predicted gap (forward increment, eq. 2.28 with lambda = kp (-g*)):
    // for a mass m on a spring kp alone, u_{n+1} = (1 - a)(2 u_n - u_{n-1}), a = h^2 kp / m, whose
    // roots stay in the unit circle for a <= 4/3, a third of the 4 of an ordinary spring
    // (h omega <= 2). So each penalty spring counts three times in the estimate.
    const double kAdded = (contact_ && copt.method == ContactMethod::Penalty) ? 3.0 * copt.penaltyStiffness : 0.0;
    b->stable = criticalTimeStep(b->rom, contactDofs, kAdded, damping);
    if (h > b->stable.critical) {
      std::ostringstream os;
      os << origin << ": 'Time->Time step' = " << h << " s exceeds the critical step " << b->stable.critical
         << " s of body '" << b->name << "' (highest frequency " << b->stable.omegaMax / (2 * M_PI) << " Hz"
         << (kAdded > 0 ? ", penalty springs included" : "") << "); the central difference would blow up. Use "
         << "'Time step' <= " << 0.9 * b->stable.critical << " s";
      if (kAdded > 0) os << " or a smaller 'Penalty stiffness'";
      if (!tp.get<bool>("Allow unstable time step")) throw Error(os.str() + ", or set 'Allow unstable time step'.");
      out << "warning: " << os.str() << "\n";
    }
  }
}

std::vector<std::vector<int>> Simulation::setupSurfacesAndContact(const ContactOptions& copt) {
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
      const std::string bodyName = s.get<std::string>("Body"), gridName = s.get<std::string>("Node grid");
      int ib = 0;  // checkScene: the body exists
      while (bodies_[static_cast<std::size_t>(ib)]->name != bodyName) ++ib;
      const Body& b = *bodies_[ib];
      const auto git = b.rom.nodeGrids.find(gridName);
      if (git == b.rom.nodeGrids.end()) {
        ErrorBuilder eb;
        eb << origin << ": '" << deck::pathOf(s, "Node grid") << "' = '" << gridName << "' is not a node grid of body '"
           << bodyName << "'; ";
        if (b.rom.nodeGrids.empty())
          eb << "it has none (imported models have no node grid); carry the surface by a built-in mesh (Box: x-, x+, "
                "y-, y+, z-, z+; Ring segment and Casing: inner, outer, ...)";
        else
          eb << "it has:";
        for (const auto& [g, grid] : b.rom.nodeGrids) eb << " '" << g << "' (" << grid.nu << " x " << grid.nv << ")";
        eb.raise();
      }
      const NodeGrid& g = git->second;
      EPAPHE_REQUIRE(g.nu >= 4 && g.nv >= 4, origin << ": surface '" << name << "': node grid '" << gridName << "' of body '"
                                                    << bodyName << "' is " << g.nu << " x " << g.nv << " nodes; a bicubic "
                                                    "surface needs at least 4 in each direction: refine the mesh");
      ContactSurface cs;
      cs.block = ib;
      const std::set<int> retained(b.rom.retainedNodes.begin(), b.rom.retainedNodes.end());
      int free = 0;
      for (int node : g.nodes) {
        const bool kept = b.rom.kind == ReductionKind::None || retained.count(node) > 0;
        EPAPHE_REQUIRE(kept, origin << ": surface '" << name << "': node " << node << " of grid '" << gridName
                                    << "' is not a retained node of body '" << bodyName << "'; add the grid's node set to "
                                    "its 'Reduction->Retained node set'");
        for (int d = 0; d < 3; ++d) {
          const int i = b.rom.nodeDof[3 * node + d];  // -1: clamped
          cs.gridDofs.push_back(i < 0 ? -1 : b.offset + i);
          cs.gridX.push_back(b.rom.coords[node][d]);
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
      setRotation(cs, s, origin);
      surfaceCarried_.push_back(true);
      contactSurfaces.push_back(std::move(cs));
      continue;
    }
    const RigidGrid grid = rigidSurfaceGrid(s, origin);
    if (grid.towardsAxis) so.orientation = -so.orientation;
    surfaces_.push_back(std::make_unique<BSplineSurface>(name, grid.nu, grid.nv, grid.points, so));
    ContactSurface cs{surfaces_.back().get(), nullptr, -1, {}, {}};
    setRotation(cs, s, origin);
    contactSurfaces.push_back(std::move(cs));
    surfaceCarried_.push_back(false);
  }

  for (auto& dofs : carriedDofs) {  // a closed grid repeats its first row
    std::sort(dofs.begin(), dofs.end());
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  }

  // ---- contact: every body's contact nodes against every surface, one joint correction ----------
  ContactNodes nodes;
  std::vector<ContactBlock> blocks;
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    Body& b = *bodies_[ib];
    blocks.push_back(ContactBlock{b.offset, b.rom.size});
    b.contactBegin = static_cast<int>(nodes.labels.size());
    if (!contactSurfaces.empty())
      for (int node : b.contactNodes) {
        int dof[3];
        for (int d = 0; d < 3; ++d) {
          const int i = b.rom.nodeDof[3 * node + d];
          EPAPHE_REQUIRE(i >= 0, origin << ": body '" << b.name << "': contact node " << node << " (direction " << "xyz"[d]
                                        << ") is not a retained DOF of the reduced model; add it to the retained node "
                                           "set, and do not clamp contact nodes");
          dof[d] = b.offset + i;
        }
        nodes.add(node, static_cast<int>(ib), dof, b.rom.coords[node].data());
      }
    b.contactEnd = static_cast<int>(nodes.labels.size());
  }
  if (nodes.labels.empty()) return carriedDofs;
  // the system flexibility: block diagonal, one block per body (dense, or diagonal for a full body)
  Flexibility flexibility;
  for (const auto& b : bodies_) flexibility.append(b->integrator->flexibility());
  contact_ = std::make_unique<SurfaceContact>(std::move(nodes), std::move(contactSurfaces), blocks, copt, flexibility);
  return carriedDofs;
}

const RunSummary& Simulation::run() {
  auto comm = rt_.comm();
  if (comm->getRank() != 0) {
    summary_.status = "idle";
    return summary_;
  }
  const ParameterList& P = *deck_.params;
  const double h = P.sublist("Time").get<double>("Time step");
  double endTime = P.sublist("Time").get<double>("End time");
  if (const double revs = P.sublist("Time").get<double>("End revolutions"); revs > 0) {
    const double omega = fastestRotation(P);
    EPAPHE_REQUIRE(omega > 0, deck_.origin << ": 'Time->End revolutions' = " << revs
                                           << " but no surface turns; give a 'Rotation speed' or use 'End time'");
    endTime = revs * 2 * M_PI / omega;
  }
  const int every = P.sublist("Output").get<int>("Every");
  const double tolBalance = P.sublist("Output").get<double>("Energy balance tolerance");
  const double progressInterval = P.sublist("Run").get<double>("Progress interval");
  const int fieldsEvery = P.sublist("Output").get<int>("Fields every");
  const long long nSteps = std::max(1LL, static_cast<long long>(std::ceil(endTime / h - 1e-9)));
  std::ostream& out = rt_.out();

  const int checkpointEvery = P.sublist("Output").get<int>("Checkpoint every");
  const double checkpointInterval = P.sublist("Output").get<double>("Checkpoint interval");

  // ---- output ---------------------------------------------------------------------------------
  // A fresh run creates the file; a restart opens it, checks that it holds this deck and a
  // checkpoint, and reads the checkpoint after the series are set up (below).
  const bool fresh = restart_.empty();
  io::Hdf5File file(output_, fresh ? io::Hdf5File::Mode::Create : io::Hdf5File::Mode::ReadWrite);
  file.setSeriesCompression(P.sublist("Output").get<bool>("Compression"));
  if (!fresh) {
    EPAPHE_REQUIRE(file.exists("/run/deck") && file.exists("/checkpoint/current"),
                   restart_ << ": no checkpoint to restart from (not an Epaphe output, or written before the "
                               "first checkpoint); run the deck anew");
    const std::string status = file.stringAttribute("/", "status");
    EPAPHE_REQUIRE(status != "complete", restart_ << ": the run is complete (status 'complete'); nothing to restart");
    const std::string stored = file.readString("/run/deck");
    if (stored != deck_.text) {
      std::size_t line = 1, i = 0;
      for (; i < std::min(stored.size(), deck_.text.size()) && stored[i] == deck_.text[i]; ++i)
        if (stored[i] == '\n') ++line;
      throw Error(restart_ + ": it was written by another deck (its /run/deck differs from " + deck_.origin +
                  " from line " + std::to_string(line) + "); restart with the deck that started the run");
    }
    const long long threads = file.intAttribute("/run", "threads");
    if (threads != rt_.threads())
      out << "warning: " << restart_ << " was run on " << threads << " thread(s), this restart on " << rt_.threads()
          << ": the results may differ in the last bits from an uninterrupted run\n";
  }
  file.setAttribute("/", "epaphe_version", version);
  file.setAttribute("/", "name", P.sublist("Run").get<std::string>("Name"));
  file.setAttribute("/", "status", "running");
  if (fresh) file.writeString("/run/deck", deck_.text);
  file.setAttribute("/run", "time_step", h);
  file.setAttribute("/run", "critical_time_step", summary_.criticalStep);
  file.setAttribute("/run", "threads", static_cast<long long>(rt_.threads()));
  file.setAttribute("/run", "mpi_ranks", static_cast<long long>(comm->getSize()));
  io::Series sTime(file, "/time", {});
  io::Series sKin(file, "/energy/kinetic", {}), sStrain(file, "/energy/strain", {}),
      sTotal(file, "/energy/total", {}), sWork(file, "/energy/contact_work", {}),
      sExt(file, "/energy/external_work", {}), sDamp(file, "/energy/damping", {}),
      sBal(file, "/energy/balance_error", {});

  struct BodyRun {
    DenseVector qPrev, q, qNext, v, uw, vw;
    std::vector<std::unique_ptr<io::Series>> disp, vel;
    std::unique_ptr<io::Series> gap, force, totalForce, momentum;
    std::vector<DenseVector> Mt;  // M t_d: rigid translations through the mass matrix
    NodeRecovery R;               // u = R q of every node, only when fields are written
    DenseVector uAll;
    std::vector<double> frame;
    std::unique_ptr<io::Series> position, displacement;
    std::vector<double> gapRec, forceRec;
    double ext = 0, diss = 0, e0 = 0;
  };
  std::vector<BodyRun> runs(bodies_.size());
  // The system coordinates q_{n-1}, q_n, q_{n+1} of all bodies, stacked (body b at b.offset), in
  // three buffers that rotate each step; each body works on its part of them.
  DenseVector Q[3] = {DenseVector("epaphe::system::q0", systemSize_), DenseVector("epaphe::system::q1", systemSize_),
                      DenseVector("epaphe::system::q2", systemSize_)};
  int iPrev = 0, iCur = 1, iNext = 2;
  auto part = [&](int buffer, const Body& b) { return DenseVector(Q[buffer].data() + b.offset, b.rom.size); };
  auto selectParts = [&]() {
    for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
      runs[ib].qPrev = part(iPrev, *bodies_[ib]);
      runs[ib].q = part(iCur, *bodies_[ib]);
      runs[ib].qNext = part(iNext, *bodies_[ib]);
    }
  };
  selectParts();
  double contactWork = 0;
  // Penalty: stable springs only give back what they hold, so the bodies' energy can never exceed
  // what they were given (initial, external work, the springs compressed by initial penetrations).
  // (Not with a turning surface: a moving casing does work on the bodies.)
  const bool penalty = contact_ && fastestRotation(P) == 0.0 &&
                       deck::getEnum<ContactMethod>(P.sublist("Contact"), "Method") == ContactMethod::Penalty;
  const double kp = P.sublist("Contact").get<double>("Penalty stiffness");
  double springEnergy0 = 0;
  std::vector<double> gapAll, forceAll;
  double energyRef = 0;
  for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
    Body& b = *bodies_[ib];
    BodyRun& r = runs[ib];
    const int n = b.rom.size;
    const std::string g = "/bodies/" + b.name;
    if (fresh) {
      file.writeDoubles(g + "/frequencies/reduced", b.reducedFrequencies);
      file.writeDoubles(g + "/frequencies/full", b.fullFrequencies);
      file.writeDoubles(g + "/frequencies/fixed_interface", b.rom.modeFrequencies);
      file.setAttribute(g, "reduction", b.rom.method());
      file.setAttribute(g, "reduced_dofs", static_cast<long long>(n));
    }
    r.v = DenseVector("v", n);
    r.uw = DenseVector("uw", b.recoveryWatched.rows());
    r.vw = DenseVector("vw", b.recoveryWatched.rows());
    // q_0 = 0, q_{-1} = q_0 - h v_0 + h^2/2 a_0, a_0 = M^{-1} f (gravity; K q_0 = 0, no contact
    // force yet): a uniform acceleration is then integrated exactly, q_n = h n v_0 + (h n)^2/2 a_0
    auto qp = Kokkos::create_mirror_view(r.qPrev);
    for (int i = 0; i < n; ++i) qp(i) = -h * b.v0[i] + 0.5 * h * h * b.a0[i];
    Kokkos::deep_copy(r.qPrev, qp);
    r.e0 = b.integrator->halfStepEnergy(r.qPrev, r.q);
    // Linear momentum p_d = t_d^T M v and rigid mass m = t_x^T M t_x (rebound velocity = p / m).
    for (int d = 0; d < 3; ++d) {
      const auto t = b.rom.rigidTranslation(d);
      const auto Mtd = b.rom.massTimes(t);
      DenseVector Mt("Mt", n);
      auto h2 = Kokkos::create_mirror_view(Mt);
      for (int i = 0; i < n; ++i) h2(i) = Mtd[i];
      Kokkos::deep_copy(Mt, h2);
      r.Mt.push_back(Mt);
      if (d == 0 && fresh) {
        double m = 0;
        for (int i = 0; i < n; ++i) m += t[i] * h2(i);
        file.setAttribute(g, "rigid_mass", m);
      }
    }
    r.momentum = std::make_unique<io::Series>(file, g + "/momentum", std::vector<std::uint64_t>{3});
    if (fieldsEvery > 0) {
      const std::uint64_t nn = static_cast<std::uint64_t>(b.rom.numNodes());
      std::vector<long long> hex;
      for (const auto& e : b.rom.hexes) hex.insert(hex.end(), e.begin(), e.end());
      if (fresh) {
        file.writeInts(g + "/mesh/hexahedra", {static_cast<std::uint64_t>(b.rom.hexes.size()), 8}, hex.data());
        file.writeDoubles(g + "/mesh/coordinates", {nn, 3}, b.rom.coords.empty() ? nullptr : b.rom.coords[0].data());
      }
      std::vector<int> every(nn);
      for (std::uint64_t k = 0; k < nn; ++k) every[k] = static_cast<int>(k);
      r.R = NodeRecovery(b.rom, every, "epaphe::fields::R");
      r.uAll = DenseVector("epaphe::fields::u", 3 * nn);
      r.frame.resize(3 * nn);
      r.position = std::make_unique<io::Series>(file, g + "/fields/position", std::vector<std::uint64_t>{nn, 3}, 16);
      r.displacement = std::make_unique<io::Series>(file, g + "/fields/displacement", std::vector<std::uint64_t>{nn, 3}, 16);
    }
    energyRef += std::abs(r.e0);
    for (const auto& [setName, nodes] : b.watched) {
      if (fresh)
        file.writeInts(g + "/nodesets/" + setName + "/nodes", std::vector<long long>(nodes.begin(), nodes.end()));
      const std::uint64_t nn = nodes.size();
      r.disp.push_back(std::make_unique<io::Series>(file, g + "/nodesets/" + setName + "/displacement",
                                                    std::vector<std::uint64_t>{nn, 3}));
      r.vel.push_back(std::make_unique<io::Series>(file, g + "/nodesets/" + setName + "/velocity",
                                                   std::vector<std::uint64_t>{nn, 3}));
    }
    if (b.contactEnd > b.contactBegin) {
      const auto& cn = contact_->nodes();
      if (fresh)
        file.writeInts(g + "/contact/nodes",
                       std::vector<long long>(cn.begin() + b.contactBegin, cn.begin() + b.contactEnd));
      const std::uint64_t nc = static_cast<std::uint64_t>(b.contactEnd - b.contactBegin);
      r.gap = std::make_unique<io::Series>(file, g + "/contact/gap", std::vector<std::uint64_t>{nc});
      r.force = std::make_unique<io::Series>(file, g + "/contact/force", std::vector<std::uint64_t>{nc});
      r.totalForce = std::make_unique<io::Series>(file, g + "/contact/total_force", std::vector<std::uint64_t>{});
      r.gapRec.resize(nc);
      r.forceRec.resize(nc);
    }
  }
  energyRef = std::max(energyRef, 1e-300);
  std::unique_ptr<io::Series> sFieldTime;
  if (fieldsEvery > 0) {
    sFieldTime = std::make_unique<io::Series>(file, "/fields/time", std::vector<std::uint64_t>{});
    for (std::size_t is = 0; is < surfaces_.size() && fresh; ++is) {
      if (surfaceCarried_[is]) continue;  // drawn with the body that carries it
      const auto& surf = surfaces_[is];
      std::vector<double> pts;
      for (int i = 0; i < surf->nu(); ++i)
        for (int j = 0; j < surf->nv(); ++j) {
          const auto p = surf->gridPoint(i, j);
          pts.insert(pts.end(), p.begin(), p.end());
        }
      file.writeDoubles("/surfaces/" + surf->name() + "/points",
                        {static_cast<std::uint64_t>(surf->nu()) * static_cast<std::uint64_t>(surf->nv()), 3}, pts.data());
    }
  }
  long long frames = 0, records = 0;

  // ---- checkpoints -------------------------------------------------------------------------------
  // Everything the next steps depend on (fixed shapes): the step to run next, q_{n-1} and q_n of
  // the system, the accumulators (contact work, per body damping and external work; the summary's
  // contact times, impulse, peak force, worst balance error), the contact's warm starts, and the
  // records of every series. Between checkpoints nothing is written to the file: the series
  // buffers (1024 records, 16 field frames) never fill, a checkpoint being taken when they are one
  // record short. A checkpoint first writes and flushes (H5Fflush) the buffered records, then
  // overwrites the older of two slots, /checkpoint/0 and /checkpoint/1, flushes, and only then
  // points /checkpoint/current at it and flushes again. A process killed at any moment thus leaves
  // a complete checkpoint in the slot /checkpoint/current names; with uncompressed series
  // (Output->Compression false, the default) the records it counts are intact too, since an
  // uncompressed chunk is rewritten in place with the same bytes for the records it already held.
  std::vector<io::Series*> series = {&sTime, &sKin, &sStrain, &sTotal, &sWork, &sExt, &sDamp, &sBal};
  for (BodyRun& r : runs) {
    series.push_back(r.momentum.get());
    for (std::size_t w = 0; w < r.disp.size(); ++w) {
      series.push_back(r.disp[w].get());
      series.push_back(r.vel[w].get());
    }
    for (io::Series* s : {r.gap.get(), r.force.get(), r.totalForce.get(), r.position.get(), r.displacement.get()})
      if (s != nullptr) series.push_back(s);
  }
  if (sFieldTime) series.push_back(sFieldTime.get());
  std::string seriesPaths;
  for (const io::Series* s : series) seriesPaths += s->path() + "\n";
  const std::vector<std::string> accumulatorNames = [&] {
    std::vector<std::string> v = {"time", "contact_work", "first_contact", "last_contact", "impulse", "max_force",
                                  "max_balance_error"};
    for (const auto& b : bodies_) {
      v.push_back(b->name + "/damping");
      v.push_back(b->name + "/external_work");
    }
    return v;
  }();
  constexpr long long kRecordBuffer = 1024, kFrameBuffer = 16;  // the series' buffers (records)
  long long recordsAtCheckpoint = 0, framesAtCheckpoint = 0;
  auto hostCopy = [](const DenseVector& v) {
    auto hv = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
    return std::vector<double>(hv.data(), hv.data() + hv.extent(0));
  };
  int slot = 0;  // the slot the next checkpoint overwrites
  auto checkpoint = [&](long long nextStep) {
    Stopwatch w;
    // First the buffered records, flushed: a kill before the checkpoint's own data is flushed then
    // leaves series at least as long as the previous checkpoint's lengths (a restart cuts them).
    file.flush();
    const std::string c = "/checkpoint/" + std::to_string(slot);
    if (!file.exists(c + "/series_paths")) {
      file.writeString(c + "/series_paths", seriesPaths);
      std::string names;
      for (const auto& a : accumulatorNames) names += (names.empty() ? "" : ",") + a;
      file.writeDoubles(c + "/accumulators", std::vector<double>(accumulatorNames.size(), 0.0));
      file.setAttribute(c + "/accumulators", "names", names);
      file.setAttribute(c, "counters", "step (the next to run), records, frames");
    }
    file.writeInts(c + "/counters", std::vector<long long>{nextStep, records, frames});
    file.writeDoubles(c + "/q_prev", hostCopy(Q[iPrev]));
    file.writeDoubles(c + "/q", hostCopy(Q[iCur]));
    std::vector<double> acc = {nextStep * h, contactWork, summary_.firstContact, summary_.lastContact,
                               summary_.impulse, summary_.maxForce, summary_.maxBalanceError};
    for (const BodyRun& r : runs) {
      acc.push_back(r.diss);
      acc.push_back(r.ext);
    }
    file.writeDoubles(c + "/accumulators", acc);
    if (contact_) {
      const auto uv = contact_->warmStarts();
      file.writeDoubles(c + "/warm_start", {uv.size() / (2 * contact_->numNodes()),
                                             static_cast<std::uint64_t>(contact_->numNodes()), 2}, uv.data());
      contact_->resetWarmStarts();  // as a restart from here will: projections and friction start anew
    }
    std::vector<long long> lengths;
    for (const io::Series* s : series) lengths.push_back(static_cast<long long>(s->size()));
    file.writeInts(c + "/series_lengths", lengths);
    file.flush();  // H5Fflush
    file.writeInts("/checkpoint/current", std::vector<long long>{slot, nextStep});
    file.flush();
    slot = 1 - slot;
    recordsAtCheckpoint = records;
    framesAtCheckpoint = frames;
    ++summary_.checkpoints;
    summary_.checkpointSeconds += w.seconds();
  };

  long long firstStep = 0;
  if (fresh) {
    checkpoint(0);
  } else {
    // Restore the last complete checkpoint; cut the series to its records; the next checkpoint
    // goes to the other slot.
    const auto current = file.readInts("/checkpoint/current");
    EPAPHE_REQUIRE(current.size() == 2 && (current[0] == 0 || current[0] == 1),
                   restart_ << ": /checkpoint/current is damaged or from another run");
    const std::string c = "/checkpoint/" + std::to_string(current[0]);
    slot = 1 - static_cast<int>(current[0]);
    const auto counters = file.readInts(c + "/counters");
    EPAPHE_REQUIRE(counters.size() == 3 && counters[0] == current[1] && counters[0] <= nSteps,
                   restart_ << ": " << c << "/counters is damaged or from another run");
    EPAPHE_REQUIRE(file.readString(c + "/series_paths") == seriesPaths,
                   restart_ << ": its series are not those of this deck's run; run the deck anew");
    const auto lengths = file.readInts(c + "/series_lengths");
    EPAPHE_REQUIRE(lengths.size() == series.size(), restart_ << ": " << c << "/series_lengths has " << lengths.size()
                                                             << " entries, " << series.size() << " expected");
    for (std::size_t i = 0; i < series.size(); ++i) series[i]->truncate(static_cast<std::size_t>(lengths[i]));
    firstStep = counters[0];
    records = recordsAtCheckpoint = counters[1];
    frames = framesAtCheckpoint = counters[2];
    auto load = [&](const DenseVector& v, const std::string& path) {
      const auto values = file.readDoubles(path);
      EPAPHE_REQUIRE(values.size() == v.extent(0), restart_ << ": " << path << " has " << values.size()
                                                            << " values, the system " << v.extent(0));
      auto hv = Kokkos::create_mirror_view(v);
      std::copy(values.begin(), values.end(), hv.data());
      Kokkos::deep_copy(v, hv);
    };
    load(Q[iPrev], c + "/q_prev");
    load(Q[iCur], c + "/q");
    const auto acc = file.readDoubles(c + "/accumulators");
    EPAPHE_REQUIRE(acc.size() == accumulatorNames.size(), restart_ << ": " << c << "/accumulators has " << acc.size()
                                                                   << " values, " << accumulatorNames.size()
                                                                   << " expected");
    contactWork = acc[1];
    summary_.firstContact = acc[2];
    summary_.lastContact = acc[3];
    summary_.impulse = acc[4];
    summary_.maxForce = acc[5];
    summary_.maxBalanceError = acc[6];
    for (std::size_t ib = 0; ib < runs.size(); ++ib) {
      runs[ib].diss = acc[7 + 2 * ib];
      runs[ib].ext = acc[8 + 2 * ib];
    }
    if (contact_) contact_->setWarmStarts(file.readDoubles(c + "/warm_start"));
    file.flush();
    out << "restarting " << restart_ << " at step " << firstStep << " of " << nSteps << " (t = " << firstStep * h
        << " s)\n";
  }
  summary_.firstStep = firstStep;

  // ---- the explicit loop -------------------------------------------------------------------------
  Stopwatch loop, sinceProgress, sinceCheckpoint;
  // EPAPHE_COUNT_KERNELS=1 (benchmarks): count the loop's Kokkos parallel regions and allocations
  std::unique_ptr<KernelCounter> kernels;
  if (const char* e = std::getenv("EPAPHE_COUNT_KERNELS"); e && std::string(e) == "1") kernels = std::make_unique<KernelCounter>();
  CostSplit& cost = summary_.cost;
  summary_.status = "complete";
  long long n = 0;
  auto fail = [&](const std::string& why) {
    summary_.status = "stopped: " + why;
    file.setAttribute("/", "status", summary_.status);
    file.flush();
    throw Error(why);
  };
  for (n = firstStep; n < nSteps; ++n) {
    const double t = n * h;
    double totalForce = 0;
    int active = 0;
    {
      ScopedPhase phase(cost, "integration");
      for (std::size_t ib = 0; ib < bodies_.size(); ++ib)
        bodies_[ib]->integrator->predict(runs[ib].q, runs[ib].qPrev, runs[ib].qNext);  // eq. 2.2
    }
    if (contact_) {
      // eqs. 2.28-2.36 on all bodies at once (eq. 2.33), friction from the motion q_n -> q*
      contact_->setTime(t + h);
      contact_->correct(Q[iNext], Q[iCur], cost);
      if (const std::string large = guards_->checkStep(*contact_, Q[iNext], Q[iCur], t, h); !large.empty()) {
        if (!guards_->options().allowLargeMotion) fail(large);
        if (summary_.largeMotionSteps++ == 0) out << "warning: " << large << " (further such steps are counted)\n";
      }
      ScopedPhase phase(cost, "energy");
      contactWork += contact_->workIncrement(Q[iNext], Q[iPrev]);
      if (penalty && n == 0) {
        const auto f0 = contact_->force();
        for (std::size_t k = 0; k < f0.extent(0); ++k) springEnergy0 += f0(k) * f0(k) / (2 * kp);
      }
      totalForce = contact_->totalForce();
      active = contact_->numActive();
    }
    {
      ScopedPhase phase(cost, "energy");
      for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
        BodyRun& r = runs[ib];
        r.diss += bodies_[ib]->integrator->dampingIncrement(r.qNext, r.qPrev);
        r.ext += bodies_[ib]->integrator->externalWorkIncrement(r.qNext, r.qPrev);
      }
    }
    if (totalForce > 0) {
      if (summary_.firstContact < 0) summary_.firstContact = t;
      summary_.lastContact = t;
      summary_.impulse += totalForce * h;
      summary_.maxForce = std::max(summary_.maxForce, totalForce);
    }

    if (n % every == 0 || n == nSteps - 1) {
      ScopedPhase phase(cost, "output");
      double kin = 0, strain = 0, total = 0, work = contactWork, ext = 0, diss = 0, e0 = 0;
      if (contact_) {
        const auto f = contact_->force();
        forceAll.assign(f.data(), f.data() + f.extent(0));
        contact_->setTime(t);
        contact_->measureGaps(Q[iCur], cost);
        const auto gp = contact_->gap();
        gapAll.assign(gp.data(), gp.data() + gp.extent(0));
      }
      for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
        Body& b = *bodies_[ib];
        BodyRun& r = runs[ib];
        // v_n = (q_{n+1} - q_{n-1}) / 2h
        Kokkos::deep_copy(r.v, r.qNext);
        epaphe::axpby(-0.5 / h, r.qPrev, 0.5 / h, r.v);
        kin += b.integrator->kinetic(r.v);
        const double p[3] = {epaphe::dot(r.Mt[0], r.v), epaphe::dot(r.Mt[1], r.v), epaphe::dot(r.Mt[2], r.v)};
        r.momentum->append(p);
        total += b.integrator->halfStepEnergy(r.q, r.qNext);
        strain += b.integrator->strain(r.q);
        ext += r.ext;
        diss += r.diss;
        e0 += r.e0;
        if (!r.disp.empty()) {
          b.recoveryWatched.apply(r.q, r.v, r.uw, r.vw);
          auto uh = Kokkos::create_mirror_view(r.uw);
          auto vh = Kokkos::create_mirror_view(r.vw);
          Kokkos::deep_copy(uh, r.uw);
          Kokkos::deep_copy(vh, r.vw);
          std::size_t off = 0;
          for (std::size_t w = 0; w < r.disp.size(); ++w) {
            r.disp[w]->append(uh.data() + off);
            r.vel[w]->append(vh.data() + off);
            off += r.disp[w]->recordSize();
          }
        }
        if (b.contactEnd > b.contactBegin) {
          double tf = 0;
          for (std::size_t k = 0; k < r.forceRec.size(); ++k) {
            r.forceRec[k] = forceAll[b.contactBegin + k];
            r.gapRec[k] = gapAll[b.contactBegin + k];
            tf += r.forceRec[k];
          }
          r.gap->append(r.gapRec.data());
          r.force->append(r.forceRec.data());
          r.totalForce->append(&tf);
        }
      }
      const double balance = (total + diss - work - ext - e0) / std::max(energyRef, std::abs(total));
      ++records;
      sTime.append(&t);
      sKin.append(&kin);
      sStrain.append(&strain);
      sTotal.append(&total);
      sWork.append(&work);
      sExt.append(&ext);
      sDamp.append(&diss);
      sBal.append(&balance);
      summary_.maxBalanceError = std::max(summary_.maxBalanceError, std::abs(balance));
      if (!std::isfinite(total)) {
        std::ostringstream os;
        os << "the solution is no longer finite at t = " << t << " s (step " << n
           << "): the time step is probably too large for the contact stiffness";
        fail(os.str());
      }
      if (penalty) {
        const double given = e0 + ext - diss + springEnergy0;
        if (total > given + 1e-3 * std::max(std::abs(given), energyRef)) {
          std::ostringstream os;
          os << "the energy of the bodies grew to " << total << " J at t = " << t << " s, more than the " << given
             << " J they were given (initial, external work, initial penalty springs): the penalty contact is "
                "unstable at this time step (the penalty on the predicted gap is stable for h^2 kp / m below "
                "4/3); use a smaller 'Penalty stiffness' or 'Time step'";
          fail(os.str());
        }
      }
      if (std::abs(balance) > tolBalance) {
        std::ostringstream os;
        os << "energy balance error " << balance << " at t = " << t << " s exceeds 'Output->Energy balance tolerance' = "
           << tolBalance << " (total " << total << " J, contact work " << work << " J, damping " << diss
           << " J, initial " << e0 << " J)";
        fail(os.str());
      }
    }
    if (fieldsEvery > 0 && (n % fieldsEvery == 0 || n == nSteps - 1)) {
      ScopedPhase phase(cost, "output");
      sFieldTime->append(&t);
      ++frames;
      for (std::size_t ib = 0; ib < bodies_.size(); ++ib) {
        BodyRun& r = runs[ib];
        r.R.apply(r.q, r.uAll);  // u = R q (eq. 2.5)
        auto uh = Kokkos::create_mirror_view(r.uAll);
        Kokkos::deep_copy(uh, r.uAll);
        const auto& X = bodies_[ib]->rom.coords;
        r.displacement->append(uh.data());
        for (std::size_t k = 0; k < r.frame.size(); ++k) r.frame[k] = X[k / 3][k % 3] + uh(k);
        r.position->append(r.frame.data());
      }
    }
    // q_{n-1} <- q_n <- q_{n+1}
    const int oldPrev = iPrev;
    iPrev = iCur;
    iCur = iNext;
    iNext = oldPrev;
    selectParts();
    if (const long long done = n + 1; done < nSteps) {
      const int sig = stopSignal;
      const bool stop = sig != 0 || done == stopAfterSteps_;
      if (stop || (checkpointEvery > 0 && done % checkpointEvery == 0) ||
          records - recordsAtCheckpoint >= kRecordBuffer - 1 || frames - framesAtCheckpoint >= kFrameBuffer - 1 ||
          (checkpointInterval > 0 && (n & 63) == 0 && sinceCheckpoint.seconds() > checkpointInterval)) {
        ScopedPhase phase(cost, "checkpoint");
        checkpoint(done);
        sinceCheckpoint.restart();
      }
      if (stop) {
        std::ostringstream os;
        if (sig != 0)
          os << "interrupted by " << signalName(sig);
        else
          os << "stopped after " << done << " steps as asked (--stop-after-steps)";
        os << " at t = " << done * h << " s (step " << done << " of " << nSteps << "); continue with epaphe-run "
           << deck_.origin << " --restart " << output_;
        summary_.status = "stopped: " + os.str();
        summary_.stopSignal = sig;
        summary_.stoppedEarly = true;
        summary_.steps = done;
        summary_.loopSeconds = loop.seconds();
        summary_.stepsPerSecond = (done - firstStep) / std::max(summary_.loopSeconds, 1e-300);
        file.setAttribute("/run", "steps", done);
        file.setAttribute("/run", "loop_time", summary_.loopSeconds);
        file.setAttribute("/run", "checkpoints", summary_.checkpoints);
        file.setAttribute("/run", "checkpoint_time", summary_.checkpointSeconds);
        file.setAttribute("/", "status", summary_.status);
        file.close();
        if (fieldsEvery > 0) writeXdmf(frames);
        out << summary_.status << "\n";
        return summary_;
      }
    }
    if (progressInterval > 0 && (n & 255) == 0 && sinceProgress.seconds() > progressInterval) {
      sinceProgress.restart();
      const double rate = (n + 1 - firstStep) / loop.seconds();
      char line[200];
      std::snprintf(line, sizeof line, "  t = %.4e s (%3.0f %%)  %.0f steps/s  %s left  active contacts %d\n", t,
                    100.0 * (n + 1) / nSteps, rate, formatDuration((nSteps - n - 1) / rate).c_str(), active);
      out << line << std::flush;
    }
  }
  summary_.steps = nSteps;
  summary_.loopSeconds = loop.seconds();
  summary_.stepsPerSecond = (nSteps - firstStep) / summary_.loopSeconds;
  file.setAttribute("/run", "checkpoints", summary_.checkpoints);
  file.setAttribute("/run", "checkpoint_time", summary_.checkpointSeconds);
  if (!fresh) file.setAttribute("/run", "restarted_at_step", firstStep);
  file.setAttribute("/run", "steps", static_cast<long long>(nSteps));
  file.setAttribute("/run", "loop_time", summary_.loopSeconds);
  file.setAttribute("/run", "setup_time", summary_.setupSeconds);
  file.setAttribute("/run", "wall_time", summary_.loopSeconds + summary_.setupSeconds);
  file.setAttribute("/run", "steps_per_second", summary_.stepsPerSecond);
  if (kernels) {
    out << "Kokkos parallel regions in the loop, per step:";
    for (const auto& [name, count] : kernels->byName()) out << " " << name << " " << double(count) / (nSteps - firstStep);
    out << "\n";
    file.setAttribute("/run", "kernel_launches", static_cast<long long>(kernels->launches()));
    file.setAttribute("/run", "kernel_allocations", static_cast<long long>(kernels->allocations()));
  }
  {
    long long bytes = 0;  // what one step's integration must read
    for (const auto& b : bodies_) bytes += static_cast<long long>(b->integrator->predictBytes());
    file.setAttribute("/run", "step_matrix_bytes", bytes);
  }
  if (contact_) {  // the correction's detections of this run (output steps' measurements not counted)
    file.setAttribute("/run", "projections", contact_->projections());
    file.setAttribute("/run", "projections_skipped", contact_->projectionsSkipped());
  }
  for (const auto& [phase, s] : cost.all()) file.setAttribute("/run/cost", phase, s);
  file.setAttribute("/", "status", "complete");
  file.close();
  if (fieldsEvery > 0) writeXdmf(frames);
  return summary_;
}

void Simulation::writeXdmf(long long frames) const {
  // XDMF 2 for ParaView's Xdmf reader: a temporal collection per body whose frames pick one record
  // of /bodies/<b>/fields/{position, displacement} by hyperslab, and the rigid surfaces as quads.
  const std::string path = stem(output_) + ".xmf";
  std::string h5 = output_;
  if (const auto slash = h5.rfind('/'); slash != std::string::npos) h5 = h5.substr(slash + 1);
  io::Hdf5File file(output_, io::Hdf5File::Mode::ReadOnly);
  const auto times = file.readDoubles("/fields/time");
  std::ostringstream x;
  x << std::setprecision(17);
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"2.0\">\n <Domain>\n";
  for (const auto& b : bodies_) {
    const std::string g = "/bodies/" + b->name;
    const long long nn = b->rom.numNodes(), ne = static_cast<long long>(b->rom.hexes.size());
    auto slab = [&](long long k, const std::string& dataset) {
      std::ostringstream s;
      s << "<DataItem ItemType=\"HyperSlab\" Dimensions=\"" << nn << " 3\" Type=\"HyperSlab\">"
        << "<DataItem Dimensions=\"3 3\" Format=\"XML\">" << k << " 0 0 1 1 1 1 " << nn << " 3</DataItem>"
        << "<DataItem Dimensions=\"" << frames << " " << nn << " 3\" NumberType=\"Float\" Precision=\"8\" "
        << "Format=\"HDF\">" << h5 << ":" << g << "/fields/" << dataset << "</DataItem></DataItem>";
      return s.str();
    };
    x << "  <Grid Name=\"" << b->name << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (long long k = 0; k < frames; ++k) {
      x << "   <Grid Name=\"" << b->name << "\" GridType=\"Uniform\"><Time Value=\"" << times[k] << "\"/>\n"
        << "    <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << ne << "\"><DataItem Dimensions=\"" << ne
        << " 8\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << h5 << ":" << g
        << "/mesh/hexahedra</DataItem></Topology>\n"
        << "    <Geometry GeometryType=\"XYZ\">" << slab(k, "position") << "</Geometry>\n"
        << "    <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">" << slab(k, "displacement")
        << "</Attribute>\n   </Grid>\n";
    }
    x << "  </Grid>\n";
  }
  for (std::size_t is = 0; is < surfaces_.size(); ++is) {
    if (surfaceCarried_[is]) continue;
    const auto& s = surfaces_[is];
    const int nu = s->nu(), nv = s->nv();
    std::ostringstream quads;
    for (int i = 0; i + 1 < nu; ++i)
      for (int j = 0; j + 1 < nv; ++j)
        quads << i * nv + j << " " << (i + 1) * nv + j << " " << (i + 1) * nv + j + 1 << " " << i * nv + j + 1 << " ";
    x << "  <Grid Name=\"" << s->name() << "\" GridType=\"Uniform\">\n"
      << "   <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << (nu - 1) * (nv - 1)
      << "\"><DataItem Dimensions=\"" << (nu - 1) * (nv - 1) << " 4\" NumberType=\"Int\" Format=\"XML\">" << quads.str()
      << "</DataItem></Topology>\n"
      << "   <Geometry GeometryType=\"XYZ\"><DataItem Dimensions=\"" << nu * nv << " 3\" NumberType=\"Float\" "
      << "Precision=\"8\" Format=\"HDF\">" << h5 << ":/surfaces/" << s->name() << "/points</DataItem></Geometry>\n"
      << "  </Grid>\n";
  }
  x << " </Domain>\n</Xdmf>\n";
  std::ofstream out(path);
  EPAPHE_REQUIRE(out, "cannot write the XDMF file " << path << ": check the directory's permissions");
  out << x.str();
}

void Simulation::printSummary(std::ostream& os) const {
  if (rt_.rank() != 0) return;
  char buf[256];
  os << "\n==== Epaphe summary: " << deck_.params->sublist("Run").get<std::string>("Name") << " ("
     << deck_.origin << ") ====\n";
  for (const auto& b : bodies_) {
    if (b->rom.sparse())
      os << "body '" << b->name << "': " << b->rom.method() << ", " << b->rom.size << " DOFs (sparse K, "
         << b->rom.sparseK.values.size() << " entries)\n";
    else
      os << "body '" << b->name << "': " << b->rom.method() << ", " << b->rom.size << " reduced DOFs ("
         << b->rom.numModes << " modes)" << (b->fromCache ? ", from cache" : "") << "\n";
    const std::size_t nf = std::min(b->fullFrequencies.size(), b->reducedFrequencies.size());
    if (nf > 0) {
      os << (b->rom.sparse() ? "   mode   consistent (Hz) lumped (Hz)  rel. error\n"
                             : "   mode   full (Hz)    reduced (Hz)   rel. error\n");
      const double fmax = *std::max_element(b->fullFrequencies.begin(), b->fullFrequencies.begin() + nf);
      for (std::size_t i = 0; i < nf; ++i) {
        const double ff = b->fullFrequencies[i], fr = b->reducedFrequencies[i];
        if (ff < 1e-4 * fmax)  // zero up to round-off: a rigid-body mode
          std::snprintf(buf, sizeof buf, "   %4zu  %11.4f  %13.4f   rigid-body mode\n", i + 1, ff, fr);
        else
          std::snprintf(buf, sizeof buf, "   %4zu  %11.4f  %13.4f   %10.3e\n", i + 1, ff, fr, (fr - ff) / ff);
        os << buf;
      }
    }
    std::snprintf(buf, sizeof buf, "   stable step %.4e s (f_max %.4g Hz)\n", b->stable.critical,
                  b->stable.omegaMax / (2 * M_PI));
    os << buf;
  }
  std::snprintf(buf, sizeof buf, "time step %.4e s (%.1f %% of critical), %lld steps\n", summary_.timeStep,
                100 * summary_.timeStep / summary_.criticalStep, summary_.steps);
  os << buf;
  std::snprintf(buf, sizeof buf, "wall time: setup %s, loop %s, %.0f steps/s on %d thread(s), %d MPI rank(s)\n",
                formatDuration(summary_.setupSeconds).c_str(), formatDuration(summary_.loopSeconds).c_str(),
                summary_.stepsPerSecond, rt_.threads(), rt_.size());
  os << buf;
  os << "per-step cost:";
  for (const auto& [phase, s] : summary_.cost.all()) {
    std::snprintf(buf, sizeof buf, " %s %.3g us", phase.c_str(), 1e6 * s / std::max(1LL, summary_.steps));
    os << buf;
  }
  os << "\n";
  if (summary_.firstContact >= 0) {
    std::snprintf(buf, sizeof buf, "contact: first %.6e s, last %.6e s, max force %.6e N, impulse %.6e N s\n",
                  summary_.firstContact, summary_.lastContact, summary_.maxForce, summary_.impulse);
    os << buf;
  } else {
    os << "contact: none\n";
  }
  if (summary_.initialPenetrations > 0) {
    std::snprintf(buf, sizeof buf, "initial penetration: %d node(s), deepest %.3e m, resolved gently\n",
                  summary_.initialPenetrations, summary_.initialPenetrationDepth);
    os << buf;
  }
  if (summary_.largeMotionSteps > 0) {
    std::snprintf(buf, sizeof buf, "warning: %lld step(s) moved a contact node farther than the smallest patch "
                  "(allowed by 'Contact->Allow large motion per step'): contact may have been missed\n",
                  summary_.largeMotionSteps);
    os << buf;
  }
  for (const auto& w : summary_.warnings) os << "warning: " << w << "\n";
  if (summary_.firstStep > 0) {
    std::snprintf(buf, sizeof buf, "restarted at step %lld\n", summary_.firstStep);
    os << buf;
  }
  std::snprintf(buf, sizeof buf, "checkpoints: %lld, %s in all (%.3g ms each)\n", summary_.checkpoints,
                formatDuration(summary_.checkpointSeconds).c_str(),
                1e3 * summary_.checkpointSeconds / std::max(1LL, summary_.checkpoints));
  os << buf;
  std::snprintf(buf, sizeof buf, "energy balance: max relative error %.3e\n", summary_.maxBalanceError);
  os << buf;
  os << "status: " << summary_.status << "; output " << output_ << "\n";
}

}  // namespace epaphe
