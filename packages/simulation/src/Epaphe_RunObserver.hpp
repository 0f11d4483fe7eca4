#pragma once
// Observers of a run (Epaphe_Simulation.hpp) beyond the built-in ones (energy monitor, history, fields,
// coating output, stop control, checkpoints, progress): an interface and a registry keyed by the
// deck's name.
//
//   RunObserver   a LoopObserver (Epaphe_ExplicitLoop.hpp) that may hand its HDF5 series to the
//                 checkpoints (a restart cuts them to the checkpoint's records and appends) and lines to
//                 the run's summary.
//   ObserverKind  a kind of observer the deck can ask for (Epaphe_ObserverKind.hpp): 'Observers-><name>'
//                 with 'Enabled' = true makes one for the run from the list's other keys.
// A program registers its kinds with registerObserver() before it reads a deck, or hands a run an
// observer it made itself with Simulation::addObserver; no file of Epaphe changes
// (docs/developer/extending.md). Both run after the built-in writers of a step (history, coating,
// fields) and before the stop control, the checkpoints and the progress report.
#include <memory>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_ObserverKind.hpp"

namespace epaphe {

class Scene;
class EnergyMonitor;

/// An observer of a run beyond the built-in ones (see the file's opening comment): a LoopObserver that
/// may hand its series to the checkpoints and lines to the summary.
class RunObserver : public LoopObserver {
public:
  /// The HDF5 series it appends to (a restart cuts them to the checkpoint's records).
  virtual std::vector<io::Series*> series() { return {}; }
  /// Lines for the run's summary, asked after the run.
  virtual std::vector<std::string> summary() const { return {}; }
};

/// What an observer made from the deck may use.
struct ObserverContext {
  io::Hdf5File& file;            ///< the run's output: write under a group of its own
  const Scene& scene;            ///< bodies, surfaces, contact
  const EnergyMonitor& monitor;  ///< monitor.measures(loop): the steps the history records
  bool fresh;                    ///< false: a restart (the file holds the records up to the checkpoint)
};

/// The observers the deck enables, in the order of registration.
std::vector<std::unique_ptr<RunObserver>> makeDeckObservers(const Teuchos::ParameterList& epaphe,
                                                            const ObserverContext& context);

}  // namespace epaphe
