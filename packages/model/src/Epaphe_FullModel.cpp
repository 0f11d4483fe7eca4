#include "Epaphe_FullModel.hpp"

#include "Epaphe_Error.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>

namespace epaphe {

FullModel assembleHexModel(const std::string& name, Mesh mesh, const Material& mat,
                           const std::vector<int>& clamped, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  checkMaterial(mat, ("body '" + name + "'").c_str());
  FullModel m;
  m.name = name;
  m.mesh = std::move(mesh);
  const int nn = m.mesh.numNodes();
  std::vector<char> fixed(static_cast<std::size_t>(nn), 0);
  for (int n : clamped) {
    EPAPHE_REQUIRE(n >= 0 && n < nn, "body '" << name << "': clamped node " << n << " is not in the mesh (0.." << nn - 1 << ")");
    fixed[n] = 1;
  }
  m.eq.assign(3 * static_cast<std::size_t>(nn), -1);
  for (int n = 0; n < nn; ++n)
    if (!fixed[n])
      for (int d = 0; d < 3; ++d) m.eq[3 * n + d] = m.numFree++;
  EPAPHE_REQUIRE(m.numFree > 0, "body '" << name << "': every node is clamped, nothing can move");

  auto map = Teuchos::rcp(new Map(m.numFree, 0, comm));
  // 27 neighbour nodes x 3 directions bound the row length of a hexahedral mesh.
  m.K = Teuchos::rcp(new CrsMatrix(map, 81));
  m.M = Teuchos::rcp(new CrsMatrix(map, 81));
  double x[8][3], Ke[24 * 24], Me[24 * 24];
  std::vector<GO> cols;
  std::vector<double> kv, mv;
  for (const auto& hex : m.mesh.hexes) {
    bool mine = false;
    for (int a = 0; a < 8 && !mine; ++a)
      for (int d = 0; d < 3; ++d) {
        const int g = m.eq[3 * hex[a] + d];
        if (g >= 0 && map->isNodeGlobalElement(g)) { mine = true; break; }
      }
    if (!mine) continue;
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) x[a][d] = m.mesh.coords[hex[a]][d];
    hex8StiffnessMass(x, mat, Ke, Me);
    for (int a = 0; a < 24; ++a) {
      const int row = m.eq[3 * hex[a / 3] + a % 3];
      if (row < 0 || !map->isNodeGlobalElement(row)) continue;
      cols.clear(); kv.clear(); mv.clear();
      for (int b = 0; b < 24; ++b) {
        const int col = m.eq[3 * hex[b / 3] + b % 3];
        if (col < 0) continue;
        cols.push_back(col);
        kv.push_back(Ke[a * 24 + b]);
        mv.push_back(Me[a * 24 + b]);
      }
      m.K->insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(kv));
      m.M->insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(mv));
    }
  }
  m.K->fillComplete();
  m.M->fillComplete();
  return m;
}

std::vector<double> gatherDense(const CrsMatrix& A) {
  const int n = static_cast<int>(A.getGlobalNumRows());
  std::vector<double> local(static_cast<std::size_t>(n) * n, 0.0), global(local.size(), 0.0);
  const auto rowMap = A.getRowMap();
  const auto colMap = A.getColMap();
  typename CrsMatrix::local_inds_host_view_type idx;
  typename CrsMatrix::values_host_view_type val;
  for (LO lr = 0; lr < static_cast<LO>(A.getNodeNumRows()); ++lr) {
    const GO gr = rowMap->getGlobalElement(lr);
    A.getLocalRowView(lr, idx, val);
    for (std::size_t k = 0; k < idx.extent(0); ++k)
      local[static_cast<std::size_t>(colMap->getGlobalElement(idx(k))) * n + gr] += val(k);
  }
  Teuchos::reduceAll(*A.getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  return global;
}

double rigidMass(const FullModel& model, int direction) {
  MultiVector t(model.M->getDomainMap(), 1), Mt(model.M->getRangeMap(), 1);
  {
    auto th = t.getLocalViewHost(Tpetra::Access::OverwriteAll);
    const auto map = t.getMap();
    for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) th(l, 0) = 0.0;
    for (int n = 0; n < model.numNodes(); ++n) {
      const int g = model.eq[3 * n + direction];
      if (g >= 0 && map->isNodeGlobalElement(g)) th(map->getLocalElement(g), 0) = 1.0;
    }
  }
  model.M->apply(t, Mt);
  Teuchos::Array<double> dot(1);
  t.dot(Mt, dot());
  return dot[0];
}

}  // namespace epaphe
