#include "Epaphe_FullModel.hpp"
#include "Epaphe_SameGraph.hpp"

#include "Epaphe_Error.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include <algorithm>
#include <limits>

namespace epaphe {

void forEachOwnedHex(const FullModel& m, const Map& rows,
                     const std::function<void(const std::array<int, 8>&, const double (&)[8][3])>& fn) {
  double x[8][3];
  for (const auto& hex : m.mesh.hexes) {
    bool mine = false;
    for (int a = 0; a < 8 && !mine; ++a)
      for (int d = 0; d < 3; ++d) {
        const int g = m.eq[3 * hex[a] + d];
        if (g >= 0 && rows.isNodeGlobalElement(g)) {
          mine = true;
          break;
        }
      }
    if (!mine) continue;
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) x[a][d] = m.mesh.coords[hex[a]][d];
    fn(hex, x);
  }
}

namespace {

/// The rows of a hexahedron's element matrix Ae (24 x 24, row-major) this rank owns, given to
/// put(row, columns, values, count) with their free DOFs' columns; false when put returns false.
template <class Put>
bool forElementRows(const FullModel& m, const std::array<int, 8>& hex, const double* Ae, const CrsMatrix& A, Put put) {
  const auto& rows = *A.getRowMap();
  GO cols[24];
  double values[24];
  for (int a = 0; a < 24; ++a) {
    const int row = m.eq[3 * hex[a / 3] + a % 3];
    if (row < 0 || !rows.isNodeGlobalElement(row)) continue;
    int n = 0;
    for (int b = 0; b < 24; ++b) {
      const int col = m.eq[3 * hex[b / 3] + b % 3];
      if (col < 0) continue;
      cols[n] = col;
      values[n++] = Ae[a * 24 + b];
    }
    if (!put(row, Teuchos::ArrayView<const GO>(cols, n), Teuchos::ArrayView<const double>(values, n))) return false;
  }
  return true;
}

}  // namespace

void insertElementMatrix(const FullModel& m, const std::array<int, 8>& hex, const double* Ae, CrsMatrix& A) {
  forElementRows(m, hex, Ae, A, [&](GO row, Teuchos::ArrayView<const GO> cols, Teuchos::ArrayView<const double> v) {
    A.insertGlobalValues(row, cols, v);
    return true;
  });
}

bool sumIntoElementMatrix(const FullModel& m, const std::array<int, 8>& hex, const double* Ae, CrsMatrix& A) {
  return forElementRows(m, hex, Ae, A,
                        [&](GO row, Teuchos::ArrayView<const GO> cols, Teuchos::ArrayView<const double> v) {
                          return A.sumIntoGlobalValues(row, cols, v) == static_cast<int>(cols.size());
                        });
}

FullModel assembleHexModel(const std::string& name, Mesh mesh, const Material& mat, const std::vector<int>& clamped,
                           const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  checkMaterial(mat, ("body '" + name + "'").c_str());
  FullModel m;
  m.name = name;
  m.mesh = std::move(mesh);
  m.material = mat;
  const int nn = m.mesh.numNodes();
  std::vector<char> fixed(static_cast<std::size_t>(nn), 0);
  for (int n : clamped) {
    EPAPHE_REQUIRE(n >= 0 && n < nn,
                   "body '" << name << "': clamped node " << n << " is not in the mesh (0.." << nn - 1 << ")");
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
  double Ke[24 * 24], Me[24 * 24];
  forEachOwnedHex(m, *map, [&](const std::array<int, 8>& hex, const double(&x)[8][3]) {
    hex8StiffnessMass(x, mat, Ke, Me);
    insertElementMatrix(m, hex, Ke, *m.K);
    insertElementMatrix(m, hex, Me, *m.M);
  });
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

MultiVector rigidTranslations(const FullModel& model) {
  MultiVector t(model.M->getDomainMap(), 3);  // zero-filled
  auto th = t.getLocalViewHost(Tpetra::Access::ReadWrite);
  const auto map = t.getMap();
  for (int n = 0; n < model.numNodes(); ++n)
    for (int d = 0; d < 3; ++d)
      if (const int g = model.eq[3 * n + d]; g >= 0 && map->isNodeGlobalElement(g))
        th(map->getLocalElement(g), d) = 1.0;
  return t;
}

double rigidMass(const FullModel& model, int direction) {
  const MultiVector all = rigidTranslations(model);
  const auto t = all.getVector(static_cast<std::size_t>(direction));
  MultiVector Mt(model.M->getRangeMap(), 1);
  model.M->apply(*t, Mt);
  Teuchos::Array<double> dot(1);
  t->dot(Mt, dot());
  return dot[0];
}

FullModel withLumpedMass(const FullModel& model) {
  const CrsMatrix& M = *model.M;
  const auto rowMap = M.getRowMap();
  const LO nLocal = static_cast<LO>(M.getNodeNumRows());
  std::vector<int> direction(static_cast<std::size_t>(model.numFree), -1);
  for (std::size_t i = 0; i < model.eq.size(); ++i)
    if (model.eq[i] >= 0) direction[model.eq[i]] = static_cast<int>(i % 3);
  Tpetra::Vector<Scalar, LO, GO> diagonal(rowMap);
  M.getLocalDiagCopy(diagonal);
  auto dh = diagonal.getLocalViewHost(Tpetra::Access::ReadOnly);
  double trace[3] = {0, 0, 0}, traceAll[3] = {0, 0, 0};
  for (LO l = 0; l < nLocal; ++l) {
    EPAPHE_REQUIRE(dh(l, 0) > 0, "body '" << model.name << "': the mass matrix has M_ii = " << dh(l, 0)
                                          << " at free DOF " << rowMap->getGlobalElement(l)
                                          << "; a lumped mass needs a positive diagonal (check the mass file)");
    trace[direction[rowMap->getGlobalElement(l)]] += dh(l, 0);
  }
  Teuchos::reduceAll(*M.getComm(), Teuchos::REDUCE_SUM, 3, trace, traceAll);
  double scale[3];
  for (int d = 0; d < 3; ++d) scale[d] = traceAll[d] > 0 ? rigidMass(model, d) / traceAll[d] : 0.0;
  FullModel lumped = model;
  lumped.M = Teuchos::rcp(new CrsMatrix(rowMap, 1));
  for (LO l = 0; l < nLocal; ++l) {
    const GO g = rowMap->getGlobalElement(l);
    const double m = dh(l, 0) * scale[direction[g]];
    lumped.M->insertGlobalValues(g, Teuchos::ArrayView<const GO>(&g, 1), Teuchos::ArrayView<const double>(&m, 1));
  }
  lumped.M->fillComplete(M.getDomainMap(), M.getRangeMap());
  return lumped;
}

SparseRows gatherRows(const CrsMatrix& A) {
  const int n = static_cast<int>(A.getGlobalNumRows());
  const auto rowMap = A.getRowMap();
  const auto colMap = A.getColMap();
  const LO nLocal = static_cast<LO>(A.getNodeNumRows());
  std::vector<int> lengthLocal(static_cast<std::size_t>(n), 0), length(lengthLocal.size(), 0);
  for (LO l = 0; l < nLocal; ++l)
    lengthLocal[rowMap->getGlobalElement(l)] = static_cast<int>(A.getNumEntriesInLocalRow(l));
  Teuchos::reduceAll(*A.getComm(), Teuchos::REDUCE_SUM, n, lengthLocal.data(), length.data());
  SparseRows S;
  S.rowStart.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i) S.rowStart[i + 1] = S.rowStart[i] + static_cast<std::size_t>(length[i]);
  const std::size_t nnz = S.rowStart.back();
  std::vector<int> colsLocal(nnz, 0);
  std::vector<double> valuesLocal(nnz, 0.0);
  typename CrsMatrix::local_inds_host_view_type idx;
  typename CrsMatrix::values_host_view_type val;
  std::vector<std::pair<int, double>> row;
  for (LO l = 0; l < nLocal; ++l) {
    A.getLocalRowView(l, idx, val);
    row.clear();
    for (std::size_t k = 0; k < idx.extent(0); ++k) row.emplace_back(colMap->getGlobalElement(idx(k)), val(k));
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const std::size_t start = S.rowStart[rowMap->getGlobalElement(l)];
    for (std::size_t k = 0; k < row.size(); ++k) {
      colsLocal[start + k] = row[k].first;
      valuesLocal[start + k] = row[k].second;
    }
  }
  S.cols.assign(nnz, 0);
  S.values.assign(nnz, 0.0);
  const auto comm = A.getComm();
  EPAPHE_REQUIRE(nnz <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                 "gathering a matrix of " << nnz << " entries: more than one MPI message can carry");
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(nnz), colsLocal.data(), S.cols.data());
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(nnz), valuesLocal.data(), S.values.data());
  return S;
}

namespace {

/// What an unreduced model takes from the full one: every free DOF as a coordinate, the mesh, its
/// sets and grids, every node retained.
ReducedModel unreducedShell(const FullModel& full, ReductionKind kind) {
  ReducedModel r;
  r.name = full.name;
  r.kind = kind;
  r.size = full.numFree;
  r.nodeDof = full.eq;
  r.coords = full.mesh.coords;
  r.nodeSets = full.mesh.nodeSets;
  r.nodeGrids = full.mesh.nodeGrids;
  r.hexes = full.mesh.hexes;
  for (int n = 0; n < full.numNodes(); ++n) r.retainedNodes.push_back(n);
  return r;
}

}  // namespace

ReducedModel unreducedModel(const FullModel& full) {
  ReducedModel r = unreducedShell(full, ReductionKind::None);
  r.K = gatherDense(*full.K);
  r.M = gatherDense(*full.M);
  r.recovery.assign(3 * static_cast<std::size_t>(full.numNodes()) * r.size, 0.0);
  for (std::size_t i = 0; i < full.eq.size(); ++i)
    if (full.eq[i] >= 0) r.recovery[i * r.size + full.eq[i]] = 1.0;
  return r;
}

ReducedModel sparseModel(const FullModel& full) {
  ReducedModel r = unreducedShell(full, ReductionKind::FullLumped);
  r.sparseK = gatherRows(*full.K);
  const SparseRows M = gatherRows(*full.M);
  r.lumpedMass.assign(static_cast<std::size_t>(r.size), 0.0);
  for (int i = 0; i < r.size; ++i) {
    EPAPHE_REQUIRE(M.rowStart[i + 1] == M.rowStart[i] + 1 && M.cols[M.rowStart[i]] == i,
                   "body '" << full.name << "': the mass matrix is not diagonal (row " << i << "); lump it first");
    r.lumpedMass[i] = M.values[M.rowStart[i]];
  }
  return r;
}

}  // namespace epaphe
