#include "Epaphe_ModelImporter.hpp"

#include "Epaphe_BuiltInMeshes.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Registry.hpp"

#include <mutex>
#include <sys/stat.h>

namespace epaphe {

using AddImporter = std::function<void(const std::string&, ImporterRegistry::Factory)>;
void registerBuiltInMeshes(const AddImporter& add);  // Epaphe_BuiltInMeshes.cpp
void registerFileImporters(const AddImporter& add);  // Epaphe_FileImporters.cpp

namespace {

/// The registry, the built-in importers first.
NamedFactories<ImporterRegistry::Factory>& registry() {
  static NamedFactories<ImporterRegistry::Factory> r("importer (Mesh Type)");
  static std::once_flag builtIns;
  std::call_once(builtIns, [] {
    const AddImporter add = [](const std::string& n, ImporterRegistry::Factory f) { r.add(n, std::move(f)); };
    registerBuiltInMeshes(add);
    registerFileImporters(add);
  });
  return r;
}

bool isFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

std::string ImportRequest::file(const std::string& key, bool required, bool job) const {
  const Teuchos::ParameterList& mp = mesh();
  const std::string value = mp.get<std::string>(key), type = mp.get<std::string>("Type");
  const std::string where = context() + ", '" + deck::pathOf(mp, key) + "'";
  if (value.empty()) {
    EPAPHE_REQUIRE(!required, where << " is empty but Mesh Type " << type
                                    << " needs it; name the file, relative to the deck's directory");
    return "";
  }
  const auto slash = deckPath.find_last_of('/');
  const std::string directory = slash == std::string::npos ? std::string() : deckPath.substr(0, slash + 1);
  const std::string path = value[0] == '/' ? value : directory + value;
  for (const std::string& s : job ? std::vector<std::string>{".sti", ".mas", ".dof"} : std::vector<std::string>{""})
    EPAPHE_REQUIRE(isFile(path + s), where << " = '" << value << "': no file " << path + s
                                           << (job ? " (the job's .sti, .mas and .dof are read; run ccx on a deck "
                                                     "with *FREQUENCY, SOLVER=MATRIXSTORAGE)"
                                                   : "")
                                           << "; paths are relative to the deck's directory");
  return path;
}

Mesh ModelImporter::mesh(const ImportRequest& request) const {
  throw Error(request.context() + ": Mesh Type " + name() + " has no built-in mesh; its model is imported");
}

void ImporterRegistry::add(const std::string& name, Factory factory) {
  registry().add(name, std::move(factory));
}

std::unique_ptr<ModelImporter> ImporterRegistry::make(const std::string& name, const std::string& context) {
  return registry().find(name, context)();
}

std::vector<std::string> ImporterRegistry::names() {
  return registry().names();
}

int ImporterRegistry::version() {
  return registry().version();
}

std::unique_ptr<ModelImporter> modelImporter(const Teuchos::ParameterList& mp) {
  return ImporterRegistry::make(mp.get<std::string>("Type"), deck::pathOf(mp, "Type"));
}

Teuchos::RCP<Teuchos::ParameterList> importerParameters() {
  Teuchos::ParameterList files, builtIn;
  for (const std::string& name : ImporterRegistry::names()) {
    const auto importer = ImporterRegistry::make(name, "the deck schema");
    (importer->builtInMesh() ? builtIn : files).setParametersNotAlreadySet(*importer->getValidParameters());
  }
  auto pl = Teuchos::rcp(new Teuchos::ParameterList("Mesh"));
  pl->setParameters(files);
  for (const std::string& key : builtInMeshKeys())
    if (builtIn.isParameter(key)) pl->setEntry(key, builtIn.getEntry(key));
  pl->setParametersNotAlreadySet(builtIn);
  return pl;
}

}  // namespace epaphe
