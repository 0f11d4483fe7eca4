#include "Epaphe_SurfaceContact.hpp"

#include "Epaphe_CoatingContact.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>

namespace epaphe {

namespace {

ContactNodes bodyNodes(const ReducedModel& body, const std::vector<int>& nodes) {
  ContactNodes cn;
  for (int node : nodes) {
    EPAPHE_REQUIRE(node >= 0 && node < body.numNodes(), "body '" << body.name << "': contact node " << node
                                                                 << " is not in the model (0.." << body.numNodes() - 1
                                                                 << ")");
    int dof[3];
    double x[3];
    for (int d = 0; d < 3; ++d) {
      dof[d] = body.nodeDof[3 * node + d];
      EPAPHE_REQUIRE(dof[d] >= 0, "body '" << body.name << "': contact node " << node << " (direction "
                                           << "xyz"[d]
                                           << ") is not a retained DOF of the reduced model; add it to the retained "
                                              "node set, and do not clamp contact nodes");
      x[d] = body.coords[node][d];
    }
    cn.add(node, 0, dof, x);
  }
  return cn;
}

std::vector<ContactSurface> rigidSurfaces(const std::vector<const BSplineSurface*>& surfaces) {
  std::vector<ContactSurface> r;
  for (const BSplineSurface* s : surfaces) r.push_back(ContactSurface{s, nullptr, -1, {}, {}});
  return r;
}

}  // namespace

SurfaceContact::SurfaceContact(const ReducedModel& body, const std::vector<int>& nodes,
                               std::vector<const BSplineSurface*> surfaces, const ContactOptions& options,
                               const Flexibility& flexibility)
    : SurfaceContact(bodyNodes(body, nodes), rigidSurfaces(surfaces), {ContactBlock{0, body.size}}, options,
                     flexibility) {}

SurfaceContact::SurfaceContact(ContactNodes nodes, std::vector<ContactSurface> surfaces,
                               std::vector<ContactBlock> blocks, const ContactOptions& options,
                               const Flexibility& flexibility)
    : opt_(options), nodes_(nodes.labels), nodeBlock_(nodes.block), surfaces_(std::move(surfaces)) {
  const int nc = static_cast<int>(nodes_.size());
  const int N = flexibility.size();
  EPAPHE_REQUIRE(nc > 0, "contact: the contact node set is empty");
  EPAPHE_REQUIRE(!surfaces_.empty(), "contact: no surface to contact");
  flex_ = std::make_unique<RelativeFlexibility>(flexibility, blocks, nodes, surfaces_);
  initDetection(nodes);
  initWorkViews(nodes, N);
  // the deck's law, with friction, and on nodes facing a coated surface the coating's law (its rows
  // solved by the deck's law): all three through the law's registry entry (Epaphe_ContactLaw.hpp)
  enforcement_ = makeContactEnforcement(opt_, nc, &detection_->views().coat, &coating_);
  frictional_ = enforcement_->frictional();
  initStepViews();
}

std::vector<double> SurfaceContact::coatingState() const {
  if (!coating_) return {};
  fence();
  const auto w = detection_->views().coat.wear;
  std::vector<double> state(w.data(), w.data() + w.extent(0));
  state.push_back(coating_->plasticDissipation());
  return state;
}

void SurfaceContact::setCoatingState(const std::vector<double>& state) {
  const auto w = detection_->views().coat.wear;
  EPAPHE_REQUIRE(coating_ && state.size() == w.extent(0) + 1,
                 "contact: a coating state of " << state.size() << " values, " << w.extent(0) + 1 << " expected");
  fence();
  std::copy(state.begin(), state.end() - 1, w.data());
  coating_->setPlasticDissipation(state.back());
}

void SurfaceContact::initDetection(const ContactNodes& nodes) {
  const DetectionOptions dopt = detectionOptions(opt_.complete());
  detection_ = std::make_unique<ContactDetection>(nodes.dofs, nodes.X, surfaces_, dopt, nodes.block);
  surfaces_ = detection_->surfaces();  // axes made unit
}

void SurfaceContact::initWorkViews(const ContactNodes& nodes, int N) {
  const int nc = static_cast<int>(nodes_.size());
  dq_ = DenseVector("epaphe::contact::correction", N);
  corrected_ = Kokkos::View<int*>("epaphe::contact::added", nc);
  {  // nodes penetrating by less than 1e-12 of the model's size after the correction are not added
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int k = 0; k < nc; ++k)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], nodes.X[3 * k + d]);
        hi[d] = std::max(hi[d], nodes.X[3 * k + d]);
      }
    gapTolerance_ = 1e-12 * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-300});
  }
  results_.tangent = Kokkos::View<double* [3]>("epaphe::contact::tangent", nc);
  results_.dir = Kokkos::View<double* [3]>("epaphe::contact::direction", nc);
  results_.mu = Kokkos::View<double*>("epaphe::contact::friction", nc);
  results_.force = Kokkos::View<double*>("epaphe::contact::force", nc);
  results_.active = Kokkos::View<int*>("epaphe::contact::active", nc);
  host_.mu = Kokkos::create_mirror_view(results_.mu);
  host_.tangent = Kokkos::create_mirror_view(results_.tangent);
  host_.gap = Kokkos::create_mirror_view(detection_->views().gap);
  host_.force = Kokkos::create_mirror_view(results_.force);
  host_.surf = Kokkos::create_mirror_view(detection_->views().selected);
  activeH_.reserve(nc);
}

void SurfaceContact::initStepViews() {
  const DetectionViews& dv = detection_->views();
  v_.gap = unmanaged(dv.gap);
  v_.surf = unmanaged(dv.selected);
  v_.normal = unmanaged(dv.normal);
  v_.x = unmanaged(dv.x);
  v_.footX = unmanaged(dv.footX);
  v_.turn = unmanaged(dv.turn);
  v_.D = flex_->motion();
  v_.C = flex_->C();
  v_.active = unmanaged(results_.active);
  v_.force = unmanaged(results_.force);
  v_.mu = unmanaged(results_.mu);
  v_.dir = unmanaged(results_.dir);
  v_.tangent = unmanaged(results_.tangent);
  v_.element = unmanaged(dv.element);
  v_.coat = dv.coat;
  v_.rows = coating_ != nullptr;
  if (v_.rows) {
    results_.row = Kokkos::View<double* [3]>("epaphe::contact::normal_rows", numNodes());
    v_.row = unmanaged(results_.row);
  }
}

std::vector<double> SurfaceContact::warmStarts() const {
  return detection_->warmStarts();
}

void SurfaceContact::setWarmStarts(const std::vector<double>& all) {
  detection_->setWarmStarts(all);
  enforcement_->reset();
}

void SurfaceContact::measureGaps(const DenseVector& q, CostSplit& cost) {
  ScopedPhase phase(cost, "projection");
  detect(q, true);
}

void SurfaceContact::detect(const DenseVector& q, bool all) {
  detection_->detect(q, time_, all);
  lastIterations_ = detection_->lastIterations();
  copy(host_.gap, detection_->views().gap);
  copy(host_.surf, detection_->views().selected);
}

void SurfaceContact::correct(const DenseVector& q, CostSplit& cost) {
  correctImpl(q, nullptr, cost);
}

void SurfaceContact::correct(const DenseVector& qPredicted, const DenseVector& qCurrent, CostSplit& cost) {
  EPAPHE_REQUIRE(qCurrent.extent(0) == qPredicted.extent(0),
                 "contact: q_n has " << qCurrent.extent(0) << " entries, q* " << qPredicted.extent(0));
  correctImpl(qPredicted, &qCurrent, cost);
}

void SurfaceContact::correctImpl(const DenseVector& q, const DenseVector* qCurrent, CostSplit& cost) {
  {
    ScopedPhase phase(cost, "projection");
    detect(q, false);
  }

  ScopedPhase phase(cost, "contact");
  // From here the step copies unmanaged views into locals and kernel captures (Epaphe_Parallel.hpp:
  // unmanaged; no reference counted) and allocates none (contact.step-budget).
  if (!startStep()) return;
  const DetectionViews& dv = detection_->untrackedViews();
  flex_->motionEntries(dv);
  flex_->forgetPairs();  // D (and so C) changed
  // Active set (Lagrange): the nodes the predictor made penetrate, less those the surface would
  // pull (lambda < 0, released inside the solves), plus those the correction of the others makes
  // penetrate through the coupling of F (their corrected gap g*_a + n_a . D_a dq < 0): solved
  // again until no node is added (at most kMaxAddPasses).
  for (int pass = 0;; ++pass) {
    numActive_ = static_cast<int>(activeH_.size());
    flex_->update(activeH_, v_.upload(activeH_), host_.surf, dv);
    enforcement_->enforce(v_, activeH_, q, qCurrent);  // lambda_a and c_a of the active nodes
    numActive_ = static_cast<int>(activeH_.size());
    lastFrictionPasses_ = enforcement_->lastPasses();
    // ascending: the correction's sums run in node order
    flex_->correction(v_.upload(activeH_), numActive_, v_.force, v_.dir, v_.surf, dq_, static_cast<int>(q.extent(0)));
    if (!enforcement_->closesGaps() || pass == kMaxAddPasses || !addPenetrating()) break;
    lastAddPasses_ = pass + 1;
  }
  flexibilityBytes_ += flex_->leastBytes();
  finishStep(q);
}

bool SurfaceContact::startStep() {
  const int nc = numNodes();
  activeH_.clear();
  for (int k = 0; k < nc; ++k) {
    host_.force(k) = 0.0;
    if (host_.surf(k) >= 0 && host_.gap(k) < 0.0) activeH_.push_back(k);
  }
  numActive_ = static_cast<int>(activeH_.size());
  const long long projected = detection_->lastProjections();  // a node on each surface but another instance's
  projections_ += projected;
  projectionsSkipped_ += detection_->projectionsUnskipped() - projected;
  if (numActive_ > 0) return true;
  enforcement_->commit(v_, activeH_);
  const auto tangent = unmanaged(v_.tangent);
  fill(v_.force, 0.0);
  if (frictional_) {
    fill(v_.mu, 0.0);
    forEach(
        "epaphe::contact::no_friction", nc, 1, KOKKOS_LAMBDA(const int k) {
          for (int d = 0; d < 3; ++d) tangent(k, d) = 0.0;
        });
  }
  return false;
}

bool SurfaceContact::addPenetrating() {
  // corrected gaps of the nodes outside the active set; a node whose projection was skipped is
  // out only if its gap's lower bound stays out, bound - |D_k dq| >= -eps (the corrected gap is
  // g + n . D_k dq >= bound - |D_k dq|); when the bound does not decide, it is projected (refine)
  // and tested again with its exact gap
  const int nc = numNodes();
  const DetectionViews& dv = detection_->untrackedViews();
  const auto dq = unmanaged(dq_);
  const auto force = unmanaged(v_.force);
  for (int attempt = 0;; ++attempt) {
    const RelativeMotion D = flex_->motion();
    const auto normal = dv.normal;
    const auto gap = dv.gap;
    const auto surf = dv.selected;
    const auto corrected = unmanaged(corrected_);
    const auto skipped = dv.skip.skipped;
    const auto refine = dv.skip.refine;
    const auto bound = dv.skip.bound;
    const auto moved = dv.skip.correctionMove;
    const double eps = gapTolerance_;
    // (a loop over the nodes, not a sum: on the team on a flexible casing, whose D_k cost ~0.3 us)
    forEach(
        "epaphe::contact::corrected_gaps", nc, 20 + static_cast<long>(flex_->applyNs()), KOKKOS_LAMBDA(const int k) {
          corrected(k) = 0;
          if (surf(k) < 0 || force(k) != 0.0 || !(gap(k) < 1e300)) return;
          double r[3];
          D.apply(k, dq, r);
          const double m = ::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
          moved(k) = m;
          if (skipped(k)) {
            if (bound(k) - m < -eps) refine(k) = 1;
            return;
          }
          double g = gap(k);
          for (int d = 0; d < 3; ++d) g += normal(k, d) * r[d];
          if (g < -eps) corrected(k) = 1;
        });
    fence();
    if (attempt > 0 || detection_->refine() == 0) break;
    flex_->motionEntries(dv);  // the refined nodes' foot points
  }
  auto addH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), corrected_);
  int added = 0;
  for (int k = 0; k < nc; ++k) added += addH(k);
  if (added == 0) return false;
  activeH_.clear();
  for (int k = 0; k < nc; ++k)
    if (host_.force(k) != 0.0 || addH(k)) activeH_.push_back(k);
  return true;
}

void SurfaceContact::finishStep(const DenseVector& q) {
  enforcement_->commit(v_, activeH_);  // a coating's wear follows the step's final forces
  if (frictional_) {
    copy(host_.mu, v_.mu);
    copy(host_.tangent, v_.tangent);
  }
  const auto dq = unmanaged(dq_);
  const auto qs = unmanaged(q);
  forEach(
      "epaphe::contact::apply_correction", q.extent(0), 1, KOKKOS_LAMBDA(const int i) { qs(i) += dq(i); });
  fence();
}

double SurfaceContact::workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const {
  double w = 0.0;
  if (numActive_ == 0) return w;
  const auto dir = unmanaged(v_.dir);
  const auto force = unmanaged(v_.force);
  const RelativeMotion D = flex_->motion();
  const Difference<DenseVector> dq{unmanaged(qNext), unmanaged(qPrev)};
  reduce(
      "epaphe::contact::work", numNodes(), 10,
      KOKKOS_LAMBDA(const int k, double& s) {
        const double l = force(k);
        if (l == 0.0) return;
        double r[3];
        D.apply(k, dq, r);
        for (int d = 0; d < 3; ++d) s += 0.5 * l * dir(k, d) * r[d];
      },
      Kokkos::Sum<double>(w));
  return w;
}

void SurfaceContact::generalizedForce(const DenseVector& gOut) const {
  const auto g = unmanaged(gOut);
  const auto dir = unmanaged(v_.dir);
  const auto force = unmanaged(v_.force);
  const RelativeMotion D = flex_->motion();
  const int* active = activeH_.data();  // ascending (correctImpl)
  const int nA = numActive_;
  fill(g, 0.0);
  if (nA == 0) return;
  // D_k^T c_k (RelativeMotion::apply transposed): w_0 c_k at the node's own DOFs, w_m R_k^T c_k at a
  // grid node's. On the calling thread: nodes share grid DOFs, and the sums run in node order on any
  // number of threads.
  forEach(
      "epaphe::contact::generalized_force", 1, 0, KOKKOS_LAMBDA(const int) {
        for (int a = 0; a < nA; ++a) {
          const int k = active[a];
          const double l = force(k);
          if (l == 0.0) continue;
          double c[3], rc[3];
          for (int d = 0; d < 3; ++d) c[d] = l * dir(k, d);
          for (int e = 0; e < 3; ++e) rc[e] = D.rot(k, 0, e) * c[0] + D.rot(k, 1, e) * c[1] + D.rot(k, 2, e) * c[2];
          D.forEachEntry(k, [&](int m, const int* dof, double w) {
            for (int e = 0; e < 3; ++e)
              if (dof[e] >= 0) g(dof[e]) += w * (m == 0 ? c[e] : rc[e]);
          });
        }
      });
  fence();
}

std::array<double, 2> SurfaceContact::workIncrementSplit(const DenseVector& qNext, const DenseVector& qPrev) const {
  double friction = 0.0;
  if (numActive_ == 0) return {0.0, 0.0};
  const auto mu = unmanaged(v_.mu);
  const auto tangent = unmanaged(v_.tangent);
  const auto force = unmanaged(v_.force);
  const RelativeMotion D = flex_->motion();
  const Difference<DenseVector> dq{unmanaged(qNext), unmanaged(qPrev)};
  reduce(
      "epaphe::contact::friction_work", numNodes(), 10,
      KOKKOS_LAMBDA(const int k, double& s) {
        const double l = force(k);
        if (l == 0.0) return;
        double r[3];
        D.apply(k, dq, r);
        for (int d = 0; d < 3; ++d) s += 0.5 * l * mu(k) * tangent(k, d) * r[d];
      },
      Kokkos::Sum<double>(friction));
  return {workIncrement(qNext, qPrev) - friction, friction};
}

void SurfaceContact::frictionHeatByNode(const DenseVector& qNext, const DenseVector& qPrev, double h, double* out,
                                        double* normalWork, double* counterfaceWork) const {
  using HostView = Kokkos::View<double*, Kokkos::HostSpace, Kokkos::MemoryUnmanaged>;
  const std::size_t n = static_cast<std::size_t>(numNodes());
  const HostView heat(out, n);
  const bool split = normalWork != nullptr && counterfaceWork != nullptr;
  const HostView normal(split ? normalWork : out, n), supplied(split ? counterfaceWork : out, n);
  if (numActive_ == 0) {
    Kokkos::deep_copy(heat, 0.0);
    if (split) {
      Kokkos::deep_copy(normal, 0.0);
      Kokkos::deep_copy(supplied, 0.0);
    }
    return;
  }
  const auto mu = unmanaged(v_.mu);
  const auto tangent = unmanaged(v_.tangent);
  const auto force = unmanaged(v_.force);
  const auto dir = unmanaged(v_.dir);
  const DetectionViews& views = detection_->untrackedViews();
  const auto turn = views.turn;
  const auto selected = views.selected;
  const auto foot = views.footX;
  const RelativeMotion D = flex_->motion();
  const Difference<DenseVector> dq{unmanaged(qNext), unmanaged(qPrev)};
  // On the calling thread whatever the thread count: an output of about 20 ns a node, and one compiled
  // copy of it, so that 1 and 2 threads give the same bits (a kernel's copy of the lambda contracted its
  // products into FMAs otherwise than the inlined loop: the normal work 1 ulp apart, faults.restart-2threads)
  fence();
  const auto byNode = KOKKOS_LAMBDA(const int k) {
    double q = 0.0, wn = 0.0, ws = 0.0;
    const double l = force(k) * mu(k);
    if (force(k) != 0.0) {
      double r[3], slip[3] = {0.0, 0.0, 0.0};
      D.apply(k, dq, r);
      if (const int s = selected(k); l != 0.0 && s >= 0 && turn(s, 8) != 0.0) {
        const double w = turn(s, 0), a[3] = {turn(s, 1), turn(s, 2), turn(s, 3)};
        const double p[3] = {foot(k, 0) - turn(s, 4), foot(k, 1) - turn(s, 5), foot(k, 2) - turn(s, 6)};
        slip[0] = h * w * (a[1] * p[2] - a[2] * p[1]);
        slip[1] = h * w * (a[2] * p[0] - a[0] * p[2]);
        slip[2] = h * w * (a[0] * p[1] - a[1] * p[0]);
      }
      for (int d = 0; d < 3; ++d) {
        q += l * tangent(k, d) * (slip[d] - 0.5 * r[d]);                    // f_a . (h V_s - D_a dq / 2)
        wn += 0.5 * force(k) * (dir(k, d) - mu(k) * tangent(k, d)) * r[d];  // lambda_a n_a . D_a dq / 2
        ws += l * tangent(k, d) * slip[d];                                  // f_a . h V_s
      }
    }
    heat(k) = q;
    if (split) {
      normal(k) = wn;
      supplied(k) = ws;
    }
  };
  for (int k = 0; k < numNodes(); ++k) byNode(k);
}

double SurfaceContact::totalForce() const {
  double s = 0;
  for (int k = 0; k < numNodes(); ++k) s += host_.force(k);
  return s;
}

}  // namespace epaphe
