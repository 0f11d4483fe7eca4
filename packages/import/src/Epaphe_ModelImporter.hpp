#pragma once
// An importer: what turns a deck body's Mesh sublist into its full model, chosen by 'Mesh->Type'. The
// built-in meshes (Box, Ring segment, Blade, Casing, Sphere: Epaphe's own 8-node hexahedra assembled
// with the body's Material, Epaphe_BuiltInMeshes.cpp) and the readers of another code's matrices
// (CalculiX, Matrix Market, code_aster: Epaphe_FileImporters.cpp) are importers. Each owns its Mesh keys
// (getValidParameters(), merged into the deck schema) and answers what the rest of Epaphe asks: the
// files it reads (the reduced-model cache key hashes them), the checks made before any model is built,
// the mesh alone (built-in meshes, for those checks) and the full model on every rank.
//
// ImporterRegistry keys the importers by their deck name. The built-in ones are registered on first
// use; an application adds its own with ImporterRegistry::add() before it reads a deck.
#include "Epaphe_FullModel.hpp"
#include "Epaphe_Mesh.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace epaphe {

/// A body of a deck, as an importer sees it.
struct ImportRequest {
  std::string body;                                    ///< the body's name in the deck
  const Teuchos::ParameterList* bodyParams = nullptr;  ///< the body's validated list (Mesh, Material, ...)
  std::string deckPath;                                ///< files are relative to its directory

  /// The body's Mesh sublist.
  const Teuchos::ParameterList& mesh() const { return bodyParams->sublist("Mesh"); }
  /// The start of every message: the deck's path, then ": body" and the body's name in single quotes.
  std::string context() const { return deckPath + ": body '" + body + "'"; }
  /// The file of Mesh key `key` resolved against the deck's directory ("" when optional and empty);
  /// with `job`, the path without extension of a CalculiX job whose .sti, .mas and .dof must exist. An
  /// Error names the deck, the key, its value, the path tried and the fix.
  std::string file(const std::string& key, bool required, bool job = false) const;
};

/// An importer: turns a deck body's Mesh sublist into its full model, chosen by 'Mesh->Type' (see the
/// file's opening comment).
class ModelImporter {
public:
  virtual ~ModelImporter() = default;

  /// The deck's name ('Mesh->Type').
  virtual std::string name() const = 0;
  /// What it builds or reads, for the documentation of 'Mesh->Type'.
  virtual std::string documentation() const = 0;
  /// Its own keys in the body's Mesh sublist, with documentation, defaults and validators. Keys that
  /// several importers share carry the same entry.
  virtual Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const = 0;

  /// True for a mesh of Epaphe's own elements: the body's Material and 'Clamped node set' are used,
  /// and the centrifugal terms of a rotating body can be built (Epaphe_ModelAtSpeed.hpp).
  virtual bool builtInMesh() const { return false; }
  /// The files it reads, resolved and checked to exist (an Error names the deck key).
  virtual std::vector<std::string> files(const ImportRequest&) const { return {}; }
  /// Refusals of its keys made by `epaphe-run --check` before any model is built.
  virtual void check(const ImportRequest&) const {}
  /// A built-in mesh alone (no matrices), for the checks made before any work.
  virtual Mesh mesh(const ImportRequest& request) const;
  /// The full model on every rank of `comm`.
  virtual FullModel build(const ImportRequest& request, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const = 0;
};

/// The importers by their deck names, in the order they were added (the built-in ones first).
class ImporterRegistry {
public:
  /// Makes a new importer.
  using Factory = std::function<std::unique_ptr<ModelImporter>()>;
  /// Adds an importer under `name`, its deck name; an Error when the name is taken.
  static void add(const std::string& name, Factory factory);
  /// A new importer of that name; an Error names `context` and the valid names.
  static std::unique_ptr<ModelImporter> make(const std::string& name, const std::string& context);
  /// The registered deck names, in the order they were added.
  static std::vector<std::string> names();
  /// Changes with every add(), so that a schema built from the registry knows when to rebuild.
  static int version();
};

/// The importer of a body's validated Mesh sublist ('Type').
std::unique_ptr<ModelImporter> modelImporter(const Teuchos::ParameterList& meshParams);

/// The Mesh keys of every registered importer, in the schema's order: the importers of files' first,
/// then the built-in meshes' (builtInMeshKeys()), then any other's.
Teuchos::RCP<Teuchos::ParameterList> importerParameters();

}  // namespace epaphe
