#include "Epaphe_SolidElements.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Inverse3.hpp"

#include <cmath>

namespace epaphe {
namespace {

/// A value and its derivatives along the three local coordinates.
struct D3 {
  double v = 0, d[3] = {0, 0, 0};
};
D3 operator+(D3 a, const D3& b) {
  a.v += b.v;
  for (int j = 0; j < 3; ++j) a.d[j] += b.d[j];
  return a;
}
D3 operator*(const D3& a, const D3& b) {
  D3 c;
  c.v = a.v * b.v;
  for (int j = 0; j < 3; ++j) c.d[j] = a.d[j] * b.v + a.v * b.d[j];
  return c;
}
D3 operator*(double s, D3 a) {
  a.v *= s;
  for (double& x : a.d) x *= s;
  return a;
}
D3 operator+(double s, D3 a) {
  a.v += s;
  return a;
}
D3 constant(double v) {
  D3 c;
  c.v = v;
  return c;
}
D3 variable(double v, int j) {
  D3 c;
  c.v = v;
  c.d[j] = 1;
  return c;
}

const std::vector<std::array<int, 2>> kNoEdges;
const std::vector<std::array<int, 2>> kTet10Edges = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
const std::vector<std::array<int, 2>> kWedge15Edges = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                                       {5, 3}, {0, 3}, {1, 4}, {2, 5}};
const std::vector<std::array<int, 2>> kHex20Edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                                     {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
const double kHexCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// The shape functions of the element at local coordinates (a, b, c).
void shapes(int nodes, const D3& a, const D3& b, const D3& c, D3* N) {
  if (nodes == 4 || nodes == 10) {
    const D3 L[4] = {1.0 + (-1.0) * (a + b + c), a, b, c};
    if (nodes == 4) {
      for (int i = 0; i < 4; ++i) N[i] = L[i];
      return;
    }
    for (int i = 0; i < 4; ++i) N[i] = L[i] * (2.0 * L[i] + constant(-1));
    for (int k = 0; k < 6; ++k) N[4 + k] = 4.0 * (L[kTet10Edges[k][0]] * L[kTet10Edges[k][1]]);
    return;
  }
  if (nodes == 6 || nodes == 15) {
    const D3 L[3] = {1.0 + (-1.0) * (a + b), a, b};
    const D3 lo = 0.5 * (1.0 + (-1.0) * c), hi = 0.5 * (1.0 + c);  // (1 -+ zeta) / 2
    if (nodes == 6) {
      for (int i = 0; i < 3; ++i) {
        N[i] = L[i] * lo;
        N[3 + i] = L[i] * hi;
      }
      return;
    }
    for (int i = 0; i < 3; ++i) {  // L (1 -+ zeta)(2 L - 2 -+ zeta) / 2
      N[i] = L[i] * lo * (2.0 * L[i] + (-1.0) * c + constant(-2));
      N[3 + i] = L[i] * hi * (2.0 * L[i] + c + constant(-2));
    }
    for (int k = 0; k < 3; ++k) {
      N[6 + k] = 4.0 * (L[k] * L[(k + 1) % 3] * lo);  // 2 L_i L_j (1 - zeta)
      N[9 + k] = 4.0 * (L[k] * L[(k + 1) % 3] * hi);
      N[12 + k] = L[k] * (1.0 + (-1.0) * (c * c));  // L_i (1 - zeta^2)
    }
    return;
  }
  const D3 x[3] = {a, b, c};
  if (nodes == 8) {
    for (int i = 0; i < 8; ++i) {
      D3 n = constant(0.125);
      for (int j = 0; j < 3; ++j) n = n * (1.0 + kHexCorner[i][j] * x[j]);
      N[i] = n;
    }
    return;
  }
  // 20 nodes: corners (1 + xi xi_i)(1 + eta eta_i)(1 + zeta zeta_i)(xi xi_i + eta eta_i + zeta zeta_i - 2) / 8;
  // a mid-side node at the middle of an edge along j: (1 - x_j^2) times the other two factors / 4
  for (int i = 0; i < 8; ++i) {
    D3 n = constant(0.125), sum = constant(-2);
    for (int j = 0; j < 3; ++j) {
      n = n * (1.0 + kHexCorner[i][j] * x[j]);
      sum = sum + kHexCorner[i][j] * x[j];
    }
    N[i] = n * sum;
  }
  for (int k = 0; k < 12; ++k) {
    const auto& e = kHex20Edges[k];
    D3 n = constant(0.25);
    for (int j = 0; j < 3; ++j) {
      const double mid = 0.5 * (kHexCorner[e[0]][j] + kHexCorner[e[1]][j]);
      n = n * (mid == 0 ? 1.0 + (-1.0) * (x[j] * x[j]) : 1.0 + mid * x[j]);
    }
    N[8 + k] = n;
  }
}

/// Point gp of the element's rule: local coordinates and weight.
void gaussPoint(int nodes, int gp, double p[3], double& w) {
  if (nodes == 4 || nodes == 10) {
    const double a = 0.1381966011250105, b = 0.5854101966249685;
    p[0] = p[1] = p[2] = a;
    if (gp > 0) p[gp - 1] = b;
    w = 1.0 / 24.0;
    return;
  }
  if (nodes == 6 || nodes == 15) {
    const double tri[3][2] = {{1.0 / 6, 1.0 / 6}, {2.0 / 3, 1.0 / 6}, {1.0 / 6, 2.0 / 3}};
    const int line = nodes == 6 ? 2 : 3;
    const double g2[2] = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)}, w2[2] = {1, 1};
    const double g3[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)}, w3[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    const int t = gp / line, l = gp % line;
    p[0] = tri[t][0];
    p[1] = tri[t][1];
    p[2] = line == 2 ? g2[l] : g3[l];
    w = (1.0 / 6) * (line == 2 ? w2[l] : w3[l]);
    return;
  }
  const int n = nodes == 8 ? 2 : 3;
  const double g2[2] = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)}, w2[2] = {1, 1};
  const double g3[3] = {-std::sqrt(0.6), 0, std::sqrt(0.6)}, w3[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
  int idx[3] = {gp % n, (gp / n) % n, gp / (n * n)};
  w = 1;
  for (int j = 0; j < 3; ++j) {
    p[j] = n == 2 ? g2[idx[j]] : g3[idx[j]];
    w *= n == 2 ? w2[idx[j]] : w3[idx[j]];
  }
}

}  // namespace

int solidCorners(int nodes) {
  switch (nodes) {
    case 4:
    case 10:
      return 4;
    case 6:
    case 15:
      return 6;
    case 8:
    case 20:
      return 8;
    default:
      throw Error("solid element of " + std::to_string(nodes) +
                  " nodes: not a C3D4, C3D10, C3D6, C3D15, C3D8 or C3D20 element");
  }
}

int solidGaussPoints(int nodes) {
  switch (solidCorners(nodes)) {
    case 4:
      return 4;
    case 6:
      return nodes == 6 ? 6 : 9;
    default:
      return nodes == 8 ? 8 : 27;
  }
}

double solidGaussPoint(int nodes, const double (*x)[3], int gp, double* N, double (*dx)[3]) {
  double p[3], w = 0;
  gaussPoint(nodes, gp, p, w);
  D3 S[20];
  shapes(nodes, variable(p[0], 0), variable(p[1], 1), variable(p[2], 2), S);
  double J[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  // J[i][j] = d x_j / d local_i
  for (int a = 0; a < nodes; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J[i][j] += S[a].d[i] * x[a][j];
  double inv[3][3];
  const double det = inverse3(J, inv);
  EPAPHE_REQUIRE(det > 0 && std::isfinite(det), "a " << nodes << "-node solid element has det(J) = " << det
                                                     << " at its Gauss point " << gp + 1
                                                     << ": it is inverted or degenerate; check its node order");
  for (int a = 0; a < nodes; ++a) {
    N[a] = S[a].v;
    for (int j = 0; j < 3; ++j)  // dN/dx_j = sum_i dN/dlocal_i dlocal_i/dx_j, dlocal/dx = J^-1
      dx[a][j] = inv[j][0] * S[a].d[0] + inv[j][1] * S[a].d[1] + inv[j][2] * S[a].d[2];
  }
  return det * w;
}

const std::vector<std::array<int, 2>>& solidEdges(int nodes) {
  switch (nodes) {
    case 10:
      return kTet10Edges;
    case 15:
      return kWedge15Edges;
    case 20:
      return kHex20Edges;
    default:
      solidCorners(nodes);  // throws for an unknown count
      return kNoEdges;
  }
}

const std::vector<std::array<int, 4>>& solidFaces(int corners) {
  static const std::vector<std::array<int, 4>> tet = {{0, 1, 2, -1}, {0, 3, 1, -1}, {1, 3, 2, -1}, {2, 3, 0, -1}};
  static const std::vector<std::array<int, 4>> wedge = {
      {0, 1, 2, -1}, {3, 4, 5, -1}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
  static const std::vector<std::array<int, 4>> hex = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return corners == 4 ? tet : corners == 6 ? wedge : hex;
}

void linearSolidHeat(int corners, const double (*x)[3], double* Ke, double* Ce) {
  for (int i = 0; i < corners * corners; ++i) Ke[i] = 0;
  for (int a = 0; a < corners; ++a) Ce[a] = 0;
  double N[8], dx[8][3];
  for (int gp = 0, n = solidGaussPoints(corners); gp < n; ++gp) {
    const double w = solidGaussPoint(corners, x, gp, N, dx);
    for (int a = 0; a < corners; ++a) {
      Ce[a] += N[a] * w;  // row sum of int N_a N_b (sum_b N_b = 1): the lumped capacity (eq. 75)
      for (int b = 0; b < corners; ++b)
        Ke[a * corners + b] += (dx[a][0] * dx[b][0] + dx[a][1] * dx[b][1] + dx[a][2] * dx[b][2]) * w;
    }
  }
}

void tri3Face(const double x[3][3], double* He, double* area) {
  double u[3], v[3];
  for (int j = 0; j < 3; ++j) {
    u[j] = x[1][j] - x[0][j];
    v[j] = x[2][j] - x[0][j];
  }
  const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double A = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int a = 0; a < 3; ++a) {
    area[a] = A / 3;
    for (int b = 0; b < 3; ++b) He[a * 3 + b] = A / 12 * (a == b ? 2 : 1);
  }
}

}  // namespace epaphe
