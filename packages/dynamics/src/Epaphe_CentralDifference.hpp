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
//
// Loads of the time (docs/theory/forced-response.md, eqs. 65-67): f(t) = sum_k g_k(t) f_k, f_k = R^T F_k
// the reduced force of nodal forces F_k (virtual work, eq. 66). The scheme takes f_n = f(t_n) in P f_n,
// and the identity above holds step by step for any f_n, so the run's external work sums
// f_n . (q_{n+1} - q_{n-1}) / 2 with the same f_n. A massless boundary takes the modal part of f_k at t_n
// (2 P on the modes, as the constant force) and the boundary part at t_{n+1}, as the contact force it
// adds to (eq. 67): the residual then holds G f_b(t_{n+1}) and the modes see the boundary force averaged
// over t_{n-1} and t_{n+1}.
#include "Epaphe_BodyOperator.hpp"
#include "Epaphe_Damping.hpp"
#include "Epaphe_Flexibility.hpp"
#include "Epaphe_LoadTimeFunction.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_StableStep.hpp"

#include <Kokkos_Core.hpp>

#include <array>
#include <string>
#include <vector>

namespace epaphe {

/// The explicit central difference of one body (see the file's opening comment): the operators A, B and P
/// formed once, the predictor, the flexibility P the contact reads and the terms of the energy identity.
class CentralDifference {
public:
  /// Forms the operators of `model` at time step `h` (s) with `damping`.
  CentralDifference(const ReducedModel& model, double h, const DampingOptions& damping);

  /// q* = 2 q_n - q_{n-1} + A q_n + B (q_n - q_{n-1}) + P f (f constant; see setConstantForce).
  /// A full model with lumped mass forms A q_n as -P (K q_n) and keeps K q_n: energies() at the same
  /// q_n (same buffer, not written in between, as in the explicit loop's step) reads it instead of a
  /// second sparse product.
  void predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar) const;
  /// predict() at step n, t = t_n (s): with loads of the time (addLoad) it adds P f(t_n) (eq. 67) and
  /// keeps f(t_n) for externalWorkIncrement(); without, the same as predict().
  void predict(const DenseVector& qn, const DenseVector& qnm1, const DenseVector& qstar, double t) const;
  /// A rotating body whose speed changes (a run-up, Epaphe_RunUp.hpp): K replaced by `K` (n x n,
  /// column-major) and A = -P K formed again in place. M, D and P, hence the contact flexibility,
  /// are kept. Dense reduced models (not a massless boundary, not a full model) only.
  void setStiffness(const std::vector<double>& K);
  /// A constant external force in reduced coordinates (gravity, a static load).
  void setConstantForce(const std::vector<double>& f);
  /// A load of the time g(t) f0 (eqs. 65-67), `f0` in reduced coordinates (R^T of the nodal forces, N):
  /// added to the force of every predict(..., t) from then on.
  void addLoad(const std::vector<double>& f0, const LoadTimeFunction& g);
  /// The whole external force at time t (N, reduced coordinates): the constant force and every load's
  /// g_k(t) f_k (eqs. 65-66) at the same t, whatever part a massless boundary takes a step later.
  std::vector<double> forceAt(double t) const;
  /// True when loads of the time were added.
  bool loaded() const { return !loads_.empty(); }
  /// The loads' energy scale (J): sum_k max|g_k|^2 f_k^T P f_k / 4, the work of each at its largest over one
  /// step at the stable limit (h omega_max = 2), a lower bound of its static energy f^T K^{-1} f / 2 that needs
  /// no K^{-1}; 0 without loads. The energy monitor's reference for a body that starts at rest.
  double loadEnergyScale() const;

  /// P = [M/h^2 + D/2h]^{-1}: dense, or diagonal for a full model with lumped mass.
  Flexibility flexibility() const;
  /// The time step h (s).
  double step() const { return h_; }
  /// True when the step applies B and counts a damping term: a damping matrix, Coriolis terms or a
  /// massless boundary (whose exchange with its residual counts as damping).
  bool damped() const { return damped_; }
  /// Bytes of the operators one predict() reads (A, and B when damped): the memory traffic floor of
  /// a step's integration. A massless boundary reads Phi_b; its residual's force comes from the contact
  /// (setContactForce), G^{-1} is not read in a step that gives it.
  std::size_t predictBytes() const {
    if (massless_.on) return massless_.phiB.size() * sizeof(double);
    return (kqn_.extent(0) > 0 ? K_ : A_).bytes() + (damped_ ? B_.bytes() : 0);  // lumped: K, not A
  }

  /// True for a massless boundary, whose step reads the contact force the correction applied
  /// (setContactForce).
  bool wantsContactForce() const { return massless_.on; }
  /// After the correction of step n: `g`, the contact force it applied on this body's coordinates
  /// (G lambda, q's layout), and `qNext` = q_{n+1}. A massless boundary's residual is then r_{n+1} =
  /// G (g_b + f_b(t_{n+1})), the loads' boundary part at t_{n+1} (predict(..., t)), so its force z =
  /// G^{-1} r is g_b + f_b(t_{n+1}), kept for q_{n+1} without G^{-1}'s product (nb^2 multiply-adds).
  /// Nothing on other models.
  void setContactForce(const DenseVector& qNext, const DenseVector& g) const;
  /// A massless boundary's residual forces z of q_{n-1} then of q_n (2 nb values; empty on other
  /// models): the state a checkpoint keeps, since a restart making them by G^{-1} r would differ from
  /// the contact's by round-off.
  std::vector<double> residualForces(const double* qn, const double* qnm1) const;
  /// The number of residualForces()' values.
  std::size_t residualForceCount() const { return massless_.on ? 2 * static_cast<std::size_t>(massless_.boundary) : 0; }
  /// Restores residualForces()'s values (residualForceCount() from `z`) for these q_n and q_{n-1}.
  void restoreResidualForces(const double* qn, const double* qnm1, const double* z) const;

  /// Energy terms of the identity above.
  double halfStepEnergy(const DenseVector& qn, const DenseVector& qnp1) const;  ///< E_{n+1/2}
  /// (q_{n+1} - q_{n-1})^T D (q_{n+1} - q_{n-1}) / 4h (J): the energy damping takes over the step.
  double dampingIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const;
  /// f . (q_{n+1} - q_{n-1}) / 2 (J): the work of the constant force and of the loads of the time (their
  /// f_n of the step's predict(..., t)) over the step (0 without any).
  double externalWorkIncrement(const DenseVector& qnp1, const DenseVector& qnm1) const;
  /// Kinetic energy 1/2 v^T M v and strain energy 1/2 q^T K q.
  double kinetic(const DenseVector& v) const;
  /// 1/2 q^T K q (J).
  double strain(const DenseVector& q) const;
  /// What an energy record needs, E_{n+1/2} (halfStepEnergy), 1/2 v^T M v and 1/2 q_n^T K q_n, with
  /// each operator read once: M on two velocities, K on q_n alone (K symmetric: q_n^T K q_{n+1} =
  /// q_{n+1}^T (K q_n)), K_res on q_n and q_{n+1} (its two quadratic forms differ): two matrix passes
  /// instead of four (six on a massless boundary). The same sums as the functions above to round-off.
  struct EnergyTerms {
    /// J: E_{n+1/2}, 1/2 v^T M v, 1/2 q_n^T K q_n
    ///@{
    double total = 0, kinetic = 0, strain = 0;
    ///@}
  };
  /// The three energies of an energy record (J), from q_n, q_{n+1} and the velocity v.
  EnergyTerms energies(const DenseVector& qn, const DenseVector& qnp1, const DenseVector& v) const;

private:
  double h_;
  bool damped_ = false;       // B is applied: damping, or the Coriolis terms
  bool dissipative_ = false;  // damping (D != 0): dampingIncrement() is not 0
  bool gyroscopic_ = false;   // the Coriolis terms Omega G_r are kept (ReducedModel::coriolis)
  bool forced_ = false;
  /// Massless boundary: the residual r = u_b - Phi_b eta of a q and its force z = G^{-1} r, made once
  /// per q: a step reads z of q_{n+1} (the exchange), of q_{n-1} (the predictor) and at a record of q_n
  /// and q_{n+1} (the energy). z is the contact's force when setContactForce() gave it (nb m products),
  /// else G^{-1} r (nb m + nb^2). Found by q's values, not its buffer: whatever wrote a buffer, a q with
  /// other values is a new entry. Four kept, the least recently used replaced: a reference stays valid
  /// over the next call. Four, because step n makes z of q_{n+1} and reads that of q_{n-1}, made at
  /// step n-2: with three, q_{n-1} is the least recently used when q_n comes.
  struct Residual {
    std::vector<double> q, r, z;
    long long used = 0;  ///< the call that last returned it (0: empty)
  };
  /// What a massless boundary adds (on: energy by Kmid_ and the residual's r . z, exchange by z).
  struct Massless {
    bool on = false;
    int boundary = 0;  ///< its DOFs, q's first entries
    int modes = 0;     ///< the modes, q's last entries
    ///@{
    std::vector<double> phiB, ae1, be1, pe;  ///< predict()'s factors (masslessOperators)
    ///@}
    ///@{
    std::vector<double> damping, ginv;  ///< and dampingIncrement()'s
    ///@}
    mutable std::array<Residual, 4> cache;  ///< residual()'s
    mutable long long uses = 0;
  };
  const Residual& residual(const double* q) const;
  /// q's entry, `made` false, or else a new one (the least recently used) with q and r made and `made` true.
  Residual& entry(const double* q, bool& made) const;
  Massless massless_;
  BodyOperator K_, M_, D_, P_, A_, B_, Kmid_;
  std::vector<double> pDense_, aDense_;  // a dense model's P (column-major) and setStiffness()'s -P K
  DenseVector f_, Pf_;
  /// A load of the time: g, and its reduced force taken at t_n (`now`) and at t_{n+1} (`next`: a massless
  /// boundary's boundary part), with P times each.
  struct Load {
    LoadTimeFunction g;
    ///@{
    std::vector<double> now, next, Pnow, Pnext;
    ///@}
  };
  std::vector<Load> loads_;
  mutable std::vector<double> fLoad_, PfLoad_;  // f(t_n) of the loads and P f(t_n), of the last predict(..., t)
  mutable DenseVector tmp_, tmp2_;
  mutable DenseVector kqn_;                // lumped mass: K q_n of the last predict()
  mutable const double* kqnOf_ = nullptr;  // and the q_n buffer it was made from
  mutable DenseMatrix pair_, image_;       // n x 2: energies()' vectors and their images
};

}  // namespace epaphe
