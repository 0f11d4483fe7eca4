#pragma once
// A body of a scene as the setup leaves it (Simulation::setup): its reduced model, frequencies,
// initial state, watched and contact nodes, stable step and integrator. The run's observers
// (history, fields, checkpoints) read it.
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_RunUp.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace epaphe {

/// u = R q (eq. 2.5) at a list of nodes, 3 rows per node: dense rows of R for a reduced body; for a
/// full body (R = I), the index in q of each row's DOF (-1: clamped, u = 0).
class NodeRecovery {
public:
  NodeRecovery() = default;
  /// The recovery of `nodes` of `rom`; `label` names it (views, messages).
  NodeRecovery(const ReducedModel& rom, const std::vector<int>& nodes, const std::string& label);
  /// 3 per node.
  std::size_t rows() const { return R_.extent(0) > 0 ? R_.extent(0) : index_.size(); }
  /// u = R q (`u`: rows() values).
  void apply(const DenseVector& q, const DenseVector& u) const;
  /// Y = R X for `cols` columns at once (X: size() x cols, Y: rows() x cols, column-major, on the
  /// host): one dgemm reads R once for all of them, where a record at a time reads R per record.
  void applyColumns(const double* X, int cols, double* Y) const;

private:
  DenseMatrix R_;
  std::vector<int> index_;
  int size_ = 0;  // the reduced model's size
};

/// A body of a scene as the setup leaves it (see the file's opening comment).
struct SceneBody {
  std::string name;    ///< the body's name in the deck
  std::string method;  ///< its reduction method's name for its model (ReductionMethod::modelName)
  /// its reduced (or full, lumped) model; the tuned instances of one deck body share it
  std::shared_ptr<ReducedModel> rom = std::make_shared<ReducedModel>();
  /// An instance of a deck body ('Instances'): its deck body's name, its index (-1: the body is not
  /// instanced), the angle (rad) it is placed at about the instancing axis, its stiffness factor
  /// (mistuning; 1: tuned).
  ///@{
  std::string deckName;
  int instance = -1;
  double poseAngle = 0, stiffnessFactor = 1;
  ///@}
  bool fromCache = false;  ///< true when the model was read from the reduced-model cache
  ReductionReport report;  ///< what its reduction did
  /// the full model's and the reduced model's lowest frequencies (Hz)
  ///@{
  std::vector<double> fullFrequencies, reducedFrequencies;
  ///@}
  std::vector<int> contactNodes;  ///< its contact nodes ('Contact node set')
  std::string contactSet;         ///< the name of its contact node set ("" for none)
  std::vector<double> v0;         ///< initial velocity in its reduced coordinates
  double speed = 0;               ///< |initial velocity| (m/s), for the run guards
  std::vector<double> a0;  ///< initial acceleration M^{-1} f of the constant force (gravity), reduced coordinates
  std::vector<std::pair<std::string, std::vector<int>>> watched;  ///< the watched node sets: name and nodes
  NodeRecovery recoveryWatched;                                   ///< the watched nodes, in order
  StableStep stable;                                              ///< its highest frequency and critical step
  std::unique_ptr<CentralDifference> integrator;                  ///< its central difference
  int offset = 0;                                                 ///< its block of the system coordinates
  ///@{
  int contactBegin = 0, contactEnd = 0;  ///< its nodes in the contact order
  ///@}
  /// A run-up ('Rotation->Speed law' Ramp): its stiffness and static state over the speeds (null: none).
  /// Until the contact is built, its growth and restX hold every node of rom; then its contact nodes.
  std::unique_ptr<RunUpModel> runUp;
};

}  // namespace epaphe
