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

void SurfaceContact::correct(const DenseVector& q, CostSplit& cost) {
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
  if (numActive_ == 0) {
    Kokkos::deep_copy(force_, 0.0);
    return;
  }
  if (opt_.method == ContactMethod::Penalty) {
    for (int k : activeH_) forceH_(k) = opt_.penaltyStiffness * (-gapH_(k));  // eq. 2.34
  } else {
    solveLagrange(numActive_);
  }
  Kokkos::deep_copy(force_, forceH_);

  // q += F G lambda (eqs. 2.35-2.36): one pass over the reduced coordinates.
  const auto F = F_;
  const auto dof = dof_;
  const auto normal = normal_;
  const auto force = force_;
  Kokkos::parallel_for(
      "epaphe::contact::correct", q.extent(0), KOKKOS_LAMBDA(const int i) {
        double dq = 0.0;
        for (std::size_t k = 0; k < force.extent(0); ++k) {
          const double l = force(k);
          if (l == 0.0) continue;
          dq += l * (F(i, dof(k, 0)) * normal(k, 0) + F(i, dof(k, 1)) * normal(k, 1) + F(i, dof(k, 2)) * normal(k, 2));
        }
        q(i) += dq;
      });
  Kokkos::fence();
}

void SurfaceContact::solveLagrange(int nA) {
  // Active set iteration: solve MC lambda = -g* (eq. 2.33), release nodes pulled by the surface.
  Teuchos::LAPACK<int, double> lapack;
  std::vector<double>& lambda = lambda_;
  for (int pass = 0; pass <= numNodes() && nA > 0; ++pass) {
    Kokkos::View<int*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> activeH(activeH_.data(), nA);
    auto active = Kokkos::subview(active_, Kokkos::make_pair(0, nA));
    Kokkos::deep_copy(active, activeH);
    const auto F = F_;
    const auto dof = dof_;
    const auto normal = normal_;
    const auto MC = MC_;
    // MC_ab = n_a^T F_ab n_b (eq. 2.32), one row per active node.
    Kokkos::parallel_for(
        "epaphe::contact::matrix", nA, KOKKOS_LAMBDA(const int a) {
          const int ka = active(a);
          for (int b = 0; b < nA; ++b) {
            const int kb = active(b);
            double s = 0.0;
            for (int d = 0; d < 3; ++d)
              for (int e = 0; e < 3; ++e) s += normal(ka, d) * F(dof(ka, d), dof(kb, e)) * normal(kb, e);
            MC(a, b) = s;
          }
        });
    Kokkos::fence();
    auto MCH = Kokkos::create_mirror_view(MC_);
    Kokkos::deep_copy(MCH, MC_);
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
    for (int a = 0; a < nA; ++a) lambda[a] = -gapH_(activeH_[a]);
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
  for (int a = 0; a < nA; ++a) forceH_(activeH_[a]) = lambda[a];
}

double SurfaceContact::workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const {
  double w = 0.0;
  if (numActive_ == 0) return w;
  const auto dof = dof_;
  const auto normal = normal_;
  const auto force = force_;
  Kokkos::parallel_reduce(
      "epaphe::contact::work", numNodes(),
      KOKKOS_LAMBDA(const int k, double& s) {
        const double l = force(k);
        if (l == 0.0) return;
        for (int d = 0; d < 3; ++d) s += 0.5 * l * normal(k, d) * (qNext(dof(k, d)) - qPrev(dof(k, d)));
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
