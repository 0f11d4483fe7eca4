#pragma once
// Full models from code_aster, as the thesis' tool took them (Leclere 2018, section 3.2): the
// assembled stiffness and mass matrices extracted from code_aster (e.g. MATR_ASSE.EXTR_MATR(sparse=True)
// written as "row column value" lines, 1-based, optionally with a Matrix Market header; one
// triangle or both), a DOF numbering file naming the DOF of every equation, including the
// non-physical ones, and the node coordinates.
//
// Boundary conditions dualized by code_aster (AFFE_CHAR_MECA / DDL_IMPO) add Lagrange multiplier
// equations, two per fixed DOF, each coupled in K to the one physical DOF it fixes. The importer
// drops every Lagrange equation and constrains the physical DOF it ties (found from K itself, and
// checked against the DOF file when that names it). A Lagrange equation tying several physical
// DOFs (LIAISON_DDL, LIAISON_SOLIDE, ...) is refused: eliminate such relations before export.
//
// DOF numbering file, one line per equation:
//   N12 DX        physical DOF (node number or name "N12"; DX/DY/DZ, x/y/z or 1/2/3)
//   N12 LAGR:DX   Lagrange equation fixing DX of node 12 (also "LAGR", "N12 LAGR", "12 -1": code_aster's
//                 DEEQ form, negative component; "0 0" a Lagrange equation of a linear relation)
#include "Epaphe_FullModel.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <string>

namespace epaphe {

/// The files of a code_aster model (see the file's opening comment for their formats).
struct CodeAsterFiles {
  std::string stiffness;     ///< BStiff.mat
  std::string mass;          ///< BMass.mat
  std::string dofs;          ///< BDof.txt: one line per equation
  std::string nodes;         ///< Body.dat: "id x y z" per line
  std::string clampedNodes;  ///< optional (BBC.dat): node ids fixed in every direction
  std::string nodeSets;      ///< optional: "name id id ..." per line
};

/// Reads on rank 0 and distributes K and M (physical free DOFs only) over `comm`.
FullModel importCodeAster(const CodeAsterFiles& files, const std::string& name,
                          const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

}  // namespace epaphe
