#include "Epaphe_ReductionShared.hpp"

#include "Epaphe_Error.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>

namespace epaphe {

/// A^T B as a dense column-major (colsA x colsB) array on every rank.
std::vector<double> transposeProduct(const MultiVector& A, const MultiVector& B) {
  const int m = static_cast<int>(A.getNumVectors()), n = static_cast<int>(B.getNumVectors());
  std::vector<double> out(static_cast<std::size_t>(m) * n, 0.0);
  if (m == 0 || n == 0) return out;
  auto local = Tpetra::createLocalMap<LO, GO>(m, A.getMap()->getComm());
  MultiVector C(local, n);
  C.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, A, B, 0.0);
  auto h = C.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) out[static_cast<std::size_t>(j) * m + i] = h(i, j);
  return out;
}

MultiVector basisOnFreeDofs(const FullModel& full, const std::vector<double>& recovery, int n,
                            const Teuchos::RCP<const Map>& map) {
  MultiVector V(map, static_cast<std::size_t>(n));
  auto v = V.getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (std::size_t i = 0; i < full.eq.size(); ++i) {
    const int g = full.eq[i];
    if (g < 0 || !map->isNodeGlobalElement(g)) continue;
    const LO l = map->getLocalElement(g);
    for (int j = 0; j < n; ++j) v(l, j) = recovery[i * n + j];
  }
  return V;
}

/// A dense nR x k array (column-major, replicated) as a multivector on a locally replicated map.
MultiVector replicated(const std::vector<double>& a, int rows, int cols,
                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  MultiVector m(Tpetra::createLocalMap<LO, GO>(rows, comm), static_cast<std::size_t>(cols));
  auto h = m.getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) h(i, j) = a[static_cast<std::size_t>(j) * rows + i];
  return m;
}

/// The rows of a distributed multivector X (rows numbered by the global free DOF g) that
/// `rowIndex[g] >= 0` selects, as a dense (numRows x cols, column-major) array on every rank.
std::vector<double> gatherRows(const MultiVector& X, const std::vector<int>& rowIndex, int numRows) {
  const int cols = static_cast<int>(X.getNumVectors());
  std::vector<double> local(static_cast<std::size_t>(numRows) * cols, 0.0), out(local.size(), 0.0);
  const auto map = X.getMap();
  auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
    const int r = rowIndex[map->getGlobalElement(l)];
    if (r < 0) continue;
    for (int j = 0; j < cols; ++j) local[static_cast<std::size_t>(j) * numRows + r] = x(l, j);
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), out.data());
  return out;
}

/// The reduced model's mesh data and its retained DOFs, numbered in the order (retained node,
/// direction) as q's first entries: `rIndex[g]` is free DOF g's index among them (-1: not retained),
/// `nR` their count.
ReducedModel retainedShell(const FullModel& full, const std::vector<int>& retained, ReductionKind kind,
                           std::vector<int>& rIndex, int& nR) {
  ReducedModel red;
  red.name = full.name;
  red.kind = kind;
  red.coords = full.mesh.coords;
  red.nodeSets = full.mesh.nodeSets;
  red.nodeGrids = full.mesh.nodeGrids;
  red.hexes = full.mesh.hexes;
  red.retainedNodes = retained;
  red.nodeDof.assign(full.eq.size(), -1);
  rIndex.assign(static_cast<std::size_t>(full.numFree), -1);
  nR = 0;
  for (int node : retained) {
    EPAPHE_REQUIRE(node >= 0 && node < full.numNodes(), "body '" << full.name << "': retained node " << node
                                                                 << " is not in the model (0.." << full.numNodes() - 1
                                                                 << ")");
    for (int d = 0; d < 3; ++d) {
      const int g = full.eq[3 * node + d];
      if (g < 0) continue;
      EPAPHE_REQUIRE(rIndex[g] < 0, "body '" << full.name << "': node " << node << " is retained twice");
      rIndex[g] = nR;
      red.nodeDof[3 * node + d] = nR;
      ++nR;
    }
  }
  EPAPHE_REQUIRE(nR > 0,
                 "body '" << full.name << "': no free DOF is retained; name a retained node set with free nodes");
  return red;
}

/// max_i K_ii / M_ii over every rank: the scale of a model's largest eigenvalue.
double largestDiagonalRatio(const CrsMatrix& K, const CrsMatrix& M) {
  Tpetra::Vector<double, LO, GO> dk(K.getRowMap()), dm(M.getRowMap());
  K.getLocalDiagCopy(dk);
  M.getLocalDiagCopy(dm);
  auto k = dk.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto m = dm.getLocalViewHost(Tpetra::Access::ReadOnly);
  double local = 0, ratio = 0;
  for (std::size_t i = 0; i < k.extent(0); ++i) local = std::max(local, k(i, 0) / m(i, 0));
  Teuchos::reduceAll(*K.getComm(), Teuchos::REDUCE_MAX, local, Teuchos::outArg(ratio));
  return ratio;
}

}  // namespace epaphe
