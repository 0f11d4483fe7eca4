// Nodes, node sets and DOF maps of the imported files (Epaphe_ImportDetails.hpp).
#include "Epaphe_ImportDetails.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <future>
#include <limits>
#include <numeric>
#include <system_error>

namespace epaphe {
namespace Details {

std::unordered_map<int, int> nodeIndex(const Mesh& mesh) {
  std::unordered_map<int, int> index;
  for (int n = 0; n < mesh.numNodes(); ++n) index.emplace(mesh.nodeId(n), n);
  return index;
}

Mesh readNodes(const std::string& path) {
  TextLines in(path, "node coordinates ('id x y z' per line)");
  Mesh mesh;
  std::unordered_map<int, int> seen;
  std::string line;
  while (in.next(line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const auto f = splitFields(t);
    long long id = 0;
    double x[3] = {0, 0, 0};
    bool ok = f.size() == 4 && parseInt(f[0], id) && id >= 0;
    for (int c = 0; ok && c < 3; ++c) ok = parseDouble(f[1 + c], x[c]) && std::isfinite(x[c]);
    EPAPHE_REQUIRE(ok, in.where() << ": expected 'id x y z' (finite coordinates), read '" << t << "'");
    auto [it, fresh] = seen.emplace(static_cast<int>(id), in.line());
    EPAPHE_REQUIRE(fresh, in.where() << ": node " << id << " is defined twice (also line " << it->second
                                     << "); node ids must be unique");
    mesh.nodeIds.push_back(static_cast<int>(id));
    mesh.coords.push_back({x[0], x[1], x[2]});
  }
  EPAPHE_REQUIRE(!mesh.coords.empty(), path << ": no node; the file must list 'id x y z' lines");
  auto& all = mesh.nodeSets["all"];
  for (int n = 0; n < mesh.numNodes(); ++n) all.push_back(n);
  return mesh;
}

void readNodeSets(const std::string& path, Mesh& mesh) {
  TextLines in(path, "node sets ('name id id ...' per line)");
  const auto index = nodeIndex(mesh);
  std::string line;
  while (in.next(line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const auto f = splitFields(t);
    auto& set = mesh.nodeSets[f[0]];
    for (std::size_t k = 1; k < f.size(); ++k) {
      long long id = 0;
      EPAPHE_REQUIRE(parseInt(f[k], id), in.where()
                                             << ": node set '" << f[0] << "': '" << f[k] << "' is not a node id");
      auto it = index.find(static_cast<int>(id));
      EPAPHE_REQUIRE(it != index.end(), in.where() << ": node set '" << f[0] << "' names node " << id
                                                   << ", which the node coordinates do not define");
      set.push_back(it->second);
    }
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
  }
}

RawModel readListedModel(const ListedModelFiles& files, const std::string& name, Storage storage,
                         std::vector<LagrangeRow>* lagrangeRows) {
  RawModel raw;
  raw.name = name;
  raw.mesh = readNodes(files.nodes);
  if (!files.nodeSets.empty()) readNodeSets(files.nodeSets, raw.mesh);
  readDofMap(files.dofs, raw, lagrangeRows != nullptr, lagrangeRows);
  const int n = static_cast<int>(raw.rowDof.size());
  readSparsePair({files.stiffness, "stiffness matrix", storage, n, files.dofs},
                 {files.mass, "mass matrix", storage, n, files.dofs}, raw.K, raw.M);
  return raw;
}

void readDofMap(const std::string& path, RawModel& raw, bool lagrange, std::vector<LagrangeRow>* lagrangeRows) {
  TextLines in(path, "DOF map ('node direction' per matrix row)");
  raw.dofPath = path;
  const auto index = nodeIndex(raw.mesh);
  std::string line;
  auto nodeNumber = [](std::string s, long long& id) {
    if (!s.empty() && (s[0] == 'N' || s[0] == 'n')) s = s.substr(1);
    return parseInt(s, id);
  };
  const char* grammar = lagrange ? "'node direction' (direction 1..3, x..z or DX..DZ) or a Lagrange row ('LAGR', "
                                   "'node LAGR:DX', 'node -1')"
                                 : "'node direction' (direction 1..3, x..z or DX..DZ)";
  while (in.next(line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t[0] == '%') continue;
    const auto f = splitFields(t);
    const int row = static_cast<int>(raw.rowDof.size());
    long long node = 0, comp = 0;
    const std::string c = f.size() == 2 ? upper(f[1]) : f.size() == 1 ? upper(f[0]) : std::string();
    const bool numeric = f.size() == 2 && parseInt(f[1], comp);
    const bool isLagrange = c.rfind("LAGR", 0) == 0 || (numeric && comp <= 0);
    if (isLagrange) {
      EPAPHE_REQUIRE(lagrange, in.where()
                                   << ": '" << t << "' is a Lagrange multiplier row; this format takes physical DOFs "
                                   << "only (use the code_aster importer, which drops them)");
      int dof = -1;
      if (f.size() == 2 && nodeNumber(f[0], node) && node > 0) {
        auto it = index.find(static_cast<int>(node));
        EPAPHE_REQUIRE(it != index.end(), in.where()
                                              << ": Lagrange row of node " << node << ", which is not in the mesh");
        const auto colon = c.find_first_of(":_");
        const int d = numeric                      ? static_cast<int>(-comp) - 1
                      : colon == std::string::npos ? -1
                                                   : parseDirection(c.substr(colon + 1));
        if (d >= 0 && d < 3) dof = 3 * it->second + d;
      }
      raw.rowDof.push_back(-1);
      raw.rowLine.push_back(in.line());
      lagrangeRows->push_back({row, in.line(), dof});
      continue;
    }
    const int d = f.size() == 2 ? parseDirection(f[1]) : -1;
    EPAPHE_REQUIRE(f.size() == 2 && nodeNumber(f[0], node) && d >= 0,
                   in.where() << ": expected " << grammar << ", read '" << t << "'");
    auto it = index.find(static_cast<int>(node));
    EPAPHE_REQUIRE(it != index.end(),
                   in.where() << ": node " << node << " is not in the mesh (" << raw.mesh.numNodes()
                              << " nodes read); the DOF map and the node coordinates must be of the same model");
    raw.rowDof.push_back(3 * it->second + d);
    raw.rowLine.push_back(in.line());
  }
}

}  // namespace Details
}  // namespace epaphe
