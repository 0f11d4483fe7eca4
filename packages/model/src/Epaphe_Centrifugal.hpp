#pragma once
// The terms a steady rotation adds to a structure modelled in its rotating frame, assembled from the
// elements of a built-in mesh. With the body turning at Omega about the unit axis a through x_0, and
// P = I - a a^T the projection onto the plane of rotation, the equation of motion in the body's frame
// (Geradin & Rixen, Mechanical Vibrations, 3rd ed., section 7.3) is
//   M u'' + Omega G u' + (K_e + K_sigma - Omega^2 M_perp) u = Omega^2 f_c,
//   f_c     = int rho N^T P (x - x_0) dV        the centrifugal load of the undeformed body,
//   M_perp  = int rho N^T P N dV                spin softening, K_Omega = -Omega^2 M_perp,
//   G       = 2 int rho N^T [a]_x N dV          Coriolis (gyroscopic, skew),
//   K_sigma = int G_N^T S(sigma_0) G_N dV       the geometric stiffness of the static stress sigma_0.
// With isoparametric elements x = sum_b N_b x_b, so an element's f_c is its M_perp times its nodes'
// P (x_b - x_0): exact for any element shape, and the nodes of the clamp carry their share.
#include "Epaphe_FullModel.hpp"

#include <array>
#include <string>
#include <vector>

namespace epaphe {

/// A rotation axis: a point of it and its direction (unit length; see spinAxis()).
struct SpinAxis {
  std::array<double, 3> point{{0, 0, 0}};      ///< a point of the axis (m)
  std::array<double, 3> direction{{0, 0, 1}};  ///< its unit direction
};

/// The axis through `point` along `direction`, normalised; an Error names `context` when the
/// direction has zero length or a value is not finite.
SpinAxis spinAxis(const std::array<double, 3>& point, const std::array<double, 3>& direction,
                  const std::string& context);

/// Per unit speed: f_c (Omega^2 f_c is the load), M_perp (-Omega^2 M_perp is the spin softening) and
/// G / 2 (Omega G is the Coriolis matrix), over the model's free DOFs.
struct CentrifugalTerms {
  Teuchos::RCP<MultiVector> load;             ///< one column
  Teuchos::RCP<CrsMatrix> perpendicularMass;  ///< M_perp, per unit speed squared
  Teuchos::RCP<CrsMatrix> coriolis;           ///< G / 2, per unit speed
};

/// Assembles the centrifugal terms of a model built from its elements (model.material set); an
/// Error says that an imported model's rotation terms must come from its FE code otherwise.
CentrifugalTerms assembleCentrifugal(const FullModel& model, const SpinAxis& axis);

/// K_sigma of the stress of the nodal displacements `u` (3 per node, the mesh's node order; zero on
/// clamped nodes), over the free DOFs.
Teuchos::RCP<CrsMatrix> assembleGeometricStiffness(const FullModel& model, const std::vector<double>& u);

/// The nodal displacements (3 per node, zero on constrained DOFs) of a vector over the free DOFs,
/// on every rank.
std::vector<double> nodalValues(const FullModel& model, const MultiVector& x);

}  // namespace epaphe
