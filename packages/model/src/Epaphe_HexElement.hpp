#pragma once
// 8-node trilinear hexahedron, isotropic linear elasticity, full 2x2x2 Gauss integration:
// element stiffness K_e = sum_g B^T D B det(J) w_g and consistent mass M_e = rho sum_g N^T N det(J) w_g.
// With incompatible modes (Wilson, Taylor, Doherty & Ghaboussi 1973; Taylor, Beresford & Wilson 1976)
// the displacement gains nine internal modes (1 - xi_k^2) alpha_k, condensed out of K_e, so that an
// element bends without parasitic shear (docs/theory/reduction.md, eq. (73)).
#include <array>

namespace epaphe {

/// How the hexahedron's stiffness is formed.
enum class HexFormulation {
  FullIntegration = 0,   ///< trilinear displacement, 2x2x2 Gauss points (locks in bending when thin)
  IncompatibleModes = 1  ///< plus nine condensed incompatible modes (QM6): exact in pure bending of a brick
};

/// An isotropic linear elastic material, and the formulation of the hexahedra made of it.
struct Material {
  double density = 0;                                            ///< kg/m^3
  double young = 0;                                              ///< Pa
  double poisson = 0;                                            ///< -
  HexFormulation formulation = HexFormulation::FullIntegration;  ///< K_e's formulation (M_e is the same)
};

/// Throws epaphe::Error naming `context` when a property is out of its physical range.
void checkMaterial(const Material& mat, const char* context);

/// Shape functions N_a, their gradients dN_a/dx_j and the weight det(J) (Gauss weights are 1) at
/// Gauss point `gp` (0..7) of the 2x2x2 rule. Throws when det(J) <= 0 there.
double hex8GaussPoint(const double x[8][3], int gp, double N[8], double dx[8][3]);

/// x: node coordinates [8][3]; Ke, Me: 24x24 row-major, DOF order (node, direction); K_e by
/// `mat.formulation`, M_e consistent.
/// Throws when the element is inverted or degenerate (det J <= 0 at a Gauss point).
void hex8StiffnessMass(const double x[8][3], const Material& mat, double* Ke, double* Me);

/// The geometric (initial-stress) stiffness of the element under the stress of its nodal
/// displacements u (24, DOF order (node, direction)): K_sigma = sum_g G^T S G det(J) w_g, per node
/// pair K_sigma,ab = (grad N_a . sigma . grad N_b) I_3, sigma = D eps(u) at each Gauss point (the
/// second variation of the Green-Lagrange strain energy under a fixed Cauchy prestress). Kg: 24x24
/// row-major, symmetric. The stress is that of the trilinear field whatever `mat.formulation`: the
/// incompatible modes are not recovered from u.
void hex8GeometricStiffness(const double x[8][3], const Material& mat, const double* u, double* Kg);

}  // namespace epaphe
