#include "Epaphe_ImportedSpeedSource.hpp"

#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>
#include <sys/stat.h>

namespace epaphe {

using Teuchos::ParameterList;

namespace {

bool isFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string resolved(const std::string& deckPath, const std::string& value) {
  const auto slash = deckPath.find_last_of('/');
  return value[0] == '/' || slash == std::string::npos ? value : deckPath.substr(0, slash + 1) + value;
}

class CalculixSpeedSource : public SpeedSampleSource {
public:
  CalculixSpeedSource(const ImportedSpeeds& imported, const std::string& body,
                      const Teuchos::RCP<const Teuchos::Comm<int>>& comm)
      : imported_(imported), body_(body), comm_(comm) {
    reference_ = read(0).model;
  }
  const FullModel& reference() const override { return reference_; }
  SpeedSample sample(double speed) override {
    for (std::size_t i = 0; i < imported_.speeds.size(); ++i)
      if (imported_.speeds[i] == speed) return read(i);
    throw Error("body '" + body_ + "': no CalculiX job was imported at " + std::to_string(speed) +
                " rad/s; the samples of an imported model are its 'Rotation->Imported speeds'");
  }
  StaticState staticState() const override { return StaticState::Linear; }

private:
  SpeedSample read(std::size_t i) {
    Stopwatch watch;
    SpeedSample s;
    s.model = i == 0 && !reference_.K.is_null() ? reference_
                                                : importCalculix({imported_.input, imported_.jobs[i]}, body_, comm_);
    s.staticDisplacement = readCalculixDisplacements(imported_.jobs[i] + ".dat", s.model.mesh);
    s.seconds = watch.seconds();
    return s;
  }
  ImportedSpeeds imported_;
  std::string body_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  FullModel reference_;
};

}  // namespace

ImportedSpeeds importedSpeeds(const std::string& body, const ParameterList& bp, const std::string& deckPath) {
  const ParameterList& rot = bp.sublist("Rotation");
  const auto speeds = deck::getDoubles(rot, "Imported speeds");
  const auto jobs = deck::getStrings(rot, "Imported jobs");
  ImportedSpeeds out;
  if (speeds.empty() && jobs.empty()) return out;
  const std::string ctx = deckPath + ": body '" + body + "', '" + deck::pathOf(rot, "Imported speeds") + "'";
  EPAPHE_REQUIRE(speeds.size() == jobs.size(), ctx << " has " << speeds.size() << " speed(s) and 'Imported jobs' "
                                                   << jobs.size() << " job(s); give one ccx job per speed");
  EPAPHE_REQUIRE(bp.sublist("Mesh").get<std::string>("Type") == "CalculiX",  // the importer these jobs are read as
                 ctx << ": the matrices at speed are read from CalculiX jobs, but 'Mesh->Type' is "
                     << bp.sublist("Mesh").get<std::string>("Type") << "; set it to CalculiX or remove the key");
  EPAPHE_REQUIRE(speeds.size() >= 2, ctx << " has " << speeds.size() << " speed; the parametric model needs 2 or more "
                                         << "(3 for the classical K_0 + Omega^2 K_1 + Omega^4 K_2)");
  for (std::size_t i = 0; i < speeds.size(); ++i)
    EPAPHE_REQUIRE(
        std::isfinite(speeds[i]) && speeds[i] >= 0 && (i == 0 || speeds[i] > speeds[i - 1]),
        ctx << ": speed " << i + 1 << " = " << speeds[i] << " rad/s; give finite speeds >= 0 in increasing order");
  const auto range = deck::getDoubles(rot, "Speed range");
  const double tol = 1e-12 * speeds.back();
  const bool ends =
      range.size() == 2 && std::abs(range[0] - speeds.front()) <= tol && std::abs(range[1] - speeds.back()) <= tol;
  const std::string given =
      range.size() == 2 ? " {" + std::to_string(range[0]) + ", " + std::to_string(range[1]) + "}" : "";
  EPAPHE_REQUIRE(ends, ctx << " = {" << speeds.front() << " .. " << speeds.back() << "} rad/s but 'Speed range' has "
                           << range.size() << " value(s)" << given << "; set 'Speed range' to {" << speeds.front()
                           << ", " << speeds.back()
                           << "}: the imported speeds are the samples, the model covers the range between them");
  out.speeds = speeds;
  for (const auto& j : jobs) {
    EPAPHE_REQUIRE(!j.empty(),
                   ctx << ": 'Imported jobs' has an empty job name; give each ccx job's path without extension");
    out.jobs.push_back(resolved(deckPath, j));
    for (const char* e : {".sti", ".mas", ".dof", ".dat"})
      EPAPHE_REQUIRE(isFile(out.jobs.back() + e),
                     deckPath << ": body '" << body << "', '" << deck::pathOf(rot, "Imported jobs") << "' job '" << j
                              << "': no file " << out.jobs.back() + e << "; run ccx on it with the centrifugal static "
                              << "step (*NODE PRINT U) and a perturbation step *FREQUENCY, SOLVER=MATRIXSTORAGE "
                              << "(docs/user/rotating-bodies.md); paths are relative to the deck's directory");
  }
  const std::string first = fileText(out.jobs[0] + ".dof");
  for (std::size_t i = 1; i < out.jobs.size(); ++i)
    EPAPHE_REQUIRE(fileText(out.jobs[i] + ".dof") == first,
                   deckPath << ": body '" << body << "', '" << deck::pathOf(rot, "Imported jobs")
                            << "': " << out.jobs[i] << ".dof numbers other DOFs than " << out.jobs[0]
                            << ".dof; every job must be the same model (mesh, *BOUNDARY) at another speed");
  out.input = resolved(deckPath, bp.sublist("Mesh").get<std::string>("Input file"));
  return out;
}

std::vector<std::string> importedSpeedFiles(const ImportedSpeeds& imported) {
  std::vector<std::string> files;
  for (const auto& j : imported.jobs)
    for (const char* e : {".sti", ".mas", ".dof", ".dat"}) files.push_back(j + e);
  return files;
}

std::unique_ptr<SpeedSampleSource> calculixSpeedSource(const ImportedSpeeds& imported, const std::string& body,
                                                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  return std::make_unique<CalculixSpeedSource>(imported, body, comm);
}

}  // namespace epaphe
