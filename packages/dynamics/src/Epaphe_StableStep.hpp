#pragma once
// The largest stable step of the central difference (thesis Table 2.1) from the highest frequency of
// a body: a dense reduced model's by LAPACK, a full model's with lumped mass by Lanczos.
#include "Epaphe_Damping.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <vector>

namespace epaphe {

/// A body's highest frequency and the central difference's critical step.
struct StableStep {
  double omegaMax = 0;  ///< highest circular frequency of (K + added stiffness, M), rad/s
  double critical = 0;  ///< largest stable step of the central difference, s
};

/// Central difference is stable for h <= 2/omega_max (thesis Table 2.1); with damping ratio xi on
/// the highest mode, h <= 2/omega_max (sqrt(1 + xi^2) - xi), xi = (alpha/omega_max + beta omega_max)/2
/// for Rayleigh damping, xi for modal damping. `addedStiffness`
/// is put on the diagonal of `stiffenedDofs` (penalty springs, conservatively on all 3 directions).
/// omega_max^2 is the highest eigenvalue of (K, M): a dense reduced model's by LAPACK, a full
/// model's by highestEigenvalue().
StableStep criticalTimeStep(const ReducedModel& model, const std::vector<int>& stiffenedDofs, double addedStiffness,
                            const DampingOptions& damping);

/// The highest eigenvalue of a full model with lumped mass (see highestEigenvalue()).
struct HighestEigenvalue {
  double value = 0;        ///< the estimate used: Ritz value + residual bound, or the Gershgorin bound
  double ritz = 0;         ///< largest Ritz value (a lower bound)
  double residual = 0;     ///< its residual bound: an eigenvalue lies within it
  double gershgorin = 0;   ///< max_i sum_j |K_ij| / m_i, an upper bound of every eigenvalue
  int iterations = 0;      ///< Lanczos iterations
  bool converged = false;  ///< false: `value` is the Gershgorin bound
};

/// The highest eigenvalue of M^{-1} (K + k S) for a full model with lumped mass (M = diag(m), K
/// sparse, S = diag(1 on `stiffenedDofs`)): Lanczos on the symmetric M^{-1/2} (K + k S) M^{-1/2},
/// products by BodyOperator's sparse product, from a fixed pseudo-random start, until the residual bound
/// beta_j |s_j| of the largest Ritz value theta is below 1e-10 theta (at most 1000 iterations, no
/// reorthogonalization: the extreme Ritz values converge first). The estimate is theta + that
/// bound, never above the Gershgorin bound, which is used when Lanczos does not converge.
HighestEigenvalue highestEigenvalue(const ReducedModel& model, const std::vector<int>& stiffenedDofs,
                                    double addedStiffness);

}  // namespace epaphe
