#pragma once
// Full models from Matrix Market files, the neutral exchange format: K and M as
// "%%MatrixMarket matrix coordinate real general|symmetric" files, a DOF map naming the DOF of
// each matrix row, node coordinates, and optionally node sets. DOFs of nodes that have no row in
// the DOF map are the model's constrained DOFs.
#include "Epaphe_FullModel.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <string>

namespace epaphe {

/// The files of a Matrix Market model (see the file's opening comment).
struct MatrixMarketFiles {
  std::string stiffness;  ///< K.mtx
  std::string mass;       ///< M.mtx
  std::string dofs;       ///< one line per matrix row: "node direction" (1..3, x..z or DX..DZ)
  std::string nodes;      ///< one line per node: "id x y z"
  std::string nodeSets;   ///< optional ("" for none): one line per set, "name id id ..."

  /// prefix.K.mtx, prefix.M.mtx, prefix.dofs, prefix.nodes, prefix.nsets
  static MatrixMarketFiles withPrefix(const std::string& prefix);
};

/// Reads on rank 0 and distributes K and M over `comm`.
FullModel importMatrixMarket(const MatrixMarketFiles& files, const std::string& name,
                             const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// Writes a model in that format (collective; rank 0 writes): K and M 'general' with 17 digits, so
/// that importMatrixMarket gives back the same matrices bit for bit, rows in free-DOF order.
void writeMatrixMarket(const FullModel& model, const MatrixMarketFiles& files);

}  // namespace epaphe
