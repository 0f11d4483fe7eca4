#include "Epaphe_ThermalGrowth.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_HexElement.hpp"
#include "Epaphe_SolidElements.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

namespace epaphe {

void hex8ThermalLoad(const double x[8][3], const Material& mat, double alpha, const double theta[8], double* fe) {
  const double bulk3 = mat.young / (1 - 2 * mat.poisson);  // 3 lambda + 2 mu
  for (int i = 0; i < 24; ++i) fe[i] = 0;
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = hex8GaussPoint(x, gp, N, dx);
    double t = 0;
    for (int a = 0; a < 8; ++a) t += N[a] * theta[a];
    const double s = bulk3 * alpha * t * w;
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) fe[3 * a + d] += dx[a][d] * s;
  }
}

void solidThermalLoad(int nodes, const double (*x)[3], const Material& mat, double alpha, const double* theta,
                      double* fe) {
  const double bulk3 = mat.young / (1 - 2 * mat.poisson);  // 3 lambda + 2 mu
  for (int i = 0; i < 3 * nodes; ++i) fe[i] = 0;
  double N[20], dx[20][3];
  for (int gp = 0, n = solidGaussPoints(nodes); gp < n; ++gp) {
    const double w = solidGaussPoint(nodes, x, gp, N, dx);
    double t = 0;
    for (int a = 0; a < nodes; ++a) t += N[a] * theta[a];
    const double s = bulk3 * alpha * t * w;  // eq. 61 on the element's own shape functions (eq. 76)
    for (int a = 0; a < nodes; ++a)
      for (int d = 0; d < 3; ++d) fe[3 * a + d] += dx[a][d] * s;
  }
}

MultiVector thermalLoads(const FullModel& mech, double alpha, const std::vector<double>& fields, int count) {
  EPAPHE_REQUIRE(mech.material.has_value(), "body '"
                                                << mech.name
                                                << "': thermal growth needs the elements' material, and the "
                                                   "model is imported; give it one (the overload with a Material)");
  return thermalLoads(mech, *mech.material, alpha, fields, count);
}

MultiVector thermalLoads(const FullModel& mech, const Material& material, double alpha,
                         const std::vector<double>& fields, int count) {
  const auto map = mech.K->getRowMap();
  MultiVector F(map, static_cast<std::size_t>(count));
  auto f = F.getLocalViewHost(Tpetra::Access::ReadWrite);
  if (!mech.mesh.solids.empty()) {
    // an imported mesh: its elements' own shape functions (eq. 76)
    double x[20][3], theta[20], fe[60];
    for (const auto& e : mech.mesh.solids) {
      const int n = static_cast<int>(e.size());
      bool mine = false;
      for (int a = 0; a < n && !mine; ++a)
        for (int d = 0; d < 3 && !mine; ++d) {
          const int g = mech.eq[3 * e[a] + d];
          mine = g >= 0 && map->isNodeGlobalElement(g);
        }
      if (!mine) continue;
      for (int a = 0; a < n; ++a)
        for (int j = 0; j < 3; ++j) x[a][j] = mech.mesh.coords[e[a]][j];
      for (int c = 0; c < count; ++c) {
        for (int a = 0; a < n; ++a) theta[a] = fields[static_cast<std::size_t>(e[a]) * count + c];
        solidThermalLoad(n, x, material, alpha, theta, fe);
        for (int i = 0; i < 3 * n; ++i)
          if (const int g = mech.eq[3 * e[i / 3] + i % 3]; g >= 0 && map->isNodeGlobalElement(g))
            f(map->getLocalElement(g), c) += fe[i];
      }
    }
    return F;
  }
  EPAPHE_REQUIRE(!mech.mesh.hexes.empty() && mech.mesh.nodeIds.empty(),
                 "body '" << mech.name << "': thermal growth needs the model's elements, and its import gives none "
                          << "(Matrix Market and code_aster give matrices and nodes only); import it from CalculiX");
  double theta[8], fe[24];
  forEachOwnedHex(mech, *map, [&](const std::array<int, 8>& hex, const double(&x)[8][3]) {
    for (int c = 0; c < count; ++c) {
      for (int a = 0; a < 8; ++a) theta[a] = fields[static_cast<std::size_t>(hex[a]) * count + c];
      hex8ThermalLoad(x, material, alpha, theta, fe);
      for (int a = 0; a < 24; ++a)
        if (const int g = mech.eq[3 * hex[a / 3] + a % 3]; g >= 0 && map->isNodeGlobalElement(g))
          f(map->getLocalElement(g), c) += fe[a];
    }
  });
  return F;
}

std::vector<double> thermalGrowth(const FullModel& mech, double alpha, const ReducedThermalModel& thermal,
                                  const std::vector<int>& nodes, LinearSolver solver) {
  EPAPHE_REQUIRE(mech.material.has_value(), "body '"
                                                << mech.name
                                                << "': thermal growth needs the elements' material, and the "
                                                   "model is imported; give it one (the overload with a Material)");
  return thermalGrowth(mech, *mech.material, alpha, thermal, nodes, solver);
}

std::vector<double> thermalGrowth(const FullModel& mech, const Material& material, double alpha,
                                  const ReducedThermalModel& thermal, const std::vector<int>& nodes,
                                  LinearSolver solver) {
  const int m = thermal.numModes();
  EPAPHE_REQUIRE(thermal.numNodes == mech.numNodes(), "body '" << mech.name << "': its thermal model has "
                                                               << thermal.numNodes << " nodes and its mechanical model "
                                                               << mech.numNodes() << "; they must share the mesh");
  const MultiVector F = thermalLoads(mech, material, alpha, thermal.basis, m);
  MultiVector U(F.getMap(), static_cast<std::size_t>(m));
  makeSolver(mech.K, solver, "K of body '" + mech.name + "'")->solve(F, U);
  const auto map = U.getMap();
  auto u = U.getLocalViewHost(Tpetra::Access::ReadOnly);
  std::vector<double> local(3 * nodes.size() * static_cast<std::size_t>(m), 0.0), G(local.size(), 0.0);
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (int d = 0; d < 3; ++d)
      if (const int g = mech.eq[3 * nodes[k] + d]; g >= 0 && map->isNodeGlobalElement(g))
        for (int i = 0; i < m; ++i) local[(3 * k + d) * m + i] = u(map->getLocalElement(g), i);
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), G.data());
  return G;
}

}  // namespace epaphe
