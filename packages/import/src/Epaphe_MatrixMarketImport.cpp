#include "Epaphe_MatrixMarketImport.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_ImportDetails.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>

#include <cstdio>
#include <memory>

namespace epaphe {

MatrixMarketFiles MatrixMarketFiles::withPrefix(const std::string& prefix) {
  return {prefix + ".K.mtx", prefix + ".M.mtx", prefix + ".dofs", prefix + ".nodes", prefix + ".nsets"};
}

FullModel importMatrixMarket(const MatrixMarketFiles& files, const std::string& name,
                             const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  return Details::distributeModel(
      [&]() {
        return Details::readListedModel({files.nodes, files.nodeSets, files.dofs, files.stiffness, files.mass}, name,
                                        Details::Storage::General, nullptr);
      },
      comm);
}

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openForWriting(const std::string& path) {
  File f(std::fopen(path.c_str(), "w"));
  EPAPHE_REQUIRE(f, path << ": cannot write (does the directory exist, is it writable?)");
  return f;
}

/// The whole matrix on rank 0 (rows in global order), nothing elsewhere.
Teuchos::RCP<CrsMatrix> onRankZero(const CrsMatrix& A) {
  const auto comm = A.getComm();
  const int n = static_cast<int>(A.getGlobalNumRows());
  auto rootMap = Teuchos::rcp(new Map(n, comm->getRank() == 0 ? n : 0, 0, comm));
  Tpetra::Import<LO, GO> importer(A.getRowMap(), rootMap);
  return Tpetra::importAndFillCompleteCrsMatrix<CrsMatrix>(Teuchos::rcpFromRef(A), importer, rootMap, rootMap);
}

void writeMatrix(const CrsMatrix& A, const std::string& path, const char* what) {
  File f = openForWriting(path);
  std::fprintf(f.get(), "%%%%MatrixMarket matrix coordinate real general\n%% %s written by Epaphe\n", what);
  std::fprintf(f.get(), "%d %d %zu\n", static_cast<int>(A.getGlobalNumRows()), static_cast<int>(A.getGlobalNumCols()),
               static_cast<std::size_t>(A.getGlobalNumEntries()));
  typename CrsMatrix::local_inds_host_view_type idx;
  typename CrsMatrix::values_host_view_type val;
  const auto rowMap = A.getRowMap();
  const auto colMap = A.getColMap();
  for (LO l = 0; l < static_cast<LO>(A.getNodeNumRows()); ++l) {
    A.getLocalRowView(l, idx, val);
    for (std::size_t k = 0; k < idx.extent(0); ++k)
      std::fprintf(f.get(), "%d %d %.17g\n", rowMap->getGlobalElement(l) + 1, colMap->getGlobalElement(idx(k)) + 1,
                   val(k));
  }
  EPAPHE_REQUIRE(!std::ferror(f.get()), path << ": write error (disk full?)");
}

}  // namespace

void writeMatrixMarket(const FullModel& model, const MatrixMarketFiles& files) {
  const auto comm = model.K->getComm();
  const auto K = onRankZero(*model.K);
  const auto M = onRankZero(*model.M);
  std::string error;
  if (comm->getRank() == 0) {
    try {
      writeMatrix(*K, files.stiffness, "stiffness matrix");
      writeMatrix(*M, files.mass, "mass matrix");
      const Mesh& mesh = model.mesh;
      std::vector<int> dofOf(static_cast<std::size_t>(model.numFree), -1);
      for (std::size_t i = 0; i < model.eq.size(); ++i)
        if (model.eq[i] >= 0) dofOf[model.eq[i]] = static_cast<int>(i);
      {
        File f = openForWriting(files.dofs);
        std::fprintf(f.get(), "# node direction, one line per row of K and M\n");
        for (int d : dofOf) std::fprintf(f.get(), "%d %d\n", mesh.nodeId(d / 3), d % 3 + 1);
      }
      {
        File f = openForWriting(files.nodes);
        std::fprintf(f.get(), "# id x y z\n");
        for (int n = 0; n < mesh.numNodes(); ++n)
          std::fprintf(f.get(), "%d %.17g %.17g %.17g\n", mesh.nodeId(n), mesh.coords[n][0], mesh.coords[n][1],
                       mesh.coords[n][2]);
      }
      if (!files.nodeSets.empty()) {
        File f = openForWriting(files.nodeSets);
        for (const auto& [name, nodes] : mesh.nodeSets) {
          std::fprintf(f.get(), "%s", name.c_str());
          for (int n : nodes) std::fprintf(f.get(), " %d", mesh.nodeId(n));
          std::fprintf(f.get(), "\n");
        }
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  int length = static_cast<int>(error.size());
  Teuchos::broadcast(*comm, 0, &length);
  error.resize(static_cast<std::size_t>(length));
  if (length > 0) Teuchos::broadcast(*comm, 0, length, &error[0]);
  if (!error.empty()) throw Error(error);
}

}  // namespace epaphe
