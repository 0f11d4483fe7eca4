#pragma once
// The full model of a deck body, from its Mesh sublist by the importer its 'Type' names
// (Epaphe_ModelImporter.hpp): a built-in mesh (Box, Ring segment, Blade, Casing, Sphere) assembled with
// the body's Material, or a model imported from the files of an FE code (CalculiX, Matrix Market,
// code_aster), paths relative to the deck file's directory. Also the text that
// keys the reduced-model cache: the Mesh sublist, the Material when it is used, and for imported
// models the size and content hash of every file read (the CalculiX *INCLUDEs too), so that a
// changed file recomputes the reduction.
#include "Epaphe_BuiltInMeshes.hpp"
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ModelImporter.hpp"
#include "Epaphe_ModelAtSpeed.hpp"
#include "Epaphe_ReductionMethod.hpp"
#include "Epaphe_SpeedSampleSource.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <memory>
#include <string>
#include <vector>

namespace epaphe {

/// The files an imported body reads, resolved against the deck's directory and checked to exist
/// (an Error names the deck, the key, the value and the path tried). Empty for built-in meshes.
std::vector<std::string> bodyModelFiles(const std::string& body, const Teuchos::ParameterList& bodyParams,
                                        const std::string& deckPath);

/// Canonical text of what the full model depends on (for the cache key). Reads the imported
/// files to hash them: call it on one rank.
std::string bodyModelKeyText(const std::string& body, const Teuchos::ParameterList& bodyParams,
                             const std::string& deckPath);

/// The refusals of the body's importer made before any model is built (ModelImporter::check).
void checkBodyImport(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath);

/// True for the built-in meshes (Box, Ring segment, Blade, Casing, Sphere), false for imported models.
bool hasBuiltInMesh(const Teuchos::ParameterList& bodyParams);

/// The built-in mesh of a body (not its matrices): cheap, for the checks made before any work.
Mesh buildBodyMesh(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath);

/// True when the body's model is imported from CalculiX ('Mesh->Type' = CalculiX): its input deck
/// gives the mesh's elements and material (a thermal model can be assembled on them).
bool hasCalculixMesh(const Teuchos::ParameterList& bodyParams);

/// The mesh of a built-in body, or of a CalculiX import read from its input deck alone (nodes,
/// elements as Mesh::solids, node sets; no matrices): what a thermal model is assembled on.
Mesh buildThermalMesh(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath);

/// What a CalculiX import's input deck says of its material (*DENSITY, *ELASTIC, *EXPANSION).
CalculixMaterial importedMaterial(const std::string& body, const Teuchos::ParameterList& bodyParams,
                                  const std::string& deckPath);

/// Builds (built-in) or imports the body's full model on every rank of `comm`.
FullModel buildBodyModel(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// The rotation of the body's Rotation sublist; an Error names `context` for a speed that is not a
/// number or an axis of zero length.
RotationOptions rotationOptions(const Teuchos::ParameterList& rotation, const std::string& context);

/// Where the full models of a rotating body at its sample speeds come from (Epaphe_SpeedSampleSource.hpp):
/// CalculiX jobs at its 'Rotation->Imported speeds' (Epaphe_ImportedSpeedSource.hpp), else Epaphe's
/// elements about `rotation`'s axis, from the body's full model at rest built into `rest` (which the
/// source refers to: keep it alive as long as the source).
std::unique_ptr<SpeedSampleSource> bodySpeedSource(const std::string& body, const Teuchos::ParameterList& bodyParams,
                                                   const std::string& deckPath,
                                                   const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                                   const RotationOptions& rotation, FullModel& rest);

/// What the model at speed depends on, for the reduced-model cache key ("" at rest).
std::string rotationKeyText(const Teuchos::ParameterList& rotation);

}  // namespace epaphe
