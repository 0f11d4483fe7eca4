#pragma once
// Checkpoints of a run in its HDF5 file, and the restart from them, as a loop observer.
//
// A checkpoint holds everything the next steps depend on (fixed shapes): the step to run next,
// q_{n-1} and q_n of the system, the loop's accumulators (contact work, per body damping and
// external work, contact times, impulse, peak force, worst balance error), the contact's warm
// starts and skipping state, a coating's wear and dissipation, the thermal models' state, and the records of every
// series. Between checkpoints
// nothing is written to the file: the series buffers (1024 records, 16 field frames) never fill, a checkpoint being
// taken when they are one record short. A checkpoint first writes and flushes (H5Fflush) the buffered records, then
// overwrites the older of two slots, /checkpoint/0 and /checkpoint/1, flushes, and only then points
// /checkpoint/current at it and flushes again. A process killed at any moment thus leaves a
// complete checkpoint in the slot /checkpoint/current names; with uncompressed series
// (Output->Compression false, the default) the records it counts are intact too, since an
// uncompressed chunk is rewritten in place with the same bytes for the records it already held.
#include "Epaphe_BodyHeat.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_FieldOutput.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_HistoryOutput.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <string>
#include <vector>

namespace epaphe {

/// When checkpoints are written (by step count, by wall time, or both).
struct CheckpointOptions {
  int every = 0;        ///< Output->Checkpoint every (steps; 0: none on this count)
  double interval = 0;  ///< Output->Checkpoint interval (s of wall time; 0: none on time)
};

/// Checkpoints of a run and the restart from them, as a loop observer (see the file's opening comment).
class Checkpoints : public LoopObserver {
public:
  /// `contact` (its warm starts, skipping and coating state) and `fields` may be null (no contact,
  /// no field frames); `more`: other observers' series (coatings), at most as long as the history's.
  Checkpoints(io::Hdf5File& file, const ExplicitLoop& loop, SurfaceContact* contact, HistoryOutput& history,
              FieldOutput* fields, const CheckpointOptions& options, const std::vector<io::Series*>& more = {});

  /// Writes a checkpoint now, `nextStep` the step a restart runs first.
  void write(const ExplicitLoop& loop, long long nextStep);
  /// Restores the last complete checkpoint of the file into the loop and the outputs, and cuts the
  /// series to its records; `what` names the file for errors. Returns the step it restarts at.
  long long restore(ExplicitLoop& loop, const std::string& what);

  /// The bodies' thermal models (heat from rubbing), whose state the checkpoints hold too; call before the first
  /// write or restore.
  void setHeat(HeatOutput* heat) { heat_ = heat; }

  /// The checkpoints written so far.
  long long count() const { return count_; }
  /// Their total wall time (s).
  double seconds() const { return seconds_; }

  void beginRun(ExplicitLoop&) override { since_.restart(); }
  /// After a step: a checkpoint when asked (stop request, count, interval) or when a buffer is full.
  void endStep(ExplicitLoop& loop) override;

private:
  io::Hdf5File& file_;
  SurfaceContact* contact_;
  HistoryOutput& history_;
  FieldOutput* fields_;
  HeatOutput* heat_ = nullptr;
  CheckpointOptions opt_;
  std::vector<io::Series*> series_;
  std::string seriesPaths_;
  std::vector<std::string> accumulatorNames_;
  int slot_ = 0;  // the slot the next checkpoint overwrites
  long long recordsAt_ = 0, framesAt_ = 0;
  long long count_ = 0;
  double seconds_ = 0;
  Stopwatch since_;
};

}  // namespace epaphe
