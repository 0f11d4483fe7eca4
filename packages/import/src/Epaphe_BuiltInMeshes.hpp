#pragma once
// The built-in meshes as importers (Epaphe_ModelImporter.hpp): Box, Ring segment, Blade, Casing and
// Sphere, Epaphe's own 8-node hexahedra (Epaphe_Mesh.hpp) assembled with the body's Material, clamped
// by its 'Clamped node set'. Also the deck keys of a casing's geometry, which the rigid Casing surface
// shares.
#include "Epaphe_Mesh.hpp"

#include <Teuchos_ParameterList.hpp>

#include <string>
#include <vector>

namespace epaphe {

/// The keys of a casing's clearance law, shared by the rigid Casing surface and the Casing mesh
/// (`who` names them in the documentation, `radiusKey` is the nominal radius' key).
void addClearanceLaw(Teuchos::ParameterList& pl, const std::string& who, const std::string& radiusKey);

/// Every built-in mesh's Mesh keys, in the schema's order.
std::vector<std::string> builtInMeshKeys();

/// The casing geometry and clearance law of `pl`: a Casing surface (radiusKey "Radius") or a Casing
/// mesh ("Inner radius"). An Error names `origin` (the deck), the key, its value and the fix.
CasingGeometry casingGeometry(const Teuchos::ParameterList& pl, const std::string& radiusKey,
                              const std::string& origin);

/// Checks a body's Casing mesh (element counts, clearance law keys) with errors naming the deck key;
/// called before any body is built.
void checkCasingMesh(const std::string& body, const Teuchos::ParameterList& meshParams, const std::string& origin);

}  // namespace epaphe
