// The readers of another code's matrices as importers (Epaphe_ModelImporter.hpp): CalculiX, Matrix
// Market and code_aster, registered under their deck names.
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_CodeAsterImport.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_MatrixMarketImport.hpp"
#include "Epaphe_ModelImporter.hpp"

#include <sys/stat.h>

namespace epaphe {

using Teuchos::ParameterList;
using namespace deck;

namespace {

/// The entry of a Mesh key that several importers share, with its one documentation.
void fileKey(ParameterList& mesh, const std::string& key) {
  if (key == "Input file")
    addString(mesh, key, "",
              "CalculiX: the input deck jobname.inp (mesh, *NSET, *BOUNDARY, *INCLUDEs) of "
              "the run with *FREQUENCY, SOLVER=MATRIXSTORAGE");
  else if (key == "Matrix job")
    addString(mesh, key, "",
              "CalculiX: path without extension of that run's jobname.sti (K), .mas (M) and "
              ".dof (DOF of each row); empty: the Input file without its .inp");
  else if (key == "Stiffness file")
    addString(mesh, key, "",
              "Matrix Market: K.mtx (%%MatrixMarket coordinate, general or symmetric); "
              "code_aster: K as 'row column value' lines (one triangle or both)");
  else if (key == "Mass file")
    addString(mesh, key, "", "Matrix Market, code_aster: M, as the Stiffness file");
  else if (key == "DOF file")
    addString(mesh, key, "",
              "Matrix Market: 'node direction' per matrix row; code_aster: the DOF numbering "
              "of every equation ('N12 DX', Lagrange rows 'N12 LAGR:DX', dropped)");
  else if (key == "Node file")
    addString(mesh, key, "", "Matrix Market, code_aster: 'id x y z' per node");
  else if (key == "Node set file")
    addString(mesh, key, "", "Matrix Market, code_aster (optional): 'name id id ...' per line");
  else if (key == "Clamped node file")
    addString(mesh, key, "",
              "code_aster (optional): node ids fixed in every direction, besides "
              "the DOFs code_aster dualized");
  else
    throw Error("fileKey: no shared Mesh key '" + key + "'");
}

Teuchos::RCP<const ParameterList> keysOf(std::initializer_list<const char*> keys) {
  auto pl = Teuchos::rcp(new ParameterList("Mesh"));
  for (const char* k : keys) fileKey(*pl, k);
  return pl;
}

/// What every importer of files says (paths relative to the deck file's directory).
std::string filesDoc(const std::string& what) {
  return "K and M imported from " + what +
         " (paths relative to the deck file's directory); the body's Material is then unused, its boundary "
         "conditions and node sets are the files' own, plus node set 'all'";
}

class CalculixImporter : public ModelImporter {
public:
  std::string name() const override { return "CalculiX"; }
  std::string documentation() const override {
    return filesDoc("a ccx run with *FREQUENCY, SOLVER=MATRIXSTORAGE (Input file, Matrix job; *BOUNDARY, *NSET)");
  }
  Teuchos::RCP<const ParameterList> getValidParameters() const override { return keysOf({"Input file", "Matrix job"}); }
  std::vector<std::string> files(const ImportRequest& r) const override {
    const CalculixFiles f = calculixFiles(r);
    std::vector<std::string> all = calculixInputFiles(f.input);
    for (const char* s : {".sti", ".mas", ".dof"}) all.push_back(f.matrices + s);
    return all;
  }
  FullModel build(const ImportRequest& r, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const override {
    return importCalculix(calculixFiles(r), r.body, comm);
  }

private:
  static CalculixFiles calculixFiles(const ImportRequest& r) {
    CalculixFiles f;
    f.input = r.file("Input file", true);
    if (!r.mesh().get<std::string>("Matrix job").empty()) {
      f.matrices = r.file("Matrix job", true, true);
      return f;
    }
    const auto dot = f.input.rfind('.'), slash = f.input.rfind('/');
    f.matrices =
        (dot != std::string::npos && (slash == std::string::npos || dot > slash)) ? f.input.substr(0, dot) : f.input;
    for (const char* s : {".sti", ".mas", ".dof"}) {
      struct stat st {};
      const std::string path = f.matrices + s;
      EPAPHE_REQUIRE(::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode),
                     r.context() << ", 'Mesh->Matrix job' is empty, so the matrices are read from " << f.matrices
                                 << ".sti/.mas/.dof, but " << f.matrices + s << " does not exist; run ccx on "
                                 << f.input << " (with *FREQUENCY, SOLVER=MATRIXSTORAGE) or set 'Matrix job'");
    }
    return f;
  }
};

class MatrixMarketImporter : public ModelImporter {
public:
  std::string name() const override { return "Matrix Market"; }
  std::string documentation() const override {
    return filesDoc("Matrix Market files (Stiffness, Mass, DOF, Node and Node set file)");
  }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    return keysOf({"Stiffness file", "Mass file", "DOF file", "Node file", "Node set file"});
  }
  std::vector<std::string> files(const ImportRequest& r) const override {
    const MatrixMarketFiles f = matrixMarketFiles(r);
    std::vector<std::string> all = {f.stiffness, f.mass, f.dofs, f.nodes};
    if (!f.nodeSets.empty()) all.push_back(f.nodeSets);
    return all;
  }
  FullModel build(const ImportRequest& r, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const override {
    return importMatrixMarket(matrixMarketFiles(r), r.body, comm);
  }

private:
  static MatrixMarketFiles matrixMarketFiles(const ImportRequest& r) {
    MatrixMarketFiles f;
    f.stiffness = r.file("Stiffness file", true);
    f.mass = r.file("Mass file", true);
    f.dofs = r.file("DOF file", true);
    f.nodes = r.file("Node file", true);
    f.nodeSets = r.file("Node set file", false);
    return f;
  }
};

class CodeAsterImporter : public ModelImporter {
public:
  std::string name() const override { return "code_aster"; }
  std::string documentation() const override {
    return filesDoc("code_aster's exported files (Stiffness, Mass, DOF, Node, Node set and Clamped node file)");
  }
  Teuchos::RCP<const ParameterList> getValidParameters() const override {
    return keysOf({"Stiffness file", "Mass file", "DOF file", "Node file", "Node set file", "Clamped node file"});
  }
  std::vector<std::string> files(const ImportRequest& r) const override {
    const CodeAsterFiles f = codeAsterFiles(r);
    std::vector<std::string> all = {f.stiffness, f.mass, f.dofs, f.nodes};
    if (!f.nodeSets.empty()) all.push_back(f.nodeSets);
    if (!f.clampedNodes.empty()) all.push_back(f.clampedNodes);
    return all;
  }
  FullModel build(const ImportRequest& r, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const override {
    return importCodeAster(codeAsterFiles(r), r.body, comm);
  }

private:
  static CodeAsterFiles codeAsterFiles(const ImportRequest& r) {
    CodeAsterFiles f;
    f.stiffness = r.file("Stiffness file", true);
    f.mass = r.file("Mass file", true);
    f.dofs = r.file("DOF file", true);
    f.nodes = r.file("Node file", true);
    f.nodeSets = r.file("Node set file", false);
    f.clampedNodes = r.file("Clamped node file", false);
    return f;
  }
};

}  // namespace

void registerFileImporters(const std::function<void(const std::string&, ImporterRegistry::Factory)>& add) {
  add("CalculiX", [] { return std::make_unique<CalculixImporter>(); });
  add("Matrix Market", [] { return std::make_unique<MatrixMarketImporter>(); });
  add("code_aster", [] { return std::make_unique<CodeAsterImporter>(); });
}

}  // namespace epaphe
