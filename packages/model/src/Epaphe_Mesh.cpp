#include "Epaphe_Mesh.hpp"

#include "Epaphe_Error.hpp"

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

}  // namespace epaphe
