#pragma once
// Guards against runs that finish while their physics is absurd: contact missed between two steps
// (tunnelling) and bodies that start interpenetrating.
//
// Motion per step. Contact is detected at the discrete times t_n only (thesis section 2.5.1): a
// node's closest point is found by Newton-Raphson started from its last foot point, and its gap
// decides whether it is corrected. Between two detections a node moves by d = |x_{n+1} - x_n|.
// Let L be the smallest patch of the surfaces (the shortest distance between neighbouring grid
// nodes, ContactDetection::smallestPatch()). While d <= L,
//   - the warm start lies within one patch of the new foot point, where the projection's Newton
//     iteration converges to the closest point (a bicubic patch is nearly affine over its size);
//   - an open surface cannot be crossed between two detections without one of them seeing the node
//     over it: crossing a patch along the surface takes more than one step, so the node is seen at a
//     negative gap above the surface (and corrected) before it can land beyond an edge.
// With d > L neither holds: a node can pass from one side of an open surface to beyond its edge in
// one step and never be seen in contact (the cube at 5e9 m/s, a units slip, crosses both rings
// with 'contact: none'). Hence the bound d <= L, checked
//   - at setup on the initial velocities (|v_0| h <= L), so that such a deck is refused before any
//     work, and
//   - at every step on the contact nodes' actual motion (max_k |x_k(q_{n+1}) - x_k(q_n)|, one pass
//     over 3 DOFs per node), so that a run that accelerates past it stops with a message.
// 'Contact->Allow large motion per step' turns both into warnings (counted in the summary).
//
// Initial penetration. At t = 0 every node is projected on every surface (q = q_0); a node whose
// gap is below -tol, tol = 1e-6 L (far above the projection's accuracy, crit_NR times a patch, and
// far below any geometric intent), starts inside a surface. With Lagrange multipliers the first
// correction would close the whole depth in one step (an impulse of m d / h: the cube cut 3 cm
// into a ring is thrown out with 2.5e9 N); with a penalty the compressed springs release their
// energy at once. Such decks are refused with the number of nodes, the deepest penetration, the
// node, its body and position, and the surface, unless 'Contact->Initial penetration' is
// 'Resolve gently': node k's gap on the surface it penetrates is then raised by its depth d_k times
// (1 - t / T), T = 'Contact->Penetration ramp time', so the bodies are pushed apart at speed d_k / T
// over the ramp; the forces this takes do work that the energy balance counts as contact work.
#include "Epaphe_SurfaceContact.hpp"

#include <array>
#include <string>
#include <vector>

namespace epaphe {

/// The worst initial penetration found at t = 0.
struct PenetrationReport {
  int count = 0;                                  ///< nodes deeper than the tolerance
  double deepest = 0.0;                           ///< largest depth (m, > 0)
  int node = -1;                                  ///< contact index of the deepest node
  int surface = -1;                               ///< the surface it penetrates
  std::array<double, 3> position{0.0, 0.0, 0.0};  ///< its position at t = 0
  double tolerance = 0.0;     ///< the depth below which a gap counts as a penetration (m, 1e-6 of the smallest patch)
  int facing = 0;             ///< nodes over a surface at t = 0 (their projection inside it)
  std::vector<double> depth;  ///< per node, 0 when not penetrating
};

/// The run guards (see the file's opening comment): the motion of the contact nodes per step against
/// the smallest patch, and the initial penetrations.
class ContactGuards {
public:
  /// `bodyNames[b]`: the name of block b, for messages; `origin` names the deck.
  ContactGuards(const GuardOptions& options, std::vector<std::string> bodyNames, std::string origin);
  /// Its deck keys (Allow large motion per step, Initial penetration, Penetration ramp time) are the
  /// detection's: ContactDetection::getValidParameters(), read by guardOptions().

  /// The per-step bound L (m) of `contact`'s surfaces.
  static double motionBound(const SurfaceContact& contact) { return contact.detection().smallestPatch(); }

  /// Setup: refuses (throws epaphe::Error) a body whose initial speed moves it more than L per
  /// step, unless allowed (then `warnings` gets the message). `speeds[b]`: |v_0| of block b.
  void checkInitialVelocities(const SurfaceContact& contact, const std::vector<double>& speeds, double h,
                              std::vector<std::string>& warnings) const;
  /// Setup: projects every node at q0, t = 0, and refuses penetrations deeper than the tolerance,
  /// or (Resolve gently) hands their depths to the detection as ramped offsets. Leaves the
  /// detection's warm starts as they were, so the run (and a restart) is unchanged by the check.
  /// Returns what it found (`count` nodes resolved gently when it returns).
  PenetrationReport checkInitialPenetration(SurfaceContact& contact, const DenseVector& q0, double h,
                                            CostSplit& cost) const;
  /// Each step: the largest motion of a contact node from qOld to qNew. Returns a message naming
  /// the node, its body, its motion and the bound when it exceeds L, "" otherwise. A node in free
  /// flight gets the tunnelling message (and a smaller step to use); a node pressed on a surface
  /// (its force of this step's correction > 0) is no tunnelling: the message says so and gives no
  /// step, the run's diagnosis (Epaphe_Divergence.hpp) tells why the motion diverges.
  std::string checkStep(const SurfaceContact& contact, const DenseVector& qNew, const DenseVector& qOld, double t,
                        double h) const;

  /// The options it was made with.
  const GuardOptions& options() const { return opt_; }

private:
  std::string surfaceName(const SurfaceContact& contact, int s) const;
  GuardOptions opt_;
  std::vector<std::string> bodies_;
  std::string origin_;
};

}  // namespace epaphe
