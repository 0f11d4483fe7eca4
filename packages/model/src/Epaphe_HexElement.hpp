#pragma once
// 8-node trilinear hexahedron, isotropic linear elasticity, full 2x2x2 Gauss integration:
// element stiffness K_e = sum_g B^T D B det(J) w_g and consistent mass M_e = rho sum_g N^T N det(J) w_g.
#include <array>

namespace epaphe {

struct Material {
  double density = 0;       // kg/m^3
  double young = 0;         // Pa
  double poisson = 0;       // -
};

/// Throws epaphe::Error naming `context` when a property is out of its physical range.
void checkMaterial(const Material& mat, const char* context);

/// x: node coordinates [8][3]; Ke, Me: 24x24 row-major, DOF order (node, direction).
/// Throws when the element is inverted or degenerate (det J <= 0 at a Gauss point).
void hex8StiffnessMass(const double x[8][3], const Material& mat, double* Ke, double* Me);

}  // namespace epaphe
