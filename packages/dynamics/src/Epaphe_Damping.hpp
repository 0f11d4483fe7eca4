#pragma once
// Damping of a body (thesis section 4.1): Rayleigh, D = alpha M + beta K (eq. 4.3), with its
// coefficients from two damping ratios, or modal, the same ratio on every mode (eqs. 4.4-4.5); a
// massless boundary damps its kept modes only.
#include "Epaphe_ReducedModel.hpp"

#include <string>
#include <vector>

namespace epaphe {

/// The damping of a body ('Damping->Type').
enum class DampingType { None = 0, Rayleigh = 1, Modal = 2 };

/// A body's damping: its type and coefficients.
struct DampingOptions {
  DampingType type = DampingType::None;  ///< none, Rayleigh or modal
  double alpha = 0.0;                    ///< Rayleigh: D = alpha M + beta K (eq. 4.3)
  double beta = 0.0;                     ///< Rayleigh: the stiffness coefficient (s)
  double ratio = 0.0;                    ///< Modal: xi, the same on every mode (eqs. 4.4-4.5)
};

/// Rayleigh coefficients giving damping ratio xi1 at f1 and xi2 at f2 (Hz), from
/// xi(omega) = alpha / (2 omega) + beta omega / 2 (the intent of thesis eqs. 4.1-4.2):
///   beta = 2 (xi2 w2 - xi1 w1) / (w2^2 - w1^2),  alpha = 2 w1 w2 (xi1 w2 - xi2 w1) / (w2^2 - w1^2).
void rayleighFromRatios(double f1, double xi1, double f2, double xi2, double& alpha, double& beta);

/// Per kept mode of a massless-boundary model, its damping d_j (D_e = diag(d)): Rayleigh
/// alpha + beta Omega_j^2, modal 2 xi Omega_j, none 0.
std::vector<double> modalDamping(const ReducedModel& model, const DampingOptions& damping);

/// The damping matrix (dense, column-major). Massless boundary: diag(0, modalDamping) (the
/// boundary carries no mass, hence no damping force). Modal (eqs. 4.4-4.5): with V the M-orthonormal modes
/// of (K, M) (V^T M V = I, V^T K V = Omega^2), D = V^{-T} diag(2 xi omega_i) V^{-1}
/// = M V diag(2 xi omega_i) V^T M, so that V^T D V = diag(2 xi omega_i): every mode of the
/// reduced structure gets the ratio xi, rigid-body modes (omega = 0) none.
std::vector<double> dampingMatrix(const ReducedModel& model, const DampingOptions& damping);

/// Why `damping` cannot be used with a full model with lumped mass (empty: it can): M/h^2 + D/2h
/// must stay diagonal, so D = alpha M (Rayleigh with beta = 0) or none.
std::string fullModelDampingProblem(const DampingOptions& damping);

}  // namespace epaphe
