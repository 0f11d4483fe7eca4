#include "Epaphe_HexElement.hpp"

#include "Epaphe_Error.hpp"

#include <cmath>

namespace epaphe {

void checkMaterial(const Material& mat, const char* context) {
  EPAPHE_REQUIRE(mat.density > 0 && std::isfinite(mat.density),
                 context << ": density = " << mat.density << " kg/m^3; it must be a finite value > 0");
  EPAPHE_REQUIRE(mat.young > 0 && std::isfinite(mat.young),
                 context << ": Young's modulus = " << mat.young << " Pa; it must be a finite value > 0");
  EPAPHE_REQUIRE(mat.poisson > -1.0 && mat.poisson < 0.5,
                 context << ": Poisson's ratio = " << mat.poisson << "; it must lie in (-1, 0.5)");
}

namespace {

const double kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                              {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// Shape functions N_a, their gradients dN_a/dx_j and the weight det(J) (Gauss weights are 1) at
/// Gauss point `gp` of the 2x2x2 rule.
double gaussPoint(const double x[8][3], int gp, double N[8], double dx[8][3]) {
  const double g = 1.0 / std::sqrt(3.0);
  const double r = kCorner[gp][0] * g, s = kCorner[gp][1] * g, t = kCorner[gp][2] * g;
  double dN[8][3];
  for (int a = 0; a < 8; ++a) {
    const double ra = 1 + kCorner[a][0] * r, sa = 1 + kCorner[a][1] * s, ta = 1 + kCorner[a][2] * t;
    N[a] = ra * sa * ta / 8;
    dN[a][0] = kCorner[a][0] * sa * ta / 8;
    dN[a][1] = ra * kCorner[a][1] * ta / 8;
    dN[a][2] = ra * sa * kCorner[a][2] / 8;
  }
  double J[3][3] = {};
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J[i][j] += dN[a][i] * x[a][j];  // J_ij = d x_j / d xi_i
  const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                     J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                     J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  EPAPHE_REQUIRE(det > 0, "hexahedron with first node at (" << x[0][0] << ", " << x[0][1] << ", " << x[0][2]
                                                            << ") is inverted or degenerate (det J = " << det
                                                            << "); check the node order (C3D8 / VTK_HEXAHEDRON)");
  double Ji[3][3];
  Ji[0][0] = (J[1][1] * J[2][2] - J[1][2] * J[2][1]) / det;
  Ji[0][1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) / det;
  Ji[0][2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / det;
  Ji[1][0] = (J[1][2] * J[2][0] - J[1][0] * J[2][2]) / det;
  Ji[1][1] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) / det;
  Ji[1][2] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) / det;
  Ji[2][0] = (J[1][0] * J[2][1] - J[1][1] * J[2][0]) / det;
  Ji[2][1] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) / det;
  Ji[2][2] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / det;
  for (int a = 0; a < 8; ++a)  // dN_a / dx_j = sum_i (J^-1)_ji dN_a/dxi_i
    for (int j = 0; j < 3; ++j) dx[a][j] = Ji[j][0] * dN[a][0] + Ji[j][1] * dN[a][1] + Ji[j][2] * dN[a][2];
  return det;
}

}  // namespace

void hex8StiffnessMass(const double x[8][3], const Material& mat, double* Ke, double* Me) {
  const double E = mat.young, nu = mat.poisson;
  const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  for (int i = 0; i < 24 * 24; ++i) Ke[i] = Me[i] = 0;
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = gaussPoint(x, gp, N, dx);
    // K_e += B^T D B w, written per node pair (a, b) with the isotropic D.
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const double dd = dx[a][0] * dx[b][0] + dx[a][1] * dx[b][1] + dx[a][2] * dx[b][2];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const double k = lam * dx[a][i] * dx[b][j] + mu * dx[a][j] * dx[b][i] + (i == j ? mu * dd : 0.0);
            Ke[(3 * a + i) * 24 + 3 * b + j] += k * w;
          }
        const double m = mat.density * N[a] * N[b] * w;
        for (int i = 0; i < 3; ++i) Me[(3 * a + i) * 24 + 3 * b + i] += m;
      }
  }
}

void hex8GeometricStiffness(const double x[8][3], const Material& mat, const double* u, double* Kg) {
  const double E = mat.young, nu = mat.poisson;
  const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  for (int i = 0; i < 24 * 24; ++i) Kg[i] = 0;
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = gaussPoint(x, gp, N, dx);
    double grad[3][3] = {};  // du_i / dx_j
    for (int a = 0; a < 8; ++a)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) grad[i][j] += u[3 * a + i] * dx[a][j];
    // sigma = lambda tr(eps) I + 2 mu eps, eps = (grad + grad^T) / 2
    const double tr = grad[0][0] + grad[1][1] + grad[2][2];
    double sigma[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) sigma[i][j] = mu * (grad[i][j] + grad[j][i]) + (i == j ? lam * tr : 0.0);
    // K_sigma,ab = (grad N_a . sigma . grad N_b) I_3 w
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        double k = 0;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) k += dx[a][i] * sigma[i][j] * dx[b][j];
        for (int i = 0; i < 3; ++i) Kg[(3 * a + i) * 24 + 3 * b + i] += k * w;
      }
  }
}

}  // namespace epaphe
