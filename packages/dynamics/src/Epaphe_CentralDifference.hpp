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
// A full body with lumped mass (ReducedModel::sparse()) takes the same form with diagonal M, D
// (Rayleigh alpha M only: beta K would make M/h^2 + D/2h non-diagonal) and P, and A = -P K kept
// sparse: a step is one KokkosKernels sparse matrix-vector product and a few vector operations, and
// the flexibility is diagonal.
//
// Energy balance. Multiplying the scheme by (q_{n+1} - q_{n-1})/2 gives the exact discrete identity
//   E_{n+1/2} - E_{n-1/2} + (q_{n+1}-q_{n-1})^T D (q_{n+1}-q_{n-1}) / 4h = f_n . (q_{n+1}-q_{n-1}) / 2
// with E_{n+1/2} = 1/2 v_{n+1/2}^T M v_{n+1/2} + 1/2 q_n^T K q_{n+1}, v_{n+1/2} = (q_{n+1}-q_n)/h.
// The run accumulates the right-hand side (contact and external work) and the damping term, so
// the balance error measures what the scheme itself does not conserve: round-off, or a bug.
//
// Coriolis terms (a body at speed that keeps them, ReducedModel::coriolis: docs/theory/integration.md).
// M q'' + (D + Omega G_r) q' + K q = f with G_r skew (G_r^T = -G_r) is the same scheme with D replaced
// by D + Omega G_r in the centred velocity (q_{n+1} - q_{n-1}) / 2h:
//   P = [M/h^2 + (D + Omega G_r)/2h]^{-1},   B = -P (D + Omega G_r) / h,
// P no longer symmetric (inverted by LU; the contact flexibility is then not symmetric either). In the
// energy identity the gyroscopic term is (q_{n+1}-q_{n-1})^T Omega G_r (q_{n+1}-q_{n-1}) / 4h = 0 for a skew
// G_r: it does no work, and the balance is the one above with D alone. The identity keeps E_{n+1/2}
// constant without damping, and E_{n+1/2} = 1/2 v^T (M - h^2 K/4) v + 1/2 q_{n+1/2}^T K q_{n+1/2} is
// positive for h < 2/omega_max of (K, M): the stable step is that of the model without the Coriolis
// terms (criticalTimeStep).
//
// A massless boundary (ReducedModel::massless(), q = [u_b, eta]) steps its modes this way and sets
// u_b = Phi_b eta + G f; its A, B and F, and the residual's energy and dissipation, are derived in
// the constructor.
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <KokkosSparse_CrsMatrix.hpp>
#include <Kokkos_Core.hpp>

#include <array>
#include <string>
#include <vector>

namespace epaphe {

enum class DampingType { None = 0, Rayleigh = 1, Modal = 2 };

struct DampingOptions {
  DampingType type = DampingType::None;
  double alpha = 0.0;  // Rayleigh: D = alpha M + beta K (eq. 4.3)
  double beta = 0.0;
  double ratio = 0.0;  // Modal: xi, the same on every mode (eqs. 4.4-4.5)
};

/// Rayleigh coefficients giving damping ratio xi1 at f1 and xi2 at f2 (Hz), from
/// xi(omega) = alpha / (2 omega) + beta omega / 2 (the intent of thesis eqs. 4.1-4.2):
///   beta = 2 (xi2 w2 - xi1 w1) / (w2^2 - w1^2),  alpha = 2 w1 w2 (xi1 w2 - xi2 w1) / (w2^2 - w1^2).
void rayleighFromRatios(double f1, double xi1, double f2, double xi2, double& alpha, double& beta);

/// One linear operator of a body in its coordinates: dense (a reduced body's K, M, D, A, B),
/// sparse (a full body's K, a KokkosKernels CrsMatrix) or diagonal (a lumped mass, a
/// mass-proportional damping). Its vectors live in host memory (the explicit step runs there).
class BodyOperator {
public:
  using Sparse = KokkosSparse::CrsMatrix<double, int, Kokkos::DefaultExecutionSpace, void, std::size_t>;
  BodyOperator() = default;
  /// n x n, column-major (stored by rows: see forRowBlocks).
  static BodyOperator dense(const std::vector<double>& a, int n, const std::string& label);
  /// A in compressed rows.
  static BodyOperator sparse(const SparseRows& a, const std::string& label);
  static BodyOperator diagonal(const std::vector<double>& d, const std::string& label);
  /// dense(), or diagonal() when every entry off the diagonal is zero (a massless boundary's mass,
  /// diag(0, I)): the same products, without reading n^2 - n zeros.
  static BodyOperator denseOrDiagonal(const std::vector<double>& a, int n, const std::string& label);

  /// y = alpha A x + beta y (beta = 0: y is overwritten).
  void apply(double alpha, const DenseVector& x, double beta, const DenseVector& y) const;
  /// Y = A X for two vectors at once (n x 2, column-major): a dense operator is read once (one BLAS
  /// dgemm, about the cost of one dgemv: 0.63 against 1.15 us for two on 68 x 68, 23 against 39 us
  /// on 419 x 419, OpenBLAS 0.3.21 on this project's machine).
  void apply2(const DenseMatrix& x, const DenseMatrix& y) const;
  /// A dense operator's entries replaced by `a` (n x n, column-major) in place, nothing allocated.
  void assignDense(const std::vector<double>& a);
  /// The dense operator, column-major (a copy: it is stored by rows; empty when not dense).
  DenseMatrix denseMatrix() const;
  /// Bytes one apply() reads of the operator's own storage (values and indices).
  std::size_t bytes() const;
  const DenseVector& diagonalEntries() const { return diagonal_; }

private:
  DenseMatrix dense_;
  Sparse sparse_;
  DenseVector diagonal_;
  enum class Kind { None, Dense, Sparse, Diagonal } kind_ = Kind::None;
};

/// Per kept mode of a massless-boundary model, its damping d_j (D_e = diag(d)): Rayleigh
/// alpha + beta Omega_j^2, modal 2 xi Omega_j, none 0.
std::vector<double> modalDamping(const ReducedModel& model, const DampingOptions& damping);

/// The damping matrix (dense, column-major). Massless boundary: diag(0, modalDamping) (the
/// boundary carries no mass, hence no damping force). Modal (eqs. 4.4-4.5): with V the M-orthonormal modes
/// of (K, M) (V^T M V = I, V^T K V = Omega^2), D = V^{-T} diag(2 xi omega_i) V^{-1}
/// = M V diag(2 xi omega_i) V^T M, so that V^T D V = diag(2 xi omega_i): every mode of the
/// reduced structure gets the ratio xi, rigid-body modes (omega = 0) none.
std::vector<double> dampingMatrix(const ReducedModel& model, const DampingOptions& damping);

struct StableStep {
  double omegaMax = 0;  // highest circular frequency of (K + added stiffness, M), rad/s
  double critical = 0;  // largest stable step of the central difference, s
};

/// Central difference is stable for h <= 2/omega_max (thesis Table 2.1); with damping ratio xi on
/// the highest mode, h <= 2/omega_max (sqrt(1 + xi^2) - xi), xi = (alpha/omega_max + beta omega_max)/2
/// for Rayleigh damping, xi for modal damping. `addedStiffness`
/// is put on the diagonal of `stiffenedDofs` (penalty springs, conservatively on all 3 directions).
/// omega_max^2 is the highest eigenvalue of (K, M): a dense reduced model's by LAPACK, a full
/// model's by highestEigenvalue().
StableStep criticalTimeStep(const ReducedModel& model, const std::vector<int>& stiffenedDofs, double addedStiffness,
                            const DampingOptions& damping);

/// Why `damping` cannot be used with a full model with lumped mass (empty: it can): M/h^2 + D/2h
/// must stay diagonal, so D = alpha M (Rayleigh with beta = 0) or none.
std::string fullModelDampingProblem(const DampingOptions& damping);

struct HighestEigenvalue {
  double value = 0;       // the estimate used: Ritz value + residual bound, or the Gershgorin bound
  double ritz = 0;        // largest Ritz value (a lower bound)
  double residual = 0;    // its residual bound: an eigenvalue lies within it
  double gershgorin = 0;  // max_i sum_j |K_ij| / m_i, an upper bound of every eigenvalue
  int iterations = 0;
  bool converged = false;  // false: `value` is the Gershgorin bound
};

/// The highest eigenvalue of M^{-1} (K + k S) for a full model with lumped mass (M = diag(m), K
/// sparse, S = diag(1 on `stiffenedDofs`)): Lanczos on the symmetric M^{-1/2} (K + k S) M^{-1/2},
/// products by BodyOperator's sparse product, from a fixed pseudo-random start, until the residual bound
/// beta_j |s_j| of the largest Ritz value theta is below 1e-10 theta (at most 1000 iterations, no
/// reorthogonalization: the extreme Ritz values converge first). The estimate is theta + that
/// bound, never above the Gershgorin bound, which is used when Lanczos does not converge.
HighestEigenvalue highestEigenvalue(const ReducedModel& model, const std::vector<int>& stiffenedDofs,
                                    double addedStiffness);

class CentralDifference {
public:
  CentralDifference(const ReducedModel& model, double h, const DampingOptions& damping);

  /// q* = 2 q_n - q_{n-1} + A q_n + B (q_n - q_{n-1}) + P f (f constant; see setConstantForce).
  /// A full model with lumped mass forms A q_n as -P (K q_n) and keeps K q_n: energies() at the same
  /// q_n (same buffer, not written in between, as in the explicit loop's step) reads it instead of a
  /// second sparse product.
  void predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar) const;
  /// A rotating body whose speed changes (a run-up, Epaphe_RunUp.hpp): K replaced by `K` (n x n,
  /// column-major) and A = -P K formed again in place. M, D and P, hence the contact flexibility,
  /// are kept. Dense reduced models (not a massless boundary, not a full model) only.
  void setStiffness(const std::vector<double>& K);
  /// A constant external force in reduced coordinates (gravity, a static load).
  void setConstantForce(const std::vector<double>& f);

  /// P = [M/h^2 + D/2h]^{-1}: dense, or diagonal for a full model with lumped mass.
  Flexibility flexibility() const;
  double step() const { return h_; }
  bool damped() const { return damped_; }
  /// Bytes of the operators one predict() reads (A, and B when damped): the memory traffic floor of
  /// a step's integration.
  std::size_t predictBytes() const {
    if (residual_) return (ginv_.size() + phiB_.size()) * sizeof(double);        // Phi_b, and G^{-1} for z_{n-1}
    return (kqn_.extent(0) > 0 ? K_ : A_).bytes() + (damped_ ? B_.bytes() : 0);  // lumped: K, not A
  }

  /// Energy terms of the identity above.
  double halfStepEnergy(const DenseVector& qn, const DenseVector& qnp1) const;  // E_{n+1/2}
  double dampingIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const;
  double externalWorkIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const;
  /// Kinetic energy 1/2 v^T M v and strain energy 1/2 q^T K q.
  double kinetic(const DenseVector& v) const;
  double strain(const DenseVector& q) const;
  /// What an energy record needs, E_{n+1/2} (halfStepEnergy), 1/2 v^T M v and 1/2 q_n^T K q_n, with
  /// each operator read once: M on two velocities, K on q_n alone (K symmetric: q_n^T K q_{n+1} =
  /// q_{n+1}^T (K q_n)), K_res on q_n and q_{n+1} (its two quadratic forms differ): two matrix passes
  /// instead of four (six on a massless boundary). The same sums as the functions above to round-off.
  struct EnergyTerms {
    double total = 0, kinetic = 0, strain = 0;
  };
  EnergyTerms energies(const DenseVector& qn, const DenseVector& qnp1, const DenseVector& v) const;

private:
  double h_;
  bool damped_ = false;       // B is applied: damping, or the Coriolis terms
  bool dissipative_ = false;  // damping (D != 0): dampingIncrement() is not 0
  bool gyroscopic_ = false;   // the Coriolis terms Omega G_r are kept (ReducedModel::coriolis)
  bool forced_ = false;
  bool residual_ = false;  // massless boundary: energy by Kmid_ and the residual's r . z, exchange by z
  int boundary_ = 0;       // massless boundary: its DOFs, q's first entries
  int modes_ = 0;          // massless boundary: the modes, q's last entries
  std::vector<double> phiB_, ae1_, be1_, pe_;  // massless boundary: predict()'s factors (masslessOperators)
  std::vector<double> modalDamping_, ginv_;    // and dampingIncrement()'s
  /// Massless boundary: the residual r = u_b - Phi_b eta of a q and its force z = G^{-1} r (nb m + nb^2
  /// products), made once per q: a step reads z of q_{n+1} (the exchange), of q_{n-1} (the predictor)
  /// and at a record of q_n and q_{n+1} (the energy). Found by q's values, not its buffer: whatever
  /// wrote a buffer, a q with other values is a new entry. Three kept, the least recently used
  /// replaced: a reference stays valid over the next call.
  struct Residual {
    std::vector<double> q, r, z;
    long long used = 0;  // the call that last returned it (0: empty)
  };
  const Residual& residual(const double* q) const;
  mutable std::array<Residual, 3> residuals_;
  mutable long long residualUses_ = 0;
  BodyOperator K_, M_, D_, P_, A_, B_, Kmid_;
  std::vector<double> pDense_, aDense_;  // a dense model's P (column-major) and setStiffness()'s -P K
  DenseVector f_, Pf_;
  mutable DenseVector tmp_, tmp2_;
  mutable DenseVector kqn_;                // lumped mass: K q_n of the last predict()
  mutable const double* kqnOf_ = nullptr;  // and the q_n buffer it was made from
  mutable DenseMatrix pair_, image_;       // n x 2: energies()' vectors and their images
};

}  // namespace epaphe
