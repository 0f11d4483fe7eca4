#pragma once
// The isoparametric solid elements of imported CalculiX meshes (Mesh::solids), known by their node
// count, nodes in CalculiX/Abaqus order (corners first):
//
//   4  C3D4   linear tetrahedron           4-point rule (degree 2)
//   10 C3D10  quadratic tetrahedron        4-point rule (ccx's)
//   6  C3D6   linear wedge                 3-point triangle x 2-point Gauss line
//   15 C3D15  quadratic wedge              3-point triangle x 3-point Gauss line (ccx's 9 points)
//   8  C3D8   trilinear hexahedron         2 x 2 x 2 Gauss
//   20 C3D20  quadratic serendipity hex    3 x 3 x 3 Gauss
//
// Local coordinates: tetrahedra (r, s, t) with L = (1 - r - s - t, r, s, t); wedges (r, s) on the
// triangle L = (1 - r - s, r, s) and zeta in [-1, 1] (corners 1-3 at zeta = -1); hexahedra (xi, eta,
// zeta) in [-1, 1]^3 (Zienkiewicz & Taylor, vol. 1, ch. 8; ccx's own shape functions). The derivatives
// are exact (forward-mode automatic differentiation of the shape functions).
//
// The thermal model of an imported mesh uses each element's corners as the linear element of its
// shape (4, 6 or 8 nodes); a mid-side node's temperature is the mean of its edge's two corners
// (solidEdges). See Epaphe_ThermalModel.hpp for why.
#include <array>
#include <vector>

namespace epaphe {

/// The corner count of an element of `nodes` nodes (4, 6 or 8); throws for an unknown node count.
int solidCorners(int nodes);

/// The Gauss points of the element's rule.
int solidGaussPoints(int nodes);

/// N_a (nodes), dN_a/dx_j (nodes x 3) at Gauss point `gp` of the element of `nodes` nodes at
/// coordinates x (nodes x 3); returns det(J) times the point's weight. Throws when det(J) <= 0.
double solidGaussPoint(int nodes, const double (*x)[3], int gp, double* N, double (*dx)[3]);

/// The mid-side nodes' edges: entry k is the two corners (local numbers) of local node corners + k;
/// empty for linear elements.
const std::vector<std::array<int, 2>>& solidEdges(int nodes);

/// The faces of the linear element on `corners` (4, 6, 8) corners: local corner numbers, cyclic; a
/// triangle's fourth entry is -1.
const std::vector<std::array<int, 4>>& solidFaces(int corners);

/// The heat conduction K_e (k = 1 W/(m K)) and lumped capacity diag(int N_a dV) (rho c = 1) of the
/// linear element on `corners` corners at x (corners x 3): Ke corners x corners row-major, Ce the
/// diagonal (docs/theory/heat.md eqs. 57, 75).
void linearSolidHeat(int corners, const double (*x)[3], double* Ke, double* Ce);

/// The convection matrix (h = 1) and nodal areas of a triangle: He 3 x 3 row-major, A / 12 (1 + delta_ab),
/// area A / 3 at each corner.
void tri3Face(const double x[3][3], double* He, double* area);

}  // namespace epaphe
