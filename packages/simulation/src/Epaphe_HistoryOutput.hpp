#pragma once
// The run's history in its HDF5 file (layout in Epaphe_Simulation.hpp) as a loop observer: at every
// step the energy monitor measures, one record of time, energies, each body's momentum, watched
// nodes (displacement, velocity) and contact nodes (gap measured at q_n, force, total force).
// Fresh runs also get the static data: frequencies, reduction, rigid mass, node lists.
//
// The watched nodes of a reduced body, u = R q and v = R qdot (eq. 2.5), are recovered 32 records
// at a time: a record keeps q and qdot (2 n numbers), and a chunk is one dgemm that reads R once,
// instead of once per record (cube-rings: R is 3993 x 419, 13 MB, larger than the caches).
#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_SceneBody.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <memory>
#include <vector>

namespace epaphe {

/// The run's history in its HDF5 file, as a loop observer (see the file's opening comment).
class HistoryOutput : public LoopObserver {
public:
  /// Records the `bodies` and the `contact` (null: none) at the steps `monitor` measures; `fresh`: a new
  /// file (a restart appends to the series it holds).
  HistoryOutput(io::Hdf5File& file, const std::vector<std::unique_ptr<SceneBody>>& bodies, SurfaceContact* contact,
                const EnergyMonitor& monitor, bool fresh);
  ~HistoryOutput() override;

  /// Records the energy balance's heat term too (a run with a thermal model, docs/theory/heat.md eq. 63):
  /// /energy/friction_heat, normal_work, counterface_work, and /energy/heat/(body) for each body with a thermal
  /// model (`heated`, indices in `bodies`: its share of the heat) and /energy/heat/counterface (the rest). Call
  /// before the checkpoints count the series.
  void recordHeat(const std::vector<int>& heated);
  /// Every series, in a fixed order (checkpoints store their lengths).
  std::vector<io::Series*> series();
  /// Records written (and buffered): the length of every series of the history.
  long long records() const { return static_cast<long long>(time_.size()); }

  void afterCorrect(ExplicitLoop& loop) override;
  /// Recovers the watched nodes of the records still pending and appends them: every series then
  /// has records() records. Checkpoints call it before they count the series.
  void completeRecords();
  void endRun(ExplicitLoop&) override { completeRecords(); }
  /// Completes the records, marks the file `stopped: <why>` and flushes it.
  void failed(ExplicitLoop& loop, const std::string& why) override;

private:
  struct BodySeries;
  void recover(std::size_t body);
  io::Hdf5File& file_;
  const std::vector<std::unique_ptr<SceneBody>>& bodies_;
  SurfaceContact* contact_;
  const EnergyMonitor& monitor_;
  io::Series time_, kinetic_, strain_, total_, work_, external_, damping_, balance_;
  std::unique_ptr<io::Series> drive_;  // /energy/drive_work, in a run-up only
  // the heat term (recordHeat): friction heat, normal work, counterface work, per heated body, counterface
  std::vector<std::unique_ptr<io::Series>> heat_;
  std::vector<int> heated_;
  std::vector<std::unique_ptr<BodySeries>> perBody_;
  std::vector<double> gapAll_, forceAll_;
};

}  // namespace epaphe
