#pragma once
// A volume mesh as Epaphe needs it: node coordinates, 8-node hexahedra, named node sets.
#include <array>
#include <map>
#include <string>
#include <vector>

namespace epaphe {

struct Mesh {
  std::vector<std::array<double, 3>> coords;
  std::vector<std::array<int, 8>> hexes;              // node indices, VTK/Abaqus C3D8 order
  std::map<std::string, std::vector<int>> nodeSets;   // sorted node indices

  int numNodes() const { return static_cast<int>(coords.size()); }
  /// The named node set, or the union of several named "x-, x+, y-" (sorted, no repeats); an
  /// unknown name raises an error listing the known ones. `context` says who asked.
  std::vector<int> nodeSet(const std::string& spec, const std::string& context) const;
};

/// Resolves "name" or "name1, name2, ..." against `sets` (see Mesh::nodeSet).
std::vector<int> resolveNodeSets(const std::map<std::string, std::vector<int>>& sets, const std::string& spec,
                                 const std::string& context);

/// Structured box [x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz] with nx x ny x nz hexahedra.
/// Node sets: "all", and the six faces "x-", "x+", "y-", "y+", "z-", "z+".
Mesh makeBoxMesh(const std::array<double, 3>& origin, const std::array<double, 3>& lengths,
                 const std::array<int, 3>& elements);

}  // namespace epaphe
