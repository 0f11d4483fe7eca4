#pragma once
// Explicit central difference on a dense reduced model (thesis eq. 2.2, Newmark beta = 0,
// gamma = 1/2):
//
//   q_{n+1} = [M/h^2 + D/2h]^{-1} [ (2M/h^2 - K) q_n + (-M/h^2 + D/2h) q_{n-1} + f_n ]
//
// With P = [M/h^2 + D/2h]^{-1} (so that P (2M/h^2) = 2I - P D/h) this is, exactly,
//
//   q_{n+1} = 2 q_n - q_{n-1} + A q_n + B (q_n - q_{n-1}) + P f_n,   A = -P K,  B = -P D / h,
//
// the form we use: a rigid-body motion (K t = 0) is then carried by 2 q_n - q_{n-1} exactly,
// instead of by a product of large matrices that cancel only to round-off. P is also the
// flexibility that the contact correction uses (eqs. 2.32, 2.35). Everything is formed once; a
// step is one (undamped) or two (damped) dense matrix-vector products.
//
// Energy balance. Multiplying the scheme by (q_{n+1} - q_{n-1})/2 gives the exact discrete identity
//   E_{n+1/2} - E_{n-1/2} + (q_{n+1}-q_{n-1})^T D (q_{n+1}-q_{n-1}) / 4h = f_n . (q_{n+1}-q_{n-1}) / 2
// with E_{n+1/2} = 1/2 v_{n+1/2}^T M v_{n+1/2} + 1/2 q_n^T K q_{n+1}, v_{n+1/2} = (q_{n+1}-q_n)/h.
// The run accumulates the right-hand side (contact and external work) and the damping term, so
// the balance error measures what the scheme itself does not conserve: round-off, or a bug.
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <Kokkos_Core.hpp>

#include <vector>

namespace epaphe {

enum class DampingType { None = 0, Rayleigh = 1, Modal = 2 };

struct DampingOptions {
  DampingType type = DampingType::None;
  double alpha = 0.0;   // Rayleigh: D = alpha M + beta K (eq. 4.3)
  double beta = 0.0;
  double ratio = 0.0;   // Modal: xi, the same on every mode (eqs. 4.4-4.5)
};

/// Rayleigh coefficients giving damping ratio xi1 at f1 and xi2 at f2 (Hz), from
/// xi(omega) = alpha / (2 omega) + beta omega / 2 (the intent of thesis eqs. 4.1-4.2):
///   beta = 2 (xi2 w2 - xi1 w1) / (w2^2 - w1^2),  alpha = 2 w1 w2 (xi1 w2 - xi2 w1) / (w2^2 - w1^2).
void rayleighFromRatios(double f1, double xi1, double f2, double xi2, double& alpha, double& beta);

/// The damping matrix (dense, column-major). Modal (eqs. 4.4-4.5): with V the M-orthonormal modes
/// of (K, M) (V^T M V = I, V^T K V = Omega^2), D = V^{-T} diag(2 xi omega_i) V^{-1}
/// = M V diag(2 xi omega_i) V^T M, so that V^T D V = diag(2 xi omega_i): every mode of the
/// reduced structure gets the ratio xi, rigid-body modes (omega = 0) none.
std::vector<double> dampingMatrix(const ReducedModel& model, const DampingOptions& damping);

struct StableStep {
  double omegaMax = 0;      // highest circular frequency of (K + added stiffness, M), rad/s
  double critical = 0;      // largest stable step of the central difference, s
};

/// Central difference is stable for h <= 2/omega_max (thesis Table 2.1); with damping ratio xi on
/// the highest mode, h <= 2/omega_max (sqrt(1 + xi^2) - xi), xi = (alpha/omega_max + beta omega_max)/2
/// for Rayleigh damping, xi for modal damping. `addedStiffness`
/// is put on the diagonal of `stiffenedDofs` (penalty springs, conservatively on all 3 directions).
StableStep criticalTimeStep(const ReducedModel& model, const std::vector<int>& stiffenedDofs, double addedStiffness,
                            const DampingOptions& damping);

class CentralDifference {
public:
  CentralDifference(const ReducedModel& model, double h, const DampingOptions& damping);

  /// q* = 2 q_n - q_{n-1} + A q_n + B (q_n - q_{n-1}) + P f (f constant; see setConstantForce).
  void predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar) const;
  /// A constant external force in reduced coordinates (gravity, a static load).
  void setConstantForce(const std::vector<double>& f);

  const DenseMatrix& flexibility() const { return P_; }
  double step() const { return h_; }
  bool damped() const { return damped_; }

  /// Energy terms of the identity above.
  double halfStepEnergy(const DenseVector& qn, const DenseVector& qnp1) const;   // E_{n+1/2}
  double dampingIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const;
  double externalWorkIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const;
  /// Kinetic energy 1/2 v^T M v and strain energy 1/2 q^T K q.
  double kinetic(const DenseVector& v) const;
  double strain(const DenseVector& q) const;

private:
  double h_;
  bool damped_ = false;
  bool forced_ = false;
  DenseMatrix K_, M_, D_, P_, A_, B_;
  DenseVector f_, Pf_;
  mutable DenseVector tmp_, tmp2_;
};

}  // namespace epaphe
