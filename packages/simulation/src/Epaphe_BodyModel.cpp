#include "Epaphe_BodyModel.hpp"

#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ImportedSpeedSource.hpp"
#include "Epaphe_ReducedModelCache.hpp"
#include "Epaphe_Runtime.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

std::string canonical(const ParameterList& pl) {
  std::ostringstream os;
  pl.print(os, Teuchos::ParameterList::PrintOptions().showTypes(true).showDoc(false).indent(0));
  return os.str();
}

ImportRequest requestOf(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  ImportRequest r;
  r.body = body;
  r.bodyParams = &bp;
  r.deckPath = deckPath;
  return r;
}

/// The body's importer ('Mesh->Type'), after the refusals every importer shares: the keys of the
/// other importers of files left set are mistakes worth naming, and an imported model carries its
/// own boundary conditions.
std::unique_ptr<ModelImporter> checkedImporter(const ImportRequest& r) {
  const ParameterList& mp = r.mesh();
  auto importer = modelImporter(mp);
  const std::string type = mp.get<std::string>("Type");
  const auto mine = importer->getValidParameters();
  for (const std::string& other : ImporterRegistry::names()) {
    if (other == type) continue;
    const auto keys = ImporterRegistry::make(other, type)->getValidParameters();
    for (auto it = keys->begin(); it != keys->end(); ++it) {
      const std::string& k = keys->name(it);
      const auto& entry = keys->entry(it);
      if (mine->isParameter(k) || !entry.isType<std::string>() || !Teuchos::getValue<std::string>(entry).empty())
        continue;
      EPAPHE_REQUIRE(mp.get<std::string>(k).empty(),
                     r.context() << ", '" << deck::pathOf(mp, k) << "' = '" << mp.get<std::string>(k)
                                 << "' is not read by Mesh Type " << type << "; remove it");
    }
  }
  if (!importer->builtInMesh())
    EPAPHE_REQUIRE(r.bodyParams->get<std::string>("Clamped node set").empty(),
                   r.context() << ", 'Clamped node set' = '" << r.bodyParams->get<std::string>("Clamped node set")
                               << "': an imported model (Mesh Type " << type
                               << ") carries its own boundary conditions; remove the key and fix the DOFs in the "
                                  "exported model (CalculiX *BOUNDARY, code_aster 'Clamped node file')");
  return importer;
}

/// "size fnv1a64" of a file's content, read in blocks.
std::string fileDigest(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  EPAPHE_REQUIRE(f != nullptr, path << " cannot be read to hash it; check its permissions");
  std::uint64_t h = 1469598103934665603ULL, size = 0;
  std::vector<unsigned char> buf(1 << 20);
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) {
    size += n;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ buf[i]) * 1099511628211ULL;
  }
  std::fclose(f);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return std::to_string(size) + " " + hex;
}

}  // namespace

std::vector<std::string> bodyModelFiles(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const ImportRequest r = requestOf(body, bp, deckPath);
  const auto importer = checkedImporter(r);
  std::vector<std::string> files = importer->files(r);
  if (!importer->builtInMesh())  // the matrices at speed (CalculiX jobs)
    for (const auto& p : importedSpeedFiles(importedSpeeds(body, bp, deckPath))) files.push_back(p);
  return files;
}

std::string bodyModelKeyText(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const std::vector<std::string> files = bodyModelFiles(body, bp, deckPath);
  std::string text = canonical(bp.sublist("Mesh"));
  if (hasBuiltInMesh(bp)) return text + canonical(bp.sublist("Material"));
  // The paths as resolved (a deck moved elsewhere reads other files) and what they hold.
  for (const auto& p : files) text += "file " + p + " " + fileDigest(p) + "\n";
  return text;
}

void checkBodyImport(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  modelImporter(bp.sublist("Mesh"))->check(requestOf(body, bp, deckPath));
}

bool hasBuiltInMesh(const ParameterList& bp) {
  return modelImporter(bp.sublist("Mesh"))->builtInMesh();
}

Mesh buildBodyMesh(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const ImportRequest r = requestOf(body, bp, deckPath);
  const auto importer = checkedImporter(r);
  EPAPHE_REQUIRE(importer->builtInMesh(), r.context() << ": buildBodyMesh called on an imported model");
  return importer->mesh(r);
}

bool hasCalculixMesh(const ParameterList& bp) {
  return modelImporter(bp.sublist("Mesh"))->name() == "CalculiX";
}

Mesh buildThermalMesh(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  if (!hasCalculixMesh(bp)) return buildBodyMesh(body, bp, deckPath);
  return readCalculixInput(requestOf(body, bp, deckPath).file("Input file", true)).mesh;
}

CalculixMaterial importedMaterial(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const ImportRequest r = requestOf(body, bp, deckPath);
  EPAPHE_REQUIRE(hasCalculixMesh(bp), r.context() << ": importedMaterial called on a model not imported from CalculiX");
  return readCalculixInput(r.file("Input file", true)).material;
}

FullModel buildBodyModel(const std::string& body, const ParameterList& bp, const std::string& deckPath,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const ImportRequest r = requestOf(body, bp, deckPath);
  bodyModelFiles(body, bp, deckPath);  // every file resolved and present before any is read
  return modelImporter(r.mesh())->build(r, comm);
}

std::unique_ptr<SpeedSampleSource> bodySpeedSource(const std::string& body, const ParameterList& bp,
                                                   const std::string& deckPath,
                                                   const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                                   const RotationOptions& rotation, FullModel& rest) {
  const ImportedSpeeds imported = importedSpeeds(body, bp, deckPath);
  if (!imported.empty()) return calculixSpeedSource(imported, body, comm);
  rest = buildBodyModel(body, bp, deckPath, comm);
  return std::make_unique<BuiltInSpeedSource>(rest, rotation);
}

RotationOptions rotationOptions(const ParameterList& rotation, const std::string& context) {
  RotationOptions o;
  o.speed = rotation.get<double>("Speed");
  EPAPHE_REQUIRE(std::isfinite(o.speed), context << "->Speed = " << o.speed << " rad/s; give a finite speed");
  o.axis = spinAxis(deck::getVec3(rotation, "Axis point", context), deck::getVec3(rotation, "Axis", context),
                    context + "->Axis");
  o.stressStiffening = rotation.get<bool>("Stress stiffening");
  o.spinSoftening = rotation.get<bool>("Spin softening");
  o.coriolis = rotation.get<bool>("Coriolis");
  o.staticState = deck::getEnum<StaticState>(rotation, "Static state");
  o.staticTolerance = rotation.get<double>("Static tolerance");
  return o;
}

std::string rotationKeyText(const ParameterList& rotation) {
  const double speed = rotation.get<double>("Speed");
  const auto range = deck::getDoubles(rotation, "Speed range");
  if (speed == 0 && range.empty()) return "";  // at rest: the key of a model without rotation
  std::ostringstream t;
  t.precision(17);
  if (range.empty())
    t << "\nrotation=" << speed;
  else  // the parametric model does not depend on the speed taken from it
    t << "\nrotation range=" << range[0] << " " << range[1] << " samples=" << rotation.get<int>("Sample speeds");
  for (double w : deck::getDoubles(rotation, "Imported speeds")) t << " imported=" << w;  // the files: bodyModelKeyText
  t << " axis=";
  for (double x : deck::getDoubles(rotation, "Axis")) t << x << " ";
  t << "point=";
  for (double x : deck::getDoubles(rotation, "Axis point")) t << x << " ";
  t << "stiffening=" << rotation.get<bool>("Stress stiffening") << " softening=" << rotation.get<bool>("Spin softening")
    << " static=" << rotation.get<std::string>("Static state")
    << " tolerance=" << rotation.get<double>("Static tolerance");
  if (rotation.get<bool>("Coriolis")) t << " coriolis";  // (absent when off: the keys of models without it)
  return t.str();
}

}  // namespace epaphe
