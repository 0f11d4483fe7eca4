#pragma once
// A full finite-element model: mesh, DOF map with Dirichlet conditions, and the stiffness and
// mass matrices over the free DOFs as distributed Tpetra matrices.
#include "Epaphe_HexElement.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_TpetraTypes.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace epaphe {

/// A full finite-element model: its mesh, the DOF map and K and M over the free DOFs (distributed).
struct FullModel {
  std::string name;     ///< the body's name
  Mesh mesh;            ///< the mesh (nodes, hexahedra, node sets)
  std::vector<int> eq;  ///< 3 * node + direction -> free DOF index, or -1 when constrained
  int numFree = 0;      ///< the number of free DOFs (the size of K and M)
  ///@{
  Teuchos::RCP<CrsMatrix> K, M;  ///< over the free DOFs, row map contiguous and uniform
  ///@}
  /// The material of a model assembled from its elements (assembleHexModel), so that terms of the
  /// same elements can be added later (the centrifugal load, the geometric stiffness); empty for an
  /// imported model, whose elements Epaphe does not know.
  std::optional<Material> material;

  /// The number of nodes of the mesh.
  int numNodes() const { return mesh.numNodes(); }
};

/// Assembles K and M of a hexahedral mesh of one material; `clamped` nodes have all three
/// directions fixed. Each rank inserts the rows it owns.
FullModel assembleHexModel(const std::string& name, Mesh mesh, const Material& mat, const std::vector<int>& clamped,
                           const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// Calls fn(hex, x) for each hexahedron of the mesh with a free DOF in `rows` (the rows this rank
/// inserts), x its nodes' coordinates.
void forEachOwnedHex(const FullModel& model, const Map& rows,
                     const std::function<void(const std::array<int, 8>&, const double (&)[8][3])>& fn);

/// Inserts into A (not yet fill-complete) the rows it owns of a 24 x 24 element matrix Ae (row-major,
/// DOF order (node, direction) of `hex`), on the free DOFs.
void insertElementMatrix(const FullModel& model, const std::array<int, 8>& hex, const double* Ae, CrsMatrix& A);

/// The dense n x n (column-major) copy of a distributed matrix, on every rank. For small models.
std::vector<double> gatherDense(const CrsMatrix& A);

/// The rigid translations over the free DOFs: column d is 1 on every free DOF along direction d.
MultiVector rigidTranslations(const FullModel& model);

/// Total mass seen by a rigid translation along `direction`: t^T M t.
double rigidMass(const FullModel& model, int direction);

/// The model with its mass lumped to a diagonal by HRZ (Hinton, Rock & Zienkiewicz 1976) on the
/// assembled matrix: m_i = M_ii t_d^T M t_d / sum_(j along d) M_jj, d the direction of DOF i.
/// HRZ rather than row sums: a row sum of the consistent mass of quadratic elements (the corner
/// rows of a 20-node hexahedron) is negative or zero, a diagonal entry of a positive definite M never
/// is. Scaling the assembled diagonal (imported models give no element matrices) equals element-wise
/// HRZ whenever every element has the same shape functions and an affine map (the ratio of an
/// element's mass to the sum of its diagonal is then a constant of the element type): the built-in
/// Box's hexahedra, where it also equals the row sum (m_e / 8 per corner). Each direction keeps the
/// consistent rigid mass t^T M t exactly, hence the momentum and kinetic energy of a translation
/// (the initial velocity). With clamped nodes t^T M t is over the free DOFs only (it misses their
/// coupling to the clamped ones), so every mass is smaller than element-wise HRZ's by one common
/// factor, 1 - O(elements at the clamp / elements): for 8-node hexahedra (N - 2C/3) / (N - C/2), C of
/// the N elements touching the clamped face; it vanishes as the mesh is refined. K is shared, not
/// copied.
FullModel withLumpedMass(const FullModel& model);

/// The rows of a distributed matrix on every rank, columns sorted in each row.
SparseRows gatherRows(const CrsMatrix& A);

/// The unreduced model as a ReducedModel with R = I (dense; for small models and references).
ReducedModel unreducedModel(const FullModel& full);

/// A full model whose mass is lumped (see lumpedMass()) as a ReducedModel kept sparse: q = u, K in
/// compressed rows and diag(M), on every rank. `full.M` must be diagonal.
ReducedModel sparseModel(const FullModel& full);

}  // namespace epaphe
