#pragma once
// Contact of a set of nodes of one reduced body with one or more rigid B-spline surfaces
// (thesis section 2.5). After the explicit predictor has produced q* (eq. 2.2 without contact):
//
//   1. positions of the contact nodes x_a = X_a + u_a(q*) (contact nodes are retained DOFs);
//   2. closest point on each surface by Newton-Raphson, warm-started (section 2.5.1); the gap
//      g*_a = (x_a - S(u_a, v_a)) . n_a, n_a the unit outward normal (eq. 2.28);
//   3. the correction direction of each node (VCT, eq. 2.31): c_a = n_a + mu_a t_a, where t_a is
//      the unit tangent opposing the node's predicted sliding over the step (eq. 2.29, normalised):
//        d_a = x*_{n+1} - x_n = u_a(q*) - u_a(q_n),   t_a = -(d_a - (d_a.n_a) n_a) / |...|
//      (t_a = 0 when that tangential motion is below 1e-14 of the node's scale |x*| + |d|), and
//      mu_a = mu (Coulomb, ContactOptions::friction) while sliding, reduced by the stick limit
//      below; mu = 0, or no q_n given, gives c_a = n_a exactly (frictionless);
//   4. for the active nodes (g*_a < 0), the forces lambda >= 0:
//        Lagrange (forward increment, Carpenter, Taylor & Katona 1991), eqs. 2.30-2.33:
//          MC lambda = -g*,  MC_ab = n_a^T F_ab c_b,  F = (M/h^2 + D/2h)^{-1}
//          (non-symmetric when mu > 0; optionally lumped: MC_aa = sum_b MC_ab), nodes with
//          lambda_a < 0 released and the system solved again; the normal gap is closed exactly,
//          since n_a measures it;
//        penalty, eq. 2.34:  lambda_a = k_p (-g*_a);
//   5. the correction q = q* + F G lambda (eqs. 2.35-2.36), G_a = c_a on node a's DOFs.
//
// Stick limit (Coulomb). Eq. 2.31 always slides: the friction impulse mu lambda_a along t_a may be
// larger than what stops the node, and would then reverse its sliding. Per node, from the diagonal
// block F_aa of the flexibility only (the node's own force), the correction moves the node along
// t_a by lambda_a t_a^T F_aa n_a + phi_a t_a^T F_aa t_a, phi_a = mu_a lambda_a the friction impulse.
// The impulse that stops the node over the step, phi_stick = (s_a - lambda_a t^T F_aa n) /
// t^T F_aa t, s_a = |d_a - (d_a.n_a) n_a| the predicted sliding, is affine in lambda_a. Coulomb:
//   phi_stick >  mu lambda_a: slide,      mu_a = mu   (c_a = n_a + mu t_a, eq. 2.31);
//   |phi_stick| <= mu lambda_a: stick,    force lambda_a (n_a - (t^T F n / t^T F t) t_a) + (s_a / t^T F t) t_a,
//                                         i.e. mu_a = phi_stick / lambda_a: no tangential motion;
//   phi_stick < -mu lambda_a: slide back, mu_a = -mu (only when t^T F_aa n > 0: the normal force
//                                         alone pushes the node back past rest; friction opposes that).
// Penalty: lambda is known, the state follows. Lagrange: the state of each node is set from lambda
// and the system (whose right-hand side then holds the stuck nodes' fixed impulses) is solved
// again while any state changes (usually one extra solve); the forces used are always those of the
// last solve, so the normal gaps still close exactly. Exact for one node, or for nodes whose
// flexibility blocks do not couple; with coupled nodes the forces on the other nodes can still
// move a stuck node a little (a slow creep, never a reversal by its own friction).
//
// The per-node work (positions, projection, directions, stick limit, contact matrix rows,
// correction) runs as named Kokkos kernels on the default execution space (OpenMP).
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>

#include <string>
#include <vector>

namespace epaphe {

enum class ContactMethod { Lagrange = 0, Penalty = 1 };

struct ContactOptions {
  ContactMethod method = ContactMethod::Lagrange;
  double penaltyStiffness = 1e10;   // k_p (N/m), penalty only
  double nrTolerance = 1e-8;        // crit_NR: Newton stop on the parameter step
  int nrMaxIterations = 50;
  bool lumped = false;              // lump the contact matrix MC (section 2.5.2)
  double friction = 0.0;            // Coulomb coefficient mu >= 0 (eq. 2.31); 0: frictionless
};

using DenseMatrix = Kokkos::View<double**, Kokkos::LayoutLeft>;
using DenseVector = Kokkos::View<double*>;

class SurfaceContact {
public:
  /// `nodes`: contact nodes of `body` (each must have its 3 DOFs among the reduced coordinates);
  /// `flexibility`: F = (M/h^2 + D/2h)^{-1}, size x size; surfaces outlive this object.
  SurfaceContact(const ReducedModel& body, const std::vector<int>& nodes,
                 std::vector<const BSplineSurface*> surfaces, const ContactOptions& options,
                 const DenseMatrix& flexibility);

  /// Detects contact at the predicted q* (`qPredicted`) and corrects it in place to q_{n+1};
  /// `qCurrent` = q_n gives each node's motion over the step, hence the friction direction t_a.
  void correct(const DenseVector& qPredicted, const DenseVector& qCurrent, CostSplit& cost);
  /// The same without q_n, i.e. with no motion over the step: no friction direction (t_a = 0,
  /// c_a = n_a) whatever ContactOptions::friction is.
  void correct(const DenseVector& q, CostSplit& cost);

  /// Gaps of the nodes at q without correcting anything (for output); gap() then returns them.
  void measureGaps(const DenseVector& q, CostSplit& cost);

  /// Work of the contact forces of the last correction over [t_{n-1}, t_{n+1}] / 2:
  /// sum_a lambda_a c_a . (u_a(qNext) - u_a(qPrev)) / 2, c_a = n_a + mu_a t_a the direction the
  /// correction used (so friction dissipation is negative contact work and the balance is exact).
  double workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const;

  int numNodes() const { return static_cast<int>(nodes_.size()); }
  int numActive() const { return numActive_; }
  const std::vector<int>& nodes() const { return nodes_; }
  /// Per node, after correct(): gap before correction (g*) -- or after measureGaps(), the gap at
  /// that q --, force lambda (N, >= 0), surface index (-1: beyond every surface), Newton
  /// iterations, and the total normal force.
  Kokkos::View<double*>::HostMirror gap() const { return gapH_; }
  Kokkos::View<double*>::HostMirror force() const { return forceH_; }
  Kokkos::View<int*>::HostMirror surfaceIndex() const { return surfH_; }
  /// Per node, after correct(): the friction coefficient mu_a actually applied, c_a = n_a + mu_a t_a
  /// (mu while sliding, |mu_a| <= mu when stuck, -mu sliding back, 0 without contact or friction
  /// direction), and the unit friction direction t_a (zero when there is none); both stay zero
  /// when ContactOptions::friction = 0.
  Kokkos::View<double*>::HostMirror appliedFriction() const { return muH_; }
  Kokkos::View<double* [3]>::HostMirror tangent() const { return tangentH_; }
  int lastIterations() const { return lastIterations_; }
  double totalForce() const;
  /// Diagonal stiffness the method adds at each contact DOF (k_p for penalty, 0 for Lagrange),
  /// for the stable-step estimate.
  double addedStiffness() const { return opt_.method == ContactMethod::Penalty ? opt_.penaltyStiffness : 0.0; }

private:
  void detect(const DenseVector& q);
  void correctImpl(const DenseVector& q, const DenseVector* qCurrent, CostSplit& cost);
  bool setDirections(const DenseVector& q, const DenseVector* qCurrent);
  int classifyFriction();
  void finalizeDirections();
  void solveLagrange(int nA);

  ContactOptions opt_;
  std::vector<int> nodes_;
  std::vector<const BSplineSurface*> surfaces_;
  DenseMatrix F_;
  Kokkos::View<int* [3]> dof_;            // q index of each contact node DOF
  Kokkos::View<double* [3]> X_;           // reference coordinates
  Kokkos::View<double* [3]> x_;           // current positions
  std::vector<Kokkos::View<double* [2]>> uv_;     // warm starts, one per surface
  std::vector<Kokkos::View<Projection*>> proj_;   // one per surface
  Kokkos::View<double* [3]> normal_;
  Kokkos::View<double* [3]> tangent_;     // t_a (unit, or zero)
  Kokkos::View<double* [3]> dir_;         // c_a = n_a + mu_a t_a (VCT, eq. 2.31); while solving,
  Kokkos::View<double* [3]> push_;        //   a stuck node's force is lambda_a dir_a + push_a
  Kokkos::View<double*> slide_;           // |tangential part of d_a| (0 when t_a = 0)
  Kokkos::View<double*> ftt_, ftn_;       // t_a^T F_aa t_a, t_a^T F_aa n_a
  Kokkos::View<int*> state_;              // kNoFriction, kSlide, kStick, kSlideBack
  Kokkos::View<double*> mu_;              // mu_a applied
  Kokkos::View<double*> rhs_;             // n_a^T sum_b F_ab push_b (Lagrange)
  Kokkos::View<double*>::HostMirror rhsH_;
  static constexpr int kNoFriction = 0, kSlide = 1, kStick = 2, kSlideBack = 3;
  Kokkos::View<double*>::HostMirror muH_;
  Kokkos::View<double* [3]>::HostMirror tangentH_;
  Kokkos::View<double*> gap_, force_;
  Kokkos::View<int*> surf_;
  Kokkos::View<double*>::HostMirror gapH_, forceH_;
  Kokkos::View<int*>::HostMirror surfH_;
  Kokkos::View<int*> active_;             // indices of active nodes
  Kokkos::View<double**, Kokkos::LayoutLeft> MC_;
  std::vector<int> activeH_, keep_, ipiv_;
  std::vector<double> lambda_, denseMC_;  // Lagrange solve work space, sized once
  int numActive_ = 0;
  int lastIterations_ = 0;
};

}  // namespace epaphe
