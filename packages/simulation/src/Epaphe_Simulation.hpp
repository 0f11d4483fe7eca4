#pragma once
// A run described by a deck: the scene (Epaphe_Scene.hpp: bodies built and reduced on every MPI
// rank, surfaces, contact) and, on rank 0, the explicit loop (Epaphe_ExplicitLoop.hpp) with its
// observers: energy monitor, HDF5 history, field frames, checkpoints, stop control and progress, and
// those a program adds or registers (Epaphe_RunObserver.hpp).
//
// Output layout (HDF5), one record every `Output->Every` steps, record k at time t_k:
//   /                      attributes: epaphe_version, name, status ("running", "complete",
//                          or "stopped: <why>") -- only "complete" is a finished result
//   /run/deck              the deck text;  /run attributes: time_step, critical_time_step,
//                          steps, wall_time, loop_time, steps_per_second, threads, mpi_ranks;
//                          with friction, the self-locking check: self_locking_{margin, node, time}
//                          (least quasi-static margin), self_locking_first_{margin, node, time}
//                          (first lock; node -1: none), correction_locking_{margin, node, time}
//   /time                  (records)
//   /energy/{kinetic, strain, total, contact_work, external_work, damping, balance_error} (records)
//   /energy/{friction_heat, normal_work, counterface_work}, /energy/heat/{<b>, counterface} (records), with a
//                          thermal model: the balance's heat term and the heat's partition (Epaphe_BodyHeat.hpp)
//   /thermal/<b>/...       a body's thermal model: temperatures, heat, growth (Epaphe_BodyHeat.hpp)
//   /bodies/<b>/frequencies/{reduced, full, fixed_interface} (Hz); attributes reduction,
//                          reduced_dofs, rigid_mass (kg) (a full model with lumped mass: reduced =
//                          the lumped model's, full = the consistent mass's)
//   /bodies/<b>/momentum   linear momentum t_d^T M v (records x 3), kg m/s
//   /bodies/<b>/nodesets/<set>/{nodes, displacement (records x n x 3), velocity (records x n x 3)}
//   /bodies/<b>/contact/{nodes, gap (records x n), force (records x n), total_force (records)}
//                          (the gap to a coated surface is to its coating's current profile)
//   /coating/<s>/...       abradable coatings: wear maps, lobes (Epaphe_CoatingOutput.hpp)
// and, with Output->Fields every > 0, frames of the whole bodies for ParaView (<stem>.xmf):
//   /fields/time (frames);  /bodies/<b>/mesh/{coordinates, hexahedra};
//   /bodies/<b>/fields/{position, displacement} (frames x nodes x 3);  /surfaces/<s>/points
//   ((nu nv) x 3, grid node (i, j) at row i nv + j)
// and the last checkpoint (overwritten in place at each checkpoint, see Epaphe_Checkpoints.hpp):
//   /checkpoint/{counters, q_prev, q, accumulators, warm_start, detection_state, series_paths, series_lengths}
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_ContactGuards.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_RunObserver.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_Scene.hpp"
#include "Epaphe_SelfLockingMonitor.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace epaphe {

class KernelCounter;

/// What a run did: its status, its steps and speed, the setup's report, the loop's totals and the
/// observers' summaries.
struct RunSummary {
  std::string status = "not run";  ///< `complete`, `stopped: <why>`, `idle` on ranks other than 0, or `not run`
  long long steps = 0;             ///< the steps run
  /// the loop's wall time (s) and its steps per second
  ///@{
  double loopSeconds = 0, stepsPerSecond = 0;
  ///@}
  SetupReport setup;                   ///< time step, critical step, setup time, initial penetrations, warnings
  LoopAccumulators totals;             ///< contact times, impulse, peak force, worst balance error (relative),
                                       ///< steps whose contact-node motion exceeded the smallest patch
  CostSplit cost;                      ///< the phases' wall times
  long long firstStep = 0;             ///< > 0 when restarted from a checkpoint
  long long checkpoints = 0;           ///< written by this run
  double checkpointSeconds = 0;        ///< their total wall time
  int stopSignal = 0;                  ///< SIGINT or SIGTERM when interrupted
  bool stoppedEarly = false;           ///< interrupted, or stopped by setStopAfterSteps
  std::vector<std::string> coating;    ///< per coated surface: wear, dissipation, lobes (complete runs)
  std::vector<std::string> observers;  ///< the summary lines of the observers a program added or registered
  double stopTime = -1;                ///< s: the time of the step an error stopped (-1: none)
  /// friction: the self-locking check over the run (Epaphe_SelfLockingMonitor.hpp), least margins
  /// and first locks, quasi-static (eq. (50)) and the correction's own (eq. (48)); `selfLocking`: the
  /// summary line (empty without friction)
  ///@{
  LockRecord lockLeast, lockLeastStep, lockFirst, lockFirstStep;
  ///@}
  std::string selfLocking;  ///< the self-locking summary line (empty without friction)
};

/// A run described by a deck (see the file's opening comment): setup(), then run(), then the summary.
class Simulation {
public:
  /// `outputOverride` replaces Output->File when not empty.
  Simulation(Deck deck, const Runtime& runtime, std::string outputOverride = "");
  ~Simulation();

  /// Builds and reduces the bodies (collective over MPI), builds the surfaces, estimates the
  /// stable step and refuses an unstable one.
  void setup();
  /// The explicit loop on rank 0; writes the history. Returns its summary (also on other ranks,
  /// with status "idle").
  const RunSummary& run();
  /// Prints the run's summary (setup, steps, speed, totals, cost split, observers) on `os`.
  void printSummary(std::ostream& os) const;

  /// Continue the run stored in `file` (an output of the same deck) from its last checkpoint:
  /// the history series are cut to the checkpoint's records and the run appends to them. The
  /// output file becomes `file`.
  void setRestart(const std::string& file);
  /// Adds an observer to the run (after the built-in writers of a step, before the stop control,
  /// checkpoints and progress; Epaphe_RunObserver.hpp), with those the deck enables. The run does not
  /// own it; it must outlive run().
  void addObserver(RunObserver* observer) { added_.push_back(observer); }
  /// Testing: after this many steps (counted from the start of the run), write a checkpoint, set
  /// the status "stopped: ..." and return, as after SIGTERM.
  void setStopAfterSteps(long long steps) { stopAfterSteps_ = steps; }
  /// Installs handlers for SIGINT and SIGTERM: the loop then stops at the end of the current
  /// step, writes a checkpoint, sets the status "stopped: interrupted by SIGINT at t = ..." and
  /// closes the file (RunSummary::stopSignal tells which signal).
  static void catchSignals();
  /// The output file (the deck's 'Output->File', the override or the restart's file).
  const std::string& outputFile() const { return output_; }

private:
  // The steps of run().
  io::Hdf5File openOutput(double h) const;
  void writeRunFigures(io::Hdf5File& file, const ExplicitLoop& loop, const KernelCounter* kernels);
  // the self-locking check's figures into the summary (and its line) and the /run attributes
  void recordSelfLocking(io::Hdf5File& file, const SelfLockingMonitor& locking);
  // A run stopped by an error: why its motion diverged (Epaphe_DivergenceCheck.cpp), "" when its
  // energy did not grow without bound.
  std::string diagnoseDivergence(const ExplicitLoop& loop, const EnergyGrowth& growth, double h) const;
  // The deck at h/2 up to tEnd: the time it stopped at, or a negative value when it reached tEnd.
  double rerunAtHalfStep(double h, double tEnd) const;
  Deck deck_;
  const Runtime& rt_;
  std::string output_;
  std::unique_ptr<Scene> scene_;  // built by setup()
  RunSummary summary_;
  std::string restart_;
  long long stopAfterSteps_ = -1;
  std::vector<RunObserver*> added_;  // addObserver
};

}  // namespace epaphe
