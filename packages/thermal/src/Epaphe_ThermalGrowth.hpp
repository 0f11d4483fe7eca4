#pragma once
// Thermal growth: the temperature field's thermal strain as a load on the mechanical model
// (docs/theory/heat.md eq. 61).
//
// An isotropic material heated by theta above its reference has the free thermal strain
// eps_th = alpha theta I; the stress is sigma = D (eps - eps_th), so the weak form gains the load
//
//   f_a = int B_a^T D eps_th dV = int grad N_a (3 lambda + 2 mu) alpha theta dV,   3 lambda + 2 mu = E / (1 - 2 nu)
//
// (Zienkiewicz & Taylor, "The finite element method", vol. 1, 2000, sec. 6.2, initial strains),
// theta interpolated by the element's shape functions, 2 x 2 x 2 Gauss rule. The static thermal
// displacement is u = K^{-1} f. A linear element holds a linear displacement exactly, so a free
// body uniformly heated grows by alpha L theta to round-off.
//
// An imported mesh (Mesh::solids) uses each element's own shape functions and Gauss rule
// (Epaphe_SolidElements.hpp; eq. 76): theta at its nodes, a mid-side node's the mean of its edge's
// corners, so theta is the thermal model's linear field and the load is consistent with the
// element's stiffness as CalculiX computed it. Its material (E, nu) comes from the import or the deck.
//
// A temperature field of the reduced thermal model, theta = B eta, gives u = K^{-1} F eta, F the
// loads of the basis' columns: the static responses G = K^{-1} F at chosen nodes are computed once,
// and the growth of those nodes at any moment is G eta.
#include "Epaphe_FullModel.hpp"
#include "Epaphe_LinearSolver.hpp"
#include "Epaphe_ReducedThermal.hpp"

#include <vector>

namespace epaphe {

/// f (24, DOF order (node, direction)) of one hexahedron with the temperatures above the reference
/// theta[8] at its nodes; alpha: the expansion coefficient (1/K).
void hex8ThermalLoad(const double x[8][3], const Material& mat, double alpha, const double theta[8], double* fe);

/// fe (3 nodes) of one solid of an imported mesh (`nodes` nodes, Epaphe_SolidElements.hpp) with the
/// temperatures above the reference theta[nodes] at its nodes (eq. 76).
void solidThermalLoad(int nodes, const double (*x)[3], const Material& mat, double alpha, const double* theta,
                      double* fe);

/// The thermal loads over the free DOFs of `mech` (assembled from its elements: its material is
/// known) of `count` temperature fields, `fields`: numNodes x count, row-major.
MultiVector thermalLoads(const FullModel& mech, double alpha, const std::vector<double>& fields, int count);

/// The same with the material given: an imported model (its mesh's solids; its K from the import).
MultiVector thermalLoads(const FullModel& mech, const Material& material, double alpha,
                         const std::vector<double>& fields, int count);

/// G (3 nodes.size() x thermal.numModes(), row-major: node k's direction d in row 3 k + d): the static
/// thermal displacement of `nodes` per unit of each thermal coordinate. `mech` must be held (its K
/// definite). Runs on every rank of mech's communicator; the result is replicated.
std::vector<double> thermalGrowth(const FullModel& mech, double alpha, const ReducedThermalModel& thermal,
                                  const std::vector<int>& nodes, LinearSolver solver);

/// The same with the material given (E, nu): an imported model.
std::vector<double> thermalGrowth(const FullModel& mech, const Material& material, double alpha,
                                  const ReducedThermalModel& thermal, const std::vector<int>& nodes,
                                  LinearSolver solver);

}  // namespace epaphe
