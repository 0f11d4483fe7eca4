#include "Epaphe_ThermalModel.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_SolidElements.hpp"

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

namespace epaphe {
namespace {

/// Calls fn(corners, x) for every face of a hexahedron whose four corners are marked in `in`.
void forEachFace(const Mesh& mesh, const std::vector<char>& in,
                 const std::function<void(const int (&)[4], const double (&)[4][3])>& fn) {
  int corners[4];
  double x[4][3];
  for (const auto& hex : mesh.hexes)
    for (const auto& face : kHexFaces) {
      bool all = true;
      for (int a = 0; a < 4 && all; ++a) all = in[hex[face[a]]] != 0;
      if (!all) continue;
      for (int a = 0; a < 4; ++a) {
        corners[a] = hex[face[a]];
        for (int j = 0; j < 3; ++j) x[a][j] = mesh.coords[corners[a]][j];
      }
      fn(corners, x);
    }
}

/// Calls fn(corners, count, x) for every boundary face (a face of one element only) of the linear
/// elements on the corners of an imported mesh's solids whose corners (3 or 4) are all marked in `in`.
void forEachSolidFace(const Mesh& mesh, const std::vector<char>& in,
                      const std::function<void(const int*, int, const double (&)[4][3])>& fn) {
  std::map<std::array<int, 4>, int> count;  // sorted corners (a triangle's last -1) -> elements holding the face
  auto key = [](std::array<int, 4> k) {
    std::sort(k.begin(), k.end());
    return k;
  };
  auto faceNodes = [](const std::vector<int>& e, const std::array<int, 4>& f) {
    return std::array<int, 4>{e[f[0]], e[f[1]], e[f[2]], f[3] < 0 ? -1 : e[f[3]]};
  };
  for (const auto& e : mesh.solids)
    for (const auto& f : solidFaces(solidCorners(static_cast<int>(e.size())))) ++count[key(faceNodes(e, f))];
  int corners[4];
  double x[4][3];
  for (const auto& e : mesh.solids)
    for (const auto& f : solidFaces(solidCorners(static_cast<int>(e.size())))) {
      const std::array<int, 4> nodes = faceNodes(e, f);
      const int n = nodes[3] < 0 ? 3 : 4;
      bool all = true;
      for (int a = 0; a < n && all; ++a) all = in[nodes[a]] != 0;
      if (!all || count[key(nodes)] != 1) continue;
      for (int a = 0; a < n; ++a) {
        corners[a] = nodes[a];
        for (int j = 0; j < 3; ++j) x[a][j] = mesh.coords[corners[a]][j];
      }
      fn(corners, n, x);
    }
}

/// The convection matrix (h = 1) and nodal areas of a face of n = 3 or 4 corners.
void faceMatrix(int n, const double (&x)[4][3], double* He, double* area) {
  if (n == 4) return quad4Face(x, He, area);
  double t[3][3];
  for (int a = 0; a < 3; ++a)
    for (int j = 0; j < 3; ++j) t[a][j] = x[a][j];
  tri3Face(t, He, area);
}

std::vector<char> marked(const Mesh& mesh, const std::vector<int>& nodes, const std::string& context) {
  std::vector<char> in(static_cast<std::size_t>(mesh.numNodes()), 0);
  for (int n : nodes) {
    EPAPHE_REQUIRE(n >= 0 && n < mesh.numNodes(),
                   context << ": node " << n << " is not in the mesh (0.." << mesh.numNodes() - 1 << ")");
    in[n] = 1;
  }
  return in;
}

/// Inserts the rows this rank owns of an element matrix Ae (n x n, row-major) on the nodes `nodes`.
void insert(const ThermalFullModel& m, const int* nodes, int n, const double* Ae, CrsMatrix& A) {
  const auto& rows = *A.getRowMap();
  GO cols[8];
  double values[8];
  for (int a = 0; a < n; ++a) {
    const int row = m.eq[nodes[a]];
    if (row < 0 || !rows.isNodeGlobalElement(row)) continue;
    int count = 0;
    for (int b = 0; b < n; ++b)
      if (const int col = m.eq[nodes[b]]; col >= 0) {
        cols[count] = col;
        values[count++] = Ae[a * n + b];
      }
    A.insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols, count),
                         Teuchos::ArrayView<const double>(values, count));
  }
}

/// The free nodes and mid-side nodes of an imported mesh's solids (eq. 75): a corner of an element not
/// held at T_ref is free; a mid-side node that is no element's corner follows its edge's corners.
void numberSolidNodes(ThermalFullModel& m, const std::vector<char>& fixed) {
  const int nn = m.numNodes();
  std::vector<char> corner(static_cast<std::size_t>(nn), 0);
  for (const auto& e : m.mesh.solids)
    for (int a = 0, c = solidCorners(static_cast<int>(e.size())); a < c; ++a) corner[e[a]] = 1;
  m.midside.assign(static_cast<std::size_t>(nn), {-1, -1});
  for (const auto& e : m.mesh.solids) {
    const int c = solidCorners(static_cast<int>(e.size()));
    const auto& edges = solidEdges(static_cast<int>(e.size()));
    for (std::size_t k = 0; k < edges.size(); ++k)
      if (const int n = e[c + k]; !corner[n]) m.midside[n] = {e[edges[k][0]], e[edges[k][1]]};
  }
  for (int n = 0; n < nn; ++n)
    if (corner[n] && !fixed[n]) m.eq[n] = m.numFree++;
}

}  // namespace

std::vector<std::pair<int, double>> ThermalFullModel::weights(int node) const {
  std::vector<std::pair<int, double>> w;
  if (eq[node] >= 0) {
    w.emplace_back(eq[node], 1.0);
  } else if (!midside.empty() && midside[node][0] >= 0) {
    for (int c : midside[node])
      if (eq[c] >= 0) w.emplace_back(eq[c], 0.5);
  }
  return w;
}

ThermalFullModel assembleThermalModel(const std::string& name, Mesh mesh, const ThermalDefinition& definition,
                                      const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const std::string context = "body '" + name + "' thermal model";
  checkThermalMaterial(definition.material, context.c_str());
  ThermalFullModel m;
  m.name = name;
  m.mesh = std::move(mesh);
  m.definition = definition;
  const bool solids = !m.mesh.solids.empty();
  const std::vector<char> fixed = marked(m.mesh, definition.fixedNodes, context + ", fixed temperature");
  m.eq.assign(static_cast<std::size_t>(m.numNodes()), -1);
  if (solids)
    numberSolidNodes(m, fixed);
  else
    for (int n = 0; n < m.numNodes(); ++n)
      if (!fixed[n]) m.eq[n] = m.numFree++;
  EPAPHE_REQUIRE(m.numFree > 0, context << ": every node is held at the reference temperature, nothing can heat");

  // a row's entries are bounded by the corners of the elements around its node: 27 on a hexahedral
  // mesh, more around a node of many tetrahedra
  std::size_t width = 27;
  if (solids) {
    std::vector<std::size_t> around(static_cast<std::size_t>(m.numNodes()), 0);
    for (const auto& e : m.mesh.solids)
      for (int a = 0, c = solidCorners(static_cast<int>(e.size())); a < c; ++a) around[e[a]] += c;
    width = std::max<std::size_t>(1, *std::max_element(around.begin(), around.end()));
  }
  auto map = Teuchos::rcp(new Map(m.numFree, 0, comm));
  m.K = Teuchos::rcp(new CrsMatrix(map, width));
  m.C = Teuchos::rcp(new CrsMatrix(map, width));
  m.load = Teuchos::rcp(new MultiVector(map, 1));
  auto mine = [&](const int* nodes, int n) {
    for (int a = 0; a < n; ++a)
      if (m.eq[nodes[a]] >= 0 && map->isNodeGlobalElement(m.eq[nodes[a]])) return true;
    return false;
  };
  if (solids) {
    // the linear element on each solid's corners (eq. 75): K_e = k int grad N^T grad N, C lumped
    const double k = definition.material.conductivity,
                 rc = definition.material.density * definition.material.specificHeat;
    double Ke[64], Cd[8], Ce[64], x[8][3];
    for (const auto& e : m.mesh.solids) {
      const int c = solidCorners(static_cast<int>(e.size()));
      if (!mine(e.data(), c)) continue;
      for (int a = 0; a < c; ++a)
        for (int j = 0; j < 3; ++j) x[a][j] = m.mesh.coords[e[a]][j];
      linearSolidHeat(c, x, Ke, Cd);
      for (int i = 0; i < c * c; ++i) {
        Ke[i] *= k;
        Ce[i] = 0;
      }
      for (int a = 0; a < c; ++a) Ce[a * c + a] = rc * Cd[a];
      insert(m, e.data(), c, Ke, *m.K);
      insert(m, e.data(), c, Ce, *m.C);
    }
  } else {
    double Ke[64], Ce[64], x[8][3];
    for (const auto& hex : m.mesh.hexes) {
      if (!mine(hex.data(), 8)) continue;
      for (int a = 0; a < 8; ++a)
        for (int j = 0; j < 3; ++j) x[a][j] = m.mesh.coords[hex[a]][j];
      hex8Heat(x, definition.material, Ke, Ce);
      insert(m, hex.data(), 8, Ke, *m.K);
      insert(m, hex.data(), 8, Ce, *m.C);
    }
  }
  auto g = m.load->getLocalViewHost(Tpetra::Access::ReadWrite);
  for (std::size_t c = 0; c < definition.convection.size(); ++c) {
    const Convection& conv = definition.convection[c];
    const std::string where = context + ", convection " + std::to_string(c + 1);
    EPAPHE_REQUIRE(conv.coefficient >= 0 && std::isfinite(conv.coefficient),
                   where << ": coefficient = " << conv.coefficient << " W/(m^2 K); it must be a finite value >= 0");
    EPAPHE_REQUIRE(std::isfinite(conv.temperature), where << ": the ambient temperature must be finite");
    int faces = 0;
    auto add = [&](const int* nodes, int n, const double(&xf)[4][3]) {
      double He[16], area[4];
      faceMatrix(n, xf, He, area);
      for (int i = 0; i < n * n; ++i) He[i] *= conv.coefficient;
      insert(m, nodes, n, He, *m.K);
      for (int a = 0; a < n; ++a)
        if (const int row = m.eq[nodes[a]]; row >= 0 && map->isNodeGlobalElement(row))
          g(map->getLocalElement(row), 0) +=
              conv.coefficient * (conv.temperature - definition.referenceTemperature) * area[a];
      ++faces;
    };
    if (solids)
      forEachSolidFace(m.mesh, marked(m.mesh, conv.nodes, where), add);
    else
      forEachFace(m.mesh, marked(m.mesh, conv.nodes, where),
                  [&](const int(&nodes)[4], const double(&xf)[4][3]) { add(nodes, 4, xf); });
    EPAPHE_REQUIRE(faces > 0, where << ": its nodes hold no " << (solids ? "boundary " : "")
                                    << "face of an element (every corner of a face is needed); name a face's "
                                       "node set");
  }
  m.K->fillComplete();
  m.C->fillComplete();
  return m;
}

std::vector<double> faceAreas(const Mesh& mesh, const std::vector<int>& nodes) {
  std::vector<double> byNode(static_cast<std::size_t>(mesh.numNodes()), 0.0);
  auto add = [&](const int* corners, int n, const double(&x)[4][3]) {
    double He[16], area[4];
    faceMatrix(n, x, He, area);
    for (int a = 0; a < n; ++a) byNode[corners[a]] += area[a];
  };
  if (mesh.solids.empty())
    forEachFace(mesh, marked(mesh, nodes, "face areas"),
                [&](const int(&corners)[4], const double(&x)[4][3]) { add(corners, 4, x); });
  else
    forEachSolidFace(mesh, marked(mesh, nodes, "face areas"), add);
  std::vector<double> out;
  out.reserve(nodes.size());
  for (int n : nodes) out.push_back(byNode[n]);
  return out;
}

}  // namespace epaphe
