// The thermal model and its growth on imported CalculiX meshes (docs/theory/heat.md eqs. 75-77),
// against the built-in hexahedral mesh of the same bar and against CalculiX (ccx) itself:
//
//  * SameBarAsBuiltIn: a 20 x 4 x 4 mm titanium bar, held at T_ref on x = 0, convecting on y = b to
//    a warmer ambient, heated by 1 W at a corner of its tip. Written as a CalculiX input of C3D8
//    (the built-in mesh's own hexahedra), C3D6 (each hexahedron as 2 wedges), C3D4 (6 tetrahedra)
//    and C3D10 (those tetrahedra with their mid-side nodes), read back by readCalculixInput. The
//    C3D8 model is the built-in one: temperatures, steady and transient, to round-off (1e-10 of the
//    rise); the others are other discretizations of the same bar: the steady tip temperature within
//    3 % of the hexahedra's, C3D10 equal to C3D4 (the same linear corners) to round-off, and the
//    temperatures of C3D10's mid-side nodes the means of their edges'. The growth loads of the
//    imported path (the mesh's solids) on the built-in bar's K are the built-in path's to 1e-12.
//  * CalculixSteadyHeat: ccx *HEAT TRANSFER, STEADY STATE on the C3D4 and C3D6 bars (fixed
//    temperature *BOUNDARY 11, *CFLUX at the tip corner, *FILM on the y = b faces): the same linear
//    elements, so every node's temperature agrees with Epaphe's reduced model's steady state (which is
//    the full model's: the static responses are in the basis) to the 6 digits ccx prints (1e-5).
//  * CalculixThermalExpansion: the C3D10 and C3D15 bars imported from a ccx MATRIXSTORAGE run
//    (statically determinate support), Epaphe's growth of every node under the steady temperature of
//    the heated bar against ccx's *STATIC step with *EXPANSION under the same nodal temperatures
//    (*INITIAL CONDITIONS, TYPE=TEMPERATURE at T_ref, *TEMPERATURE in the step): within 1e-5 of the
//    largest displacement; and a bar heated uniformly (convection alone, no input) grows by
//    alpha L theta to 1e-9.
//  * CalculixGrowthAsBuiltIn: the C3D8 bar imported from ccx's matrices (clamped at x = 0) against the
//    built-in bar: the growth of every node under the heated bar's steady temperature within 1e-6 of the
//    largest (the same hexahedra; ccx's K against Epaphe's).
// The ccx tests need EPAPHE_CCX (the ccx binary) and EPAPHE_THERMAL_WORKDIR.
#include "Epaphe_BuiltInMeshes.hpp"
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_SolidElements.hpp"
#include "Epaphe_ThermalGrowth.hpp"
#include "Epaphe_ThermalModel.hpp"
#include "Epaphe_ThermalReduction.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

using namespace epaphe;
namespace fs = std::filesystem;

namespace {

const double kL = 0.02, kB = 0.004;                        // bar length and side (m)
const ThermalMaterial kTitanium{7.0, 560.0, 4430.0};       // k, c, rho
const double kE = 1.1e11, kNu = 0.34, kAlpha = 8.6e-6;     // the growth's material
const double kRef = 20.0, kAmbient = 50.0, kFilm = 500.0;  // T_ref, T_inf, h
const double kPower = 1.0;                                 // W at the tip corner

Teuchos::RCP<const Teuchos::Comm<int>> comm() {
  return Teuchos::DefaultComm<int>::getComm();
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

/// The built-in bar, 10 x 2 x 2 hexahedra.
Mesh builtInBar() {
  return makeBoxMesh({0, 0, 0}, {kL, kB, kB}, {10, 2, 2});
}

double signedVolume(const Mesh& m, const std::vector<int>& e) {
  const auto& a = m.coords[e[0]];
  double u[3][3];
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) u[k][j] = m.coords[e[k + 1]][j] - a[j];
  return u[0][0] * (u[1][1] * u[2][2] - u[1][2] * u[2][1]) - u[0][1] * (u[1][0] * u[2][2] - u[1][2] * u[2][0]) +
         u[0][2] * (u[1][0] * u[2][1] - u[1][1] * u[2][0]);
}

/// The bar's elements of a CalculiX type on the built-in mesh's nodes (mid-side nodes appended):
/// C3D8 its hexahedra, C3D6 two wedges each, C3D4 six tetrahedra each (about the diagonal 0-6), C3D10
/// those with mid-side nodes, C3D15 the wedges with theirs.
struct Bar {
  Mesh mesh;
  std::string type;
  std::vector<std::vector<int>> elements;
};

Bar makeBar(const std::string& type) {
  Bar bar{builtInBar(), type, {}};
  Mesh& m = bar.mesh;
  for (const auto& h : m.hexes) {
    if (type == "C3D8" || type == "C3D20") {
      bar.elements.push_back({h.begin(), h.end()});
    } else if (type == "C3D6" || type == "C3D15") {
      bar.elements.push_back({h[0], h[1], h[2], h[4], h[5], h[6]});
      bar.elements.push_back({h[0], h[2], h[3], h[4], h[6], h[7]});
    } else {
      const int t[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
      for (const auto& k : t) {
        std::vector<int> e = {h[k[0]], h[k[1]], h[k[2]], h[k[3]]};
        if (signedVolume(m, e) < 0) std::swap(e[1], e[2]);
        bar.elements.push_back(e);
      }
    }
  }
  const int nodes = type == "C3D10" ? 10 : type == "C3D15" ? 15 : type == "C3D20" ? 20 : 0;
  if (nodes > 0) {
    std::map<std::array<int, 2>, int> mid;
    for (auto& e : bar.elements) {
      const int c = static_cast<int>(e.size());
      for (const auto& edge : solidEdges(nodes)) {
        std::array<int, 2> key{std::min(e[edge[0]], e[edge[1]]), std::max(e[edge[0]], e[edge[1]])};
        auto [it, fresh] = mid.emplace(key, m.numNodes());
        if (fresh) {
          std::array<double, 3> x{};
          for (int j = 0; j < 3; ++j) x[j] = 0.5 * (m.coords[key[0]][j] + m.coords[key[1]][j]);
          m.coords.push_back(x);
        }
        e.push_back(it->second);
      }
      (void)c;
    }
  }
  return bar;
}

/// The nodes with coordinate j at value v.
std::vector<int> nodesAt(const Mesh& m, int j, double v) {
  std::vector<int> out;
  for (int n = 0; n < m.numNodes(); ++n)
    if (std::abs(m.coords[n][j] - v) < 1e-12) out.push_back(n);
  return out;
}

/// The tip corner heated: (L, b, b).
int tipCorner(const Mesh& m) {
  for (int n = 0; n < m.numNodes(); ++n)
    if (std::abs(m.coords[n][0] - kL) + std::abs(m.coords[n][1] - kB) + std::abs(m.coords[n][2] - kB) < 1e-12) return n;
  throw Error("no tip corner");
}

/// Writes the bar as a CalculiX input (nodes numbered from 1 in mesh order) with node sets X0, XL, YB
/// (x = 0, x = L, y = b) and the elements; `tail` is appended (material, steps).
void writeInp(const Bar& bar, const std::string& path, const std::string& tail) {
  std::ofstream out(path);
  out.precision(12);  // ccx reads fields of up to 20 characters
  out << "*NODE, NSET=NALL\n";
  for (int n = 0; n < bar.mesh.numNodes(); ++n)
    out << n + 1 << ", " << bar.mesh.coords[n][0] << ", " << bar.mesh.coords[n][1] << ", " << bar.mesh.coords[n][2]
        << "\n";
  out << "*ELEMENT, TYPE=" << bar.type << ", ELSET=EALL\n";
  for (std::size_t e = 0; e < bar.elements.size(); ++e) {
    out << e + 1;
    for (std::size_t a = 0; a < bar.elements[e].size(); ++a)
      out << (a > 0 && a % 15 == 0 ? ",\n" : ", ") << bar.elements[e][a] + 1;
    out << "\n";
  }
  auto nset = [&](const char* name, const std::vector<int>& nodes) {
    out << "*NSET, NSET=" << name << "\n";
    for (int n : nodes) out << n + 1 << ",\n";
  };
  nset("X0", nodesAt(bar.mesh, 0, 0.0));
  nset("XL", nodesAt(bar.mesh, 0, kL));
  nset("YB", nodesAt(bar.mesh, 1, kB));
  out << tail;
}

/// The thermal definition of the bar: held at x = 0, convection on y = b (unless `film` is false).
ThermalDefinition barDefinition(const Mesh& m, bool film = true) {
  ThermalDefinition def;
  def.material = kTitanium;
  def.referenceTemperature = kRef;
  def.fixedNodes = nodesAt(m, 0, 0.0);
  if (film) def.convection.push_back({nodesAt(m, 1, kB), kFilm, kAmbient});
  return def;
}

/// The steady coordinates of the reduced model under `power` at its heated nodes and the ambient.
std::vector<double> steadyEta(const ReducedThermalModel& r, const std::vector<double>& power) {
  std::vector<double> eta(static_cast<std::size_t>(r.numModes()));
  for (int i = 0; i < r.numModes(); ++i) {
    double f = r.ambientLoad[i];
    for (std::size_t k = 0; k < power.size(); ++k) f += r.heatedRows[k * r.numModes() + i] * power[k];
    eta[i] = f / r.rate[i];
  }
  return eta;
}

struct Thermal {
  ThermalFullModel full;
  ReducedThermalModel reduced;
  std::vector<double> eta;  // steady
};

Thermal barThermal(Mesh mesh, const std::vector<int>& heated, const std::vector<double>& power, bool film = true) {
  Thermal t;
  const ThermalDefinition def = barDefinition(mesh, film);
  t.full = assembleThermalModel("bar", std::move(mesh), def, comm());
  ThermalReductionOptions opt;
  opt.modes = 10;
  t.reduced = reduceThermal(t.full, heated, opt);
  t.eta = steadyEta(t.reduced, power);
  return t;
}

/// kPower at the tip corner.
Thermal barThermal(Mesh mesh, int heated, bool film = true) {
  return barThermal(std::move(mesh), {heated}, {kPower}, film);
}

/// kPower spread uniformly over the tip face x = L (each node its area's share, faceAreas).
Thermal tipFluxThermal(const Mesh& mesh) {
  const std::vector<int> tip = nodesAt(mesh, 0, kL);
  std::vector<double> power = faceAreas(mesh, tip);
  for (double& p : power) p *= kPower / (kB * kB);
  return barThermal(mesh, tip, power);
}

/// The temperatures printed by *NODE PRINT ... NT in a ccx .dat, by node number.
std::map<int, double> readNodalTemperatures(const std::string& dat) {
  std::ifstream in(dat);
  std::map<int, double> T;
  std::string line;
  bool block = false;
  while (std::getline(in, line)) {
    if (line.find("temperatures for set") != std::string::npos) {
      block = true;
      continue;
    }
    if (!block) continue;
    std::istringstream s(line);
    int n = 0;
    double v = 0;
    if (s >> n >> v)
      T[n] = v;
    else if (!T.empty())
      block = false;
  }
  return T;
}

std::string runCcx(const std::string& dir, const std::string& job) {
  const std::string cmd =
      "cd '" + dir + "' && OMP_NUM_THREADS=1 '" + env("EPAPHE_CCX") + "' -i " + job + " > " + job + ".log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << "ccx failed; see " << dir << "/" << job << ".log";
  return dir + "/" + job;
}

std::string workdir(const std::string& name) {
  const std::string root = env("EPAPHE_THERMAL_WORKDIR");
  const fs::path dir = fs::path(root.empty() ? "." : root) / name;
  fs::create_directories(dir);
  return dir.string();
}

/// *FILM lines for the boundary faces on y = b (ccx face numbers, solidFaces' order).
std::string filmLines(const Bar& bar) {
  std::ostringstream out;
  out << "*FILM\n";
  const int c = solidCorners(static_cast<int>(bar.elements[0].size()));
  for (std::size_t e = 0; e < bar.elements.size(); ++e) {
    const auto& faces = solidFaces(c);
    for (std::size_t f = 0; f < faces.size(); ++f) {
      bool on = true;
      for (int a = 0; a < 4 && on; ++a)
        if (faces[f][a] >= 0) on = std::abs(bar.mesh.coords[bar.elements[e][faces[f][a]]][1] - kB) < 1e-12;
      if (on) out << e + 1 << ", F" << f + 1 << ", " << kAmbient << ", " << kFilm << "\n";
    }
  }
  return out.str();
}

}  // namespace

TEST(ImportedThermal, SameBarAsBuiltIn) {
  const fs::path dir = workdir("same-bar");
  const Mesh hexMesh = builtInBar();
  const int tip = tipCorner(hexMesh);
  const Thermal hex = barThermal(hexMesh, tip);
  const Thermal hexFlux = tipFluxThermal(hexMesh);
  const double rise = hex.reduced.temperature(tip, hex.eta) - kRef;
  const double fluxRise = hexFlux.reduced.temperature(tip, hexFlux.eta) - kRef;
  ASSERT_GT(rise, 1.0);
  ASSERT_GT(fluxRise, 1.0);
  std::map<std::string, Thermal> imported;
  for (const std::string type : {"C3D8", "C3D6", "C3D4", "C3D10"}) {
    const Bar bar = makeBar(type);
    const std::string path = (dir / (type + ".inp")).string();
    writeInp(bar, path, "");
    const CalculixInput in = readCalculixInput(path);
    ASSERT_EQ(in.mesh.solids.size(), bar.elements.size());
    imported[type] = barThermal(in.mesh, tipCorner(in.mesh));
    const Thermal& t = imported[type];
    if (type == "C3D8") {
      double worst = 0;
      for (int n = 0; n < hexMesh.numNodes(); ++n)
        worst = std::max(worst, std::abs(t.reduced.temperature(n, t.eta) - hex.reduced.temperature(n, hex.eta)));
      std::cout << "C3D8 against the built-in mesh, 1 W at the tip corner: every node within " << worst / rise
                << " of the rise (" << rise << " K)\n";
      EXPECT_LT(worst, 1e-10 * rise);
      // transient: the same model, the same integration
      ThermalIntegrator a(hex.reduced), b(t.reduced);
      double transient = 0;
      for (int step = 0; step < 50; ++step) {
        a.advance(0.02, &kPower);
        b.advance(0.02, &kPower);
        for (int n = 0; n < hexMesh.numNodes(); ++n)
          transient = std::max(transient, std::abs(a.temperature(n) - b.temperature(n)));
      }
      std::cout << "  transient (1 s): within " << transient / rise << " of the steady rise\n";
      EXPECT_LT(transient, 1e-10 * rise);
    }
    // another discretization of the same bar: 1 W spread over the tip face, every node of the
    // hexahedral mesh (the imported meshes' first nodes) against the hexahedra's
    const Thermal f = tipFluxThermal(in.mesh);
    double worst = 0;
    for (int n = 0; n < hexMesh.numNodes(); ++n)
      worst = std::max(worst, std::abs(f.reduced.temperature(n, f.eta) - hexFlux.reduced.temperature(n, hexFlux.eta)));
    std::cout << type << ", 1 W over the tip face: every node within " << worst / fluxRise
              << " of the hexahedra's tip rise (" << fluxRise << " K)\n";
    EXPECT_LT(worst, (type == "C3D8" ? 1e-10 : 0.03) * fluxRise) << type;
  }
  // C3D10's corners are C3D4's linear tetrahedra; its mid-side nodes the means of their edges'
  const Bar b10 = makeBar("C3D10");
  const Thermal& t4 = imported["C3D4"];
  const Thermal& t10 = imported["C3D10"];
  double corners = 0, mids = 0;
  for (int n = 0; n < hexMesh.numNodes(); ++n)
    corners = std::max(corners, std::abs(t10.reduced.temperature(n, t10.eta) - t4.reduced.temperature(n, t4.eta)));
  for (const auto& e : b10.elements)
    for (std::size_t k = 0; k < 6; ++k) {
      const auto& edge = solidEdges(10)[k];
      const double mean =
          0.5 * (t10.reduced.temperature(e[edge[0]], t10.eta) + t10.reduced.temperature(e[edge[1]], t10.eta));
      mids = std::max(mids, std::abs(t10.reduced.temperature(e[4 + k], t10.eta) - mean));
    }
  std::cout << "C3D10 against C3D4 at the corners: " << corners / rise << "; mid-side nodes against their edges' "
            << "mean: " << mids / rise << "\n";
  EXPECT_LT(corners, 1e-9 * rise);
  EXPECT_LT(mids, 1e-12 * rise);

  // the growth loads: the imported path (the mesh's solids) on the built-in bar's model
  FullModel mech = assembleHexModel("bar", hexMesh, Material{4430, kE, kNu}, nodesAt(hexMesh, 0, 0.0), comm());
  const MultiVector builtIn = thermalLoads(mech, kAlpha, hex.reduced.basis, hex.reduced.numModes());
  for (const auto& h : mech.mesh.hexes) mech.mesh.solids.push_back({h.begin(), h.end()});
  const MultiVector solids =
      thermalLoads(mech, Material{4430, kE, kNu}, kAlpha, hex.reduced.basis, hex.reduced.numModes());
  std::vector<double> nb(builtIn.getNumVectors()), nd(builtIn.getNumVectors());
  MultiVector diff(solids, Teuchos::Copy);
  diff.update(-1.0, builtIn, 1.0);
  builtIn.normInf(Teuchos::ArrayView<double>(nb));
  diff.normInf(Teuchos::ArrayView<double>(nd));
  for (std::size_t i = 0; i < nb.size(); ++i) EXPECT_LE(nd[i], 1e-12 * nb[i]) << "column " << i;
}

TEST(ImportedThermal, CalculixSteadyHeat) {
  ASSERT_FALSE(env("EPAPHE_CCX").empty()) << "set EPAPHE_CCX to the ccx binary";
  struct Case {
    std::string type;
    bool film;
    double tolerance;  // of the rise
  };
  // ccx integrates a triangular face's film at its centroid (H_ab = h A / 9; Epaphe's exact rule, eq. 77,
  // h A / 12 (1 + delta_ab)): with the film the tetrahedra differ by that rule's error, 0.56 % measured
  // (2.8e-7 with ccx's rule put in Epaphe's place); without it and on quadrilateral faces they are the
  // same discrete problem
  for (const Case& c : {Case{"C3D4", false, 1e-5}, Case{"C3D8", true, 1e-5}, Case{"C3D4", true, 1e-2}}) {
    const std::string dir = workdir("steady-" + c.type + (c.film ? "-film" : ""));
    const Bar bar = makeBar(c.type);
    const int tip = tipCorner(bar.mesh);
    std::ostringstream tail;
    tail.precision(12);
    tail << "*MATERIAL, NAME=TI\n*CONDUCTIVITY\n"
         << kTitanium.conductivity << "\n*DENSITY\n"
         << kTitanium.density << "\n*SPECIFIC HEAT\n"
         << kTitanium.specificHeat << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=TI\n"
         << "*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, " << kRef << "\n*STEP\n*HEAT TRANSFER, STEADY STATE\n"
         << "*BOUNDARY\nX0, 11, 11, " << kRef << "\n*CFLUX\n"
         << tip + 1 << ", 11, " << kPower << "\n"
         << (c.film ? filmLines(bar) : "") << "*NODE PRINT, NSET=NALL\nNT\n*END STEP\n";
    writeInp(bar, dir + "/heat.inp", tail.str());
    writeInp(bar, dir + "/geometry.inp", "");  // Epaphe reads no temperature *BOUNDARY (DOF 11)
    const std::string job = runCcx(dir, "heat");
    const std::map<int, double> T = readNodalTemperatures(job + ".dat");
    ASSERT_EQ(static_cast<int>(T.size()), bar.mesh.numNodes()) << job << ".dat";
    const CalculixInput in = readCalculixInput(dir + "/geometry.inp");
    const Thermal t = barThermal(in.mesh, tip, c.film);
    const double rise = T.at(tip + 1) - kRef;
    double worst = 0;
    for (int n = 0; n < bar.mesh.numNodes(); ++n)
      worst = std::max(worst, std::abs(t.reduced.temperature(n, t.eta) - T.at(n + 1)));
    std::cout << c.type << (c.film ? " with" : " without") << " the film: ccx's steady tip temperature "
              << T.at(tip + 1) << " (rise " << rise << " K); Epaphe's every node within " << worst / rise
              << " of the rise\n";
    EXPECT_GT(rise, 1.0);
    EXPECT_LT(worst, c.tolerance * rise) << c.type;
  }
}

TEST(ImportedThermal, CalculixThermalExpansion) {
  ASSERT_FALSE(env("EPAPHE_CCX").empty()) << "set EPAPHE_CCX to the ccx binary";
  for (const std::string type : {"C3D10", "C3D15"}) {
    const std::string dir = workdir("expansion-" + type);
    const Bar bar = makeBar(type);
    const int tip = tipCorner(bar.mesh);
    // a statically determinate support: x = 0 slides in its plane, the origin is held, (0, b, 0) in z
    // and (0, 0, b) in y: the thermal expansion is free
    int yb = -1, zb = -1, origin = -1;
    for (int n : nodesAt(bar.mesh, 0, 0.0)) {
      const auto& x = bar.mesh.coords[n];
      if (x[1] == 0 && x[2] == 0) origin = n;
      if (std::abs(x[1] - kB) < 1e-12 && x[2] == 0) yb = n;
      if (x[1] == 0 && std::abs(x[2] - kB) < 1e-12) zb = n;
    }
    ASSERT_TRUE(origin >= 0 && yb >= 0 && zb >= 0);
    std::ostringstream material;
    material.precision(12);
    material << "*MATERIAL, NAME=TI\n*ELASTIC\n"
             << kE << ", " << kNu << "\n*EXPANSION\n"
             << kAlpha << "\n*DENSITY\n"
             << kTitanium.density << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=TI\n*BOUNDARY\nX0, 1, 1\n"
             << origin + 1 << ", 2, 3\n"
             << yb + 1 << ", 3, 3\n"
             << zb + 1 << ", 2, 2\n";
    writeInp(bar, dir + "/mat.inp", material.str() + "*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n");
    runCcx(dir, "mat");
    const FullModel mech = importCalculix({dir + "/mat.inp", dir + "/mat"}, "bar", comm());
    ASSERT_EQ(mech.mesh.solids.size(), bar.elements.size());
    const CalculixMaterial cm = readCalculixInput(dir + "/mat.inp").material;
    EXPECT_TRUE(cm.problem.empty()) << cm.problem;
    EXPECT_EQ(cm.young, kE);
    EXPECT_EQ(cm.poisson, kNu);
    EXPECT_EQ(cm.expansion, kAlpha);
    const Material mat{cm.density, cm.young, cm.poisson};

    // the heated bar's steady temperature, its growth at every node against ccx's under it
    const Thermal t = barThermal(mech.mesh, tip);
    std::vector<int> all(static_cast<std::size_t>(mech.numNodes()));
    for (int n = 0; n < mech.numNodes(); ++n) all[n] = n;
    const std::vector<double> G = thermalGrowth(mech, mat, kAlpha, t.reduced, all, LinearSolver::Klu2);
    const int m = t.reduced.numModes();
    std::ostringstream temps;
    temps.precision(12);
    temps << "*TEMPERATURE\n";
    for (int n = 0; n < mech.numNodes(); ++n) temps << n + 1 << ", " << t.reduced.temperature(n, t.eta) << "\n";
    writeInp(bar, dir + "/grow.inp",
             material.str() + "*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, " + std::to_string(kRef) +
                 "\n*STEP\n*STATIC\n" + temps.str() + "*NODE PRINT, NSET=NALL\nU\n*END STEP\n");
    const std::string job = runCcx(dir, "grow");
    const std::vector<double> u = readCalculixDisplacements(job + ".dat", mech.mesh);
    double largest = 0, worst = 0;
    for (int n = 0; n < mech.numNodes(); ++n)
      for (int d = 0; d < 3; ++d) {
        double g = 0;
        for (int i = 0; i < m; ++i) g += G[(3 * static_cast<std::size_t>(n) + d) * m + i] * t.eta[i];
        largest = std::max(largest, std::abs(u[3 * n + d]));
        worst = std::max(worst, std::abs(g - u[3 * n + d]));
      }
    std::cout << type << ": ccx's largest thermal displacement " << largest << " m; Epaphe's growth within "
              << worst / largest << " of it at every node\n";
    EXPECT_GT(largest, 1e-8);
    EXPECT_LT(worst, 1e-5 * largest) << type;

    // uniform heating: convection alone (no input, no fixed face) brings the bar to T_inf
    ThermalDefinition def;
    def.material = kTitanium;
    def.referenceTemperature = kRef;
    def.convection.push_back({nodesAt(mech.mesh, 1, kB), kFilm, kAmbient});
    const ThermalFullModel full = assembleThermalModel("bar", mech.mesh, def, comm());
    const ReducedThermalModel r = reduceThermal(full, {}, ThermalReductionOptions{});
    const std::vector<double> eta = steadyEta(r, {});
    const std::vector<double> Gu = thermalGrowth(mech, mat, kAlpha, r, {tip}, LinearSolver::Klu2);
    double ux = 0;
    for (int i = 0; i < r.numModes(); ++i) ux += Gu[static_cast<std::size_t>(i)] * eta[i];
    const double expected = kAlpha * kL * (kAmbient - kRef);
    std::cout << "  uniform heating: tip grows " << ux << " m, alpha L theta " << expected << " m\n";
    EXPECT_NEAR(ux, expected, 1e-9 * expected) << type;
  }
}

// (a) with the growth: the bar's C3D8 model imported from ccx's matrices (clamped at x = 0) against the
// built-in bar assembled by Epaphe (the same hexahedra, the same clamp): the thermal growth G eta of every
// node under the heated bar's steady temperature, the imported path (the mesh's solids, the input's
// *ELASTIC and *EXPANSION, ccx's K) against the built-in one
TEST(ImportedThermal, CalculixGrowthAsBuiltIn) {
  ASSERT_FALSE(env("EPAPHE_CCX").empty()) << "set EPAPHE_CCX to the ccx binary";
  const std::string dir = workdir("growth-C3D8");
  const Bar bar = makeBar("C3D8");
  std::ostringstream material;
  material.precision(12);
  material << "*MATERIAL, NAME=TI\n*ELASTIC\n"
           << kE << ", " << kNu << "\n*EXPANSION\n"
           << kAlpha << "\n*DENSITY\n"
           << kTitanium.density << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=TI\n*BOUNDARY\nX0, 1, 3\n";
  writeInp(bar, dir + "/mat.inp", material.str() + "*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n");
  runCcx(dir, "mat");
  const FullModel imported = importCalculix({dir + "/mat.inp", dir + "/mat"}, "bar", comm());
  const CalculixMaterial cm = readCalculixInput(dir + "/mat.inp").material;
  const Mesh hexMesh = builtInBar();
  const FullModel builtIn =
      assembleHexModel("bar", hexMesh, Material{kTitanium.density, kE, kNu}, nodesAt(hexMesh, 0, 0.0), comm());
  const int tip = tipCorner(hexMesh);
  const Thermal a = barThermal(imported.mesh, tip), b = barThermal(hexMesh, tip);
  std::vector<int> all(static_cast<std::size_t>(hexMesh.numNodes()));
  for (int n = 0; n < hexMesh.numNodes(); ++n) all[n] = n;
  const std::vector<double> Ga = thermalGrowth(imported, Material{cm.density, cm.young, cm.poisson}, cm.expansion,
                                               a.reduced, all, LinearSolver::Klu2);
  const std::vector<double> Gb = thermalGrowth(builtIn, kAlpha, b.reduced, all, LinearSolver::Klu2);
  const int m = a.reduced.numModes();
  ASSERT_EQ(m, b.reduced.numModes());
  double largest = 0, worst = 0;
  for (std::size_t r = 0; r < 3 * all.size(); ++r) {
    double ua = 0, ub = 0;
    for (int i = 0; i < m; ++i) {
      ua += Ga[r * m + i] * a.eta[i];
      ub += Gb[r * m + i] * b.eta[i];
    }
    largest = std::max(largest, std::abs(ub));
    worst = std::max(worst, std::abs(ua - ub));
  }
  std::cout << "C3D8 imported from ccx against the built-in bar: the growth of every node within " << worst / largest
            << " of the largest (" << largest << " m)\n";
  EXPECT_GT(largest, 1e-8);
  EXPECT_LT(worst, 1e-6 * largest);
}
