#include "Epaphe_HexElement.hpp"

#include "Epaphe_Inverse3.hpp"

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

}  // namespace

double hex8GaussPoint(const double x[8][3], int gp, double N[8], double dx[8][3]) {
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
  double Ji[3][3];
  const double det = inverse3(J, Ji);
  EPAPHE_REQUIRE(det > 0, "hexahedron with first node at (" << x[0][0] << ", " << x[0][1] << ", " << x[0][2]
                                                            << ") is inverted or degenerate (det J = " << det
                                                            << "); check the node order (C3D8 / VTK_HEXAHEDRON)");
  for (int a = 0; a < 8; ++a)  // dN_a / dx_j = sum_i (J^-1)_ji dN_a/dxi_i
    for (int j = 0; j < 3; ++j) dx[a][j] = Ji[j][0] * dN[a][0] + Ji[j][1] * dN[a][1] + Ji[j][2] * dN[a][2];
  return det;
}

namespace {

/// J (J_ij = d x_j / d xi_i) at the element's centre: its inverse Ji and its determinant.
double centreJacobian(const double x[8][3], double Ji[3][3]) {
  double J[3][3] = {};
  for (int a = 0; a < 8; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J[i][j] += kCorner[a][i] / 8 * x[a][j];
  return inverse3(J, Ji);
}

/// The isotropic stiffness between two shape functions of gradients ga, gb, directions i and j:
/// lambda ga_i gb_j + mu ga_j gb_i + mu (ga . gb) delta_ij.
inline double pairStiffness(const double* ga, const double* gb, int i, int j, double lam, double mu) {
  return lam * ga[i] * gb[j] + mu * ga[j] * gb[i] +
         (i == j ? mu * (ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2]) : 0.0);
}

/// K_e with the nine incompatible modes P_k = 1 - xi_k^2 (k = 1..3, three directions each) condensed:
/// K_e = K_uu - K_ua K_aa^-1 K_au (eq. (73)). Their gradients use J at the centre, scaled by
/// det J_0 / det J (Taylor, Beresford & Wilson 1976), so that int B_a dV = 0: a constant strain
/// leaves them at rest and the element passes the patch test on any shape.
void incompatibleStiffness(const double x[8][3], double lam, double mu, double* Ke) {
  double J0i[3][3];
  const double det0 = centreJacobian(x, J0i);
  double Kua[24][9] = {}, Kaa[9][9] = {};
  const double g = 1.0 / std::sqrt(3.0);
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = hex8GaussPoint(x, gp, N, dx);
    // dP_k/dxi_i = -2 xi_k delta_ik; dP_k/dx_j = (J_0^-1)_jk dP_k/dxi_k det J_0 / det J
    double ga[3][3];
    for (int k = 0; k < 3; ++k) {
      const double dP = -2 * kCorner[gp][k] * g * det0 / w;
      for (int j = 0; j < 3; ++j) ga[k][j] = J0i[j][k] * dP;
    }
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) {
        for (int a = 0; a < 8; ++a)
          for (int j = 0; j < 3; ++j) Kua[3 * a + j][3 * k + i] += pairStiffness(dx[a], ga[k], j, i, lam, mu) * w;
        for (int l = 0; l < 3; ++l)
          for (int j = 0; j < 3; ++j) Kaa[3 * k + i][3 * l + j] += pairStiffness(ga[k], ga[l], i, j, lam, mu) * w;
      }
  }
  // X = K_aa^-1 K_au by Gauss-Jordan on the 9 x 9 symmetric positive definite block (no pivoting needed)
  double X[9][24];
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 24; ++c) X[r][c] = Kua[c][r];
  for (int p = 0; p < 9; ++p) {
    const double d = Kaa[p][p];
    for (int c = 0; c < 9; ++c) Kaa[p][c] /= d;
    for (int c = 0; c < 24; ++c) X[p][c] /= d;
    for (int r = 0; r < 9; ++r) {
      if (r == p) continue;
      const double f = Kaa[r][p];
      for (int c = 0; c < 9; ++c) Kaa[r][c] -= f * Kaa[p][c];
      for (int c = 0; c < 24; ++c) X[r][c] -= f * X[p][c];
    }
  }
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 24; ++c) {
      double s = 0;
      for (int k = 0; k < 9; ++k) s += Kua[r][k] * X[k][c];
      Ke[r * 24 + c] -= s;
    }
  for (int r = 0; r < 24; ++r)  // symmetric to round-off, then exactly
    for (int c = r + 1; c < 24; ++c) Ke[r * 24 + c] = Ke[c * 24 + r] = 0.5 * (Ke[r * 24 + c] + Ke[c * 24 + r]);
}

}  // namespace

void hex8StiffnessMass(const double x[8][3], const Material& mat, double* Ke, double* Me) {
  const double E = mat.young, nu = mat.poisson;
  const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  for (int i = 0; i < 24 * 24; ++i) Ke[i] = Me[i] = 0;
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = hex8GaussPoint(x, gp, N, dx);
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
  if (mat.formulation == HexFormulation::IncompatibleModes) incompatibleStiffness(x, lam, mu, Ke);
}

void hex8GeometricStiffness(const double x[8][3], const Material& mat, const double* u, double* Kg) {
  const double E = mat.young, nu = mat.poisson;
  const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  for (int i = 0; i < 24 * 24; ++i) Kg[i] = 0;
  for (int gp = 0; gp < 8; ++gp) {
    double N[8], dx[8][3];
    const double w = hex8GaussPoint(x, gp, N, dx);
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
