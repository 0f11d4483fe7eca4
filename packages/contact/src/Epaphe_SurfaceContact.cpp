#include "Epaphe_SurfaceContact.hpp"

#include "Epaphe_Error.hpp"

#include <Teuchos_LAPACK.hpp>

#include <cmath>

namespace epaphe {

SurfaceContact::SurfaceContact(const ReducedModel& body, const std::vector<int>& nodes,
                               std::vector<const BSplineSurface*> surfaces, const ContactOptions& options,
                               const DenseMatrix& flexibility)
    : opt_(options), nodes_(nodes), surfaces_(std::move(surfaces)), F_(flexibility) {
  const int nc = static_cast<int>(nodes_.size());
  EPAPHE_REQUIRE(nc > 0, "body '" << body.name << "': the contact node set is empty");
  EPAPHE_REQUIRE(!surfaces_.empty(), "body '" << body.name << "': no surface to contact");
  EPAPHE_REQUIRE(F_.extent(0) == static_cast<std::size_t>(body.size) && F_.extent(1) == F_.extent(0),
                 "contact: flexibility matrix is " << F_.extent(0) << " x " << F_.extent(1) << ", expected "
                                                   << body.size << " x " << body.size);
  EPAPHE_REQUIRE(surfaces_.size() <= 2, "body '" << body.name << "': " << surfaces_.size()
                                                 << " surfaces on one contact node set; at most 2 are supported");
  EPAPHE_REQUIRE(opt_.method != ContactMethod::Penalty || opt_.penaltyStiffness > 0,
                 "contact: penalty stiffness = " << opt_.penaltyStiffness << " N/m; it must be > 0");
  EPAPHE_REQUIRE(std::isfinite(opt_.friction) && opt_.friction >= 0.0,
                 "body '" << body.name << "': friction coefficient mu = " << opt_.friction
                          << "; it must be a finite value >= 0 (0: frictionless)");
  dof_ = Kokkos::View<int* [3]>("epaphe::contact::dof", nc);
  X_ = Kokkos::View<double* [3]>("epaphe::contact::X", nc);
  auto dofH = Kokkos::create_mirror_view(dof_);
  auto XH = Kokkos::create_mirror_view(X_);
  for (int k = 0; k < nc; ++k) {
    const int node = nodes_[k];
    EPAPHE_REQUIRE(node >= 0 && node < body.numNodes(),
                   "body '" << body.name << "': contact node " << node << " is not in the model (0.." << body.numNodes() - 1 << ")");
    for (int d = 0; d < 3; ++d) {
      const int i = body.nodeDof[3 * node + d];
      EPAPHE_REQUIRE(i >= 0, "body '" << body.name << "': contact node " << node << " (direction " << "xyz"[d]
                                      << ") is not a retained DOF of the reduced model; add it to the retained "
                                         "node set, and do not clamp contact nodes");
      dofH(k, d) = i;
      XH(k, d) = body.coords[node][d];
    }
  }
  Kokkos::deep_copy(dof_, dofH);
  Kokkos::deep_copy(X_, XH);
  x_ = Kokkos::View<double* [3]>("epaphe::contact::x", nc);
  normal_ = Kokkos::View<double* [3]>("epaphe::contact::normal", nc);
  tangent_ = Kokkos::View<double* [3]>("epaphe::contact::tangent", nc);
  dir_ = Kokkos::View<double* [3]>("epaphe::contact::direction", nc);
  slide_ = Kokkos::View<double*>("epaphe::contact::slide", nc);
  mu_ = Kokkos::View<double*>("epaphe::contact::friction", nc);
  push_ = Kokkos::View<double* [3]>("epaphe::contact::push", nc);
  ftt_ = Kokkos::View<double*>("epaphe::contact::ftt", nc);
  ftn_ = Kokkos::View<double*>("epaphe::contact::ftn", nc);
  state_ = Kokkos::View<int*>("epaphe::contact::state", nc);
  rhs_ = Kokkos::View<double*>("epaphe::contact::rhs", nc);
  rhsH_ = Kokkos::create_mirror_view(rhs_);
  muH_ = Kokkos::create_mirror_view(mu_);
  tangentH_ = Kokkos::create_mirror_view(tangent_);
  Kokkos::deep_copy(muH_, 0.0);
  Kokkos::deep_copy(tangentH_, 0.0);
  gap_ = Kokkos::View<double*>("epaphe::contact::gap", nc);
  force_ = Kokkos::View<double*>("epaphe::contact::force", nc);
  surf_ = Kokkos::View<int*>("epaphe::contact::surface", nc);
  active_ = Kokkos::View<int*>("epaphe::contact::active", nc);
  MC_ = Kokkos::View<double**, Kokkos::LayoutLeft>("epaphe::contact::MC", nc, nc);
  gapH_ = Kokkos::create_mirror_view(gap_);
  forceH_ = Kokkos::create_mirror_view(force_);
  surfH_ = Kokkos::create_mirror_view(surf_);
  activeH_.reserve(nc);
  keep_.reserve(nc);
  ipiv_.reserve(nc);
  lambda_.reserve(nc);
  denseMC_.reserve(static_cast<std::size_t>(nc) * nc);
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    uv_.emplace_back("epaphe::contact::uv", nc);
    Kokkos::deep_copy(uv_.back(), std::nan(""));  // cold start from the nearest grid node
    proj_.emplace_back("epaphe::contact::projection", nc);
  }
}

void SurfaceContact::measureGaps(const DenseVector& q, CostSplit& cost) {
  ScopedPhase phase(cost, "projection");
  detect(q);
}

void SurfaceContact::detect(const DenseVector& q) {
  const int nc = numNodes();
  const auto dof = dof_;
  const auto X = X_;
  const auto x = x_;
  Kokkos::parallel_for(
      "epaphe::contact::positions", nc, KOKKOS_LAMBDA(const int k) {
        for (int d = 0; d < 3; ++d) x(k, d) = X(k, d) + q(dof(k, d));
      });
  for (std::size_t s = 0; s < surfaces_.size(); ++s)
    projectNodes(surfaces_[s]->view(), x_, uv_[s], proj_[s], opt_.nrTolerance, opt_.nrMaxIterations);
  // Per node, the surface with the smallest gap among those the node is not beyond.
  const auto gap = gap_;
  const auto normal = normal_;
  const auto surf = surf_;
  const auto p0 = proj_[0];
  const auto p1 = surfaces_.size() > 1 ? proj_[1] : proj_[0];
  const int ns = static_cast<int>(surfaces_.size());
  int iters = 0;
  Kokkos::parallel_reduce(
      "epaphe::contact::select", nc,
      KOKKOS_LAMBDA(const int k, int& maxIt) {
        int best = -1;
        double g = 1e300;
        for (int s = 0; s < ns; ++s) {
          const Projection& p = s == 0 ? p0(k) : p1(k);
          if (p.iterations > maxIt) maxIt = p.iterations;
          if (!p.outside && p.gap < g) {
            g = p.gap;
            best = s;
            for (int d = 0; d < 3; ++d) normal(k, d) = p.normal[d];
          }
        }
        gap(k) = g;
        surf(k) = best;
      },
      Kokkos::Max<int>(iters));
  lastIterations_ = iters;
  Kokkos::deep_copy(gapH_, gap_);
  Kokkos::deep_copy(surfH_, surf_);
}

void SurfaceContact::correct(const DenseVector& q, CostSplit& cost) { correctImpl(q, nullptr, cost); }

void SurfaceContact::correct(const DenseVector& qPredicted, const DenseVector& qCurrent, CostSplit& cost) {
  EPAPHE_REQUIRE(qCurrent.extent(0) == qPredicted.extent(0),
                 "contact: q_n has " << qCurrent.extent(0) << " entries, q* " << qPredicted.extent(0));
  correctImpl(qPredicted, &qCurrent, cost);
}

void SurfaceContact::correctImpl(const DenseVector& q, const DenseVector* qCurrent, CostSplit& cost) {
  const int nc = numNodes();
  {
    ScopedPhase phase(cost, "projection");
    detect(q);
  }

  ScopedPhase phase(cost, "contact");
  activeH_.clear();
  for (int k = 0; k < nc; ++k) {
    forceH_(k) = 0.0;
    if (surfH_(k) >= 0 && gapH_(k) < 0.0) activeH_.push_back(k);
  }
  numActive_ = static_cast<int>(activeH_.size());
  const bool friction = opt_.friction > 0.0;
  if (numActive_ == 0) {
    Kokkos::deep_copy(force_, 0.0);
    if (friction) {
      Kokkos::deep_copy(muH_, 0.0);
      Kokkos::deep_copy(tangentH_, 0.0);
    }
    return;
  }
  // t_a, and c_a = n_a + mu t_a (eq. 2.31) for every node: all start sliding. True when some node
  // has a friction direction.
  const bool sliding = setDirections(q, qCurrent);
  if (opt_.method == ContactMethod::Penalty) {
    for (int k : activeH_) forceH_(k) = opt_.penaltyStiffness * (-gapH_(k));  // eq. 2.34
    Kokkos::deep_copy(force_, forceH_);
    if (sliding) classifyFriction();  // lambda does not depend on the directions: one pass
  } else {
    // A stuck node's friction impulse is affine in its lambda, so a solve with a given slide /
    // stick / slide-back state per node is exact; lambda decides the states: solve again while
    // any changes (a few passes at most). The final solve is the one whose directions are used, so
    // the gaps close exactly.
    constexpr int maxPasses = 8;
    for (int pass = 0;; ++pass) {
      solveLagrange(numActive_);
      Kokkos::deep_copy(force_, forceH_);
      if (!sliding || numActive_ == 0 || pass + 1 == maxPasses) break;
      if (classifyFriction() == 0) break;
    }
  }
  if (sliding) finalizeDirections();
  if (friction) {
    Kokkos::deep_copy(muH_, mu_);
    Kokkos::deep_copy(tangentH_, tangent_);
  }

  // q += F G lambda (eqs. 2.35-2.36), G_a = c_a: one pass over the reduced coordinates.
  const auto F = F_;
  const auto dof = dof_;
  const auto dir = dir_;
  const auto force = force_;
  Kokkos::parallel_for(
      "epaphe::contact::correct", q.extent(0), KOKKOS_LAMBDA(const int i) {
        double dq = 0.0;
        for (std::size_t k = 0; k < force.extent(0); ++k) {
          const double l = force(k);
          if (l == 0.0) continue;
          dq += l * (F(i, dof(k, 0)) * dir(k, 0) + F(i, dof(k, 1)) * dir(k, 1) + F(i, dof(k, 2)) * dir(k, 2));
        }
        q(i) += dq;
      });
  Kokkos::fence();
}

bool SurfaceContact::setDirections(const DenseVector& q, const DenseVector* qCurrent) {
  const int nc = numNodes();
  const auto normal = normal_;
  const auto tangent = tangent_;
  const auto dir = dir_;
  const auto push = push_;
  const auto slide = slide_;
  const auto state = state_;
  const auto muA = mu_;
  const double mu = opt_.friction;
  if (mu == 0.0 || qCurrent == nullptr) {  // frictionless: c_a = n_a exactly
    Kokkos::parallel_for(
        "epaphe::contact::normal_direction", nc, KOKKOS_LAMBDA(const int k) {
          for (int d = 0; d < 3; ++d) {
            dir(k, d) = normal(k, d);
            push(k, d) = 0.0;
            tangent(k, d) = 0.0;
          }
          slide(k) = 0.0;
          state(k) = kNoFriction;
          muA(k) = 0.0;
        });
    Kokkos::fence();
    return false;
  }
  const DenseVector qn = *qCurrent;
  const auto F = F_;
  const auto dof = dof_;
  const auto x = x_;
  const auto ftt = ftt_;
  const auto ftn = ftn_;
  int withTangent = 0;
  Kokkos::parallel_reduce(
      "epaphe::contact::tangent", nc,
      KOKKOS_LAMBDA(const int k, int& count) {
        // d = x*_{n+1} - x_n = u(q*) - u(q_n); its tangential part d_t = d - (d.n) n;
        // t = n x (n x d) / |d_t| = -d_t / |d_t| (eq. 2.29, normalised).
        double dsp[3], dn = 0.0, dd = 0.0, xx = 0.0;
        for (int e = 0; e < 3; ++e) {
          dsp[e] = q(dof(k, e)) - qn(dof(k, e));
          dn += dsp[e] * normal(k, e);
          dd += dsp[e] * dsp[e];
          xx += x(k, e) * x(k, e);
          push(k, e) = 0.0;
        }
        double dt[3], tt = 0.0;
        for (int e = 0; e < 3; ++e) {
          dt[e] = dsp[e] - dn * normal(k, e);
          tt += dt[e] * dt[e];
        }
        const double len = ::sqrt(tt);
        if (!(len > 1e-14 * (::sqrt(xx) + ::sqrt(dd)))) {  // no sliding: no direction
          for (int e = 0; e < 3; ++e) {
            tangent(k, e) = 0.0;
            dir(k, e) = normal(k, e);
          }
          slide(k) = 0.0;
          state(k) = kNoFriction;
          muA(k) = 0.0;
          return;
        }
        for (int e = 0; e < 3; ++e) {
          tangent(k, e) = -dt[e] / len;
          dir(k, e) = normal(k, e) + mu * tangent(k, e);
        }
        // the node's own flexibility seen along t: t^T F_kk t (> 0) and t^T F_kk n
        double stt = 0.0, stn = 0.0;
        for (int d = 0; d < 3; ++d)
          for (int e = 0; e < 3; ++e) {
            const double f = F(dof(k, d), dof(k, e));
            stt += tangent(k, d) * f * tangent(k, e);
            stn += tangent(k, d) * f * normal(k, e);
          }
        ftt(k) = stt;
        ftn(k) = stn;
        slide(k) = len;
        state(k) = kSlide;
        muA(k) = mu;
        ++count;
      },
      withTangent);
  return withTangent > 0;
}

int SurfaceContact::classifyFriction() {
  // The node's own correction moves it along t by lambda t^T F_kk n + phi t^T F_kk t (phi: the
  // friction impulse along t). Stopping it (stick) takes phi = (s - lambda ftn) / ftt: the force
  // lambda (n - ftn/ftt t) + (s/ftt) t, affine in lambda. Coulomb: stick while |phi| <= mu lambda;
  // beyond, it slides with |phi| = mu lambda: forward (phi = mu lambda, friction against the
  // predicted sliding), or back (phi = -mu lambda) when the normal force alone pushes the node back
  // past rest (t^T F_kk n > 0 and large) and friction opposes that motion instead.
  const auto normal = normal_;
  const auto tangent = tangent_;
  const auto dir = dir_;
  const auto push = push_;
  const auto slide = slide_;
  const auto ftt = ftt_;
  const auto ftn = ftn_;
  const auto state = state_;
  const auto force = force_;
  const double mu = opt_.friction;
  int changed = 0;
  Kokkos::parallel_reduce(
      "epaphe::contact::stick", numNodes(),
      KOKKOS_LAMBDA(const int k, int& count) {
        const double l = force(k);
        if (!(l > 0.0) || state(k) == kNoFriction) return;
        const double s = slide(k);
        int next = kStick;
        if (s > l * (ftn(k) + mu * ftt(k))) next = kSlide;      // phi_stick > mu lambda
        if (s < l * (ftn(k) - mu * ftt(k))) next = kSlideBack;  // phi_stick < -mu lambda
        if (next == state(k)) return;
        state(k) = next;
        const double mt = next == kSlide ? mu : (next == kSlideBack ? -mu : -ftn(k) / ftt(k));
        const double pt = next == kStick ? s / ftt(k) : 0.0;
        for (int e = 0; e < 3; ++e) {
          dir(k, e) = normal(k, e) + mt * tangent(k, e);
          push(k, e) = pt * tangent(k, e);
        }
        ++count;
      },
      changed);
  return changed;
}

void SurfaceContact::finalizeDirections() {
  // The force of each node as lambda_a c_a, c_a = n_a + mu_a t_a, mu_a = phi_a / lambda_a.
  const auto normal = normal_;
  const auto tangent = tangent_;
  const auto dir = dir_;
  const auto push = push_;
  const auto slide = slide_;
  const auto ftt = ftt_;
  const auto ftn = ftn_;
  const auto state = state_;
  const auto muA = mu_;
  const auto force = force_;
  const double mu = opt_.friction;
  Kokkos::parallel_for(
      "epaphe::contact::friction", numNodes(), KOKKOS_LAMBDA(const int k) {
        const double l = force(k);
        const int st = state(k);
        double m = 0.0;
        if (l > 0.0 && st == kSlide) m = mu;
        if (l > 0.0 && st == kSlideBack) m = -mu;
        if (l > 0.0 && st == kStick) m = (slide(k) / l - ftn(k)) / ftt(k);
        muA(k) = m;
        if (st == kNoFriction) return;
        for (int e = 0; e < 3; ++e) {
          dir(k, e) = normal(k, e) + m * tangent(k, e);
          push(k, e) = 0.0;
        }
      });
  Kokkos::fence();
}

void SurfaceContact::solveLagrange(int nA) {
  // Active set iteration: solve MC lambda = -g* - n^T F p (eq. 2.33; p: the fixed part of the
  // stuck nodes' friction), release nodes pulled by the surface.
  Teuchos::LAPACK<int, double> lapack;
  std::vector<double>& lambda = lambda_;
  for (int pass = 0; pass <= numNodes() && nA > 0; ++pass) {
    Kokkos::View<int*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> activeH(activeH_.data(), nA);
    auto active = Kokkos::subview(active_, Kokkos::make_pair(0, nA));
    Kokkos::deep_copy(active, activeH);
    const auto F = F_;
    const auto dof = dof_;
    const auto normal = normal_;
    const auto dir = dir_;
    const auto push = push_;
    const auto MC = MC_;
    const auto rhs = rhs_;
    // MC_ab = n_a^T F_ab c_b (eq. 2.32; VC^T F VCT, non-symmetric with friction), one row per
    // active node, and rhs_a = n_a^T sum_b F_ab p_b.
    Kokkos::parallel_for(
        "epaphe::contact::matrix", nA, KOKKOS_LAMBDA(const int a) {
          const int ka = active(a);
          double r = 0.0;
          for (int b = 0; b < nA; ++b) {
            const int kb = active(b);
            double s = 0.0;
            for (int d = 0; d < 3; ++d)
              for (int e = 0; e < 3; ++e) {
                const double f = normal(ka, d) * F(dof(ka, d), dof(kb, e));
                s += f * dir(kb, e);
                r += f * push(kb, e);
              }
            MC(a, b) = s;
          }
          rhs(a) = r;
        });
    Kokkos::fence();
    auto MCH = Kokkos::create_mirror_view(MC_);
    Kokkos::deep_copy(MCH, MC_);
    Kokkos::deep_copy(rhsH_, rhs_);
    std::vector<double>& A = denseMC_;
    A.resize(static_cast<std::size_t>(nA) * nA);
    for (int b = 0; b < nA; ++b)
      for (int a = 0; a < nA; ++a) A[static_cast<std::size_t>(b) * nA + a] = MCH(a, b);
    if (opt_.lumped) {  // row sums on the diagonal (section 2.5.2)
      for (int a = 0; a < nA; ++a) {
        double s = 0;
        for (int b = 0; b < nA; ++b) { s += A[static_cast<std::size_t>(b) * nA + a]; A[static_cast<std::size_t>(b) * nA + a] = 0; }
        A[static_cast<std::size_t>(a) * nA + a] = s;
      }
    }
    lambda.assign(static_cast<std::size_t>(nA), 0.0);
    for (int a = 0; a < nA; ++a) lambda[a] = -gapH_(activeH_[a]) - rhsH_(a);
    ipiv_.assign(static_cast<std::size_t>(nA), 0);
    int info = 0;
    lapack.GESV(nA, 1, A.data(), nA, ipiv_.data(), lambda.data(), nA, &info);
    EPAPHE_REQUIRE(info == 0, "contact: the contact matrix of " << nA << " active nodes is singular (LAPACK info "
                                                                << info << "); try lumping it ('Lump contact matrix')");
    keep_.clear();
    for (int a = 0; a < nA; ++a)
      if (lambda[a] >= 0.0) keep_.push_back(activeH_[a]);
    if (static_cast<int>(keep_.size()) == nA) break;
    activeH_.swap(keep_);
    nA = static_cast<int>(activeH_.size());
  }
  numActive_ = nA;
  for (int k = 0; k < numNodes(); ++k) forceH_(k) = 0.0;  // also nodes released on a former solve
  for (int a = 0; a < nA; ++a) forceH_(activeH_[a]) = lambda[a];
}

double SurfaceContact::workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const {
  double w = 0.0;
  if (numActive_ == 0) return w;
  const auto dof = dof_;
  const auto dir = dir_;
  const auto force = force_;
  Kokkos::parallel_reduce(
      "epaphe::contact::work", numNodes(),
      KOKKOS_LAMBDA(const int k, double& s) {
        const double l = force(k);
        if (l == 0.0) return;
        for (int d = 0; d < 3; ++d) s += 0.5 * l * dir(k, d) * (qNext(dof(k, d)) - qPrev(dof(k, d)));
      },
      w);
  return w;
}

double SurfaceContact::totalForce() const {
  double s = 0;
  for (int k = 0; k < numNodes(); ++k) s += forceH_(k);
  return s;
}

}  // namespace epaphe
