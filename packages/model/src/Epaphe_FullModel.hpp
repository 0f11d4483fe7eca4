#pragma once
// A full finite-element model: mesh, DOF map with Dirichlet conditions, and the stiffness and
// mass matrices over the free DOFs as distributed Tpetra matrices.
#include "Epaphe_HexElement.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_TpetraTypes.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <string>
#include <vector>

namespace epaphe {

struct FullModel {
  std::string name;
  Mesh mesh;
  std::vector<int> eq;      // 3 * node + direction -> free DOF index, or -1 when constrained
  int numFree = 0;
  Teuchos::RCP<CrsMatrix> K, M;   // over the free DOFs, row map contiguous and uniform

  int numNodes() const { return mesh.numNodes(); }
};

/// Assembles K and M of a hexahedral mesh of one material; `clamped` nodes have all three
/// directions fixed. Each rank inserts the rows it owns.
FullModel assembleHexModel(const std::string& name, Mesh mesh, const Material& mat,
                           const std::vector<int>& clamped, const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// The dense n x n (column-major) copy of a distributed matrix, on every rank. For small models.
std::vector<double> gatherDense(const CrsMatrix& A);

/// Total mass seen by a rigid translation along `direction`: t^T M t.
double rigidMass(const FullModel& model, int direction);

}  // namespace epaphe
