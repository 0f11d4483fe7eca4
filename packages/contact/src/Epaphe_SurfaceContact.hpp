#pragma once
// Contact of a set of nodes of one reduced body with one or more rigid B-spline surfaces
// (thesis section 2.5). After the explicit predictor has produced q* (eq. 2.2 without contact):
//
//   1. positions of the contact nodes x_a = X_a + u_a(q*) (contact nodes are retained DOFs);
//   2. closest point on each surface by Newton-Raphson, warm-started (section 2.5.1); the gap
//      g*_a = (x_a - S(u_a, v_a)) . n_a, n_a the unit outward normal (eq. 2.28);
//   3. for the active nodes (g*_a < 0), the forces lambda >= 0:
//        Lagrange (forward increment, Carpenter, Taylor & Katona 1991), eqs. 2.30-2.33:
//          MC lambda = -g*,  MC_ab = n_a^T F_ab n_b,  F = (M/h^2 + D/2h)^{-1}
//          (optionally lumped: MC_aa = sum_b MC_ab), nodes with lambda_a < 0 released and the
//          system solved again;
//        penalty, eq. 2.34:  lambda_a = k_p (-g*_a);
//   4. the correction q = q* + F G lambda (eqs. 2.35-2.36), G_a = n_a on node a's DOFs.
//
// The per-node work (positions, projection, contact matrix rows, correction) runs as named Kokkos
// kernels on the default execution space (OpenMP).
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

  /// Detects contact at the predicted q* and corrects it in place to q_{n+1}.
  void correct(const DenseVector& q, CostSplit& cost);

  /// Gaps of the nodes at q without correcting anything (for output); gap() then returns them.
  void measureGaps(const DenseVector& q, CostSplit& cost);

  /// Work of the contact forces of the last correction over [t_{n-1}, t_{n+1}] / 2:
  /// sum_a lambda_a n_a . (u_a(qNext) - u_a(qPrev)) / 2.
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
  int lastIterations() const { return lastIterations_; }
  double totalForce() const;
  /// Diagonal stiffness the method adds at each contact DOF (k_p for penalty, 0 for Lagrange),
  /// for the stable-step estimate.
  double addedStiffness() const { return opt_.method == ContactMethod::Penalty ? opt_.penaltyStiffness : 0.0; }

private:
  void detect(const DenseVector& q);
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
