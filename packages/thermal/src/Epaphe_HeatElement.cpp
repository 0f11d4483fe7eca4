#include "Epaphe_HeatElement.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_HexElement.hpp"

#include <cmath>

namespace epaphe {

const int kHexFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

double ThermalMaterial::effusivity() const {
  return std::sqrt(conductivity * density * specificHeat);
}

void checkThermalMaterial(const ThermalMaterial& mat, const char* context) {
  EPAPHE_REQUIRE(mat.conductivity > 0 && std::isfinite(mat.conductivity),
                 context << ": conductivity = " << mat.conductivity << " W/(m K); it must be a finite value > 0");
  EPAPHE_REQUIRE(mat.specificHeat > 0 && std::isfinite(mat.specificHeat),
                 context << ": specific heat = " << mat.specificHeat << " J/(kg K); it must be a finite value > 0");
  EPAPHE_REQUIRE(mat.density > 0 && std::isfinite(mat.density),
                 context << ": density = " << mat.density << " kg/m^3; it must be a finite value > 0");
}

void hex8Heat(const double x[8][3], const ThermalMaterial& mat, double* Ke, double* Ce) {
  const double rc = mat.density * mat.specificHeat;
  for (int i = 0; i < 64; ++i) Ke[i] = Ce[i] = 0;
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = hex8GaussPoint(x, gp, N, dx);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        Ke[a * 8 + b] += mat.conductivity * (dx[a][0] * dx[b][0] + dx[a][1] * dx[b][1] + dx[a][2] * dx[b][2]) * w;
        Ce[a * 8 + a] += rc * N[a] * N[b] * w;  // C_aa = sum_b (rc N_a N_b): row-sum lumping (eq. 57)
      }
  }
}

void quad4Face(const double x[4][3], double* He, double* area) {
  const double g = 1.0 / std::sqrt(3.0);
  const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int i = 0; i < 16; ++i) He[i] = 0;
  for (int a = 0; a < 4; ++a) area[a] = 0;
  for (int gp = 0; gp < 4; ++gp) {
    const double r = corner[gp][0] * g, s = corner[gp][1] * g;
    double N[4], tr[3] = {0, 0, 0}, ts[3] = {0, 0, 0};
    for (int a = 0; a < 4; ++a) {
      const double ra = 1 + corner[a][0] * r, sa = 1 + corner[a][1] * s;
      N[a] = ra * sa / 4;
      for (int j = 0; j < 3; ++j) {
        tr[j] += corner[a][0] * sa / 4 * x[a][j];
        ts[j] += ra * corner[a][1] / 4 * x[a][j];
      }
    }
    const double n[3] = {tr[1] * ts[2] - tr[2] * ts[1], tr[2] * ts[0] - tr[0] * ts[2], tr[0] * ts[1] - tr[1] * ts[0]};
    const double w = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 4; ++a) {
      area[a] += N[a] * w;
      for (int b = 0; b < 4; ++b) He[a * 4 + b] += N[a] * N[b] * w;
    }
  }
}

}  // namespace epaphe
