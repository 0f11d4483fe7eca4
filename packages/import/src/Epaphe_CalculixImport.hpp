#pragma once
// Full models from CalculiX (ccx): the stiffness and mass matrices written by
//
//   *FREQUENCY, SOLVER=MATRIXSTORAGE
//
// (jobname.sti and jobname.mas: upper triangle, lines "row column value", 1-based; jobname.dof:
// the DOF of each row as "node.direction"), and the mesh of the input deck (jobname.inp and the
// files it *INCLUDEs): *NODE, *ELEMENT, *NSET (GENERATE too), *BOUNDARY. CalculiX leaves the DOFs
// fixed by *BOUNDARY out of the matrices; they become the model's constrained DOFs.
//
// Elements: C3D8 (R, I), C3D20 (R), C3D15, C3D6, C3D10, C3D4. Their corner nodes are kept as
// (degenerate) hexahedra for output, and every element's nodes as Mesh::solids (the thermal model
// and its growth); mid-side nodes are nodes of the model like the others. The material's *DENSITY,
// *ELASTIC and *EXPANSION are read for the thermal model and its growth (CalculixMaterial).
#include "Epaphe_FullModel.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <limits>

#include <string>
#include <vector>

namespace epaphe {

/// The files of a CalculiX model: the input deck and the matrices of its MATRIXSTORAGE run.
struct CalculixFiles {
  std::string input;     ///< jobname.inp: mesh, node sets, *BOUNDARY
  std::string matrices;  ///< the job of the MATRIXSTORAGE run: path without extension of .sti, .mas, .dof
};

/// What a CalculiX input says of its material: the thermal model's density and the thermal growth's
/// E, nu and alpha (docs/user/heat.md). NaN where the input gives nothing; each `...Where` names the
/// file and line it was read at. `problem` says why the input's material cannot serve a thermal growth
/// (several *MATERIALs, an anisotropic or temperature-dependent table, *EXPANSION with ZERO=); empty
/// when it can. Other imports never read it, so none of this is refused when reading.
struct CalculixMaterial {
  double density = std::numeric_limits<double>::quiet_NaN();    ///< *DENSITY (the input's units)
  double young = std::numeric_limits<double>::quiet_NaN();      ///< E of *ELASTIC
  double poisson = std::numeric_limits<double>::quiet_NaN();    ///< nu of *ELASTIC
  double expansion = std::numeric_limits<double>::quiet_NaN();  ///< alpha of *EXPANSION (1/K)
  std::string densityWhere;                                     ///< file:line of *DENSITY's value
  std::string elasticWhere;                                     ///< file:line of *ELASTIC's values
  std::string expansionWhere;                                   ///< file:line of *EXPANSION's value
  std::string problem;  ///< why the material cannot serve a thermal growth (with where); empty when it can
};

/// The parts of a CalculiX/Abaqus input deck Epaphe reads.
struct CalculixInput {
  Mesh mesh;                  ///< nodeIds: CalculiX node numbers; node sets named as in the deck, plus "all"
  std::vector<char> fixed;    ///< 3 * numNodes: DOFs fixed by *BOUNDARY
  std::vector<char> used;     ///< numNodes: node belongs to an element
  CalculixMaterial material;  ///< *DENSITY, *ELASTIC, *EXPANSION
};

/// Reads `path` and the files it *INCLUDEs (relative to the including file).
CalculixInput readCalculixInput(const std::string& path);

/// Reads on rank 0 and distributes K and M over `comm` (row map contiguous and uniform).
FullModel importCalculix(const CalculixFiles& files, const std::string& name,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// `path` and every file it *INCLUDEs, recursively (what the model read from the input deck depends on).
std::vector<std::string> calculixInputFiles(const std::string& path);

/// The static displacement (3 per node of `mesh`, its order) printed in jobname.dat by *NODE PRINT
/// ... U: the displacement blocks before any eigenvalue output, the last value of a node kept. An
/// Error names the first node of the mesh printed nowhere.
std::vector<double> readCalculixDisplacements(const std::string& datPath, const Mesh& mesh);

/// The eigenvalues (omega^2, ascending as printed) of the first *FREQUENCY step in jobname.dat.
std::vector<double> readCalculixEigenvalues(const std::string& datPath);

}  // namespace epaphe
