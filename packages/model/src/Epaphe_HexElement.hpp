#pragma once
// 8-node trilinear hexahedron, isotropic linear elasticity, full 2x2x2 Gauss integration:
// element stiffness K_e = sum_g B^T D B det(J) w_g and consistent mass M_e = rho sum_g N^T N det(J) w_g.
#include <array>

namespace epaphe {

/// An isotropic linear elastic material.
struct Material {
  double density = 0;  ///< kg/m^3
  double young = 0;    ///< Pa
  double poisson = 0;  ///< -
};

/// Throws epaphe::Error naming `context` when a property is out of its physical range.
void checkMaterial(const Material& mat, const char* context);

/// x: node coordinates [8][3]; Ke, Me: 24x24 row-major, DOF order (node, direction).
/// Throws when the element is inverted or degenerate (det J <= 0 at a Gauss point).
void hex8StiffnessMass(const double x[8][3], const Material& mat, double* Ke, double* Me);

/// The geometric (initial-stress) stiffness of the element under the stress of its nodal
/// displacements u (24, DOF order (node, direction)): K_sigma = sum_g G^T S G det(J) w_g, per node
/// pair K_sigma,ab = (grad N_a . sigma . grad N_b) I_3, sigma = D eps(u) at each Gauss point (the
/// second variation of the Green-Lagrange strain energy under a fixed Cauchy prestress). Kg: 24x24
/// row-major, symmetric.
void hex8GeometricStiffness(const double x[8][3], const Material& mat, const double* u, double* Kg);

}  // namespace epaphe
