#include "Epaphe_BodyModel.hpp"

#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_CodeAsterImport.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ImportedSpeedSource.hpp"
#include "Epaphe_MatrixMarketImport.hpp"
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

bool isImported(MeshType t) {
  return t == MeshType::Calculix || t == MeshType::MatrixMarket || t == MeshType::CodeAster;
}

std::string deckDirectory(const std::string& deckPath) {
  const auto slash = deckPath.find_last_of('/');
  return slash == std::string::npos ? std::string() : deckPath.substr(0, slash + 1);
}

bool isFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/// The resolved file of `key` ("" when optional and empty); an Error names the deck, key, value and fix.
std::string fileKey(const ParameterList& mesh, const std::string& key, bool required, const std::string& deckPath,
                    const std::string& body, const std::string& type, const std::string& suffixes = "") {
  const std::string value = mesh.get<std::string>(key);
  const std::string where = deckPath + ": body '" + body + "', '" + deck::pathOf(mesh, key) + "'";
  if (value.empty()) {
    EPAPHE_REQUIRE(!required, where << " is empty but Mesh Type " << type
                                    << " needs it; name the file, relative to "
                                       "the deck's directory");
    return "";
  }
  const std::string path = value[0] == '/' ? value : deckDirectory(deckPath) + value;
  for (const std::string& s :
       suffixes.empty() ? std::vector<std::string>{""} : std::vector<std::string>{".sti", ".mas", ".dof"})
    EPAPHE_REQUIRE(isFile(path + s), where
                                         << " = '" << value << "': no file " << path + s
                                         << (suffixes.empty() ? ""
                                                              : " (the job's .sti, .mas and .dof are read; run "
                                                                "ccx on a deck with *FREQUENCY, SOLVER=MATRIXSTORAGE)")
                                         << "; paths are relative to the deck's directory");
  return path;
}

struct ImportFiles {
  MeshType type;
  CalculixFiles ccx;
  MatrixMarketFiles mm;
  CodeAsterFiles aster;
  std::vector<std::string> all;  // every file read
};

ImportFiles importFiles(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const ParameterList& mp = bp.sublist("Mesh");
  ImportFiles f;
  f.type = deck::getEnum<MeshType>(mp, "Type");
  const std::string type = mp.get<std::string>("Type");
  const std::string ctx = deckPath + ": body '" + body + "'";
  // Keys of the other types (or of the built-in meshes) left set are mistakes worth naming.
  auto unused = [&](std::initializer_list<const char*> keys) {
    for (const char* k : keys)
      EPAPHE_REQUIRE(mp.get<std::string>(k).empty(), ctx << ", '" << deck::pathOf(mp, k) << "' = '"
                                                         << mp.get<std::string>(k) << "' is not read by Mesh Type "
                                                         << type << "; remove it");
  };
  if (!isImported(f.type)) {
    unused({"Input file", "Matrix job", "Stiffness file", "Mass file", "DOF file", "Node file", "Node set file",
            "Clamped node file"});
    return f;
  }
  EPAPHE_REQUIRE(bp.get<std::string>("Clamped node set").empty(),
                 ctx << ", 'Clamped node set' = '" << bp.get<std::string>("Clamped node set") << "': an imported model "
                     << "(Mesh Type " << type << ") carries its own boundary conditions; remove the key and fix the "
                     << "DOFs in the exported model (CalculiX *BOUNDARY, code_aster 'Clamped node file')");
  if (f.type == MeshType::Calculix) {
    unused({"Stiffness file", "Mass file", "DOF file", "Node file", "Node set file", "Clamped node file"});
    f.ccx.input = fileKey(mp, "Input file", true, deckPath, body, type);
    std::string job = mp.get<std::string>("Matrix job");
    if (job.empty()) {
      const auto dot = f.ccx.input.rfind('.'), slash = f.ccx.input.rfind('/');
      f.ccx.matrices = (dot != std::string::npos && (slash == std::string::npos || dot > slash))
                           ? f.ccx.input.substr(0, dot)
                           : f.ccx.input;
      for (const char* s : {".sti", ".mas", ".dof"})
        EPAPHE_REQUIRE(isFile(f.ccx.matrices + s),
                       ctx << ", 'Mesh->Matrix job' is empty, so the matrices are read from " << f.ccx.matrices
                           << ".sti/.mas/.dof, but " << f.ccx.matrices + s << " does not exist; run ccx on "
                           << f.ccx.input << " (with *FREQUENCY, SOLVER=MATRIXSTORAGE) or set 'Matrix job'");
    } else {
      f.ccx.matrices = fileKey(mp, "Matrix job", true, deckPath, body, type, "sti");
    }
    f.all = calculixInputFiles(f.ccx.input);
    for (const char* s : {".sti", ".mas", ".dof"}) f.all.push_back(f.ccx.matrices + s);
    for (const auto& p : importedSpeedFiles(importedSpeeds(body, bp, deckPath))) f.all.push_back(p);  // at speed
  } else if (f.type == MeshType::MatrixMarket) {
    unused({"Input file", "Matrix job", "Clamped node file"});
    f.mm.stiffness = fileKey(mp, "Stiffness file", true, deckPath, body, type);
    f.mm.mass = fileKey(mp, "Mass file", true, deckPath, body, type);
    f.mm.dofs = fileKey(mp, "DOF file", true, deckPath, body, type);
    f.mm.nodes = fileKey(mp, "Node file", true, deckPath, body, type);
    f.mm.nodeSets = fileKey(mp, "Node set file", false, deckPath, body, type);
    f.all = {f.mm.stiffness, f.mm.mass, f.mm.dofs, f.mm.nodes};
    if (!f.mm.nodeSets.empty()) f.all.push_back(f.mm.nodeSets);
  } else {
    unused({"Input file", "Matrix job"});
    f.aster.stiffness = fileKey(mp, "Stiffness file", true, deckPath, body, type);
    f.aster.mass = fileKey(mp, "Mass file", true, deckPath, body, type);
    f.aster.dofs = fileKey(mp, "DOF file", true, deckPath, body, type);
    f.aster.nodes = fileKey(mp, "Node file", true, deckPath, body, type);
    f.aster.nodeSets = fileKey(mp, "Node set file", false, deckPath, body, type);
    f.aster.clampedNodes = fileKey(mp, "Clamped node file", false, deckPath, body, type);
    f.all = {f.aster.stiffness, f.aster.mass, f.aster.dofs, f.aster.nodes};
    if (!f.aster.nodeSets.empty()) f.all.push_back(f.aster.nodeSets);
    if (!f.aster.clampedNodes.empty()) f.all.push_back(f.aster.clampedNodes);
  }
  return f;
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
  return importFiles(body, bp, deckPath).all;
}

std::string bodyModelKeyText(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const ImportFiles f = importFiles(body, bp, deckPath);
  std::string text = canonical(bp.sublist("Mesh"));
  if (!isImported(f.type)) return text + canonical(bp.sublist("Material"));
  // The paths as resolved (a deck moved elsewhere reads other files) and what they hold.
  for (const auto& p : f.all) text += "file " + p + " " + fileDigest(p) + "\n";
  return text;
}

namespace {

template <class T>
std::string listed(const std::vector<T>& v) {
  std::ostringstream os;
  os << "{";
  for (std::size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  return os.str() + "}";
}

}  // namespace

CasingGeometry casingGeometry(const ParameterList& pl, const std::string& radiusKey, const std::string& origin) {
  CasingGeometry g;
  g.radius = pl.get<double>(radiusKey);
  g.axialPosition = pl.get<double>("Axial position");
  g.coneAngle = pl.get<double>("Cone angle");
  const auto ax = deck::getDoubles(pl, "Axial range");
  EPAPHE_REQUIRE(ax.size() == 2 && ax[1] > ax[0], origin << ": '" << deck::pathOf(pl, "Axial range") << "' = "
                                                         << listed(ax) << "; give {first, last} with last > first (m)");
  g.axialRange = {ax[0], ax[1]};
  g.law = deck::getEnum<ClearanceLaw>(pl, "Clearance law");
  g.clearance = pl.get<double>("Clearance");
  g.orders = deck::getInts(pl, "Harmonic orders");
  g.amplitudesFirst = deck::getDoubles(pl, "Amplitudes at first end");
  g.amplitudesLast = deck::getDoubles(pl, "Amplitudes at last end");
  if (g.law == ClearanceLaw::Harmonics)
    EPAPHE_REQUIRE(
        !g.orders.empty() && g.amplitudesFirst.size() == g.orders.size() && g.amplitudesLast.size() == g.orders.size(),
        origin << ": '" << deck::pathOf(pl, "Harmonic orders") << "' has " << g.orders.size()
               << " orders, the amplitudes " << g.amplitudesFirst.size() << " and " << g.amplitudesLast.size()
               << "; give one amplitude per order at each end");
  return g;
}

void checkCasingMesh(const std::string& body, const ParameterList& mp, const std::string& origin) {
  const auto el = deck::getInts(mp, "Elements");
  const std::string where = origin + ": body '" + body + "', '" + deck::pathOf(mp, "Elements") + "' = " + listed(el);
  EPAPHE_REQUIRE(el.size() == 3, where << "; a Casing mesh needs {through the thickness, around the circumference, "
                                          "along the axis}, e.g. {1, 48, 3}");
  EPAPHE_REQUIRE(el[1] >= 4, where << ": " << el[1] << " element(s) around the circumference; a Casing needs at least "
                                   << "4 (its inner face is a closed bicubic B-spline through one node per element): "
                                   << "give e.g. {" << el[0] << ", 48, " << el[2] << "}");
  EPAPHE_REQUIRE(el[0] >= 1 && el[2] >= 1,
                 where << "; give at least 1 element through the thickness and along the axis");
  casingGeometry(mp, "Inner radius", origin);
}

bool hasBuiltInMesh(const ParameterList& bp) {
  const auto type = deck::getEnum<MeshType>(bp.sublist("Mesh"), "Type");
  return type != MeshType::Calculix && type != MeshType::MatrixMarket && type != MeshType::CodeAster;
}

Mesh buildBodyMesh(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const std::string ctx = deckPath + ": body '" + body + "'";
  const ParameterList& mp = bp.sublist("Mesh");
  const auto type = deck::getEnum<MeshType>(mp, "Type");
  EPAPHE_REQUIRE(hasBuiltInMesh(bp), ctx << ": buildBodyMesh called on an imported model");
  const auto el = deck::getInts(mp, "Elements");
  EPAPHE_REQUIRE(el.size() == 3, ctx << ": 'Mesh->Elements' has " << el.size() << " values; give {nx, ny, nz}");
  Mesh mesh;
  if (type == MeshType::Box) {
    const auto origin = deck::getVec3(mp, "Origin", deckPath), lengths = deck::getVec3(mp, "Lengths", deckPath);
    try {
      mesh = makeBoxMesh(origin, lengths, {el[0], el[1], el[2]});
    } catch (const Error& e) {
      throw Error(ctx + ", Mesh Type Box ('" + deck::pathOf(mp, "Elements") + "', 'Lengths'): " + e.what());
    }
  } else if (type == MeshType::Blade) {
    BladeGeometry g;
    g.hubRadius = mp.get<double>("Hub radius");
    g.tipRadius = mp.get<double>("Tip radius");
    g.chord = mp.get<double>("Chord");
    g.thickness = mp.get<double>("Blade thickness");
    g.stagger = mp.get<double>("Stagger");
    g.twist = mp.get<double>("Twist");
    g.camber = mp.get<double>("Camber");
    g.coneAngle = mp.get<double>("Cone angle");
    g.axialPosition = mp.get<double>("Axial position");
    mesh = makeBladeMesh(g, {el[0], el[1], el[2]});
  } else if (type == MeshType::Casing) {
    checkCasingMesh(body, mp, deckPath);
    try {
      mesh = makeCasingMesh(casingGeometry(mp, "Inner radius", deckPath), mp.get<double>("Thickness"),
                            {el[0], el[1], el[2]});
    } catch (const Error& e) {
      throw Error(ctx + ", Mesh Type Casing: " + e.what());
    }
  } else if (type == MeshType::Sphere) {
    try {
      mesh = makeSphereMesh(deck::getVec3(mp, "Center", deckPath), mp.get<double>("Radius"), {el[0], el[1], el[2]},
                            mp.get<double>("Pole grading"));
    } catch (const Error& e) {
      throw Error(ctx + ", Mesh Type Sphere ('" + deck::pathOf(mp, "Elements") +
                  "', 'Radius', 'Pole grading'): " + e.what());
    }
  } else {
    const auto ang = deck::getDoubles(mp, "Angles"), ax = deck::getDoubles(mp, "Axial range");
    EPAPHE_REQUIRE(ang.size() == 2 && ax.size() == 2, ctx << ": 'Mesh->Angles' and 'Mesh->Axial range' must each "
                                                             "be {first, last}");
    mesh = makeRingSegmentMesh(deck::getVec3(mp, "Origin", deckPath), mp.get<double>("Inner radius"),
                               mp.get<double>("Thickness"), {ang[0], ang[1]}, {ax[0], ax[1]}, {el[0], el[1], el[2]});
  }
  return mesh;
}

FullModel buildBodyModel(const std::string& body, const ParameterList& bp, const std::string& deckPath,
                         const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const ImportFiles f = importFiles(body, bp, deckPath);
  const std::string ctx = deckPath + ": body '" + body + "'";
  if (f.type == MeshType::Calculix) return importCalculix(f.ccx, body, comm);
  if (f.type == MeshType::MatrixMarket) return importMatrixMarket(f.mm, body, comm);
  if (f.type == MeshType::CodeAster) return importCodeAster(f.aster, body, comm);
  Mesh mesh = buildBodyMesh(body, bp, deckPath);
  Material mat;
  mat.density = bp.sublist("Material").get<double>("Density");
  mat.young = bp.sublist("Material").get<double>("Young's modulus");
  mat.poisson = bp.sublist("Material").get<double>("Poisson's ratio");
  std::vector<int> clamped;
  if (const std::string cs = bp.get<std::string>("Clamped node set"); !cs.empty())
    clamped = mesh.nodeSet(cs, ctx + ", 'Clamped node set'");
  return assembleHexModel(body, std::move(mesh), mat, clamped, comm);
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

CraigBamptonOptions reductionOptions(const ParameterList& rp) {
  CraigBamptonOptions o;
  o.modes =
      deck::getEnum<ReductionMethod>(rp, "Method") == ReductionMethod::Guyan ? 0 : rp.get<int>("Fixed-interface modes");
  o.solver = deck::getEnum<LinearSolver>(rp, "Linear solver");
  o.iterativeTolerance = rp.get<double>("Iterative tolerance");
  o.checkFrequencies = rp.get<int>("Frequency check");
  o.candidates = rp.get<int>("Candidate modes");
  o.denseEigen = rp.get<std::string>("Eigensolver") == "LAPACK dense";
  const auto d = deck::getDoubles(rp, "Load direction");
  for (std::size_t i = 0; i < 3 && i < d.size(); ++i) o.loadDirection[i] = d[i];
  return o;
}

ReducedModel reduceBody(const FullModel& full, const std::vector<int>& retainedNodes, const ParameterList& rp,
                        const CraigBamptonOptions& options, ReductionReport* report) {
  switch (deck::getEnum<ReductionMethod>(rp, "Method")) {
    case ReductionMethod::MasslessBoundary:
      return masslessBoundary(full, retainedNodes, options, report);
    case ReductionMethod::CraigBampton:
      return craigBampton(full, retainedNodes, options, report);
    case ReductionMethod::Guyan: {
      CraigBamptonOptions guyan = options;
      guyan.modes = 0;
      return craigBampton(full, retainedNodes, guyan, report);
    }
    case ReductionMethod::None:
      return unreducedModel(full);
    case ReductionMethod::FullLumped:
      return sparseModel(withLumpedMass(full));
  }
  throw Error("body '" + full.name + "': unknown '" + deck::pathOf(rp, "Method") + "'");
}

FrequencyCheck frequencyCheck(const FullModel& full, const ReducedModel& model, const CraigBamptonOptions& o, int count,
                              const ReductionReport& report) {
  FrequencyCheck c;
  Stopwatch sw;
  count = std::min(count, full.numFree - 1);
  if (static_cast<int>(model.fullFrequencies.size()) >= count && !model.sparse()) {
    // Craig-Bampton and Guyan computed them through their own K_CC factor (CraigBamptonOptions::checkFrequencies).
    c.full.assign(model.fullFrequencies.begin(), model.fullFrequencies.begin() + count);
    c.throughReduction = true;
    c.seconds = report.checkSeconds;
    return c;
  }
  if (model.kind == ReductionKind::MasslessBoundary) {
    // Its modes are the full model's lowest (retained nodes free), from the reduction's own solve;
    // its reduced model has no other frequency (the boundary carries no mass) to compare.
    const auto& f = model.modeFrequencies;
    c.full.assign(f.begin(), f.begin() + std::min<std::ptrdiff_t>(count, static_cast<std::ptrdiff_t>(f.size())));
    c.reused = true;
    return c;
  }
  if (model.sparse())  // the lumped model's own frequencies, against the consistent model's
    c.lumped = fullModelFrequencies(withLumpedMass(full), count, o.solver, o.iterativeTolerance);
  // The reduced model's frequencies (Rayleigh-Ritz upper bounds; a lumped model's, close) place the
  // shift just below the lowest modes: a shift far below them costs minutes on a fine mesh.
  c.full = fullModelFrequencies(full, count, o.solver, o.iterativeTolerance,
                                model.sparse() ? c.lumped : reducedFrequencies(model));
  c.seconds = sw.seconds();
  return c;
}

}  // namespace epaphe
