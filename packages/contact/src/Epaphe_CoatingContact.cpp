#include "Epaphe_CoatingContact.hpp"

#include <algorithm>

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

namespace epaphe {

CoatingContact::CoatingContact(std::unique_ptr<ContactEnforcement> inner, bool penalty, double kp,
                               const CoatingViews& coat, int numNodes)
    : inner_(std::move(inner)),
      penalty_(penalty),
      kp_(kp),
      coat_(coat),
      branch_("epaphe::coating::branch", numNodes),
      changed_("epaphe::coating::changed", numNodes),
      p_("epaphe::coating::penetration", numNodes),
      upNext_("epaphe::coating::up_next", numNodes),
      sigma_("epaphe::coating::stress", numNodes),
      energy_("epaphe::coating::energy"),
      nodeDissipation_("epaphe::coating::node_dissipation", numNodes) {
  EPAPHE_REQUIRE(inner_ != nullptr, "coating: no inner contact law");
  for (int s = 0; s < static_cast<int>(coat_.law.extent(0)); ++s) {
    if (coat_.grid(s, 0) == 0) continue;
    EPAPHE_REQUIRE(coat_.law(s, 0) >= 0.0 && coat_.law(s, 1) > 0.0 && coat_.law(s, 2) > 0.0 && coat_.law(s, 3) >= 0.0,
                   "coating of surface " << s << ": thickness " << coat_.law(s, 0) << " m, E " << coat_.law(s, 1)
                                         << " Pa, yield stress " << coat_.law(s, 2) << " Pa, hardening "
                                         << coat_.law(s, 3) << " Pa; give t >= 0, E > 0, sigma_Y > 0, H >= 0");
  }
}

double CoatingContact::addedStiffness() const {
  if (!penalty_) return 0.0;  // Lagrange: the coating's compliance is in the solve (implicit)
  double k = kp_;
  for (int e = 0; e < coat_.numElements(); ++e) {
    const ElementLaw L = coat_.elementLaw(e);
    if (L.t > 0.0) k = std::max(k, L.A * L.E / L.t);
  }
  return k;
}

void CoatingContact::setRows(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA) {
  const auto row = v.row;
  const auto gap = v.gap;
  const auto element = v.element;
  const auto branch = unmanaged(branch_);
  const CoatingViews c = coat_;
  const bool penalty = penalty_;
  const double kp = kp_;
  forEach(
      "epaphe::coating::rows", nA, 10, KOKKOS_LAMBDA(const int a) {
        const int k = active(a), e = element(k);
        const double g = gap(k);
        if (e < 0) {  // a surface without a coating: the rigid law
          row(k, 0) = penalty ? 0.0 : 1.0;
          row(k, 1) = penalty ? 1.0 : 0.0;
          row(k, 2) = penalty ? kp * (-g) : -g;
          return;
        }
        const ElementLaw L = c.elementLaw(e);
        const double t = L.t, E = L.E, A = L.A, up = c.wear(e);
        if (penalty) {  // the element's force at the predicted penetration; the penalty spring past it
          const double delta = up - g;
          row(k, 0) = 0.0;
          row(k, 1) = 1.0;
          row(k, 2) = A * L.stress(delta, up) + (delta > t ? kp * (delta - t) : 0.0);
          return;
        }
        if (branch(k) == kElastic) {
          row(k, 0) = 1.0;
          row(k, 1) = t / (A * E);
          row(k, 2) = -g;
        } else if (branch(k) == kPlastic) {
          const double kt = A * E * L.H / (t * (E + L.H)), l0 = A * E * L.sY / (E + L.H);
          row(k, 0) = kt;
          row(k, 1) = 1.0;
          row(k, 2) = kt * (up - g) + l0;
        } else {
          row(k, 0) = 1.0;
          row(k, 1) = 0.0;
          row(k, 2) = -(g + t - up);
        }
      });
  fence();
}

void CoatingContact::penetrations(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA) {
  // p_a = -(g*_a + n_a^T sum_b C_ab c_b lambda_b): the penetration into the profile after the correction
  const auto C = v.C;
  const auto normal = v.normal;
  const auto dir = v.dir;
  const auto force = v.force;
  const auto gap = v.gap;
  const auto p = unmanaged(p_);
  forEach(
      "epaphe::coating::penetration", nA, 10L * nA, KOKKOS_LAMBDA(const int a) {
        const int ka = active(a);
        double s = gap(ka);
        for (int b = 0; b < nA; ++b) {
          const int kb = active(b);
          const double l = force(kb);
          if (l == 0.0) continue;
          for (int d = 0; d < 3; ++d)
            for (int e = 0; e < 3; ++e) s += normal(ka, d) * C(ka, kb, d, e) * dir(kb, e) * l;
        }
        p(ka) = -s;
      });
  fence();
}

int CoatingContact::classify(const ContactStepViews& v, const Kokkos::View<int*>& active, int nA, bool guess) {
  // the branch of the law at the node's penetration p (guess: the predicted one, -g*): rigid when
  // the element would be crushed (delta >= t), else elastic below the current yield stress, else
  // plastic; a rigid node whose force the coating alone would carry leaves the surface behind
  const auto element = v.element;
  const auto gap = v.gap;
  const auto force = v.force;
  const auto branch = unmanaged(branch_);
  const auto p = unmanaged(p_);
  const CoatingViews c = coat_;
  int changes = 0;
  reduce(
      "epaphe::coating::classify", nA, 10,
      KOKKOS_LAMBDA(const int a, int& n) {
        const int k = active(a), e = element(k);
        if (e < 0) {
          branch(k) = kRigid;
          return;
        }
        const ElementLaw L = c.elementLaw(e);
        const double t = L.t, up = c.wear(e);
        const double pen = guess ? -gap(k) : p(k);
        int next;
        const bool crushedNow = !guess && branch(k) == kRigid;
        if (crushedNow) {
          const double holds = L.A * L.stress(t, up);
          next = force(k) < holds ? (L.elastic(t - up, up) ? kElastic : kPlastic) : kRigid;
        } else if (!(t > 0.0) || pen >= t - up) {
          next = kRigid;
        } else {
          next = L.elastic(pen, up) ? kElastic : kPlastic;
        }
        if (next != branch(k)) ++n;
        branch(k) = next;
      },
      Kokkos::Sum<int>(changes));
  return changes;
}

void CoatingContact::enforce(const ContactStepViews& v, std::vector<int>& active, const DenseVector& q,
                             const DenseVector* qn) {
  EPAPHE_REQUIRE(v.rows && v.row.extent(0) == branch_.extent(0),
                 "coating: the step's views carry no normal rows (SurfaceContact sets them for a coated surface)");
  lastBranchPasses_ = 0;
  if (active.empty()) return inner_->enforce(v, active, q, qn);
  if (penalty_) {
    const auto act = v.upload(active);
    setRows(v, act, static_cast<int>(active.size()));
    inner_->enforce(v, active, q, qn);
    lastBranchPasses_ = 1;
    return;
  }
  auto act = v.upload(active);
  classify(v, act, static_cast<int>(active.size()), true);
  for (int pass = 0;; ++pass) {
    setRows(v, act, static_cast<int>(active.size()));
    inner_->enforce(v, active, q, qn);  // may release nodes: `active` shrinks
    lastBranchPasses_ = pass + 1;
    if (active.empty()) break;
    act = v.upload(active);  // the nodes kept, for the classification and the next pass
    const int nA = static_cast<int>(active.size());
    penetrations(v, act, nA);
    if (pass + 1 == kMaxPasses || classify(v, act, nA, false) == 0) break;
  }
}

void CoatingContact::commit(const ContactStepViews& v, const std::vector<int>& active) {
  const int nA = static_cast<int>(active.size());
  if (nA == 0) {
    energy_(1) = 0.0;
    if (nodeDissipationSet_) Kokkos::deep_copy(nodeDissipation_, 0.0);  // no node made any this step
    nodeDissipationSet_ = false;
    return;
  }
  nodeDissipationSet_ = true;
  const auto act = v.upload(active);
  if (penalty_) {  // the element's compression is the predicted one (the force was computed there)
    const auto p = unmanaged(p_);
    const auto gap = v.gap;
    forEach(
        "epaphe::coating::predicted", nA, 2, KOKKOS_LAMBDA(const int a) { p(act(a)) = -gap(act(a)); });
    fence();
  } else {
    penetrations(v, act, nA);
  }
  const auto element = v.element;
  const auto force = v.force;
  const auto p = unmanaged(p_);
  const auto upNext = unmanaged(upNext_);
  const auto sigma = unmanaged(sigma_);
  const auto energy = unmanaged(energy_);
  const auto nodeDissipation = unmanaged(nodeDissipation_);
  const CoatingViews c = coat_;
  // per node: the return mapping at its final compression (Epaphe_AbradableCoating.hpp)
  forEach(
      "epaphe::coating::return_mapping", nA, 20, KOKKOS_LAMBDA(const int a) {
        const int k = act(a), e = element(k);
        if (e < 0 || force(k) == 0.0) {
          upNext(a) = -1.0;
          return;
        }
        const ElementLaw L = c.elementLaw(e);
        const double up = c.wear(e), delta = up + (p(k) > 0.0 ? p(k) : 0.0);
        upNext(a) = L.plasticShortening(delta, up);
        sigma(a) = L.stress(delta, up);
      });
  // then the elements, in node order (two nodes on one element: the larger shortening), and the energies
  forEach(
      "epaphe::coating::commit", 1, 0, KOKKOS_LAMBDA(const int) {
        double elastic = 0.0;
        for (std::size_t k = 0; k < nodeDissipation.extent(0); ++k) nodeDissipation(k) = 0.0;
        for (int a = 0; a < nA; ++a) {
          if (upNext(a) < 0.0) continue;
          const int e = element(act(a));
          const ElementLaw L = c.elementLaw(e);
          const double up0 = c.wear(e), up1 = upNext(a) > up0 ? upNext(a) : up0;
          const double d = L.dissipation(up0, up1);
          energy(0) += d;
          nodeDissipation(act(a)) += d;  // the node that shortened the element made it
          c.wear(e) = up1;
          elastic += L.A * L.t * sigma(a) * sigma(a) / (2.0 * L.E);
        }
        energy(1) = elastic;
      });
  fence();
}

}  // namespace epaphe
