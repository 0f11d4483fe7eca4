#include "Epaphe_Mesh.hpp"

#include "Epaphe_Error.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace epaphe {

std::vector<int> resolveNodeSets(const std::map<std::string, std::vector<int>>& sets, const std::string& spec,
                                 const std::string& context) {
  std::set<int> nodes;
  std::stringstream ss(spec);
  std::string name;
  while (std::getline(ss, name, ',')) {
    const auto b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t");
    name = b == std::string::npos ? "" : name.substr(b, e - b + 1);
    auto it = sets.find(name);
    if (it == sets.end()) {
      ErrorBuilder eb;
      eb << context << ": unknown node set '" << name << "'; the model has:";
      for (const auto& [n, s] : sets) eb << " '" << n << "' (" << s.size() << " nodes)";
      eb.raise();
    }
    nodes.insert(it->second.begin(), it->second.end());
  }
  return std::vector<int>(nodes.begin(), nodes.end());
}

std::vector<int> Mesh::nodeSet(const std::string& spec, const std::string& context) const {
  return resolveNodeSets(nodeSets, spec, context);
}

Mesh makeBoxMesh(const std::array<double, 3>& origin, const std::array<double, 3>& lengths,
                 const std::array<int, 3>& elements) {
  for (int d = 0; d < 3; ++d) {
    EPAPHE_REQUIRE(lengths[d] > 0, "box mesh: length along " << "xyz"[d] << " is " << lengths[d] << ", it must be > 0");
    EPAPHE_REQUIRE(elements[d] >= 1, "box mesh: " << elements[d] << " elements along " << "xyz"[d] << ", at least 1 is needed");
  }
  const int nx = elements[0], ny = elements[1], nz = elements[2];
  const int px = nx + 1, py = ny + 1, pz = nz + 1;
  auto id = [&](int i, int j, int k) { return i + px * (j + py * k); };
  Mesh m;
  m.coords.resize(static_cast<std::size_t>(px) * py * pz);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i)
        m.coords[id(i, j, k)] = {origin[0] + lengths[0] * i / nx, origin[1] + lengths[1] * j / ny,
                                 origin[2] + lengths[2] * k / nz};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  auto& all = m.nodeSets["all"];
  for (int n = 0; n < m.numNodes(); ++n) all.push_back(n);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < py; ++j)
      for (int i = 0; i < px; ++i) {
        const int n = id(i, j, k);
        if (i == 0) m.nodeSets["x-"].push_back(n);
        if (i == nx) m.nodeSets["x+"].push_back(n);
        if (j == 0) m.nodeSets["y-"].push_back(n);
        if (j == ny) m.nodeSets["y+"].push_back(n);
        if (k == 0) m.nodeSets["z-"].push_back(n);
        if (k == nz) m.nodeSets["z+"].push_back(n);
      }
  return m;
}

Mesh makeRingSegmentMesh(const std::array<double, 3>& center, double innerRadius, double thickness,
                         const std::array<double, 2>& angles, const std::array<double, 2>& axial,
                         const std::array<int, 3>& elements) {
  EPAPHE_REQUIRE(innerRadius > 0 && thickness > 0, "ring segment mesh: inner radius " << innerRadius << " m and thickness "
                                                       << thickness << " m must both be > 0");
  EPAPHE_REQUIRE(angles[1] > angles[0] && angles[1] - angles[0] < 360.0,
                 "ring segment mesh: angles {" << angles[0] << ", " << angles[1]
                                               << "} degrees; give {first, last} with 0 < last - first < 360");
  EPAPHE_REQUIRE(axial[1] > axial[0], "ring segment mesh: axial range {" << axial[0] << ", " << axial[1]
                                                                      << "}; give {first, last} with last > first");
  for (int d = 0; d < 3; ++d)
    EPAPHE_REQUIRE(elements[d] >= 1, "ring segment mesh: " << elements[d] << " elements "
                                                           << (d == 0 ? "through the thickness" : d == 1 ? "along the arc" : "along the axis")
                                                           << ", at least 1 is needed");
  const int nr = elements[0], nt = elements[1], nz = elements[2];
  const int pr = nr + 1, pt = nt + 1, pz = nz + 1;
  // i radial, j angular, k axial: r x theta = z keeps every hexahedron right-handed.
  auto id = [&](int i, int j, int k) { return i + pr * (j + pt * k); };
  Mesh m;
  m.coords.resize(static_cast<std::size_t>(pr) * pt * pz);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < pt; ++j)
      for (int i = 0; i < pr; ++i) {
        const double r = innerRadius + thickness * i / nr;
        const double a = (angles[0] + (angles[1] - angles[0]) * j / nt) * M_PI / 180.0;
        m.coords[id(i, j, k)] = {center[0] + r * std::cos(a), center[1] + r * std::sin(a),
                                 center[2] + axial[0] + (axial[1] - axial[0]) * k / nz};
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < nt; ++j)
      for (int i = 0; i < nr; ++i)
        m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  auto& all = m.nodeSets["all"];
  for (int n = 0; n < m.numNodes(); ++n) all.push_back(n);
  for (int k = 0; k < pz; ++k)
    for (int j = 0; j < pt; ++j)
      for (int i = 0; i < pr; ++i) {
        const int n = id(i, j, k);
        if (i == 0) m.nodeSets["inner"].push_back(n);
        if (i == nr) m.nodeSets["outer"].push_back(n);
        if (j == 0) m.nodeSets["end-"].push_back(n);
        if (j == nt) m.nodeSets["end+"].push_back(n);
        if (k == 0) m.nodeSets["z-"].push_back(n);
        if (k == nz) m.nodeSets["z+"].push_back(n);
      }
  for (auto& [name, nodes] : m.nodeSets) std::sort(nodes.begin(), nodes.end());
  for (const auto& [name, i] : {std::pair<std::string, int>{"inner", 0}, {"outer", nr}}) {
    NodeGrid g{pt, pz, {}};
    for (int j = 0; j < pt; ++j)
      for (int k = 0; k < pz; ++k) g.nodes.push_back(id(i, j, k));
    m.nodeGrids[name] = g;
  }
  return m;
}

}  // namespace epaphe
