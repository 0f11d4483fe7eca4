// Fuzzing the importers (packages/import): one file of a base model -- Matrix Market (K.mtx, M.mtx,
// dofs.txt, nodes.txt), CalculiX (model.inp, mesh.inp, model.sti, model.mas, model.dof) or code_aster
// (K.txt, M.txt, dofs.txt, nodes.txt) -- is replaced by a mutation of itself and the whole model is
// imported on one MPI rank. Every input must import or be refused with epaphe::Error.
// The seeds are the files of the base models; the parent directory's name (base-mm, base-calculix,
// base-aster) gives the format.
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_CodeAsterImport.hpp"
#include "Epaphe_MatrixMarketImport.hpp"
#include "Epaphe_Runtime.hpp"
#include "fuzz_driver.hpp"

#include <Teuchos_DefaultComm.hpp>

#include <filesystem>
#include <map>

namespace fs = std::filesystem;

namespace {

std::string workRoot = "fuzz-import-work";

/// The case directory of `seedPath`'s format, a copy of the base model made once.
std::string caseDir(const fs::path& seed) {
  static std::map<std::string, std::string> made;
  const std::string format = seed.parent_path().filename().string();
  auto it = made.find(format);
  if (it != made.end()) return it->second;
  const fs::path dir = fs::path(workRoot) / format;
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const auto& e : fs::directory_iterator(seed.parent_path()))
    if (e.is_regular_file()) fs::copy_file(e.path(), dir / e.path().filename());
  return made[format] = dir.string();
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

void target(const std::string& input, const std::string& seedPath) {
  const fs::path seed(seedPath);
  const std::string dir = caseDir(seed);
  const std::string format = seed.parent_path().filename().string();
  const fs::path file = fs::path(dir) / seed.filename();
  writeText(file, input);
  struct Restore {
    fs::path file, seed;
    ~Restore() { writeText(file, epaphe::fuzz::readFile(seed.string())); }
  } restore{file, seed};
  auto comm = Teuchos::DefaultComm<int>::getComm();
  if (format == "base-mm") {
    epaphe::importMatrixMarket({dir + "/K.mtx", dir + "/M.mtx", dir + "/dofs.txt", dir + "/nodes.txt", ""}, "fuzz",
                               comm);
  } else if (format == "base-calculix") {
    epaphe::importCalculix({dir + "/model.inp", dir + "/model"}, "fuzz", comm);
  } else if (format == "base-aster") {
    epaphe::importCodeAster({dir + "/K.txt", dir + "/M.txt", dir + "/dofs.txt", dir + "/nodes.txt", "", ""}, "fuzz",
                            comm);
  } else {
    throw std::logic_error("fuzz_import: seed '" + seedPath + "' is not in base-mm, base-calculix or base-aster");
  }
}

}  // namespace

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--work") workRoot = argv[i + 1];
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (std::string(argv[i]) == "--work") {
      ++i;
      continue;
    }
    args.push_back(argv[i]);
  }
  return epaphe::fuzz::runDriver("import", static_cast<int>(args.size()), args.data(), target);
}
