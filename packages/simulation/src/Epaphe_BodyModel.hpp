#pragma once
// The full model of a deck body, from its Mesh sublist: a built-in mesh (Box, Ring segment, Blade,
// Casing) assembled with the body's Material, or a model imported from the files of an FE code
// (CalculiX, Matrix Market, code_aster), paths relative to the deck file's directory. Also the text that
// keys the reduced-model cache: the Mesh sublist, the Material when it is used, and for imported
// models the size and content hash of every file read (the CalculiX *INCLUDEs too), so that a
// changed file recomputes the reduction.
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ModelAtSpeed.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

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

/// True for the built-in meshes (Box, Ring segment, Blade, Casing, Sphere), false for imported models.
bool hasBuiltInMesh(const Teuchos::ParameterList& bodyParams);

/// The built-in mesh of a body (not its matrices): cheap, for the checks made before any work.
Mesh buildBodyMesh(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath);

/// Builds (built-in) or imports the body's full model on every rank of `comm`.
FullModel buildBodyModel(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// The casing geometry and clearance law of `pl`: a Casing surface (radiusKey "Radius") or a Casing
/// mesh ("Inner radius"). An Error names `origin` (the deck), the key, its value and the fix.
CasingGeometry casingGeometry(const Teuchos::ParameterList& pl, const std::string& radiusKey,
                              const std::string& origin);

/// Checks a body's Casing mesh (element counts, clearance law keys) with errors naming the deck key;
/// called before any body is built.
void checkCasingMesh(const std::string& body, const Teuchos::ParameterList& meshParams, const std::string& origin);

/// The rotation of the body's Rotation sublist; an Error names `context` for a speed that is not a
/// number or an axis of zero length.
RotationOptions rotationOptions(const Teuchos::ParameterList& rotation, const std::string& context);

/// What the model at speed depends on, for the reduced-model cache key ("" at rest).
std::string rotationKeyText(const Teuchos::ParameterList& rotation);

/// The Craig-Bampton options of the body's Reduction sublist (modes: its 'Fixed-interface modes').
CraigBamptonOptions reductionOptions(const Teuchos::ParameterList& reductionParams);

/// The reduction factory of epaphe-run and epaphe-modes: the body's model by its Reduction sublist's
/// 'Method' -- Craig-Bampton, Guyan (Craig-Bampton with no modes), Massless boundary (with
/// `retainedNodes` and `options`: reductionOptions(), or another mode count), None (the full model,
/// dense) or Full, lumped mass (K sparse, M lumped). The model carries its kind.
ReducedModel reduceBody(const FullModel& full, const std::vector<int>& retainedNodes,
                        const Teuchos::ParameterList& reductionParams, const CraigBamptonOptions& options,
                        ReductionReport* report);

/// The frequency check of a body ('Reduction->Frequency check' = count > 0): the full model's lowest
/// `count` frequencies (Hz), at the cost of what the reduction has not computed yet: a massless
/// boundary's modes are the full model's lowest (reused); otherwise Anasazi on the full model, its
/// shift placed by the reduced model's frequencies. A lumped model's own frequencies (it has no
/// dense matrices to give them) come in `lumped`.
struct FrequencyCheck {
  std::vector<double> full, lumped;
  bool reused = false;            // the reduction's own modes are the full model's (massless boundary)
  bool throughReduction = false;  // computed by the reduction through its factor (Craig-Bampton, Guyan)
  double seconds = 0;
};
FrequencyCheck frequencyCheck(const FullModel& full, const ReducedModel& model, const CraigBamptonOptions& options,
                              int count, const ReductionReport& report);

}  // namespace epaphe
