#include "Epaphe_ReducedModelCache.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_Version.hpp"

#include <cstdio>
#include <unistd.h>
#include <fstream>
#include <functional>
#include <memory>

namespace epaphe {

// Bump when the cache layout changes: older files then miss and are rebuilt.
constexpr const char* cacheFormat = "5 (Galerkin static state at speed)";

std::string contentKey(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text + "|epaphe " + version + "|cache format " + cacheFormat) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

namespace {

/// Writes `path` through a temporary file renamed at the end, so that a reader never sees half a file.
void writeAtomically(const std::string& path, const std::function<void(io::Hdf5File&)>& write) {
  // a file of this process's own: runs of a speed sweep on several ranks may write the same cache at
  // once, and the rename leaves one whole file whichever comes last
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    io::Hdf5File f(tmp, io::Hdf5File::Mode::Create);
    write(f);
    f.close();
  }
  EPAPHE_REQUIRE(std::rename(tmp.c_str(), path.c_str()) == 0, "cannot move the reduced-model cache "
                                                                  << tmp << " to " << path
                                                                  << ": check the directory's permissions");
}

void writeReducedModel(io::Hdf5File& f, const ReducedModel& r, const std::string& key) {
  {
    const auto n = static_cast<std::uint64_t>(r.size);
    const auto nn = static_cast<std::uint64_t>(r.numNodes());
    f.setAttribute("/", "key", key);
    f.setAttribute("/", "name", r.name);
    f.setAttribute("/", "method", r.method());
    f.setAttribute("/", "size", static_cast<long long>(r.size));
    f.setAttribute("/", "modes", static_cast<long long>(r.numModes));
    f.writeDoubles("/K", {n, n}, r.K.data());
    f.writeDoubles("/M", {n, n}, r.M.data());
    f.writeDoubles("/recovery", {3 * nn, n}, r.recovery.data());
    f.writeDoubles("/coordinates", {nn, 3}, r.coords.empty() ? nullptr : r.coords[0].data());
    f.writeInts("/nodeDof", std::vector<long long>(r.nodeDof.begin(), r.nodeDof.end()));
    std::vector<long long> hex;
    for (const auto& h : r.hexes) hex.insert(hex.end(), h.begin(), h.end());
    f.writeInts("/hexahedra", {static_cast<std::uint64_t>(r.hexes.size()), 8}, hex.data());
    f.writeInts("/retainedNodes", std::vector<long long>(r.retainedNodes.begin(), r.retainedNodes.end()));
    f.writeDoubles("/modeFrequencies", r.modeFrequencies);
    f.writeDoubles("/fullFrequencies", r.fullFrequencies);
    f.writeDoubles("/speed", std::vector<double>{r.speed});
    f.writeDoubles("/staticDisplacement", r.staticDisplacement);
    if (!r.coriolis.empty()) f.writeDoubles("/coriolis", {n, n}, r.coriolis.data());
    f.writeDoubles("/boundaryModes", r.boundaryModes);
    f.writeDoubles("/residualFlexibility", r.residualFlexibility);
    f.writeDoubles("/modalTranslation", r.modalTranslation);
    f.writeDoubles("/translationMass", std::vector<double>(r.translationMass.begin(), r.translationMass.end()));
    std::string names;
    for (const auto& [name, nodes] : r.nodeSets) {
      f.writeInts("/nodeSets/" + name, std::vector<long long>(nodes.begin(), nodes.end()));
      names += name + "\n";
    }
    f.setAttribute("/", "nodeSetNames", names);
    std::string grids;
    for (const auto& [name, g] : r.nodeGrids) {
      f.writeInts("/nodeGrids/" + name, {static_cast<std::uint64_t>(g.nu), static_cast<std::uint64_t>(g.nv)},
                  std::vector<long long>(g.nodes.begin(), g.nodes.end()).data());
      grids += name + "\n";
    }
    f.setAttribute("/", "nodeGridNames", grids);
  }
}

bool readReducedModel(const io::Hdf5File& f, const std::string& path, ReducedModel& r) {
  auto toInts = [](const std::vector<long long>& v) { return std::vector<int>(v.begin(), v.end()); };
  r.name = f.stringAttribute("/", "name");
  r.kind = reductionKindNamed(f.stringAttribute("/", "method"));
  r.size = static_cast<int>(f.intAttribute("/", "size"));
  r.numModes = static_cast<int>(f.intAttribute("/", "modes"));
  r.K = f.readDoubles("/K");
  r.M = f.readDoubles("/M");
  r.recovery = f.readDoubles("/recovery");
  const auto xyz = f.readDoubles("/coordinates");
  r.coords.resize(xyz.size() / 3);
  for (std::size_t i = 0; i < r.coords.size(); ++i) r.coords[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  r.nodeDof = toInts(f.readInts("/nodeDof"));
  const auto hex = f.readInts("/hexahedra");
  r.hexes.resize(hex.size() / 8);
  for (std::size_t e = 0; e < r.hexes.size(); ++e)
    for (int a = 0; a < 8; ++a) r.hexes[e][a] = static_cast<int>(hex[8 * e + a]);
  r.retainedNodes = toInts(f.readInts("/retainedNodes"));
  r.modeFrequencies = f.readDoubles("/modeFrequencies");
  r.fullFrequencies = f.readDoubles("/fullFrequencies");
  const auto speed = f.readDoubles("/speed");
  r.speed = speed.empty() ? 0.0 : speed[0];
  r.staticDisplacement = f.readDoubles("/staticDisplacement");
  r.coriolis = f.exists("/coriolis") ? f.readDoubles("/coriolis") : std::vector<double>();
  r.boundaryModes.clear();  // massless boundary only (files written before it have neither)
  r.residualFlexibility.clear();
  r.modalTranslation.clear();
  r.translationMass = {0, 0, 0};
  if (r.massless()) {
    if (!f.exists("/modalTranslation")) return false;  // written before free bodies: reduce again
    r.boundaryModes = f.readDoubles("/boundaryModes");
    r.residualFlexibility = f.readDoubles("/residualFlexibility");
    r.modalTranslation = f.readDoubles("/modalTranslation");
    const auto tm = f.readDoubles("/translationMass");
    EPAPHE_REQUIRE(tm.size() == 3, "reduced-model cache " << path << ": /translationMass has " << tm.size()
                                                          << " entries, not 3; delete the file to reduce again");
    for (int d = 0; d < 3; ++d) r.translationMass[d] = tm[d];
  }
  r.nodeSets.clear();
  const std::string names = f.stringAttribute("/", "nodeSetNames");
  for (std::size_t b = 0, e; (e = names.find('\n', b)) != std::string::npos; b = e + 1) {
    const std::string name = names.substr(b, e - b);
    r.nodeSets[name] = toInts(f.readInts("/nodeSets/" + name));
  }
  r.nodeGrids.clear();
  const std::string grids = f.stringAttribute("/", "nodeGridNames");
  for (std::size_t b = 0, e; (e = grids.find('\n', b)) != std::string::npos; b = e + 1) {
    const std::string name = grids.substr(b, e - b);
    std::vector<std::uint64_t> dims;
    const auto nodes = toInts(f.readInts("/nodeGrids/" + name, &dims));
    EPAPHE_REQUIRE(dims.size() == 2, "reduced-model cache " << path << ": node grid '" << name
                                                            << "' is not 2-D; "
                                                               "delete the file to rebuild it");
    r.nodeGrids[name] = NodeGrid{static_cast<int>(dims[0]), static_cast<int>(dims[1]), nodes};
  }
  return true;
}

/// The file's key matches: false when it is absent or holds another.
bool openWithKey(const std::string& path, const std::string& key, std::unique_ptr<io::Hdf5File>& f) {
  if (!std::ifstream(path)) return false;
  f = std::make_unique<io::Hdf5File>(path, io::Hdf5File::Mode::ReadOnly);
  return f->hasAttribute("/", "key") && f->stringAttribute("/", "key") == key;
}

}  // namespace

void saveReducedModel(const ReducedModel& r, const std::string& path, const std::string& key) {
  writeAtomically(path, [&](io::Hdf5File& f) { writeReducedModel(f, r, key); });
}

bool loadReducedModel(const std::string& path, const std::string& key, ReducedModel& r) {
  std::unique_ptr<io::Hdf5File> f;
  return openWithKey(path, key, f) && readReducedModel(*f, path, r);
}

// The parametric model: its common-basis model as a reduced model, and under /parametric the sample
// speeds, the boundary size, the stiffness coefficients C_1.. and the static state's g_0.. (as many as its polynomial's
// degree + 1)
void saveParametricModel(const SpeedParametricModel& p, const std::string& path, const std::string& key) {
  writeAtomically(path, [&](io::Hdf5File& f) {
    writeReducedModel(f, p.base, key);
    const auto N = static_cast<std::uint64_t>(p.base.size);
    f.writeDoubles("/parametric/speeds", p.speeds);
    f.setAttribute("/", "boundarySize", static_cast<long long>(p.boundarySize));
    f.setAttribute("/", "staticState", static_cast<long long>(p.staticState));
    for (std::size_t k = 0; k < p.stiffness.size(); ++k)
      f.writeDoubles("/parametric/stiffness" + std::to_string(k + 1), {N, N}, p.stiffness[k].data());
    for (std::size_t k = 0; k < p.growth.size(); ++k)
      f.writeDoubles("/parametric/growth" + std::to_string(k), p.growth[k]);
  });
}

bool loadParametricModel(const std::string& path, const std::string& key, SpeedParametricModel& p) {
  std::unique_ptr<io::Hdf5File> f;
  if (!openWithKey(path, key, f) || !readReducedModel(*f, path, p.base) || !f->exists("/parametric/speeds"))
    return false;
  p.speeds = f->readDoubles("/parametric/speeds");
  p.boundarySize = static_cast<int>(f->intAttribute("/", "boundarySize"));
  p.staticState = static_cast<StaticState>(f->intAttribute("/", "staticState"));
  p.stiffness.clear();
  p.growth.clear();
  for (std::size_t k = 1; k < p.speeds.size(); ++k)
    p.stiffness.push_back(f->readDoubles("/parametric/stiffness" + std::to_string(k)));
  for (std::size_t k = 0; f->exists("/parametric/growth" + std::to_string(k)); ++k)
    p.growth.push_back(f->readDoubles("/parametric/growth" + std::to_string(k)));
  return true;
}

}  // namespace epaphe
