#pragma once
// A run described by a deck: bodies built and reduced (on every MPI rank), surfaces (rigid, or
// carried by a body), the explicit loop with contact (on rank 0), monitors and the HDF5 history.
//
// Output layout (HDF5), one record every `Output->Every` steps, record k at time t_k:
//   /                      attributes: epaphe_version, name, status ("running", "complete",
//                          or "stopped: <why>") -- only "complete" is a finished result
//   /run/deck              the deck text;  /run attributes: time_step, critical_time_step,
//                          steps, wall_time, loop_time, steps_per_second, threads, mpi_ranks
//   /time                  (records)
//   /energy/{kinetic, strain, total, contact_work, external_work, damping, balance_error} (records)
//   /bodies/<b>/frequencies/{reduced, full, fixed_interface} (Hz); attributes reduction,
//                          reduced_dofs, rigid_mass (kg) (a full model with lumped mass: reduced =
//                          the lumped model's, full = the consistent mass's)
//   /bodies/<b>/momentum   linear momentum t_d^T M v (records x 3), kg m/s
//   /bodies/<b>/nodesets/<set>/{nodes, displacement (records x n x 3), velocity (records x n x 3)}
//   /bodies/<b>/contact/{nodes, gap (records x n), force (records x n), total_force (records)}
// and, with Output->Fields every > 0, frames of the whole bodies for ParaView (<stem>.xmf):
//   /fields/time (frames);  /bodies/<b>/mesh/{coordinates, hexahedra};
//   /bodies/<b>/fields/{position, displacement} (frames x nodes x 3);  /surfaces/<s>/points
//   ((nu nv) x 3, grid node (i, j) at row i nv + j)
// and the last checkpoint (overwritten in place at each checkpoint, see run()):
//   /checkpoint/{counters, q_prev, q, accumulators, warm_start, series_paths, series_lengths}
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_ContactGuards.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace epaphe {

struct RunSummary {
  std::string status = "not run";
  long long steps = 0;
  double setupSeconds = 0, loopSeconds = 0, stepsPerSecond = 0;
  double timeStep = 0, criticalStep = 0;
  double maxBalanceError = 0;        // relative to the largest energy
  double firstContact = -1, lastContact = -1, maxForce = 0, impulse = 0;
  CostSplit cost;
  long long firstStep = 0;           // > 0 when restarted from a checkpoint
  long long checkpoints = 0;         // written by this run
  double checkpointSeconds = 0;      // their total wall time
  int stopSignal = 0;                // SIGINT or SIGTERM when interrupted
  bool stoppedEarly = false;         // interrupted, or stopped by setStopAfterSteps
  // run guards (Epaphe_ContactGuards.hpp): initial penetrations resolved gently (count, deepest in
  // m), steps whose contact-node motion exceeded the smallest patch (allowed by the deck), and
  // the setup's warnings
  int initialPenetrations = 0;
  double initialPenetrationDepth = 0;
  long long largeMotionSteps = 0;
  std::vector<std::string> warnings;
};

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
  void printSummary(std::ostream& os) const;

  /// Continue the run stored in `file` (an output of the same deck) from its last checkpoint:
  /// the history series are cut to the checkpoint's records and the run appends to them. The
  /// output file becomes `file`.
  void setRestart(const std::string& file);
  /// Testing: after this many steps (counted from the start of the run), write a checkpoint, set
  /// the status "stopped: ..." and return, as after SIGTERM.
  void setStopAfterSteps(long long steps) { stopAfterSteps_ = steps; }
  /// Installs handlers for SIGINT and SIGTERM: the loop then stops at the end of the current
  /// step, writes a checkpoint, sets the status "stopped: interrupted by SIGINT at t = ..." and
  /// closes the file (RunSummary::stopSignal tells which signal).
  static void catchSignals();
  const std::string& outputFile() const { return output_; }

private:
  struct Body;
  /// Builds the surfaces and the contact; returns, per body, the reduced DOFs of the surfaces it
  /// carries (penalty springs act on them too, for the stable step).
  std::vector<std::vector<int>> setupSurfacesAndContact(const ContactOptions& options);
  // The steps of setup(), in order.
  void loadOrReduce(Body* body, const Teuchos::ParameterList& bodyParams);
  void setInitialState(Body* body, const Teuchos::ParameterList& bodyParams, double h, const DampingOptions& damping);
  void checkContactAtStart(const Teuchos::ParameterList& contactParams, double h);
  void checkStableSteps(const std::vector<std::vector<int>>& carriedDofs, const ContactOptions& copt,
                        const DampingOptions& damping);
  void writeXdmf(long long frames) const;
  Deck deck_;
  const Runtime& rt_;
  std::string output_;
  std::vector<std::unique_ptr<Body>> bodies_;
  std::vector<std::unique_ptr<BSplineSurface>> surfaces_;
  std::vector<bool> surfaceCarried_;       // per surface: carried by a body (else rigid)
  int systemSize_ = 0;                      // all bodies' reduced coordinates, stacked
  std::unique_ptr<SurfaceContact> contact_; // null without contact nodes or surfaces
  std::unique_ptr<ContactGuards> guards_;   // with contact_
  RunSummary summary_;
  std::string restart_;
  long long stopAfterSteps_ = -1;
};

}  // namespace epaphe
