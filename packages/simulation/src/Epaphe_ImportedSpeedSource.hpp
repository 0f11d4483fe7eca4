#pragma once
// A CalculiX model at speed: the full model of a rotating body read from one ccx run per sample speed
// (Rotation->Imported speeds and Imported jobs), each a static centrifugal step (*DLOAD CENTRIF, with
// NLGEOM or not) whose displacement is printed (*NODE PRINT U), followed by a perturbation step
// storing the tangent matrices (*STEP, PERTURBATION / *FREQUENCY, SOLVER=MATRIXSTORAGE). The
// parametric model over the speed range is built from them (Epaphe_SpeedParametricModel.hpp) as from
// Epaphe's own elements. ccx's tangent carries the initial-displacement stiffness K_u of the static
// state, which Epaphe's built-in K(Omega) leaves out (docs/user/rotating-bodies.md).
#include "Epaphe_SpeedSampleSource.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <string>
#include <vector>

namespace epaphe {

/// A body's imported CalculiX runs at speed ('Rotation->Imported speeds', 'Imported jobs').
struct ImportedSpeeds {
  std::vector<double> speeds;     ///< rad/s, increasing
  std::vector<std::string> jobs;  ///< resolved paths without extension, one per speed
  std::string input;              ///< the CalculiX input deck (mesh, sets, *BOUNDARY)
  /// True when the body has none.
  bool empty() const { return speeds.empty(); }
};

/// The body's Rotation->Imported speeds and jobs, checked up front (an Error names the deck key, the
/// value and the fix): both or neither, Mesh Type CalculiX, 2 or more increasing speeds >= 0,
/// 'Speed range' = {first, last}, every job's .sti, .mas, .dof and .dat present and every .dof the
/// same as the first (one DOF numbering). Empty when the body has none.
ImportedSpeeds importedSpeeds(const std::string& body, const Teuchos::ParameterList& bodyParams,
                              const std::string& deckPath);

/// The files the imported speeds read (for the reduced-model cache key).
std::vector<std::string> importedSpeedFiles(const ImportedSpeeds& imported);

/// The source of the parametric model reading `imported` (the samples are its speeds).
std::unique_ptr<SpeedSampleSource> calculixSpeedSource(const ImportedSpeeds& imported, const std::string& body,
                                                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

}  // namespace epaphe
