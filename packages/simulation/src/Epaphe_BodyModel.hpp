#pragma once
// The full model of a deck body, from its Mesh sublist: a built-in mesh (Box, Ring segment)
// assembled with the body's Material, or a model imported from the files of an FE code (CalculiX,
// Matrix Market, code_aster), paths relative to the deck file's directory. Also the text that
// keys the reduced-model cache: the Mesh sublist, the Material when it is used, and for imported
// models the size and content hash of every file read (the CalculiX *INCLUDEs too), so that a
// changed file recomputes the reduction.
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_FullModel.hpp"

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

/// Builds (built-in) or imports the body's full model on every rank of `comm`.
FullModel buildBodyModel(const std::string& body, const Teuchos::ParameterList& bodyParams, const std::string& deckPath,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

/// The Craig-Bampton options of the body's Reduction sublist (modes: its 'Fixed-interface modes').
CraigBamptonOptions reductionOptions(const Teuchos::ParameterList& reductionParams);

}  // namespace epaphe
