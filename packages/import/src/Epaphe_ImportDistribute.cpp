// The ranks of an import (Epaphe_ImportDetails.hpp): K and M parsed at once on ranks 0 and 1, and the raw
// model read on rank 0 distributed as Tpetra matrices.
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

namespace {

/// Rank 1's offer to parse a matrix for rank 0 while distributeModel runs `read` on rank 0: set there
/// on rank 0 only. Protocol (tag-free point-to-point between ranks 0 and 1, in this order): rank 0
/// sends one job flag, then the job if there is one; rank 1 answers with whether it can open the file
/// (it may not share rank 0's file system), then with the entries or the error message.
struct ReadHelper {
  const Teuchos::Comm<int>* comm = nullptr;
  bool asked = false;  // the one job was sent (or declined by sending no job)
};
ReadHelper* readHelper = nullptr;

enum : int { kNoJob = 0, kJob = 1 };

void sendString(const Teuchos::Comm<int>& comm, const std::string& s, int to) {
  const int n = static_cast<int>(s.size());
  Teuchos::send(comm, n, to);
  if (n > 0) Teuchos::send(comm, n, s.data(), to);
}

std::string receiveString(const Teuchos::Comm<int>& comm, int from) {
  int n = 0;
  Teuchos::receive(comm, from, &n);
  std::string s(static_cast<std::size_t>(n), '\0');
  if (n > 0) Teuchos::receive(comm, from, n, &s[0]);
  return s;
}

template <class T>
void sendArray(const Teuchos::Comm<int>& comm, const std::vector<T>& v, int to) {
  if (!v.empty()) Teuchos::send(comm, static_cast<int>(v.size()), v.data(), to);
}

template <class T>
void receiveArray(const Teuchos::Comm<int>& comm, std::vector<T>& v, int count, int from) {
  v.resize(static_cast<std::size_t>(count));
  if (count > 0) Teuchos::receive(comm, from, count, v.data());
}

/// Rank 1: serves the job rank 0 may send while it reads the model (distributeModel).
void serveRead(const Teuchos::Comm<int>& comm) {
  int job = kNoJob;
  Teuchos::receive(comm, 0, &job);
  if (job != kJob) return;
  SparseFile f;
  f.path = receiveString(comm, 0);
  f.what = receiveString(comm, 0);
  f.sizeSource = receiveString(comm, 0);
  int storage = 0;
  Teuchos::receive(comm, 0, &storage);
  Teuchos::receive(comm, 0, &f.size);
  f.storage = static_cast<Storage>(storage);
  const int canOpen = std::ifstream(f.path, std::ios::binary).good() ? 1 : 0;
  Teuchos::send(comm, canOpen, 0);
  if (!canOpen) return;
  std::string error;
  SparseEntries A;
  try {
    A = readSparse(f.path, f.what, f.storage, f.size, f.sizeSource);
    EPAPHE_REQUIRE(A.val.size() <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                   f.path << ": " << A.val.size() << " entries exceed one message");
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "reading " + f.path + " failed";
  }
  sendString(comm, error, 0);
  if (!error.empty()) return;
  const int head[3] = {A.size, A.triangle ? 1 : 0, static_cast<int>(A.val.size())};
  Teuchos::send(comm, 3, head, 0);
  sendString(comm, A.storageNote, 0);
  sendArray(comm, A.row, 0);
  sendArray(comm, A.col, 0);
  sendArray(comm, A.line, 0);
  sendArray(comm, A.val, 0);
}

/// Rank 0: asks rank 1 to parse `f`; false when rank 1 cannot open it.
bool askRead(const Teuchos::Comm<int>& comm, const SparseFile& f) {
  Teuchos::send(comm, static_cast<int>(kJob), 1);
  sendString(comm, f.path, 1);
  sendString(comm, f.what, 1);
  sendString(comm, f.sizeSource, 1);
  Teuchos::send(comm, static_cast<int>(f.storage), 1);
  Teuchos::send(comm, f.size, 1);
  int canOpen = 0;
  Teuchos::receive(comm, 1, &canOpen);
  return canOpen != 0;
}

/// Rank 0: rank 1's answer to askRead; its Error is thrown here.
SparseEntries collectRead(const Teuchos::Comm<int>& comm, const SparseFile& f) {
  const std::string error = receiveString(comm, 1);
  if (!error.empty()) throw Error(error);
  int head[3] = {0, 0, 0};
  Teuchos::receive(comm, 1, 3, head);
  SparseEntries A;
  A.path = f.path;
  A.what = f.what;
  A.size = head[0];
  A.triangle = head[1] != 0;
  A.storageNote = receiveString(comm, 1);
  receiveArray(comm, A.row, head[2], 1);
  receiveArray(comm, A.col, head[2], 1);
  receiveArray(comm, A.line, head[2], 1);
  receiveArray(comm, A.val, head[2], 1);
  return A;
}

}  // namespace

void readSparsePair(const SparseFile& k, const SparseFile& m, SparseEntries& K, SparseEntries& M) {
  auto read = [](const SparseFile& f) { return readSparse(f.path, f.what, f.storage, f.size, f.sizeSource); };
  // K here while M is parsed elsewhere; `mass()` waits for M. K's Error first, as when read one
  // after the other, but M is still waited for (rank 1 is sending it, the thread is running).
  auto readKThen = [&](auto&& mass) {
    try {
      K = read(k);
    } catch (...) {
      try {
        mass();
      } catch (...) {
      }
      throw;
    }
    M = mass();
  };
  if (readHelper != nullptr && !readHelper->asked) {
    readHelper->asked = true;
    const Teuchos::Comm<int>& comm = *readHelper->comm;
    if (askRead(comm, m)) return readKThen([&] { return collectRead(comm, m); });
  } else if (readHelper == nullptr && Kokkos::is_initialized() &&
             Kokkos::DefaultHostExecutionSpace::concurrency() >= 2) {
    auto mass = std::async(std::launch::async, read, m);
    return readKThen([&] { return mass.get(); });
  }
  K = read(k);
  M = read(m);
}

namespace {

const char* directionName(int d) {
  return d == 0 ? "x" : d == 1 ? "y" : "z";
}

/// Matrix entries in free-DOF numbering; `mirror`: one triangle, (j, i) stands also for (i, j).
struct Triplets {
  std::vector<int> row, col;
  std::vector<double> val;
  bool mirror = false;
};

/// Rank 0: numbers the free DOFs, checks the diagonals, renumbers the entries.
void freeSystem(RawModel& raw, FullModel& m, Triplets& K, Triplets& M) {
  const int n = static_cast<int>(raw.rowDof.size());
  const int nn = raw.mesh.numNodes();
  for (const SparseEntries* A : {&raw.K, &raw.M})
    EPAPHE_REQUIRE(A->size == n, A->path << ": the " << A->what << " is " << A->size << " x " << A->size
                                         << " but the DOF map " << raw.dofPath << " has " << n
                                         << " lines; export both from the same model");
  raw.constrained.resize(3 * static_cast<std::size_t>(nn), 0);
  m.name = raw.name;
  m.eq.assign(3 * static_cast<std::size_t>(nn), -1);
  std::vector<int> firstRow(3 * static_cast<std::size_t>(nn), -1), rowFree(static_cast<std::size_t>(n), -1);
  for (int r = 0; r < n; ++r) {
    const int d = raw.rowDof[r];
    if (d < 0) continue;
    EPAPHE_REQUIRE(firstRow[d] < 0, raw.dofPath << ":" << raw.rowLine[r] << ": node " << raw.mesh.nodeId(d / 3)
                                                << " direction " << directionName(d % 3)
                                                << " is named twice (also at line "
                                                << (firstRow[d] >= 0 ? raw.rowLine[firstRow[d]] : 0)
                                                << "); each DOF has one matrix row");
    firstRow[d] = r;
    if (raw.constrained[d]) continue;
    m.eq[d] = rowFree[r] = m.numFree++;
  }
  EPAPHE_REQUIRE(m.numFree > 0,
                 raw.dofPath << ": every DOF of body '" << raw.name << "' is constrained; nothing can move");

  for (int which = 0; which < 2; ++which) {
    const SparseEntries& A = which == 0 ? raw.K : raw.M;
    Triplets& T = which == 0 ? K : M;
    std::vector<double> diag(static_cast<std::size_t>(m.numFree), 0.0);
    std::vector<int> diagLine(static_cast<std::size_t>(m.numFree), 0);
    T.mirror = A.triangle;
    T.row.reserve(A.val.size());
    T.col.reserve(A.val.size());
    T.val.reserve(A.val.size());
    for (std::size_t k = 0; k < A.val.size(); ++k) {
      const int fi = rowFree[A.row[k]], fj = rowFree[A.col[k]];
      if (fi < 0 || fj < 0) continue;
      T.row.push_back(fi);
      T.col.push_back(fj);
      T.val.push_back(A.val[k]);
      if (fi == fj) {
        diag[fi] += A.val[k];
        if (!diagLine[fi]) diagLine[fi] = A.line[k];
      }
    }
    const char sym = which == 0 ? 'K' : 'M';
    for (int r = 0; r < n; ++r) {
      const int f = rowFree[r];
      if (f < 0) continue;
      const int d = raw.rowDof[r];
      EPAPHE_REQUIRE(diag[f] >= 0, A.path << ":" << diagLine[f] << ": the " << A.what << " has a negative diagonal "
                                          << sym << "(" << r + 1 << ", " << r + 1 << ") = " << diag[f] << " at node "
                                          << raw.mesh.nodeId(d / 3) << " direction " << directionName(d % 3)
                                          << ": the matrix is indefinite; check the export (sign, a flipped element, "
                                             "K and M swapped)");
      EPAPHE_REQUIRE(diag[f] > 0, A.path << ": the " << A.what << " has no diagonal " << sym << "(" << r + 1 << ", "
                                         << r + 1 << ") at node " << raw.mesh.nodeId(d / 3) << " direction "
                                         << directionName(d % 3) << " (DOF map line " << raw.rowLine[r]
                                         << "); a free DOF needs stiffness and mass: constrain it or check the model");
    }
  }
  m.mesh = std::move(raw.mesh);
}

template <class T>
void broadcastVector(const Teuchos::Comm<int>& comm, std::vector<T>& v) {
  int n = static_cast<int>(v.size());
  Teuchos::broadcast(comm, 0, &n);
  v.resize(static_cast<std::size_t>(n));
  if (n > 0) Teuchos::broadcast(comm, 0, n, v.data());
}

void broadcastString(const Teuchos::Comm<int>& comm, std::string& s) {
  std::vector<char> c(s.begin(), s.end());
  broadcastVector(comm, c);
  s.assign(c.begin(), c.end());
}

void broadcastMesh(const Teuchos::Comm<int>& comm, Mesh& mesh) {
  std::vector<double> x;
  std::vector<int> hex, setSizes, setNodes, solidSizes, solidNodes;
  std::string names;
  if (comm.getRank() == 0) {
    for (const auto& c : mesh.coords) x.insert(x.end(), c.begin(), c.end());
    for (const auto& h : mesh.hexes) hex.insert(hex.end(), h.begin(), h.end());
    for (const auto& e : mesh.solids) {
      solidSizes.push_back(static_cast<int>(e.size()));
      solidNodes.insert(solidNodes.end(), e.begin(), e.end());
    }
    for (const auto& [name, nodes] : mesh.nodeSets) {
      names += name + '\n';
      setSizes.push_back(static_cast<int>(nodes.size()));
      setNodes.insert(setNodes.end(), nodes.begin(), nodes.end());
    }
  }
  broadcastVector(comm, x);
  broadcastVector(comm, hex);
  broadcastVector(comm, mesh.nodeIds);
  broadcastVector(comm, setSizes);
  broadcastVector(comm, setNodes);
  broadcastString(comm, names);
  broadcastVector(comm, solidSizes);
  broadcastVector(comm, solidNodes);
  if (comm.getRank() == 0) return;
  mesh.solids.clear();
  for (std::size_t e = 0, at = 0; e < solidSizes.size(); at += static_cast<std::size_t>(solidSizes[e++]))
    mesh.solids.emplace_back(solidNodes.begin() + static_cast<long>(at),
                             solidNodes.begin() + static_cast<long>(at) + solidSizes[e]);
  mesh.coords.resize(x.size() / 3);
  for (std::size_t i = 0; i < mesh.coords.size(); ++i) mesh.coords[i] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
  mesh.hexes.resize(hex.size() / 8);
  for (std::size_t e = 0; e < mesh.hexes.size(); ++e)
    for (int a = 0; a < 8; ++a) mesh.hexes[e][a] = hex[8 * e + a];
  std::size_t pos = 0, at = 0;
  for (int size : setSizes) {
    const auto end = names.find('\n', pos);
    auto& set = mesh.nodeSets[names.substr(pos, end - pos)];
    set.assign(setNodes.begin() + static_cast<long>(at), setNodes.begin() + static_cast<long>(at + size));
    pos = end + 1;
    at += static_cast<std::size_t>(size);
  }
}

/// The fill-complete matrix of the entries of the rows this rank owns (T may hold other ranks'
/// rows: rank 0's), built as local CSR arrays: what insertGlobalValues and fillComplete would make,
/// bit for bit, without their per-entry insertion (about 30 ns per entry on the blades):
///  - column Map as Tpetra's makeColMap makes it: the owned GIDs in the row Map's order (every
///    owned row has its diagonal, so every owned column appears), then the remote GIDs ascending
///    (ascending GID is ascending owner on a contiguous Map); on one rank, the row Map itself;
///  - in each row, entries sorted by local column index, repeated (i, j) summed in file order.
Teuchos::RCP<CrsMatrix> buildMatrix(const Teuchos::RCP<const Map>& map, const Triplets& T) {
  const LO nLocal = static_cast<LO>(map->getNodeNumElements());
  const GO first = nLocal > 0 ? map->getMinGlobalIndex() : 0;
  auto owned = [&](GO g) { return g >= first && g < first + nLocal; };
  // Every entry (i, j, v) as it stands for the matrix: (i, j), then its mirror (j, i) if any, in
  // file order (the order of mirrored Triplets before).
  auto forEachEntry = [&](auto&& f) {
    for (std::size_t k = 0; k < T.row.size(); ++k) {
      const GO i = T.row[k], j = T.col[k];
      if (owned(i)) f(i, j, T.val[k]);
      if (T.mirror && i != j && owned(j)) f(j, i, T.val[k]);
    }
  };
  // Group the entries by row, keeping file order within a row (counting sort).
  std::vector<std::size_t> start(static_cast<std::size_t>(nLocal) + 1, 0);
  std::vector<GO> remote;
  forEachEntry([&](GO i, GO j, double) {
    ++start[i - first + 1];
    if (!owned(j)) remote.push_back(j);
  });
  for (LO l = 0; l < nLocal; ++l) start[l + 1] += start[l];
  std::sort(remote.begin(), remote.end());
  remote.erase(std::unique(remote.begin(), remote.end()), remote.end());
  auto localColumn = [&](GO g) -> LO {
    if (owned(g)) return static_cast<LO>(g - first);
    return nLocal + static_cast<LO>(std::lower_bound(remote.begin(), remote.end(), g) - remote.begin());
  };
  Teuchos::ArrayRCP<LO> col(start.back());
  Teuchos::ArrayRCP<double> val(start.back());
  std::vector<char> sorted(static_cast<std::size_t>(nLocal), 1);  // strictly ascending as filled
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    forEachEntry([&](GO i, GO j, double v) {
      const LO r = static_cast<LO>(i - first);
      const std::size_t p = fill[r]++;
      col[p] = localColumn(j);
      val[p] = v;
      if (p > start[r] && col[p] <= col[p - 1]) sorted[r] = 0;
    });
  }
  // Sort each row by column (stable: repeated entries stay in file order), merge repeats.
  Teuchos::ArrayRCP<std::size_t> rowPtr(static_cast<std::size_t>(nLocal) + 1);
  struct Entry {
    LO col;
    std::size_t at;  // position in file order: the tie-break that makes the sort stable
    double val;
    bool operator<(const Entry& o) const { return col != o.col ? col < o.col : at < o.at; }
  };
  std::vector<Entry> row;
  std::size_t out = 0;  // rows are compacted in place: out <= start[l] (the row is copied first)
  rowPtr[0] = 0;
  for (LO l = 0; l < nLocal; ++l) {
    if (sorted[l]) {  // ccx's column-major triangle fills every row in order
      for (std::size_t p = start[l]; p < start[l + 1]; ++p, ++out) {
        col[out] = col[p];
        val[out] = val[p];
      }
      rowPtr[l + 1] = out;
      continue;
    }
    row.clear();
    for (std::size_t p = start[l]; p < start[l + 1]; ++p) row.push_back({col[p], p, val[p]});
    std::sort(row.begin(), row.end());
    const std::size_t rowBegin = out;
    for (const Entry& e : row) {
      if (out > rowBegin && col[out - 1] == e.col) {
        val[out - 1] += e.val;
        continue;
      }
      col[out] = e.col;
      val[out] = e.val;
      ++out;
    }
    rowPtr[l + 1] = out;
  }
  Teuchos::RCP<const Map> colMap = map;
  if (map->getComm()->getSize() > 1) {
    std::vector<GO> gids(static_cast<std::size_t>(nLocal) + remote.size());
    std::iota(gids.begin(), gids.begin() + nLocal, first);
    std::copy(remote.begin(), remote.end(), gids.begin() + nLocal);
    colMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                  Teuchos::ArrayView<const GO>(gids), map->getIndexBase(), map->getComm()));
  }
  auto A = Teuchos::rcp(new CrsMatrix(map, colMap, rowPtr, col.persistingView(0, static_cast<long>(out)),
                                      val.persistingView(0, static_cast<long>(out))));
  A->expertStaticFillComplete(map, map);
  return A;
}

/// Rank 0 holds every entry; it sends each other rank the entries of the rows that rank owns, and
/// of a stored triangle also those whose mirror lies in its rows (point-to-point, one rank's share
/// packed at a time), and keeps them all, since buildMatrix takes only a rank's own rows: no rank
/// but 0 ever holds more than its share of the model. `map` is contiguous, its ranges ascending
/// with the rank.
void scatterRows(const Map& map, Triplets& T) {
  const Teuchos::Comm<int>& comm = *map.getComm();
  const int P = comm.getSize();
  if (P == 1) return;
  std::vector<long long> counts(static_cast<std::size_t>(P)), starts(static_cast<std::size_t>(P) + 1, 0);
  const long long mine = static_cast<long long>(map.getNodeNumElements());
  Teuchos::gatherAll(comm, 1, &mine, P, counts.data());
  for (int r = 0; r < P; ++r) starts[r + 1] = starts[r] + counts[r];
  int mirror = T.mirror ? 1 : 0;
  Teuchos::broadcast(comm, 0, &mirror);
  T.mirror = mirror != 0;
  if (comm.getRank() != 0) {
    int count = 0;
    Teuchos::receive(comm, 0, &count);
    receiveArray(comm, T.row, count, 0);
    receiveArray(comm, T.col, count, 0);
    receiveArray(comm, T.val, count, 0);
    return;
  }
  for (int r = 1; r < P; ++r) {
    Triplets share;
    auto ownedBy = [&](int g) { return g >= starts[r] && g < starts[r + 1]; };
    for (std::size_t k = 0; k < T.row.size(); ++k)
      if (ownedBy(T.row[k]) || (T.mirror && ownedBy(T.col[k]))) {
        share.row.push_back(T.row[k]);
        share.col.push_back(T.col[k]);
        share.val.push_back(T.val[k]);
      }
    EPAPHE_REQUIRE(share.row.size() <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                   "import: " << share.row.size() << " matrix entries for MPI rank " << r
                              << " exceed one message; use more ranks");
    Teuchos::send(comm, static_cast<int>(share.row.size()), r);
    sendArray(comm, share.row, r);
    sendArray(comm, share.col, r);
    sendArray(comm, share.val, r);
  }
}

}  // namespace

FullModel distributeModel(const std::function<RawModel()>& read, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  FullModel m;
  Triplets K, M;
  std::string error;
  if (comm->getRank() == 0) {
    ReadHelper helper{comm.get(), false};
    const bool lend = comm->getSize() > 1;
    if (lend) readHelper = &helper;
    try {
      RawModel raw = read();
      freeSystem(raw, m, K, M);
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "import failed";
    }
    readHelper = nullptr;
    if (lend && !helper.asked) Teuchos::send(*comm, static_cast<int>(kNoJob), 1);
  } else if (comm->getRank() == 1) {
    serveRead(*comm);
  }
  broadcastString(*comm, error);
  if (!error.empty()) throw Error(error);
  broadcastString(*comm, m.name);
  broadcastMesh(*comm, m.mesh);
  broadcastVector(*comm, m.eq);
  Teuchos::broadcast(*comm, 0, &m.numFree);
  auto map = Teuchos::rcp(new Map(m.numFree, 0, comm));
  scatterRows(*map, K);
  scatterRows(*map, M);
  m.K = buildMatrix(map, K);
  m.M = buildMatrix(map, M);
  return m;
}

}  // namespace Details
}  // namespace epaphe
