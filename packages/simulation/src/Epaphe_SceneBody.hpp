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
  NodeRecovery(const ReducedModel& rom, const std::vector<int>& nodes, const std::string& label);
  std::size_t rows() const { return R_.extent(0) > 0 ? R_.extent(0) : index_.size(); }
  void apply(const DenseVector& q, const DenseVector& u) const;
  /// Y = R X for `cols` columns at once (X: size() x cols, Y: rows() x cols, column-major, on the
  /// host): one dgemm reads R once for all of them, where a record at a time reads R per record.
  void applyColumns(const double* X, int cols, double* Y) const;

private:
  DenseMatrix R_;
  std::vector<int> index_;
  int size_ = 0;  // the reduced model's size
};

struct SceneBody {
  std::string name;
  std::string method;  ///< its reduction method's name for its model (ReductionMethod::modelName)
  ReducedModel rom;
  bool fromCache = false;
  ReductionReport report;
  std::vector<double> fullFrequencies, reducedFrequencies;
  std::vector<int> contactNodes;
  std::string contactSet;
  std::vector<double> v0;
  double speed = 0;        ///< |initial velocity| (m/s), for the run guards
  std::vector<double> a0;  ///< initial acceleration M^{-1} f of the constant force (gravity), reduced coordinates
  std::vector<std::pair<std::string, std::vector<int>>> watched;
  NodeRecovery recoveryWatched;  ///< the watched nodes, in order
  StableStep stable;
  std::unique_ptr<CentralDifference> integrator;
  int offset = 0;  ///< its block of the system coordinates
  ///@{
  int contactBegin = 0, contactEnd = 0;  ///< its nodes in the contact order
  ///@}
  /// A run-up ('Rotation->Speed law' Ramp): its stiffness and static state over the speeds (null: none).
  /// Until the contact is built, its growth and restX hold every node of rom; then its contact nodes.
  std::unique_ptr<RunUpModel> runUp;
};

}  // namespace epaphe
