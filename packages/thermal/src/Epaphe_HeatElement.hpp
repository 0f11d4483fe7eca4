#pragma once
// The 8-node trilinear hexahedron for heat conduction (2x2x2 Gauss rule), and the bilinear
// quadrilateral face for convection and surface fluxes (2x2 Gauss rule):
//
//   K_e = k sum_g (grad N)^T (grad N) det(J) w_g          conduction (W/K), 8 x 8
//   C_e = diag( rho c sum_g N_a (sum_b N_b) det(J) w_g )   lumped heat capacity (J/K), 8 x 8 diagonal
//   H_f = h sum_g N^T N |x_,xi x x_,eta| w_g                convection (W/K), 4 x 4
//   a_f = sum_g N |x_,xi x x_,eta| w_g                      area of each face node (m^2), 4
//
// the Galerkin form of rho c dT/dt = div(k grad T) with -k dT/dn = h (T - T_inf) on the convected
// faces (Lewis, Nithiarasu & Seetharamu, "Fundamentals of the finite element method for heat and
// fluid flow", 2004, eqs. 7.7-7.9). A uniform flux q on a face gives the nodal heat inputs q a_f.
//
// The capacity is lumped by row sums (docs/theory/heat.md eq. 57): each node carries the heat capacity
// of its share of the element, and C is diagonal and positive. The consistent capacity's inverse has
// negative entries between neighbours, so a heat input at a node cools its neighbours at first (by about
// half its own rise across one element): a point input, the contact's, undershoots. With the lumped
// capacity the first response to an input is at the node alone. Where K's off-diagonal entries are
// all <= 0 (cubes; an element elongated along an edge gives that edge a small positive entry), the
// full model keeps every temperature at or above its initial value under heat inputs (exp(-t C^-1 K)
// is then non-negative entry by entry: a discrete maximum principle). Both capacities converge at the
// same order in the mesh size.
#include <array>

namespace epaphe {

/// The thermal properties of an isotropic material.
struct ThermalMaterial {
  double conductivity = 0;  ///< k, W/(m K)
  double specificHeat = 0;  ///< c, J/(kg K)
  double density = 0;       ///< rho, kg/m^3

  /// k / (rho c), m^2/s.
  double diffusivity() const { return conductivity / (density * specificHeat); }
  /// sqrt(k rho c), J/(m^2 K s^1/2): the share of a heat flux two bodies in perfect contact take.
  double effusivity() const;
};

/// Throws epaphe::Error naming `context` when a property is not a finite value > 0.
void checkThermalMaterial(const ThermalMaterial& mat, const char* context);

/// x: node coordinates [8][3] (VTK/C3D8 order); Ke, Ce: 8 x 8 row-major. Throws when the element is
/// inverted or degenerate.
void hex8Heat(const double x[8][3], const ThermalMaterial& mat, double* Ke, double* Ce);

/// x: the face's 4 corners in cyclic order; He: 4 x 4 row-major for h = 1 W/(m^2 K); area: the
/// area each node carries (sum: the face's area).
void quad4Face(const double x[4][3], double* He, double* area);

/// The faces of the hexahedra (local corner numbers, cyclic) in VTK/C3D8 order.
extern const int kHexFaces[6][4];

}  // namespace epaphe
