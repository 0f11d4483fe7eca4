// CalculiX import against CalculiX itself: cantilever beams of C3D20 and C3D15 elements are
// generated here, ccx writes their matrices (*FREQUENCY, SOLVER=MATRIXSTORAGE) and solves their
// eigenproblem (*FREQUENCY); the imported model's lowest eigenvalues from Anasazi must agree with
// ccx's to 1e-6, and Craig-Bampton must take the model as it is. Needs EPAPHE_CCX (the ccx binary)
// and EPAPHE_IMPORT_WORKDIR.
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_Runtime.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

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

/// A cantilever beam [0, L] x [0, b] x [0, h] of nx x ny x nz cells, each a C3D20 hexahedron or
/// two C3D15 wedges; clamped on x = 0 (node set FIX), the tip x = L in node set TIP. Nodes live on
/// the grid of half cells and are numbered as the elements first use them.
struct BeamDeck {
  std::string type;
  std::array<int, 3> cells;
  std::array<double, 3> lengths{0.4, 0.05, 0.04};
  int numNodes = 0, numFixed = 0;

  void write(const std::string& dir) {
    std::map<std::array<int, 3>, int> id;
    auto node = [&](int i, int j, int k) {
      auto [it, fresh] = id.emplace(std::array<int, 3>{i, j, k}, static_cast<int>(id.size()) + 1);
      (void)fresh;
      return it->second;
    };
    std::vector<std::vector<int>> elements;
    for (int k = 0; k < 2 * cells[2]; k += 2)
      for (int j = 0; j < 2 * cells[1]; j += 2)
        for (int i = 0; i < 2 * cells[0]; i += 2) {
          if (type == "C3D20") {
            const int c[20][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2},
                                  {0, 2, 2}, {1, 0, 0}, {2, 1, 0}, {1, 2, 0}, {0, 1, 0}, {1, 0, 2}, {2, 1, 2},
                                  {1, 2, 2}, {0, 1, 2}, {0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};
            std::vector<int> e;
            for (const auto& p : c) e.push_back(node(i + p[0], j + p[1], k + p[2]));
            elements.push_back(e);
          } else {  // two wedges per cell: triangles in (y, z), extruded along x
            const int tri[2][3][2] = {{{0, 0}, {2, 0}, {2, 2}}, {{0, 0}, {2, 2}, {0, 2}}};
            for (const auto& t : tri) {
              std::vector<int> e;
              for (int x : {0, 2})
                for (const auto& p : t) e.push_back(node(i + x, j + p[0], k + p[1]));
              for (int x : {0, 2})
                for (int a = 0; a < 3; ++a) {
                  const auto& p = t[a];
                  const auto& q = t[(a + 1) % 3];
                  e.push_back(node(i + x, j + (p[0] + q[0]) / 2, k + (p[1] + q[1]) / 2));
                }
              for (const auto& p : t) e.push_back(node(i + 1, j + p[0], k + p[1]));
              elements.push_back(e);
            }
          }
        }
    numNodes = static_cast<int>(id.size());
    std::ofstream mesh(dir + "/mesh.inp");
    mesh.precision(17);
    mesh << "** " << type << " cantilever written by test_import_calculix\n*NODE, NSET=NALL\n";
    std::vector<std::array<int, 3>> where(id.size());
    for (const auto& [p, n] : id) where[n - 1] = p;
    for (int n = 1; n <= numNodes; ++n) {
      const auto& p = where[n - 1];
      mesh << n;
      for (int d = 0; d < 3; ++d) mesh << ", " << lengths[d] * p[d] / (2.0 * cells[d]);
      mesh << "\n";
    }
    mesh << "*ELEMENT, TYPE=" << type << ", ELSET=EALL\n";
    for (std::size_t e = 0; e < elements.size(); ++e) {
      mesh << e + 1;
      for (std::size_t a = 0; a < elements[e].size(); ++a)
        mesh << (a == 10 ? ",\n" : ", ") << elements[e][a];  // continuation line
      mesh << "\n";
    }
    for (const char* set : {"FIX", "TIP"}) {
      mesh << "*NSET, NSET=" << set << "\n";
      int onLine = 0, count = 0;
      for (int n = 1; n <= numNodes; ++n)
        if (where[n - 1][0] == (set[0] == 'F' ? 0 : 2 * cells[0])) {
          mesh << (onLine ? ", " : "") << n;
          ++count;
          if (++onLine == 12) {
            mesh << ",\n";
            onLine = 0;
          }
        }
      if (onLine) mesh << "\n";
      if (set[0] == 'F') numFixed = count;
    }
    const std::string common =
        "*INCLUDE, INPUT=mesh.inp\n*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7800.\n"
        "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3\n*STEP\n";
    std::ofstream(dir + "/mat.inp") << common << "*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n";
    std::ofstream(dir + "/freq.inp") << common << "*FREQUENCY\n10\n*END STEP\n";
  }
};

/// Writes the beam and runs ccx on rank 0 (both decks); every rank gets the directory.
std::string runCcx(BeamDeck& beam, const std::string& name) {
  const std::string ccx = env("EPAPHE_CCX");
  const fs::path dir = fs::path(env("EPAPHE_IMPORT_WORKDIR")) / name;
  int status = 0;
  if (comm()->getRank() == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    beam.write(dir.string());
    const std::string cmd = "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 '" + ccx +
                            "' -i mat > mat.log 2>&1 && OMP_NUM_THREADS=1 '" + ccx + "' -i freq > freq.log 2>&1";
    status = std::system(cmd.c_str());
  }
  Teuchos::broadcast(*comm(), 0, &status);
  Teuchos::broadcast(*comm(), 0, &beam.numNodes);
  Teuchos::broadcast(*comm(), 0, &beam.numFixed);
  EXPECT_EQ(status, 0) << "ccx failed; see " << dir << "/*.log";
  return dir.string();
}

int countLines(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  int n = 0;
  while (std::getline(in, line))
    if (!line.empty()) ++n;
  return n;
}

void checkAgainstCcx(const std::string& type, std::array<int, 3> cells) {
  ASSERT_FALSE(env("EPAPHE_CCX").empty()) << "set EPAPHE_CCX to the ccx binary";
  BeamDeck beam{type, cells};
  const std::string dir = runCcx(beam, "ccx-" + type);
  Stopwatch sw;
  const FullModel model = importCalculix({dir + "/mat.inp", dir + "/mat"}, "beam", comm());
  const double seconds = sw.seconds();

  // Sizes: one free DOF per line of ccx's .dof, the clamped face gone.
  EXPECT_EQ(model.numFree, countLines(dir + "/mat.dof"));
  EXPECT_EQ(model.numNodes(), beam.numNodes);
  EXPECT_EQ(model.numFree, 3 * (beam.numNodes - beam.numFixed));
  for (int n : model.mesh.nodeSets.at("FIX"))
    for (int d = 0; d < 3; ++d) EXPECT_EQ(model.eq[3 * n + d], -1);
  // K and M symmetric (ccx stores the upper triangle; the import mirrors it).
  const int n = model.numFree;
  const auto K = gatherDense(*model.K), M = gatherDense(*model.M);
  for (int j = 0; j < n; ++j)
    for (int i = j + 1; i < n; ++i) {
      ASSERT_EQ(K[static_cast<std::size_t>(j) * n + i], K[static_cast<std::size_t>(i) * n + j]);
      ASSERT_EQ(M[static_cast<std::size_t>(j) * n + i], M[static_cast<std::size_t>(i) * n + j]);
    }

  // Lowest eigenvalues: Anasazi on the imported (K, M) against ccx's own *FREQUENCY step.
  const auto lambdaCcx = readCalculixEigenvalues(dir + "/freq.dat");
  ASSERT_EQ(lambdaCcx.size(), 10u);
  const auto f = fullModelFrequencies(model, 10);
  ASSERT_EQ(f.size(), 10u);
  double worst = 0;
  for (int k = 0; k < 10; ++k) {
    const double lambda = std::pow(2 * M_PI * f[k], 2);
    const double rel = std::abs(lambda - lambdaCcx[k]) / lambdaCcx[k];
    worst = std::max(worst, rel);
    EXPECT_LT(rel, 1e-6) << type << " mode " << k + 1 << ": Anasazi " << lambda << ", ccx " << lambdaCcx[k];
  }
  if (comm()->getRank() == 0)
    std::cout << "[import] " << type << " cantilever " << cells[0] << "x" << cells[1] << "x" << cells[2] << ": "
              << model.numNodes() << " nodes, " << n << " free DOFs, import " << seconds << " s on "
              << comm()->getSize() << " rank(s); f1 = " << f[0]
              << " Hz; worst eigenvalue difference to ccx over 10 modes " << worst << "\n";

  // Craig-Bampton takes the imported model unchanged: tip retained, 10 fixed-interface modes.
  CraigBamptonOptions cb;
  cb.modes = 10;
  const ReducedModel red = craigBampton(model, model.mesh.nodeSets.at("TIP"), cb);
  const auto fr = denseFrequencies(red.K, red.M, red.size);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(fr[k], f[k] * (1 - 1e-9)) << "Craig-Bampton is an upper bound";
    EXPECT_LT(fr[k], f[k] * (1 + 1e-3)) << "mode " << k + 1;
  }
}

}  // namespace

TEST(Calculix, C3D20CantileverMatchesCcx) {
  checkAgainstCcx("C3D20", {6, 2, 2});
}

TEST(Calculix, C3D15CantileverMatchesCcx) {
  checkAgainstCcx("C3D15", {6, 2, 2});
}

// Reports the import time of a larger model (no timed assertion).
TEST(Calculix, LargerModelImportTime) {
  BeamDeck beam{"C3D20", {40, 6, 6}};
  const fs::path dir = fs::path(env("EPAPHE_IMPORT_WORKDIR")) / "ccx-large";
  int status = 0;
  if (comm()->getRank() == 0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    beam.write(dir.string());
    status = std::system(
        ("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 '" + env("EPAPHE_CCX") + "' -i mat > mat.log 2>&1").c_str());
  }
  Teuchos::broadcast(*comm(), 0, &status);
  ASSERT_EQ(status, 0);
  Stopwatch sw;
  const FullModel model = importCalculix({dir.string() + "/mat.inp", dir.string() + "/mat"}, "large", comm());
  const double seconds = sw.seconds();
  EXPECT_EQ(model.numFree, countLines(dir.string() + "/mat.dof"));
  if (comm()->getRank() == 0)
    std::cout << "[import] C3D20 40x6x6: " << model.numNodes() << " nodes, " << model.numFree << " free DOFs, "
              << model.K->getGlobalNumEntries() << " entries of K, import " << seconds << " s on " << comm()->getSize()
              << " rank(s)\n";
}
