#pragma once
// Contact enforcement: the law that turns the detected gaps of the active nodes into contact forces
// (thesis section 2.5.2), behind one interface, made from the deck's Contact list by the law 'Method' names.
//
//   ForwardIncrementLagrange  eqs. 2.30-2.33: MC lambda = -g*, the gaps close exactly
//   PenaltyContact            eq. 2.34: lambda = k_p (-g*)
//   CoulombFriction           eqs. 2.29, 2.31: a joint normal-tangential solve with either normal law
//   CoatingContact            an abradable coating's element law (Legrand et al. 2012) on the nodes
//                             facing a coated surface, as rows the law above it solves (made
//                             through the law's registry entry when a surface has a coating)
//
// A strategy sees the step through ContactStepViews (views allocated once by SurfaceContact and
// shared with the detection) and the host list of active nodes; it writes, per active node, the
// force lambda_k and the direction c_k = n_k + mu_k t_k of the correction, and removes from the
// list the nodes it releases. The correction q += F G lambda and the add passes are the operator's
// (Epaphe_SurfaceContact.cpp). Each law owns its deck parameters and is made through the registry of
// Epaphe_ContactLaw.hpp, keyed by 'Contact->Method'.
#include "Epaphe_AbradableCoating.hpp"
#include "Epaphe_ContactLaw.hpp"
#include "Epaphe_RelativeMotion.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <string>
#include <vector>

namespace epaphe {

class CoatingContact;

/// What the contact operator is built from: the deck's Contact list (its 'Method' names a registered
/// law, Epaphe_ContactLaw.hpp; then the law's own keys, friction's and the detection's; a key not
/// given takes its default) and the time step.
struct ContactOptions {
  /// The Contact list: 'Method', the law's keys, friction's and the detection's.
  Teuchos::ParameterList contact{"Contact"};
  double timeStep = 0.0;  ///< h: the rotation of turning surfaces over a step (friction)
  /// Sets a key of the Contact list ("Method", "Penalty stiffness", "Friction coefficient", ...).
  template <class T>
  ContactOptions& set(const std::string& key, const T& value) {
    contact.set(key, value);
    return *this;
  }
  /// Same, for a string value given as a C string.
  ContactOptions& set(const std::string& key, const char* value) { return set(key, std::string(value)); }
  /// The Contact list with every key (defaults for those not set).
  Teuchos::ParameterList complete() const;
  /// The law 'Method' names ("Lagrange" when not set).
  std::string method() const;
};

/// What a strategy reads and writes at a step, per contact node k unless said. Views only: copy
/// members into kernels by value.
struct ContactStepViews {
  /// A view of 3-vectors, [k][3].
  using Vec3 = Kokkos::View<double* [3]>;
  Kokkos::View<double*> gap;  ///< g*_k (detection)
  Kokkos::View<int*> surf;    ///< selected surface (-1: none)
  ///@{
  Vec3 normal, x, footX;  ///< n_k, position, foot point (bodies' frame)
  ///@}
  Kokkos::View<double* [9]> turn;   ///< [s] omega, axis, center, ... (ContactDetection)
  RelativeMotion D;                 ///< D_k's entries (valid for the nodes on a surface)
  Kokkos::View<double** [3][3]> C;  ///< C_ab = D_a F D_b^T of the active pairs
  Kokkos::View<int*> active;        ///< the active nodes (first nA entries, see upload())
  Kokkos::View<double*> force;      ///< lambda_k (N)
  Kokkos::View<double*> mu;         ///< mu_k applied (friction)
  Vec3 dir;                         ///< c_k = n_k + mu_k t_k
  Vec3 tangent;                     ///< t_k (unit, or zero)
  /// A normal law other than the rigid one (CoatingContact) states each active node's normal row,
  ///     alpha_k n_k^T sum_b C_kb f_b + beta_k lambda_k = gamma_k   (f_b = lambda_b c_b),
  /// when `rows` is set: row(k) = {alpha, beta, gamma}; {1, 0, -g*_k} is the rigid Lagrange row
  /// (eq. 2.33) and {0, 1, F} a known force F (penalty). Lagrange and friction solve these rows.
  Kokkos::View<double* [3]> row;
  bool rows = false;           ///< true when the law states its rows in `row` (a coating), false for the rigid rows
  Kokkos::View<int*> element;  ///< coating element under node k (-1: none; detection)
  CoatingViews coat;           ///< the coatings (detection)
  /// Copies the host list into `active` (no allocation) and returns the view of its entries.
  Kokkos::View<int*> upload(const std::vector<int>& list) const;
};

/// The self-locking check of the sliding nodes at one step (CoulombFriction; docs/theory/divergence.md,
/// eqs. (48)-(50)). A margin is 1 - mu / mu*_a: at most 0 when the node is locked. `margin`: the
/// quasi-static one (the body's static compliance, eq. (50)); `stepMargin`: the correction's own
/// (its Delassus block C_aa, eq. (48)). Nodes are contact indices (-1: no sliding node).
struct SelfLocking {
  double margin = 1.0;      ///< least quasi-static margin of the sliding nodes (1: none checked)
  int node = -1;            ///< its node
  double stepMargin = 1.0;  ///< least margin of the correction's Delassus block
  int stepNode = -1;        ///< its node
  int sliding = 0;          ///< sliding nodes checked
};

/// A contact law's enforcement at a step (see the file's opening comment): forces and directions of the
/// active nodes, the nodes it releases, and what it carries from step to step.
class ContactEnforcement {
public:
  virtual ~ContactEnforcement() = default;
  /// The law's name ("Lagrange", "Penalty", "Coulomb friction", ...), for messages.
  virtual const char* name() const = 0;
  /// Forces and directions of the nodes in `active` (C of their pairs is up to date). q: predicted
  /// coordinates q*; qn: q_n (nullptr: no motion over the step, no friction direction). Nodes the
  /// law releases (lambda < 0) are removed from `active`, and their force is zero.
  virtual void enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
                       const DenseVector* qn) = 0;
  /// True when the law closes the gaps exactly (Lagrange): nodes that the correction of the others
  /// makes penetrate are added and the law applied again.
  virtual bool closesGaps() const = 0;
  /// Diagonal stiffness the law adds at each contact DOF (k_p for penalty), for the stable step.
  virtual double addedStiffness() const { return 0.0; }
  /// True when the law applies friction (directions c_k off the normals).
  virtual bool frictional() const { return false; }
  /// Classification passes of the last step (friction), 0 otherwise.
  virtual int lastPasses() const { return 0; }
  /// Forgets what the law carries from step to step (friction's warm start): the next step starts
  /// as a restart from a checkpoint would.
  virtual void reset() {}
  /// Called once per step after the last enforce() of the step (`active`: the final active set):
  /// a law with a state (a coating's wear) updates it here.
  virtual void commit(const ContactStepViews& /*v*/, const std::vector<int>& /*active*/) {}
  /// The self-locking check of the last step (friction), null without friction.
  virtual const SelfLocking* selfLocking() const { return nullptr; }
  /// Per contact node, the 3 x 3 static compliance of its body at its DOFs, S_a = (K^{-1})_aa
  /// (row-major, 9 per node; NaN: not available), for the quasi-static self-locking check.
  virtual void setStaticCompliance(const std::vector<double>& /*blocks*/) {}
};

/// The enforcement the options ask for: the law 'Method' names (ContactLaw::make), wrapped in Coulomb
/// friction when 'Friction coefficient' > 0 (ContactLaw::withFriction), then, when `coat` holds a
/// coating, in the coating law (ContactLaw::withCoating; `coating` then points to it, else nullptr).
/// `numNodes`: the contact nodes (work arrays are sized once for all of them).
std::unique_ptr<ContactEnforcement> makeContactEnforcement(const ContactOptions& options, int numNodes,
                                                           const CoatingViews* coat = nullptr,
                                                           CoatingContact** coating = nullptr);

/// The options of a validated Contact list; h is the time step.
ContactOptions contactOptions(const Teuchos::ParameterList& contact, double h);

}  // namespace epaphe
