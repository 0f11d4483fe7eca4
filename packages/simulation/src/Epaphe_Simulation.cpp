#include "Epaphe_Simulation.hpp"
#include "Epaphe_SteadyState.hpp"

#include "Epaphe_BodyHeat.hpp"
#include "Epaphe_Checkpoints.hpp"
#include "Epaphe_CoatingOutput.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FieldOutput.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_HistoryOutput.hpp"
#include "Epaphe_Parallel.hpp"
#include "Epaphe_ParallelChooser.hpp"
#include "Epaphe_RunControl.hpp"
#include "Epaphe_SceneCheck.hpp"
#include "Epaphe_Version.hpp"

#include <Teuchos_DefaultSerialComm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <sstream>

namespace epaphe {

using Teuchos::ParameterList;

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
  StopControl::catchStopSignals();
}

void Simulation::setup() {
  scene_ = std::make_unique<Scene>(deck_, rt_, output_, !restart_.empty());
  scene_->build();
  summary_.setup = scene_->report();
}

// A fresh run creates the file; a restart opens it and checks that it holds this deck and a
// checkpoint (read by Checkpoints::restore once the series are set up). Then the run's attributes.
io::Hdf5File Simulation::openOutput(double h) const {
  const ParameterList& P = *deck_.params;
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
      rt_.out() << "warning: " << restart_ << " was run on " << threads << " thread(s), this restart on "
                << rt_.threads() << ": the results may differ in the last bits from an uninterrupted run\n";
  }
  file.setAttribute("/", "epaphe_version", version);
  file.setAttribute("/", "name", P.sublist("Run").get<std::string>("Name"));
  file.setAttribute("/", "status", "running");
  if (fresh) file.writeString("/run/deck", deck_.text);
  file.setAttribute("/run", "time_step", h);
  file.setAttribute("/run", "critical_time_step", summary_.setup.criticalStep);
  file.setAttribute("/run", "threads", static_cast<long long>(rt_.threads()));
  file.setAttribute("/run", "mpi_ranks", static_cast<long long>(rt_.size()));
  return file;
}

// The run on rank 0: the explicit loop (Epaphe_ExplicitLoop.hpp) with its observers, in the order
// their hooks must run: the energy monitor measures before the history records and checks after it;
// stop requests come before the checkpoint that follows them.
const RunSummary& Simulation::run() {
  if (rt_.rank() != 0) {
    summary_.status = "idle";
    return summary_;
  }
  const ParameterList& P = *deck_.params;
  const ParameterList& O = P.sublist("Output");
  const double h = P.sublist("Time").get<double>("Time step");
  const long long nSteps = numberOfSteps(P, deck_.origin);  // checked by checkScene
  const bool fresh = restart_.empty();
  io::Hdf5File file = openOutput(h);
  const auto& bodies = scene_->bodies();
  SurfaceContact* contact = scene_->contact();

  std::vector<LoopBody> loopBodies;
  std::vector<RunUp::Driven> driven;
  for (std::size_t ib = 0; ib < bodies.size(); ++ib) {
    const auto& b = bodies[ib];
    loopBodies.push_back({b->name, b->integrator.get(), b->offset, b->rom->size, b->runUp != nullptr});
    if (b->runUp) driven.push_back({ib, b->integrator.get(), b->runUp.get()});
  }
  ExplicitLoop loop(loopBodies, h, nSteps, scene_->corrector(), summary_.cost, rt_.out());
  // q_0 = 0, q_{-1} = q_0 - h v_0 + h^2/2 a_0, a_0 = M^{-1} f (gravity; K q_0 = 0, no contact
  // force yet): a uniform acceleration is then integrated exactly, q_n = h n v_0 + (h n)^2/2 a_0
  for (std::size_t ib = 0; ib < bodies.size(); ++ib) {
    const SceneBody& b = *bodies[ib];
    const DenseVector qPrev = loop.part(loop.previous(), ib);
    auto qp = Kokkos::create_mirror_view(qPrev);
    for (int i = 0; i < b.rom->size; ++i) qp(i) = -h * b.v0[i] + 0.5 * h * h * b.a0[i];
    if (const std::vector<double>& q0 = scene_->initialState(); !q0.empty()) {
      // eq. 71: q_0 the static equilibrium, at rest under its loads: q_{-1} = q_0 - h v_0
      const DenseVector qCur = loop.part(loop.current(), ib);
      auto qc = Kokkos::create_mirror_view(qCur);
      for (int i = 0; i < b.rom->size; ++i) {
        qc(i) = q0[static_cast<std::size_t>(b.offset + i)];
        qp(i) = qc(i) - h * b.v0[i];
      }
      Kokkos::deep_copy(qCur, qc);
    }
    Kokkos::deep_copy(qPrev, qp);
  }
  // A law whose forces are stable springs (Penalty) only gives back what they hold, so the bodies'
  // energy can never exceed what they were given (initial, external work, the springs compressed by
  // initial penetrations). (Not with a turning surface: a moving casing does work on the bodies.)
  // a run-up puts its bodies at their start before the energy monitor takes E_0
  std::unique_ptr<RunUp> runUp;
  if (!driven.empty()) runUp = std::make_unique<RunUp>(driven, scene_->corrector(), scene_->contactPositions());
  const ParameterList& cp = P.sublist("Contact");
  const double springs =
      contact && fastestRotation(P) == 0.0 ? contactLaw(cp.get<std::string>("Method")).springStiffness(cp) : 0.0;
  EnergyMonitor monitor(loop, {O.get<int>("Every"), O.get<double>("Energy balance tolerance"), springs});
  HistoryOutput history(file, bodies, contact, monitor, fresh);
  std::unique_ptr<FieldOutput> fields;
  if (const int fieldsEvery = O.get<int>("Fields every"); fieldsEvery > 0) {
    std::vector<const BSplineSurface*> drawn;  // carried surfaces are drawn with their body
    for (std::size_t is = 0; is < scene_->surfaces().size(); ++is)
      if (!scene_->surfaceCarried()[is]) drawn.push_back(scene_->surfaces()[is].get());
    fields = std::make_unique<FieldOutput>(file, bodies, drawn, fieldsEvery, fresh);
  }
  // heat from rubbing: the bodies' thermal models (on this rank alone), fed by the friction
  std::unique_ptr<HeatOutput> heat;
  if (contact) {
    auto heats = buildBodyHeats(P, deck_.origin, bodies, Teuchos::rcp(new Teuchos::SerialComm<int>()), rt_.out());
    if (!heats.empty()) {
      // the energy balance gains its heat term (eq. 63): the accumulators, and the history's series
      std::vector<int> heated;
      for (const auto& hb : heats) heated.push_back(hb->body);
      loop.accumulators().heatReceived.assign(bodies.size(), 0.0);
      history.recordHeat(heated);
      heat = std::make_unique<HeatOutput>(file, std::move(heats), *contact, bodies, O.get<int>("Every"),
                                          scene_->contactPositions());
    }
  }
  std::unique_ptr<CoatingOutput> coating;
  if (contact && contact->coating()) {
    const long long wearEvery = O.get<int>("Wear every") > 0 ? O.get<int>("Wear every") : 100LL * O.get<int>("Every");
    coating = std::make_unique<CoatingOutput>(file, *contact, monitor, wearEvery, fresh);
  }
  if (fields && coating) fields->setCoatings(coating->surfaces());
  if (fields && heat)
    for (const auto& h : heat->heats()) fields->setTemperature(h->body, h->integrator.get());
  // the observers the deck enables (registry) and those a program added, with their series
  const std::vector<std::unique_ptr<RunObserver>> made = makeDeckObservers(P, {file, *scene_, monitor, fresh});
  std::vector<RunObserver*> extra;
  for (const auto& o : made) extra.push_back(o.get());
  extra.insert(extra.end(), added_.begin(), added_.end());
  std::vector<io::Series*> series = coating ? coating->series() : std::vector<io::Series*>{};
  if (heat)
    for (io::Series* hs : heat->series()) series.push_back(hs);
  for (RunObserver* o : extra)
    for (io::Series* os : o->series()) series.push_back(os);
  Checkpoints checkpoints(file, loop, contact, history, fields.get(),
                          {O.get<int>("Checkpoint every"), O.get<double>("Checkpoint interval")}, series);
  checkpoints.setHeat(heat.get());
  StopControl stop(stopAfterSteps_, "continue with epaphe-run " + deck_.origin + " --restart " + output_);
  ProgressReport progress(P.sublist("Run").get<double>("Progress interval"));
  SelfLockingMonitor locking(contact, h);
  std::unique_ptr<SteadyStateMonitor> steady;  // eq. (70), 'Steady state'
  if (const SteadyStateOptions so = steadyStateOptions(P, deck_.origin); so.enabled)
    for (std::size_t ib = 0; ib < bodies.size(); ++ib)
      if (bodies[ib]->name == so.body) steady = std::make_unique<SteadyStateMonitor>(so, *bodies[ib], ib, h);
  // the heat's sources before the energy monitor (its record's heat term), the thermal update after the history
  // with a thread team, the loops parallel or serial by timing both on this run (Epaphe_ParallelChooser.hpp)
  std::unique_ptr<ParallelChooser> chooser;
  if (P.sublist("Run").get<bool>("Adaptive threads") && Kokkos::DefaultHostExecutionSpace().concurrency() > 1)
    chooser = std::make_unique<ParallelChooser>(serialWorkNs());
  std::vector<LoopObserver*> observers{chooser.get(), runUp.get(), &locking,      heat ? heat->sources() : nullptr,
                                       &monitor,      &history,    coating.get(), heat.get(),
                                       fields.get(),  steady.get()};
  observers.insert(observers.end(), extra.begin(), extra.end());
  observers.insert(observers.end(), {&stop, &checkpoints, &progress});
  for (LoopObserver* o : observers)
    if (o != nullptr) loop.addObserver(o);

  if (fresh) {
    checkpoints.write(loop, 0);
  } else {
    const long long first = checkpoints.restore(loop, restart_);
    rt_.out() << "restarting " << restart_ << " at step " << first << " of " << nSteps << " (t = " << first * h
              << " s)\n";
  }
  summary_.firstStep = loop.firstStep();
  // EPAPHE_COUNT_KERNELS=1 (benchmarks): count the loop's Kokkos parallel regions and allocations
  std::unique_ptr<KernelCounter> kernels;
  if (const char* e = std::getenv("EPAPHE_COUNT_KERNELS"); e && std::string(e) == "1")
    kernels = std::make_unique<KernelCounter>();
  summary_.status = "complete";
  bool complete = false;
  try {
    complete = loop.run();
  } catch (const Error& e) {
    summary_.stopTime = loop.time();
    recordSelfLocking(file, locking);
    std::string diagnosis = diagnoseDivergence(loop, monitor.growth(), h);
    if (summary_.lockFirst.node >= 0 || summary_.lockFirstStep.node >= 0)
      diagnosis += (diagnosis.empty() ? "" : ". ") + summary_.selfLocking;
    summary_.status = std::string("stopped: ") + e.what() + (diagnosis.empty() ? "" : ". Diagnosis: " + diagnosis);
    history.completeRecords();  // every series as long as /time, as when an observer fails the run
    if (diagnosis.empty()) throw;
    throw Error(std::string(e.what()) + ". Diagnosis: " + diagnosis);
  }
  summary_.totals = loop.accumulators();
  if (runUp) rt_.out() << "run-up: " << runUp->refreshes() << " stiffness refreshes\n";
  if (coating) summary_.coating = coating->summary();
  summary_.observers.clear();
  for (RunObserver* o : extra)
    for (const std::string& line : o->summary()) summary_.observers.push_back(line);
  if (chooser) {
    summary_.observers.push_back(chooser->summary());
    const ParallelChoice& pc = chooser->choice();
    file.setAttribute("/run", "parallel_fraction",
                      pc.steps() > 0 ? static_cast<double>(pc.parallelSteps()) / static_cast<double>(pc.steps()) : 0.0);
  }
  summary_.checkpoints = checkpoints.count();
  summary_.checkpointSeconds = checkpoints.seconds();
  summary_.steps = loop.stepsDone();
  summary_.loopSeconds = loop.seconds();
  summary_.stepsPerSecond = (loop.stepsDone() - loop.firstStep()) / std::max(summary_.loopSeconds, 1e-300);
  file.setAttribute("/run", "steps", loop.stepsDone());
  file.setAttribute("/run", "loop_time", summary_.loopSeconds);
  file.setAttribute("/run", "checkpoints", summary_.checkpoints);
  file.setAttribute("/run", "checkpoint_time", summary_.checkpointSeconds);
  recordSelfLocking(file, locking);
  if (steady) {
    steady->write(file);
    summary_.observers.push_back(steady->summary());
  }
  if (!complete && steady && steady->steady() && loop.stopReason().rfind("steady state", 0) == 0) {
    summary_.status = "complete: " + loop.stopReason();  // stopped by the steady state, as asked
    writeRunFigures(file, loop, kernels.get());
  } else if (!complete) {
    summary_.status = "stopped: " + loop.stopReason();
    summary_.stopSignal = stop.signal();
    summary_.stoppedEarly = true;
  } else {
    writeRunFigures(file, loop, kernels.get());
  }
  file.setAttribute("/", "status", summary_.status);
  file.close();
  if (fields) fields->writeXdmf(output_, stem(output_) + ".xmf");
  if (!complete) rt_.out() << summary_.status << "\n";
  return summary_;
}

// A complete run's figures in /run: restart step, setup and wall times, speed, the Kokkos regions
// counted (EPAPHE_COUNT_KERNELS=1), the integration's matrix bytes, the projections, the cost split.
void Simulation::writeRunFigures(io::Hdf5File& file, const ExplicitLoop& loop, const KernelCounter* kernels) {
  if (loop.firstStep() > 0) file.setAttribute("/run", "restarted_at_step", loop.firstStep());
  file.setAttribute("/run", "setup_time", summary_.setup.setupSeconds);
  file.setAttribute("/run", "wall_time", summary_.loopSeconds + summary_.setup.setupSeconds);
  file.setAttribute("/run", "steps_per_second", summary_.stepsPerSecond);
  if (kernels) {
    const double steps = static_cast<double>(loop.stepsDone() - loop.firstStep());
    rt_.out() << "Kokkos parallel regions in the loop, per step:";
    for (const auto& [name, count] : kernels->byName()) rt_.out() << " " << name << " " << double(count) / steps;
    rt_.out() << "\n";
    file.setAttribute("/run", "kernel_launches", static_cast<long long>(kernels->launches()));
    file.setAttribute("/run", "kernel_allocations", static_cast<long long>(kernels->allocations()));
  }
  long long bytes = 0;  // what one step's integration must read
  for (const auto& b : scene_->bodies()) bytes += static_cast<long long>(b->integrator->predictBytes());
  file.setAttribute("/run", "step_matrix_bytes", bytes);
  if (SurfaceContact* contact =
          scene_->contact()) {  // the correction's detections of this run (output steps' measurements not counted)
    file.setAttribute("/run", "projections", contact->projections());
    file.setAttribute("/run", "projections_skipped", contact->projectionsSkipped());
    file.setAttribute("/run", "flexibility_bytes", contact->flexibilityBytes());
  }
  for (const auto& [phase, s] : summary_.cost.all()) file.setAttribute("/run/cost", phase, s);
}

// Eqs. (48)-(50) of docs/theory/divergence.md: the least margins over the run and the first locks,
// nodes named by their body and node number.
void Simulation::recordSelfLocking(io::Hdf5File& file, const SelfLockingMonitor& locking) {
  summary_.lockLeast = locking.least();
  summary_.lockLeastStep = locking.leastStep();
  summary_.lockFirst = locking.firstLock();
  summary_.lockFirstStep = locking.firstStepLock();
  const SurfaceContact* contact = scene_->contact();
  if (contact == nullptr || contact->enforcement().selfLocking() == nullptr) return;
  const auto& bodies = scene_->bodies();
  auto label = [&](int k) { return static_cast<long long>(k < 0 ? -1 : contact->nodes()[k]); };
  auto where = [&](const LockRecord& r) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "node %d of '%s' at t = %.6e s", contact->nodes()[r.node],
                  bodies[contact->nodeBlocks()[r.node]]->name.c_str(), r.time);
    return std::string(buf);
  };
  auto put = [&](const std::string& key, const LockRecord& r) {
    file.setAttribute("/run", key + "_margin", r.node < 0 ? 1.0 : r.margin);
    file.setAttribute("/run", key + "_node", label(r.node));
    file.setAttribute("/run", key + "_time", r.time);
  };
  put("self_locking", summary_.lockLeast);
  put("self_locking_first", summary_.lockFirst);
  put("correction_locking", summary_.lockLeastStep);
  put("correction_locking_first", summary_.lockFirstStep);
  std::ostringstream os;
  os << "self-locking (sliding nodes checked " << locking.checks() << " times): ";
  if (summary_.lockLeast.node >= 0) {
    os << "least quasi-static margin " << summary_.lockLeast.margin << " (" << where(summary_.lockLeast) << ")";
    if (summary_.lockFirst.node >= 0)
      os << ", first locked " << where(summary_.lockFirst) << " (margin " << summary_.lockFirst.margin
         << "): friction can drive the normal force without bound";
    os << "; ";
  } else if (locking.checks() > 0) {
    os << "no static compliance for the sliding nodes; ";
  }
  if (summary_.lockLeastStep.node >= 0) {
    os << "least margin of the correction's Delassus block " << summary_.lockLeastStep.margin << " ("
       << where(summary_.lockLeastStep) << ")";
    if (summary_.lockFirstStep.node >= 0)
      os << ", first locked " << where(summary_.lockFirstStep) << " (margin " << summary_.lockFirstStep.margin
         << "): the correction cannot push that node out";
  } else {
    os << "no node slid";
  }
  summary_.selfLocking = os.str();
}

void Simulation::printSummary(std::ostream& os) const {
  if (rt_.rank() != 0) return;
  char buf[256];
  os << "\n==== Epaphe summary: " << deck_.params->sublist("Run").get<std::string>("Name") << " (" << deck_.origin
     << ") ====\n";
  for (const auto& b : scene_->bodies()) {
    // a stage: the model of instance 0 stands for every tuned instance; a mistuned one has its own
    if (b->instance > 0 && b->stiffnessFactor == 1) continue;
    if (b->instance >= 0)
      os << "instance " << b->instance << " of body '" << b->deckName << "'"
         << (b->stiffnessFactor == 1 ? " (its model shared by every tuned instance)"
                                     : " (stiffness factor " + std::to_string(b->stiffnessFactor) + ")")
         << ":\n";
    if (b->rom->sparse())
      os << "body '" << b->name << "': " << b->method << ", " << b->rom->size << " DOFs (sparse K, "
         << b->rom->sparseK.values.size() << " entries)\n";
    else
      os << "body '" << b->name << "': " << b->method << ", " << b->rom->size << " reduced DOFs (" << b->rom->numModes
         << " modes)" << (b->fromCache ? ", from cache" : "") << "\n";
    const std::size_t nf = std::min(b->fullFrequencies.size(), b->reducedFrequencies.size());
    if (nf > 0) {
      os << (b->rom->sparse() ? "   mode   consistent (Hz) lumped (Hz)  rel. error\n"
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
  std::snprintf(buf, sizeof buf, "time step %.4e s (%.1f %% of critical), %lld steps\n", summary_.setup.timeStep,
                100 * summary_.setup.timeStep / summary_.setup.criticalStep, summary_.steps);
  os << buf;
  std::snprintf(buf, sizeof buf, "wall time: setup %s, loop %s, %.0f steps/s on %d thread(s), %d MPI rank(s)\n",
                formatDuration(summary_.setup.setupSeconds).c_str(), formatDuration(summary_.loopSeconds).c_str(),
                summary_.stepsPerSecond, rt_.threads(), rt_.size());
  os << buf;
  os << "per-step cost:";
  for (const auto& [phase, s] : summary_.cost.all()) {
    std::snprintf(buf, sizeof buf, " %s %.3g us", phase.c_str(), 1e6 * s / std::max(1LL, summary_.steps));
    os << buf;
  }
  os << "\n";
  if (summary_.totals.firstContact >= 0) {
    std::snprintf(buf, sizeof buf, "contact: first %.6e s, last %.6e s, max force %.6e N, impulse %.6e N s\n",
                  summary_.totals.firstContact, summary_.totals.lastContact, summary_.totals.maxForce,
                  summary_.totals.impulse);
    os << buf;
  } else {
    os << "contact: none\n";
  }
  if (summary_.setup.initialPenetrations > 0) {
    std::snprintf(buf, sizeof buf, "initial penetration: %d node(s), deepest %.3e m, resolved gently\n",
                  summary_.setup.initialPenetrations, summary_.setup.initialPenetrationDepth);
    os << buf;
  }
  if (summary_.totals.largeMotionSteps > 0) {
    std::snprintf(buf, sizeof buf,
                  "warning: %lld step(s) moved a contact node farther than the smallest patch "
                  "(allowed by 'Contact->Allow large motion per step'): contact may have been missed\n",
                  summary_.totals.largeMotionSteps);
    os << buf;
  }
  for (const auto& w : summary_.setup.warnings) os << "warning: " << w << "\n";
  if (summary_.firstStep > 0) {
    std::snprintf(buf, sizeof buf, "restarted at step %lld\n", summary_.firstStep);
    os << buf;
  }
  std::snprintf(buf, sizeof buf, "checkpoints: %lld, %s in all (%.3g ms each)\n", summary_.checkpoints,
                formatDuration(summary_.checkpointSeconds).c_str(),
                1e3 * summary_.checkpointSeconds / std::max(1LL, summary_.checkpoints));
  os << buf;
  for (const auto& line : summary_.coating) os << line << "\n";
  if (!summary_.selfLocking.empty()) os << summary_.selfLocking << "\n";
  for (const auto& line : summary_.observers) os << line << "\n";
  std::snprintf(buf, sizeof buf, "energy balance: max relative error %.3e\n", summary_.totals.maxBalanceError);
  os << buf;
  os << "status: " << summary_.status << "; output " << output_ << "\n";
}

}  // namespace epaphe
