// Importers: Matrix Market round trip, code_aster files with Lagrange DOFs, and the catalogue of
// malformed inputs in fixtures/errors (each case: expect.txt says the format, an optional missing
// file, and the substrings the error message must hold; the case's files replace the base's).
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_CodeAsterImport.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ImportDetails.hpp"
#include "Epaphe_MatrixMarketImport.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace epaphe;
namespace fs = std::filesystem;

namespace {

Teuchos::RCP<const Teuchos::Comm<int>> comm() {
  return Teuchos::DefaultComm<int>::getComm();
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

/// A fresh directory under the test's work directory, made by rank 0, seen by all.
std::string workDir(const std::string& name) {
  const fs::path dir =
      fs::path(env("EPAPHE_IMPORT_WORKDIR").empty() ? "import-work" : env("EPAPHE_IMPORT_WORKDIR")) / name;
  if (comm()->getRank() == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  comm()->barrier();
  return dir.string();
}

const Material steel{7800, 2.1e11, 0.3};

FullModel clampedBox(const std::string& name) {
  Mesh mesh = makeBoxMesh({0, 0, 0}, {0.3, 0.04, 0.05}, {6, 2, 2});
  const auto clamped = mesh.nodeSet("x-", "test");
  return assembleHexModel(name, mesh, steel, clamped, comm());
}

/// The clamped box written as Matrix Market files in a fresh work directory `name`, with its dense K.
struct WrittenBox {
  FullModel ref;
  MatrixMarketFiles files;
  int n;
  std::vector<double> K;
};
WrittenBox writtenBox(const std::string& name) {
  WrittenBox b{clampedBox("box"), MatrixMarketFiles::withPrefix(workDir(name) + "/box"), 0, {}};
  writeMatrixMarket(b.ref, b.files);
  b.n = b.ref.numFree;
  b.K = gatherDense(*b.ref.K);
  return b;
}

}  // namespace

TEST(MatrixMarket, RoundTripOfABuiltInModelIsExact) {
  const FullModel ref = clampedBox("box");
  const auto files = MatrixMarketFiles::withPrefix(workDir("mm-round-trip") + "/box");
  writeMatrixMarket(ref, files);
  const FullModel got = importMatrixMarket(files, "box", comm());
  EXPECT_EQ(got.numFree, ref.numFree);
  EXPECT_EQ(got.eq, ref.eq);
  EXPECT_EQ(got.mesh.coords, ref.mesh.coords);
  EXPECT_EQ(got.mesh.nodeSets, ref.mesh.nodeSets);
  EXPECT_TRUE(got.K->getRowMap()->isContiguous());
  EXPECT_TRUE(got.K->getRowMap()->isSameAs(*ref.K->getRowMap()));
  EXPECT_EQ(gatherDense(*got.K), gatherDense(*ref.K));  // bit for bit
  EXPECT_EQ(gatherDense(*got.M), gatherDense(*ref.M));
}

// Matrix files are read in 4 MiB blocks: entries whose lines straddle block boundaries, a comment
// line longer than a block (the block grows), CRLF line ends and a last line without '\n' are read
// exactly as written, with their line numbers.
TEST(SparseFile, LinesAcrossBlocksAndLongerThanABlockAreReadExactly) {
  const std::string path = workDir("sparse-blocks") + "/A.mtx";  // collective
  if (comm()->getRank() != 0) return;                            // the file is read on rank 0
  const int n = 400, entries = 250000;                           // about 7 MB: two block boundaries
  std::vector<int> rows, cols;
  std::vector<double> vals;
  {
    std::ofstream out(path, std::ios::binary);
    out << "% " << std::string(5u << 20, 'x') << "\n";  // 5 MiB comment: longer than a block
    out.precision(17);
    for (int k = 0; k < entries; ++k) {
      const int a = 1 + (k * 7) % n, b = 1 + (k * 13) % n, i = std::max(a, b), j = std::min(a, b);  // one triangle
      const double v = std::ldexp(1.0 + k, -(k % 40)) * (k % 3 == 0 ? -1 : 1);
      rows.push_back(i - 1);
      cols.push_back(j - 1);
      vals.push_back(v);
      out << i << (k % 2 ? "," : " ") << j << "  " << v << (k % 5 == 0 ? "\r\n" : "\n");
    }
    out << 1 << " " << 1 << " " << 2.5;  // no final newline
    rows.push_back(0);
    cols.push_back(0);
    vals.push_back(2.5);
  }
  const auto A = Details::readSparse(path, "test matrix", Details::Storage::Triangle, n, "the test");
  ASSERT_EQ(A.val.size(), vals.size());
  EXPECT_EQ(A.row, rows);
  EXPECT_EQ(A.col, cols);
  EXPECT_EQ(A.val, vals);
  EXPECT_EQ(A.line.front(), 2);
  EXPECT_EQ(A.line.back(), entries + 2);
}

// The import builds its CSR arrays itself (not entry by entry through insertGlobalValues): on a
// full-storage K whose entries are shuffled and some split in two (repeated (i, j), summed), the
// imported matrix equals, bit for bit and in the same order, the matrix insertGlobalValues and
// fillComplete make from the same entries in the same order (every rank its own rows).
TEST(MatrixMarket, ShuffledRepeatedEntriesGiveTpetrasOwnMatrix) {
  const WrittenBox box = writtenBox("mm-shuffled");
  const auto& files = box.files;
  const int n = box.n;
  const auto& K = box.K;
  struct E {
    int i, j;
    double v;
  };
  std::vector<E> entries;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (const double v = K[static_cast<std::size_t>(j) * n + i]; v != 0.0) {
        if ((i + 3 * j) % 5 == 0) {  // split: a part now, the rest later in the file
          entries.push_back({i, j, 0.25 * v});
          entries.push_back({i, j, v - 0.25 * v});
        } else {
          entries.push_back({i, j, v});
        }
      }
  std::uint64_t state = 12345;  // the same shuffle on every rank
  for (std::size_t k = entries.size(); k > 1; --k) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    std::swap(entries[k - 1], entries[static_cast<std::size_t>(state >> 33) % k]);
  }
  if (comm()->getRank() == 0) {
    std::ofstream out(files.stiffness);
    out.precision(17);
    out << "%%MatrixMarket matrix coordinate real general\n" << n << " " << n << " " << entries.size() << "\n";
    for (const E& e : entries) out << e.i + 1 << " " << e.j + 1 << " " << e.v << "\n";
  }
  comm()->barrier();
  const FullModel got = importMatrixMarket(files, "box", comm());
  ASSERT_EQ(got.numFree, n);
  const auto map = got.K->getRowMap();
  std::vector<std::size_t> perRow(map->getNodeNumElements(), 0);
  for (const E& e : entries)
    if (map->isNodeGlobalElement(e.i)) ++perRow[map->getLocalElement(e.i)];
  CrsMatrix want(map, Teuchos::ArrayView<const std::size_t>(perRow));
  for (const E& e : entries)
    if (map->isNodeGlobalElement(e.i))
      want.insertGlobalValues(e.i, Teuchos::tuple<GO>(e.j), Teuchos::tuple<double>(e.v));
  want.fillComplete();
  const auto gc = got.K->getColMap()->getNodeElementList(), wc = want.getColMap()->getNodeElementList();
  ASSERT_EQ(std::vector<GO>(gc.begin(), gc.end()), std::vector<GO>(wc.begin(), wc.end()));
  ASSERT_EQ(got.K->getNodeNumEntries(), want.getNodeNumEntries());
  for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
    CrsMatrix::local_inds_host_view_type gi, wi;
    CrsMatrix::values_host_view_type gv, wv;
    got.K->getLocalRowView(l, gi, gv);
    want.getLocalRowView(l, wi, wv);
    ASSERT_EQ(gi.extent(0), wi.extent(0)) << "row " << l;
    for (std::size_t k = 0; k < gi.extent(0); ++k) {
      EXPECT_EQ(gi(k), wi(k)) << "row " << l;
      EXPECT_EQ(gv(k), wv(k)) << "row " << l;  // bit for bit: the repeats summed in file order
    }
  }
}

// K and M are parsed at once (M by rank 1 on 2 ranks, by a second thread on one): a broken M is
// reported with its own file and line, and when both are broken K's error comes first, as when
// they are read one after the other.
TEST(MatrixMarket, ConcurrentReadsReportTheFirstFilesError) {
  const auto files = writtenBox("mm-broken-pair").files;
  auto breakFile = [&](const std::string& path) {
    if (comm()->getRank() == 0) std::ofstream(path, std::ios::app) << "1 1 x-is-not-a-number\n";
    comm()->barrier();
  };
  auto message = [&] {
    try {
      importMatrixMarket(files, "box", comm());
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  breakFile(files.mass);
  const std::string massOnly = message();
  EXPECT_NE(massOnly.find(files.mass + ":"), std::string::npos) << massOnly;
  EXPECT_NE(massOnly.find("mass matrix"), std::string::npos) << massOnly;
  breakFile(files.stiffness);
  const std::string both = message();
  EXPECT_NE(both.find(files.stiffness + ":"), std::string::npos) << both;
  EXPECT_NE(both.find("stiffness matrix"), std::string::npos) << both;
  EXPECT_EQ(both.find("mass matrix"), std::string::npos) << both;
}

TEST(MatrixMarket, OneTriangleIsMirrored) {
  const WrittenBox box = writtenBox("mm-triangle");
  const auto& files = box.files;
  const int n = box.n;
  const auto& K = box.K;
  if (comm()->getRank() == 0) {  // rewrite K as its lower triangle, 'symmetric'
    std::ostringstream body;
    int count = 0;
    for (int j = 0; j < n; ++j)
      for (int i = j; i < n; ++i)
        if (K[static_cast<std::size_t>(j) * n + i] != 0.0) {
          body.precision(17);
          body << i + 1 << " " << j + 1 << " " << K[static_cast<std::size_t>(j) * n + i] << "\n";
          ++count;
        }
    std::ofstream(files.stiffness) << "%%MatrixMarket matrix coordinate real symmetric\n"
                                   << n << " " << n << " " << count << "\n"
                                   << body.str();
  }
  comm()->barrier();
  const FullModel got = importMatrixMarket(files, "box", comm());
  const auto G = gatherDense(*got.K);
  double worst = 0, scale = 0;
  for (std::size_t k = 0; k < K.size(); ++k) {
    worst = std::max(worst, std::abs(G[k] - K[k]));
    scale = std::max(scale, std::abs(K[k]));
  }
  EXPECT_LT(worst, 1e-12 * scale);
}

// A code_aster-like export of the same clamped box: the free-free matrices with the clamped DOFs
// fixed by dualized conditions, i.e. double Lagrange equations l1, l2 around each fixed DOF u:
//   [ K      a b   a b ] [u ]      b: unit row picking u;  a: code_aster's conditioning factor
//   [ a b^T  -a    a   ] [l1]
//   [ a b^T   a   -a   ] [l2]
TEST(CodeAster, LagrangeDofsAreDroppedAndTheirDofsClamped) {
  const FullModel ref = clampedBox("box");
  Mesh mesh = makeBoxMesh({0, 0, 0}, {0.3, 0.04, 0.05}, {6, 2, 2});
  const auto clamped = mesh.nodeSet("x-", "test");
  const FullModel freeFree = assembleHexModel("free", mesh, steel, {}, comm());
  const int n = freeFree.numFree;
  const auto K = gatherDense(*freeFree.K), M = gatherDense(*freeFree.M);
  const std::string dir = workDir("aster-lagrange");
  CodeAsterFiles files{dir + "/BStiff.mat", dir + "/BMass.mat", dir + "/BDof.txt", dir + "/Body.dat", "",
                       dir + "/sets.txt"};
  if (comm()->getRank() == 0) {
    std::vector<char> fixed(static_cast<std::size_t>(mesh.numNodes()), 0);
    for (int c : clamped) fixed[c] = 1;
    std::ofstream dofs(files.dofs), Kf(files.stiffness), Mf(files.mass), nodes(files.nodes), sets(files.nodeSets);
    Kf.precision(17);
    Mf.precision(17);
    nodes.precision(17);
    std::vector<int> row(static_cast<std::size_t>(n));  // physical DOF -> equation (1-based)
    int eq = 0;
    const double a = 1e11;
    std::vector<std::array<int, 3>> lagrange;  // l1, u, l2
    for (int node = 0; node < mesh.numNodes(); ++node) {
      nodes << node + 1 << " " << mesh.coords[node][0] << " " << mesh.coords[node][1] << " " << mesh.coords[node][2]
            << "\n";
      for (int d = 0; d < 3; ++d) {
        const char* comp[3] = {"DX", "DY", "DZ"};
        if (fixed[node]) dofs << "N" << node + 1 << " LAGR:" << comp[d] << "\n";
        dofs << "N" << node + 1 << " " << comp[d] << "\n";
        if (fixed[node]) dofs << node + 1 << " " << -(d + 1) << "\n";  // code_aster's DEEQ form
        if (fixed[node]) {
          lagrange.push_back({eq + 1, eq + 2, eq + 3});
          row[3 * node + d] = eq + 2;
          eq += 3;
        } else
          row[3 * node + d] = ++eq;
      }
    }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double k = K[static_cast<std::size_t>(j) * n + i], m = M[static_cast<std::size_t>(j) * n + i];
        if (k != 0.0) Kf << row[i] << " " << row[j] << " " << k << "\n";
        if (m != 0.0) Mf << row[i] << " " << row[j] << " " << m << "\n";
      }
    for (const auto& l : lagrange)
      Kf << l[0] << " " << l[1] << " " << a << "\n"
         << l[1] << " " << l[0] << " " << a << "\n"
         << l[2] << " " << l[1] << " " << a << "\n"
         << l[1] << " " << l[2] << " " << a << "\n"
         << l[0] << " " << l[0] << " " << -a << "\n"
         << l[2] << " " << l[2] << " " << -a << "\n"
         << l[0] << " " << l[2] << " " << a << "\n"
         << l[2] << " " << l[0] << " " << a << "\n";
    sets << "x+";
    for (int node : mesh.nodeSets.at("x+")) sets << " " << node + 1;
    sets << "\n";
  }
  comm()->barrier();
  const FullModel got = importCodeAster(files, "box", comm());
  EXPECT_EQ(got.numFree, ref.numFree);
  EXPECT_EQ(got.eq, ref.eq);
  EXPECT_EQ(got.mesh.nodeIds.front(), 1);
  EXPECT_EQ(got.mesh.nodeSets.at("x+"), ref.mesh.nodeSets.at("x+"));
  EXPECT_EQ(gatherDense(*got.K), gatherDense(*ref.K));
  EXPECT_EQ(gatherDense(*got.M), gatherDense(*ref.M));
  const auto fRef = fullModelFrequencies(ref, 6), fGot = fullModelFrequencies(got, 6);
  ASSERT_EQ(fGot.size(), fRef.size());
  for (std::size_t k = 0; k < fRef.size(); ++k) EXPECT_NEAR(fGot[k], fRef[k], 1e-9 * fRef[k]) << "mode " << k + 1;
}

namespace {

struct ErrorCase {
  std::string name, format, missing;
  std::vector<std::string> expect;
};

std::vector<ErrorCase> errorCases() {
  std::vector<ErrorCase> cases;
  const fs::path root = fs::path(env("EPAPHE_IMPORT_FIXTURES")) / "errors";
  for (const auto& entry : fs::directory_iterator(root)) {
    ErrorCase c;
    c.name = entry.path().filename().string();
    std::ifstream in(entry.path() / "expect.txt");
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("format: ", 0) == 0)
        c.format = line.substr(8);
      else if (line.rfind("missing: ", 0) == 0)
        c.missing = line.substr(9);
      else if (!line.empty())
        c.expect.push_back(line);
    }
    cases.push_back(c);
  }
  std::sort(cases.begin(), cases.end(), [](const ErrorCase& a, const ErrorCase& b) { return a.name < b.name; });
  return cases;
}

/// The base files of `format`, then the case's own, copied to a work directory.
std::string assembleCase(const std::string& format, const std::string& caseName, const std::string& missing) {
  const fs::path fixtures = env("EPAPHE_IMPORT_FIXTURES");
  const std::string dir = workDir("errors/" + (caseName.empty() ? "base-" + format : caseName));
  if (comm()->getRank() == 0) {
    for (const auto& e : fs::directory_iterator(fixtures / ("base-" + format)))
      fs::copy_file(e.path(), fs::path(dir) / e.path().filename(), fs::copy_options::overwrite_existing);
    if (!caseName.empty())
      for (const auto& e : fs::directory_iterator(fixtures / "errors" / caseName))
        if (e.path().filename() != "expect.txt")
          fs::copy_file(e.path(), fs::path(dir) / e.path().filename(), fs::copy_options::overwrite_existing);
    if (!missing.empty()) fs::remove(fs::path(dir) / missing);
  }
  comm()->barrier();
  return dir;
}

FullModel importFixture(const std::string& format, const std::string& dir) {
  if (format == "mm")
    return importMatrixMarket({dir + "/K.mtx", dir + "/M.mtx", dir + "/dofs.txt", dir + "/nodes.txt", ""}, "fixture",
                              comm());
  if (format == "calculix") return importCalculix({dir + "/model.inp", dir + "/model"}, "fixture", comm());
  if (format == "aster")
    return importCodeAster({dir + "/K.txt", dir + "/M.txt", dir + "/dofs.txt", dir + "/nodes.txt", "", ""}, "fixture",
                           comm());
  throw Error("unknown fixture format '" + format + "'");
}

}  // namespace

TEST(Fixtures, BasesImport) {
  const FullModel mm = importFixture("mm", assembleCase("mm", "", ""));
  EXPECT_EQ(mm.numFree, 6);
  EXPECT_EQ(mm.mesh.nodeIds, (std::vector<int>{10, 20}));
  const FullModel ccx = importFixture("calculix", assembleCase("calculix", "", ""));
  EXPECT_EQ(ccx.numFree, 12);
  EXPECT_EQ(ccx.mesh.hexes.size(), 1u);
  EXPECT_EQ(ccx.mesh.nodeSets.at("TIP"), (std::vector<int>{1, 2, 5, 6}));
  EXPECT_EQ(ccx.eq[0], -1);  // node 1 clamped
  const FullModel aster = importFixture("aster", assembleCase("aster", "", ""));
  EXPECT_EQ(aster.numFree, 5);
  EXPECT_EQ(aster.eq[0], -1);  // x of node 1 fixed by its Lagrange equations
  EXPECT_EQ(aster.eq[1], 0);
}

TEST(Fixtures, EachMalformedInputIsAClearError) {
  const auto cases = errorCases();
  ASSERT_GE(cases.size(), 30u);
  for (const auto& c : cases) {
    const std::string dir = assembleCase(c.format, c.name, c.missing);
    std::string message;
    try {
      importFixture(c.format, dir);
    } catch (const Error& e) {
      message = e.what();
    }
    ASSERT_FALSE(message.empty()) << c.name << ": no error raised";
    for (const auto& s : c.expect)
      EXPECT_NE(message.find(s), std::string::npos) << c.name << ": '" << s << "' not in: " << message;
    if (comm()->getRank() == 0 && env("EPAPHE_IMPORT_VERBOSE") == "1") std::cout << c.name << ": " << message << "\n";
  }
}
