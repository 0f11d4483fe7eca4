#pragma once
// The full thermal finite-element model of a body: the heat equation (Epaphe_HeatElement.hpp;
// docs/theory/heat.md eq. 57)
//
//   C dtheta/dt + K theta = Q + g,   theta = T - T_ref,   K = K_conduction + H_convection,
//   g = sum_faces h (T_inf - T_ref) a_f,
//
// over the free nodes as distributed Tpetra matrices (8-node hexahedra of a built-in mesh; an imported
// mesh's solids as the linear element on their corners, eq. 75, a mid-side node's temperature the mean
// of its edge's corners), theta = 0 on the nodes held at the reference
// temperature T_ref (also the body's initial, uniform, temperature). Q: the heat inputs (W) at the
// nodes, from contact or a prescribed flux.
#include "Epaphe_HeatElement.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_TpetraTypes.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace epaphe {

/// Convection -k dT/dn = h (T - T_inf) on the faces of the hexahedra whose four corners are in
/// `nodes` (an imported mesh: the boundary faces, triangles and quadrilaterals, of its solids' corners).
struct Convection {
  std::vector<int> nodes;  ///< the nodes of the convective faces
  double coefficient = 0;  ///< h, W/(m^2 K)
  double temperature = 0;  ///< T_inf
};

/// A body's thermal problem: the material, the reference temperature and where heat leaves.
struct ThermalDefinition {
  ThermalMaterial material;            ///< conductivity, specific heat, density
  double referenceTemperature = 0;     ///< T_ref: initial temperature, and that of the fixed nodes
  std::vector<int> fixedNodes;         ///< held at T_ref
  std::vector<Convection> convection;  ///< the convective faces
};

/// A body's full thermal model: K (conduction and convection), C (capacity) and g over the free nodes.
struct ThermalFullModel {
  std::string name;              ///< the body's name
  Mesh mesh;                     ///< its mesh
  ThermalDefinition definition;  ///< what it was assembled from
  std::vector<int> eq;           ///< node -> free index, or -1 (held at T_ref, a mid-side node, in no element)
  /// Imported meshes with quadratic elements: node -> the two corners of the edge it is the middle of
  /// ({-1, -1}: not a mid-side node); its temperature is their mean (eq. 75). Empty otherwise.
  std::vector<std::array<int, 2>> midside;
  int numFree = 0;  ///< the number of free nodes (the size of K and C)
  ///@{
  Teuchos::RCP<CrsMatrix> K, C;  ///< over the free nodes, row map contiguous and uniform
  ///@}
  Teuchos::RCP<MultiVector> load;  ///< g, one column

  /// The number of nodes of the mesh.
  int numNodes() const { return mesh.numNodes(); }
  /// What node `node`'s temperature is made of: (free index, weight) pairs; a free node itself (1), a
  /// mid-side node the free corners of its edge (1/2 each), a node held at T_ref or in no element none.
  std::vector<std::pair<int, double>> weights(int node) const;
};

/// Assembles K, C and g (every rank inserts the rows it owns). `name` names the body in errors.
ThermalFullModel assembleThermalModel(const std::string& name, Mesh mesh, const ThermalDefinition& definition,
                                      const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// The area (m^2) each node of `nodes` carries on the faces whose four corners are in `nodes` (the
/// nodal heat inputs of a uniform flux q are q times these), in the order of `nodes`.
std::vector<double> faceAreas(const Mesh& mesh, const std::vector<int>& nodes);

}  // namespace epaphe
