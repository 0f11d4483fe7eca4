#include "Epaphe_SurfaceContact.hpp"

#include "Epaphe_Error.hpp"

#include <KokkosBlas1_axpby.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>

namespace epaphe {

namespace {

ContactNodes bodyNodes(const ReducedModel& body, const std::vector<int>& nodes) {
  ContactNodes cn;
  for (int node : nodes) {
    EPAPHE_REQUIRE(node >= 0 && node < body.numNodes(),
                   "body '" << body.name << "': contact node " << node << " is not in the model (0.." << body.numNodes() - 1 << ")");
    int dof[3];
    double x[3];
    for (int d = 0; d < 3; ++d) {
      dof[d] = body.nodeDof[3 * node + d];
      EPAPHE_REQUIRE(dof[d] >= 0, "body '" << body.name << "': contact node " << node << " (direction " << "xyz"[d]
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

/// Node k's motion relative to its surface, D_k v (see the header), as a list of entries
/// (DOF triple, weight): the node itself with weight 1, then the grid nodes of a carried surface
/// with weights -w_p w_q (DOF -1: clamped, fixed), whose motion is in the carrying body's frame and
/// turned into the node's by rot(k) (R of a turning surface, else the identity). Valid for the
/// nodes relativeFlexibility() saw active. Copy into kernels by value.
struct RelativeMotion {
  Kokkos::View<int** [3]> dof;
  Kokkos::View<double**> w;
  Kokkos::View<int*> count;
  Kokkos::View<double* [3][3]> rot;

  /// r = D_k v for any accessor v(i) of the system coordinates:
  ///   r_d = v(node DOF d) + sum_e R_k(d, e) sum_(m >= 1) w_m v(grid DOF (m, e)).
  template <class V>
  KOKKOS_INLINE_FUNCTION void apply(int k, const V& v, double r[3]) const {
    double g[3] = {0.0, 0.0, 0.0};
    for (int m = 1; m < count(k); ++m)
      for (int e = 0; e < 3; ++e) {
        const int i = dof(k, m, e);
        if (i >= 0) g[e] += w(k, m) * v(i);
      }
    for (int d = 0; d < 3; ++d)
      r[d] = w(k, 0) * v(dof(k, 0, d)) + rot(k, d, 0) * g[0] + rot(k, d, 1) * g[1] + rot(k, d, 2) * g[2];
  }
  /// The entry of D_k in row e at DOF (m, e2): w_0 at the node's own DOF e, w_m R_k(e, e2) at a
  /// grid node's (turned into the node's frame).
  KOKKOS_INLINE_FUNCTION double coefficient(int k, int m, int e, int e2) const {
    return m == 0 ? (e2 == e ? w(k, 0) : 0.0) : w(k, m) * rot(k, e, e2);
  }
};

/// Column 3 k + e of F D^T as an accessor of the system rows, for RelativeMotion::apply: Y, stored
/// on the dense rows of F; in a diagonal block of F, F_ii times the weights of node k's entries at
/// DOF i (the only rows where D_k^T is not zero).
template <class Y>
struct FlexibleColumn {
  Y y;
  Flexibility::Packed F;
  RelativeMotion D;
  int k, e;
  KOKKOS_INLINE_FUNCTION double operator()(int i) const {
    const int r = F.denseRow(i);
    if (r >= 0) return y(r, 3 * k + e);
    double s = 0.0;
    for (int m = 0; m < D.count(k); ++m)
      for (int e2 = 0; e2 < 3; ++e2)
        if (D.dof(k, m, e2) == i) s += D.coefficient(k, m, e, e2);
    return F.diag(i) * s;
  }
};

template <class V>
struct Difference {
  V a, b;
  KOKKOS_INLINE_FUNCTION double operator()(int i) const { return a(i) - b(i); }
};

}  // namespace

SurfaceContact::SurfaceContact(const ReducedModel& body, const std::vector<int>& nodes,
                               std::vector<const BSplineSurface*> surfaces, const ContactOptions& options,
                               const Flexibility& flexibility)
    : SurfaceContact(bodyNodes(body, nodes), rigidSurfaces(surfaces), {ContactBlock{0, body.size}}, options,
                     flexibility) {}

SurfaceContact::SurfaceContact(ContactNodes nodes, std::vector<ContactSurface> surfaces,
                               std::vector<ContactBlock> blocks, const ContactOptions& options,
                               const Flexibility& flexibility)
    : opt_(options), nodes_(std::move(nodes.labels)), nodeBlock_(std::move(nodes.block)),
      surfaces_(std::move(surfaces)), F_(flexibility.pack()) {
  const int nc = static_cast<int>(nodes_.size());
  const int N = flexibility.size();
  EPAPHE_REQUIRE(nc > 0, "contact: the contact node set is empty");
  EPAPHE_REQUIRE(!surfaces_.empty(), "contact: no surface to contact");
  EPAPHE_REQUIRE(flexibility.numBlocks() == static_cast<int>(blocks.size()),
                 "contact: the flexibility has " << flexibility.numBlocks() << " blocks, the bodies " << blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b)
    EPAPHE_REQUIRE(flexibility.offset(b) == blocks[b].offset && flexibility.blockSize(b) == blocks[b].size,
                   "contact: block " << b << " of the flexibility is [" << flexibility.offset(b) << ", "
                                     << flexibility.offset(b) + flexibility.blockSize(b) << "), its body's ["
                                     << blocks[b].offset << ", " << blocks[b].offset + blocks[b].size << ")");
  EPAPHE_REQUIRE(surfaces_.size() <= 2, "contact: " << surfaces_.size() << " surfaces; at most 2 are supported");
  EPAPHE_REQUIRE(opt_.method != ContactMethod::Penalty || opt_.penaltyStiffness > 0,
                 "contact: penalty stiffness = " << opt_.penaltyStiffness << " N/m; it must be > 0");
  EPAPHE_REQUIRE(std::isfinite(opt_.friction) && opt_.friction >= 0.0,
                 "contact: friction coefficient mu = " << opt_.friction
                                                        << "; it must be a finite value >= 0 (0: frictionless)");
  const int nb = static_cast<int>(blocks.size());
  blocks_ = Kokkos::View<int* [2]>("epaphe::contact::blocks", nb);
  auto bH = Kokkos::create_mirror_view(blocks_);
  for (int b = 0; b < nb; ++b) {
    EPAPHE_REQUIRE(blocks[b].offset >= 0 && blocks[b].size > 0 && blocks[b].offset + blocks[b].size <= N,
                   "contact: block " << b << " [" << blocks[b].offset << ", " << blocks[b].offset + blocks[b].size
                                     << ") does not fit the " << N << " system coordinates");
    bH(b, 0) = blocks[b].offset;
    bH(b, 1) = blocks[b].size;
  }
  Kokkos::deep_copy(blocks_, bH);
  auto inBlock = [&](int dof, int b) { return b >= 0 && b < nb && dof >= bH(b, 0) && dof < bH(b, 0) + bH(b, 1); };
  dof_ = Kokkos::View<int* [3]>("epaphe::contact::dof", nc);
  X_ = Kokkos::View<double* [3]>("epaphe::contact::X", nc);
  nodeBlk_ = Kokkos::View<int*>("epaphe::contact::node_block", nc);
  auto dofH = Kokkos::create_mirror_view(dof_);
  auto XH = Kokkos::create_mirror_view(X_);
  auto blkH = Kokkos::create_mirror_view(nodeBlk_);
  EPAPHE_REQUIRE(nodes.dofs.size() == 3 * std::size_t(nc) && nodes.X.size() == 3 * std::size_t(nc) &&
                     nodeBlock_.size() == std::size_t(nc),
                 "contact: the node arrays disagree in size");
  for (int k = 0; k < nc; ++k) {
    blkH(k) = nodeBlock_[k];
    for (int d = 0; d < 3; ++d) {
      dofH(k, d) = nodes.dofs[3 * k + d];
      XH(k, d) = nodes.X[3 * k + d];
      EPAPHE_REQUIRE(inBlock(dofH(k, d), blkH(k)), "contact: node " << nodes_[k] << " DOF " << dofH(k, d)
                                                                    << " is outside its body's block " << blkH(k));
    }
  }
  Kokkos::deep_copy(dof_, dofH);
  Kokkos::deep_copy(X_, XH);
  Kokkos::deep_copy(nodeBlk_, blkH);

  // Carried surfaces: grid DOFs and interpolation operators, concatenated.
  const int ns = static_cast<int>(surfaces_.size());
  info_ = Kokkos::View<int* [6]>("epaphe::contact::surface_info", ns);
  gridOff_ = Kokkos::View<int*>("epaphe::contact::grid_offset", ns);
  opOff_ = Kokkos::View<int* [2]>("epaphe::contact::operator_offset", ns);
  auto infoH = Kokkos::create_mirror_view(info_);
  auto goH = Kokkos::create_mirror_view(gridOff_);
  auto ooH = Kokkos::create_mirror_view(opOff_);
  std::vector<int> gd;
  std::vector<double> ops;
  for (int s = 0; s < ns; ++s) {
    ContactSurface& cs = surfaces_[s];
    if (cs.moving) cs.surface = cs.moving;
    EPAPHE_REQUIRE(cs.surface, "contact: surface " << s << " is null");
    const BSplineSurface& S = *cs.surface;
    infoH(s, 0) = cs.moving ? cs.block : -1;
    infoH(s, 1) = S.nu();
    infoH(s, 2) = S.nv();
    infoH(s, 3) = S.inputNv();
    infoH(s, 4) = S.periodicU();
    infoH(s, 5) = S.periodicV();
    goH(s) = static_cast<int>(gd.size() / 3);
    ooH(s, 0) = static_cast<int>(ops.size());
    ops.insert(ops.end(), S.operatorU().begin(), S.operatorU().end());
    ooH(s, 1) = static_cast<int>(ops.size());
    ops.insert(ops.end(), S.operatorV().begin(), S.operatorV().end());
    gridX_.emplace_back();
    gridPos_.emplace_back();
    if (!cs.moving) continue;
    const std::size_t ng = std::size_t(S.inputNu()) * S.inputNv();
    EPAPHE_REQUIRE(cs.gridDofs.size() == 3 * ng && cs.gridX.size() == 3 * ng,
                   "contact: surface '" << S.name() << "' has " << ng << " grid nodes but " << cs.gridDofs.size() / 3
                                        << " grid DOF triples and " << cs.gridX.size() / 3 << " positions");
    for (std::size_t g = 0; g < 3 * ng; ++g)
      EPAPHE_REQUIRE(cs.gridDofs[g] < 0 || inBlock(cs.gridDofs[g], cs.block), "contact: surface '" << S.name() << "' grid DOF "
                                                                             << cs.gridDofs[g] << " is outside its body's block");
    for (int k = 0; k < nc; ++k)
      EPAPHE_REQUIRE(blkH(k) != cs.block, "contact: node " << nodes_[k] << " belongs to the body that carries surface '"
                                                            << S.name() << "'; self-contact is not supported");
    gd.insert(gd.end(), cs.gridDofs.begin(), cs.gridDofs.end());
    gridX_.back() = Kokkos::View<double* [3]>("epaphe::contact::grid_X", ng);
    gridPos_.back() = Kokkos::View<double* [3]>("epaphe::contact::grid_x", ng);
    auto gxH = Kokkos::create_mirror_view(gridX_.back());
    for (std::size_t g = 0; g < ng; ++g)
      for (int d = 0; d < 3; ++d) gxH(g, d) = cs.gridX[3 * g + d];
    Kokkos::deep_copy(gridX_.back(), gxH);
    maxGrid_[0] = std::max(maxGrid_[0], S.nu());
    maxGrid_[1] = std::max(maxGrid_[1], S.nv());
  }
  gridDof_ = Kokkos::View<int* [3]>("epaphe::contact::grid_dof", gd.size() / 3);
  auto gdH = Kokkos::create_mirror_view(gridDof_);
  for (std::size_t g = 0; g < gd.size() / 3; ++g)
    for (int d = 0; d < 3; ++d) gdH(g, d) = gd[3 * g + d];
  Kokkos::deep_copy(gridDof_, gdH);
  ops_ = Kokkos::View<double*>("epaphe::contact::operators", ops.size());
  Kokkos::deep_copy(ops_, Kokkos::View<const double*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(
                              ops.data(), ops.size()));
  Kokkos::deep_copy(info_, infoH);
  Kokkos::deep_copy(gridOff_, goH);
  gridOffH_.assign(goH.data(), goH.data() + ns);
  Kokkos::deep_copy(opOff_, ooH);
  foot_ = Kokkos::View<double* [2]>("epaphe::contact::foot", nc);
  footX_ = Kokkos::View<double* [3]>("epaphe::contact::foot_point", nc);
  rot_ = Kokkos::View<double* [3][3]>("epaphe::contact::rotation", ns);
  turn_ = Kokkos::View<double* [7]>("epaphe::contact::turning", ns);
  {
    auto tH = Kokkos::create_mirror_view(turn_);
    for (int s = 0; s < ns; ++s) {
      ContactSurface& cs = surfaces_[s];
      EPAPHE_REQUIRE(std::isfinite(cs.omega), "contact: surface '" << cs.surface->name() << "' turns at " << cs.omega
                                                                    << " rad/s; give a finite speed");
      const double l = std::sqrt(cs.axis[0] * cs.axis[0] + cs.axis[1] * cs.axis[1] + cs.axis[2] * cs.axis[2]);
      EPAPHE_REQUIRE(l > 0.0, "contact: surface '" << cs.surface->name() << "' has a zero rotation axis");
      for (double& a : cs.axis) a /= l;
      tH(s, 0) = cs.omega;
      for (int d = 0; d < 3; ++d) {
        tH(s, 1 + d) = cs.axis[d];
        tH(s, 4 + d) = cs.center[d];
      }
      EPAPHE_REQUIRE(std::isfinite(cs.phase), "contact: surface '" << cs.surface->name() << "' has the initial angle "
                                                                    << cs.phase << " rad; give a finite angle");
      xs_.emplace_back(cs.omega != 0.0 || cs.phase != 0.0 ? Kokkos::View<double* [3]>("epaphe::contact::x_surface", nc)
                                       : Kokkos::View<double* [3]>());
    }
    Kokkos::deep_copy(turn_, tH);
  }
  wu_ = Kokkos::View<double**>("epaphe::contact::weights_u", nc, maxGrid_[0]);
  wv_ = Kokkos::View<double**>("epaphe::contact::weights_v", nc, maxGrid_[1]);
  Y_ = Kokkos::View<double**, Kokkos::LayoutLeft>("epaphe::contact::FDt", F_.denseRows, 3 * nc);
  dq_ = DenseVector("epaphe::contact::correction", N);
  corrected_ = Kokkos::View<int*>("epaphe::contact::added", nc);
  {  // nodes penetrating by less than 1e-12 of the model's size after the correction are not added
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int k = 0; k < nc; ++k)
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], XH(k, d));
        hi[d] = std::max(hi[d], XH(k, d));
      }
    gapTolerance_ = 1e-12 * std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-300});
  }
  const int maxEntries = 1 + std::min(maxGrid_[0], 46) * std::min(maxGrid_[1], 46);
  entDof_ = Kokkos::View<int** [3]>("epaphe::contact::entry_dof", nc, maxEntries);
  entW_ = Kokkos::View<double**>("epaphe::contact::entry_weight", nc, maxEntries);
  entN_ = Kokkos::View<int*>("epaphe::contact::entries", nc);
  entRot_ = Kokkos::View<double* [3][3]>("epaphe::contact::entry_rotation", nc);
  C_ = Kokkos::View<double** [3][3]>("epaphe::contact::relative_flexibility", nc, nc);
  x_ = Kokkos::View<double* [3]>("epaphe::contact::x", nc);
  normal_ = Kokkos::View<double* [3]>("epaphe::contact::normal", nc);
  tangent_ = Kokkos::View<double* [3]>("epaphe::contact::tangent", nc);
  dir_ = Kokkos::View<double* [3]>("epaphe::contact::direction", nc);
  mu_ = Kokkos::View<double*>("epaphe::contact::friction", nc);
  basis_ = Kokkos::View<double* [3][3]>("epaphe::contact::basis", nc);
  disp_ = Kokkos::View<double* [3]>("epaphe::contact::motion", nc);
  nextState_ = Kokkos::View<int*>("epaphe::contact::next_state", nc);
  returns_ = Kokkos::View<int*>("epaphe::contact::slide_to_stick", nc);
  bestState_ = Kokkos::View<int*>("epaphe::contact::best_state", nc);
  nextTangent_ = Kokkos::View<double* [3]>("epaphe::contact::next_tangent", nc);
  bestTangent_ = Kokkos::View<double* [3]>("epaphe::contact::best_tangent", nc);
  if (opt_.friction > 0.0) {  // joint friction solve: up to 3 unknowns per contact node
    MCf_ = Kokkos::View<double**, Kokkos::LayoutLeft>("epaphe::contact::friction_matrix", 3 * nc, 3 * nc);
    sol_ = Kokkos::View<double*>("epaphe::contact::friction_solution", 3 * nc);
    MCfH_ = Kokkos::create_mirror_view(MCf_);
    solH_ = Kokkos::create_mirror_view(sol_);
  }
  state_ = Kokkos::View<int*>("epaphe::contact::state", nc);
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
  ipiv_.reserve(3 * static_cast<std::size_t>(nc));
  lambda_.reserve(nc);
  denseMC_.reserve(static_cast<std::size_t>(nc) * nc);
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    uv_.emplace_back("epaphe::contact::uv", nc);
    Kokkos::deep_copy(uv_.back(), std::nan(""));  // cold start from the nearest grid node
    proj_.emplace_back("epaphe::contact::projection", nc);
  }
}

std::vector<double> SurfaceContact::warmStarts() const {
  const std::size_t nc = static_cast<std::size_t>(numNodes());
  std::vector<double> all(2 * nc * uv_.size());
  for (std::size_t s = 0; s < uv_.size(); ++s) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), uv_[s]);
    for (std::size_t k = 0; k < nc; ++k)
      for (int c = 0; c < 2; ++c) all[2 * (s * nc + k) + c] = h(k, c);
  }
  return all;
}

void SurfaceContact::setWarmStarts(const std::vector<double>& all) {
  const std::size_t nc = static_cast<std::size_t>(numNodes());
  EPAPHE_REQUIRE(all.size() == 2 * nc * uv_.size(), "contact: " << all.size() << " warm-start parameters given, "
                                                          << 2 * nc * uv_.size() << " expected (2 per node, "
                                                          << nc << " nodes, " << uv_.size() << " surfaces)");
  for (std::size_t s = 0; s < uv_.size(); ++s) {
    auto h = Kokkos::create_mirror_view(uv_[s]);
    for (std::size_t k = 0; k < nc; ++k)
      for (int c = 0; c < 2; ++c) h(k, c) = all[2 * (s * nc + k) + c];
    Kokkos::deep_copy(uv_[s], h);
  }
}

void SurfaceContact::measureGaps(const DenseVector& q, CostSplit& cost) {
  ScopedPhase phase(cost, "projection");
  detect(q);
}

void SurfaceContact::detect(const DenseVector& q) {
  const int nc = numNodes();
  // Surfaces carried by a body: rebuilt from their moved grid nodes (operators reused).
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    if (!surfaces_[s].moving) continue;
    const auto gX = gridX_[s];
    const auto gx = gridPos_[s];
    const auto gdof = gridDof_;
    const int off = gridOffH_[s];
    Kokkos::parallel_for(
        "epaphe::contact::surface_nodes", gx.extent(0), KOKKOS_LAMBDA(const int g) {
          for (int d = 0; d < 3; ++d) gx(g, d) = gX(g, d) + (gdof(off + g, d) >= 0 ? q(gdof(off + g, d)) : 0.0);
        });
    auto gxH = Kokkos::create_mirror_view(gx);
    Kokkos::deep_copy(gxH, gx);
    surfaces_[s].moving->update(gxH.data());  // (ng x 3, LayoutRight: the layout update() reads)
  }
  const auto dof = dof_;
  const auto X = X_;
  const auto x = x_;
  Kokkos::parallel_for(
      "epaphe::contact::positions", nc, KOKKOS_LAMBDA(const int k) {
        for (int d = 0; d < 3; ++d) x(k, d) = X(k, d) + q(dof(k, d));
      });
  // Turning surfaces: R(omega t) by Rodrigues' formula; the nodes projected in their frame.
  auto rotH = Kokkos::create_mirror_view(rot_);
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    const ContactSurface& cs = surfaces_[s];
    const double th = cs.omega * time_ + cs.phase, c = std::cos(th), sn = std::sin(th);
    const auto& a = cs.axis;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double cross = (i == j) ? 0.0 : ((j == (i + 1) % 3) ? -a[3 - i - j] : a[3 - i - j]);
        rotH(s, i, j) = (i == j ? c : 0.0) + (1 - c) * a[i] * a[j] + sn * cross;
      }
  }
  Kokkos::deep_copy(rot_, rotH);
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    if (surfaces_[s].omega == 0.0 && surfaces_[s].phase == 0.0) {
      projectNodes(surfaces_[s].surface->view(), x_, uv_[s], proj_[s], opt_.nrTolerance, opt_.nrMaxIterations);
      continue;
    }
    const auto xs = xs_[s];
    const auto R = Kokkos::subview(rot_, s, Kokkos::ALL, Kokkos::ALL);
    const double c0 = surfaces_[s].center[0], c1 = surfaces_[s].center[1], c2 = surfaces_[s].center[2];
    Kokkos::parallel_for(
        "epaphe::contact::to_surface_frame", nc, KOKKOS_LAMBDA(const int k) {
          const double r[3] = {x(k, 0) - c0, x(k, 1) - c1, x(k, 2) - c2}, cc[3] = {c0, c1, c2};
          for (int i = 0; i < 3; ++i) xs(k, i) = cc[i] + R(0, i) * r[0] + R(1, i) * r[1] + R(2, i) * r[2];  // R^T r
        });
    projectNodes(surfaces_[s].surface->view(), xs, uv_[s], proj_[s], opt_.nrTolerance, opt_.nrMaxIterations);
  }
  // Per node, the surface with the smallest gap among those the node is not beyond.
  const auto gap = gap_;
  const auto normal = normal_;
  const auto surf = surf_;
  const auto foot = foot_;
  const auto footX = footX_;
  const auto rot = rot_;
  const auto turn = turn_;
  const auto p0 = proj_[0];
  const auto p1 = surfaces_.size() > 1 ? proj_[1] : proj_[0];
  const int ns = static_cast<int>(surfaces_.size());
  const double edgeTol = opt_.edgeTolerance > opt_.nrTolerance ? opt_.edgeTolerance : opt_.nrTolerance;
  int iters = 0;
  Kokkos::parallel_reduce(
      "epaphe::contact::select", nc,
      KOKKOS_LAMBDA(const int k, int& maxIt) {
        int best = -1;
        double g = 1e300;
        for (int s = 0; s < ns; ++s) {
          const Projection& p = s == 0 ? p0(k) : p1(k);
          if (p.iterations > maxIt) maxIt = p.iterations;
          if (!(p.beyond > edgeTol) && p.gap < g) {
            g = p.gap;
            best = s;
            for (int d = 0; d < 3; ++d) {  // back to the bodies' frame: n = R n_s, S = c + R (S_s - c)
              normal(k, d) = rot(s, d, 0) * p.normal[0] + rot(s, d, 1) * p.normal[1] + rot(s, d, 2) * p.normal[2];
              double y = turn(s, 4 + d);
              for (int e = 0; e < 3; ++e) y += rot(s, d, e) * (p.point[e] - turn(s, 4 + e));
              footX(k, d) = y;
            }
            foot(k, 0) = p.u;
            foot(k, 1) = p.v;
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
  motionEntries();
  // Active set (Lagrange): the nodes the predictor made penetrate, less those the surface would
  // pull (lambda < 0, released inside the solves), plus those the correction of the others makes
  // penetrate through the coupling of F (their corrected gap g*_a + n_a . D_a dq < 0): solved
  // again until no node is added (at most kMaxAddPasses).
  const auto dq = dq_;
  for (int pass = 0;; ++pass) {
    numActive_ = static_cast<int>(activeH_.size());
    relativeColumns();
    if (!friction || qCurrent == nullptr) {  // frictionless: c_a = n_a exactly
      setNormalDirections();
      if (opt_.method == ContactMethod::Penalty) {
        for (int k : activeH_) forceH_(k) = opt_.penaltyStiffness * (-gapH_(k));  // eq. 2.34
      } else {
        solveLagrange(numActive_);
      }
      Kokkos::deep_copy(force_, forceH_);
    } else {
      prepareFriction(q, *qCurrent);
      solveFriction();
    }
    // dq = F G lambda (eqs. 2.35-2.36), G_a = D_a^T c_a: on the dense rows of F, F D_a^T = Y, one
    // pass over them; on a diagonal block, dq_i = F_ii (sum_a D_a^T c_a lambda_a)_i, scattered from
    // the entries of D (one thread: the same sums in the same order on any number of threads).
    const auto Y = Y_;
    const auto F = F_;
    const auto dir = dir_;
    const auto force = force_;
    Kokkos::parallel_for(
        "epaphe::contact::correction", q.extent(0), KOKKOS_LAMBDA(const int i) {
          const int r = F.denseRow(i);
          double s = 0.0;
          for (std::size_t k = 0; r >= 0 && k < force.extent(0); ++k) {
            const double l = force(k);
            if (l == 0.0) continue;
            s += l * (Y(r, 3 * k) * dir(k, 0) + Y(r, 3 * k + 1) * dir(k, 1) + Y(r, 3 * k + 2) * dir(k, 2));
          }
          dq(i) = s;
        });
    if (F.denseRows < F.size()) {
      const RelativeMotion Dk{entDof_, entW_, entN_, entRot_};
      Kokkos::parallel_for(
          "epaphe::contact::correction_diagonal", Kokkos::RangePolicy<>(0, 1), KOKKOS_LAMBDA(const int) {
            for (std::size_t k = 0; k < force.extent(0); ++k) {
              const double l = force(k);
              if (l == 0.0) continue;
              // (D_k^T c)_i at DOF i = (m, e)
              for (int m = 0; m < Dk.count(k); ++m)
                for (int e = 0; e < 3; ++e) {
                  const int i = Dk.dof(k, m, e);
                  if (i < 0 || F.denseRow(i) >= 0) continue;
                  const double c = Dk.coefficient(k, m, 0, e) * dir(k, 0) + Dk.coefficient(k, m, 1, e) * dir(k, 1) +
                                   Dk.coefficient(k, m, 2, e) * dir(k, 2);
                  dq(i) += F.diag(i) * l * c;
                }
            }
          });
    }
    if (opt_.method == ContactMethod::Penalty || pass == kMaxAddPasses) break;
    // corrected gaps of the nodes outside the active set
    const RelativeMotion D{entDof_, entW_, entN_, entRot_};
    const auto normal = normal_;
    const auto gap = gap_;
    const auto surf = surf_;
    const auto corrected = corrected_;
    const double eps = gapTolerance_;
    int added = 0;
    Kokkos::parallel_reduce(
        "epaphe::contact::corrected_gaps", nc,
        KOKKOS_LAMBDA(const int k, int& n) {
          corrected(k) = 0;
          if (surf(k) < 0 || force(k) != 0.0 || !(gap(k) < 1e300)) return;
          double g = gap(k), r[3];
          D.apply(k, dq, r);
          for (int d = 0; d < 3; ++d) g += normal(k, d) * r[d];
          if (g < -eps) {
            corrected(k) = 1;
            ++n;
          }
        },
        added);
    if (added == 0) break;
    auto addH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), corrected_);
    activeH_.clear();
    for (int k = 0; k < nc; ++k)
      if (forceH_(k) != 0.0 || addH(k)) activeH_.push_back(k);
    lastAddPasses_ = pass + 1;
  }
  if (friction) {
    Kokkos::deep_copy(muH_, mu_);
    Kokkos::deep_copy(tangentH_, tangent_);
  }
  KokkosBlas::axpy(1.0, dq_, q);
  Kokkos::fence();
}

void SurfaceContact::setNormalDirections() {
  const auto normal = normal_;
  const auto tangent = tangent_;
  const auto dir = dir_;
  const auto muA = mu_;
  Kokkos::parallel_for(
      "epaphe::contact::normal_direction", numNodes(), KOKKOS_LAMBDA(const int k) {
        for (int d = 0; d < 3; ++d) {
          dir(k, d) = normal(k, d);
          tangent(k, d) = 0.0;
        }
        muA(k) = 0.0;
      });
  Kokkos::fence();
}

void SurfaceContact::prepareFriction(const DenseVector& q, const DenseVector& qn) {
  // Per node: d_a = u_a(q*) - u_a(q_n), the tangent-plane basis (e1, e2) of n_a, and the initial
  // state: sliding against the predicted tangential motion (t = -d_t / |d_t|) when there is one,
  // stuck otherwise.
  const auto normal = normal_;
  const auto basis = basis_;
  const auto disp = disp_;
  const auto tangent = tangent_;
  const auto state = state_;
  const auto returns = returns_;
  const auto x = x_;
  const RelativeMotion D{entDof_, entW_, entN_, entRot_};
  const Difference<DenseVector> dq{q, qn};
  const auto surfOf = surf_;
  const auto turn = turn_;
  const auto footX = footX_;
  const double h = opt_.timeStep;
  Kokkos::parallel_for(
      "epaphe::contact::friction_prepare", numNodes(), KOKKOS_LAMBDA(const int k) {
        double n[3], dsp[3], dn = 0.0, dd = 0.0, xx = 0.0;
        for (int e = 0; e < 3; ++e) n[e] = normal(k, e);
        D.apply(k, dq, dsp);  // relative motion d_a = D_a (q* - q_n)
        if (surfOf(k) >= 0 && turn(surfOf(k), 0) != 0.0) {
          // less the turning surface's own motion over the step, h omega a x (S - c)
          const int s = surfOf(k);
          const double w = h * turn(s, 0);
          const double r[3] = {footX(k, 0) - turn(s, 4), footX(k, 1) - turn(s, 5), footX(k, 2) - turn(s, 6)};
          const double a[3] = {turn(s, 1), turn(s, 2), turn(s, 3)};
          dsp[0] -= w * (a[1] * r[2] - a[2] * r[1]);
          dsp[1] -= w * (a[2] * r[0] - a[0] * r[2]);
          dsp[2] -= w * (a[0] * r[1] - a[1] * r[0]);
        }
        for (int e = 0; e < 3; ++e) {
          disp(k, e) = dsp[e];
          dn += dsp[e] * n[e];
          dd += dsp[e] * dsp[e];
          xx += x(k, e) * x(k, e);
        }
        // e1: the coordinate axis least aligned with n, made orthogonal to n; e2 = n x e1
        const int ax = ::fabs(n[0]) <= ::fabs(n[1]) && ::fabs(n[0]) <= ::fabs(n[2]) ? 0 : (::fabs(n[1]) <= ::fabs(n[2]) ? 1 : 2);
        double e1[3] = {0.0, 0.0, 0.0};
        e1[ax] = 1.0;
        double an = n[ax], l1 = 0.0;
        for (int e = 0; e < 3; ++e) {
          e1[e] -= an * n[e];
          l1 += e1[e] * e1[e];
        }
        l1 = ::sqrt(l1);
        for (int e = 0; e < 3; ++e) e1[e] /= l1;
        const double e2[3] = {n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
        for (int e = 0; e < 3; ++e) {
          basis(k, 0, e) = n[e];
          basis(k, 1, e) = e1[e];
          basis(k, 2, e) = e2[e];
        }
        double dt[3], tt = 0.0;
        for (int e = 0; e < 3; ++e) {
          dt[e] = dsp[e] - dn * n[e];
          tt += dt[e] * dt[e];
        }
        const double len = ::sqrt(tt);
        const bool moving = len > 1e-14 * (::sqrt(xx) + ::sqrt(dd));
        for (int e = 0; e < 3; ++e) tangent(k, e) = moving ? -dt[e] / len : 0.0;
        state(k) = moving ? kSlide : kStick;
        returns(k) = 0;
      });
  Kokkos::fence();
}

Kokkos::View<int*> SurfaceContact::uploadActive(int nA) {
  Kokkos::View<int*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> activeH(activeH_.data(), nA);
  auto active = Kokkos::subview(active_, Kokkos::make_pair(0, nA));
  Kokkos::deep_copy(active, activeH);
  return active;
}

void SurfaceContact::motionEntries() {
  // For every node on a surface: the entries of D_k, i.e. the spline weights of its foot point on
  // a carried surface.
  const auto foot = foot_;
  const auto ops = ops_;
  const auto opOff = opOff_;
  const auto info = info_;
  const auto surf = surf_;
  const auto gridOff = gridOff_;
  const auto gridDof = gridDof_;
  const auto dof = dof_;
  const auto wu = wu_, wv = wv_;
  const auto entDof = entDof_;
  const auto entW = entW_;
  const auto entN = entN_;
  const auto entRot = entRot_;
  const auto rot = rot_;
  const int maxE = static_cast<int>(entW_.extent(1));
  Kokkos::parallel_for(
      "epaphe::contact::relative_motion", numNodes(), KOKKOS_LAMBDA(const int k) {
        for (int d = 0; d < 3; ++d) entDof(k, 0, d) = dof(k, d);
        entW(k, 0) = 1.0;
        int m = 1;
        const int s = surf(k);
        for (int d = 0; d < 3; ++d)  // R of the surface at this detection (identity when it does not turn)
          for (int e = 0; e < 3; ++e) entRot(k, d, e) = s >= 0 ? rot(s, d, e) : (d == e ? 1.0 : 0.0);
        if (s >= 0 && info(s, 0) >= 0) {
          // w_p = sum_r b_r B(i + r, p): the cubic basis (eq. 2.22) contracted with the rows of the
          // interpolation operator (eq. 2.26, row-major n_ext x n) the patch reads
          for (int dir = 0; dir < 2; ++dir) {
            const int n = info(s, 1 + dir);
            const auto& wgt = dir == 0 ? wu : wv;
            int i;
            double t, bs[4], db[4], ddb[4], wmax = 0.0;
            surface_detail::locate(foot(k, dir), n, info(s, 4 + dir) != 0, i, t);
            surface_detail::cubicBasis(t, bs, db, ddb);
            for (int p = 0; p < n; ++p) {
              double x = 0.0;
              for (int r = 0; r < 4; ++r) x += bs[r] * ops(opOff(s, dir) + (i + r) * n + p);
              wgt(k, p) = x;
              wmax = ::fabs(x) > wmax ? ::fabs(x) : wmax;
            }
            for (int p = 0; p < n; ++p)  // they decay like 0.27^distance: at most 46 are kept
              if (::fabs(wgt(k, p)) < 1e-12 * wmax) wgt(k, p) = 0.0;
          }
          const int nu = info(s, 1), nv = info(s, 2), inNv = info(s, 3), off = gridOff(s);
          for (int p = 0; p < nu; ++p) {
            if (wu(k, p) == 0.0) continue;
            for (int q = 0; q < nv && m < maxE; ++q) {
              if (wv(k, q) == 0.0) continue;
              const int g = off + p * inNv + q;
              for (int d = 0; d < 3; ++d) entDof(k, m, d) = gridDof(g, d);
              entW(k, m) = -wu(k, p) * wv(k, q);
              ++m;
            }
          }
        }
        entN(k) = m;
      });
}

void SurfaceContact::relativeColumns() {
  // For the active nodes: Y_k = F D_k^T (N x 3; only the rows of the node's block and of the
  // surface's block are not zero) and C_ab = D_a Y_b (3 x 3 per active pair).
  const int nA = numActive_;
  const auto active = uploadActive(nA);
  const auto surf = surf_;
  const auto info = info_;
  const auto entDof = entDof_;
  const auto entN = entN_;
  const auto F = F_;
  const auto Y = Y_;
  const auto blocks = blocks_;
  const auto nodeBlk = nodeBlk_;
  const RelativeMotion D{entDof_, entW_, entN_, entRot_};
  const int rows = F.denseRows;
  // Y(:, 3k + e) = sum_m w_m F(:, dof_m,e) on the dense rows: axpys of contiguous columns over the
  // entry's block (a diagonal block's part of F D^T is read from the entries, FlexibleColumn)
  Kokkos::parallel_for(
      "epaphe::contact::relative_columns", 3 * nA, KOKKOS_LAMBDA(const int ae) {
        const int k = active(ae / 3), e = ae % 3, c = 3 * k + e;
        for (int r = 0; r < rows; ++r) Y(r, c) = 0.0;
        const int s = surf(k);
        for (int m = 0; m < entN(k); ++m) {
          const int blk = m == 0 ? nodeBlk(k) : info(s, 0);
          const int b0 = blocks(blk, 0), n = blocks(blk, 1), r0 = F.denseRow(b0);
          for (int e2 = 0; e2 < 3; ++e2) {
            const double w = D.coefficient(k, m, e, e2);
            const int j = entDof(k, m, e2);
            if (w == 0.0 || j < 0 || F.denseRow(j) < 0) continue;
            const std::size_t col = F.start(blk) + static_cast<std::size_t>(j - b0) * n;
            for (int i = 0; i < n; ++i) Y(r0 + i, c) += w * F.dense(col + i);
          }
        }
      });
  const auto C = C_;
  Kokkos::parallel_for(
      "epaphe::contact::relative_flexibility", nA * nA, KOKKOS_LAMBDA(const int ab) {
        const int ka = active(ab / nA), kb = active(ab % nA);
        for (int e = 0; e < 3; ++e) {
          const FlexibleColumn<decltype(Y)> col{Y, F, D, kb, e};
          double r[3];
          D.apply(ka, col, r);
          for (int d = 0; d < 3; ++d) C(ka, kb, d, e) = r[d];
        }
      });
  Kokkos::fence();
}

namespace {
/// Column vectors of node k's unknowns (lambda, s1, s2): stuck, force lambda n + s1 e1 + s2 e2;
/// sliding, lambda (n + mu t) and no tangential unknowns (their rows are s1 = s2 = 0).
template <class B, class T, class S>
KOKKOS_INLINE_FUNCTION void frictionColumns(const B& basis, const T& tangent, const S& state, int k, double mu,
                                            int slide, double c[3][3]) {
  const bool sl = state(k) == slide;
  for (int e = 0; e < 3; ++e) {
    c[0][e] = basis(k, 0, e) + (sl ? mu * tangent(k, e) : 0.0);
    c[1][e] = sl ? 0.0 : basis(k, 1, e);
    c[2][e] = sl ? 0.0 : basis(k, 2, e);
  }
}
}  // namespace

void SurfaceContact::solveFriction() {
  // Joint solve over the active set, 3 unknowns per active node a (lambda_a, s1_a, s2_a):
  //   normal row:     g*_a + n_a^T sum_b F_ab f_b = 0, f_b the force on node b (the gap closes;
  //                   penalty: lambda_a = k_p (-g*_a) instead);
  //   stuck, rows i:  e_i,a^T (d_a + sum_b F_ab f_b) = 0  (no tangential motion over the step);
  //   sliding:        s1_a = s2_a = 0, the node's force being lambda_a (n_a + mu t_a).
  // Then classify: stuck -> sliding when |s_a| > mu lambda_a (t_a = s_a / |s_a|); sliding -> stuck
  // when the corrected tangential motion w_a does not oppose t_a (w_a . t_a > 0), else t_a follows
  // -w_a / |w_a|. Repeat while anything changes (at most kMaxFrictionPasses; then the pass with the
  // fewest changes is solved again and kept). Lagrange nodes with lambda_a < 0 are released.
  Teuchos::LAPACK<int, double> lapack;
  const bool penalty = opt_.method == ContactMethod::Penalty;
  const double mu = opt_.friction, kp = opt_.penaltyStiffness;
  const int nc = numNodes();
  const int ld = 3 * nc;
  int bestChanges = -1, passes = 0, releases = 0;
  bool restored = false;
  int nA = numActive_;
  for (;;) {
    const auto active = uploadActive(nA);
    const auto C = C_;
    const auto basis = basis_;
    const auto tangent = tangent_;
    const auto state = state_;
    const auto disp = disp_;
    const auto gap = gap_;
    const auto A = MCf_;
    const auto sol = sol_;
    constexpr int slide = kSlide;
    Kokkos::parallel_for(
        "epaphe::contact::friction_matrix", nA, KOKKOS_LAMBDA(const int a) {
          const int ka = active(a);
          const bool sl = state(ka) == slide;
          for (int b = 0; b < nA; ++b) {
            const int kb = active(b);
            double c[3][3];
            frictionColumns(basis, tangent, state, kb, mu, slide, c);
            double G[3][3];  // G[d][j] = (F_ab c_j)_d
            for (int d = 0; d < 3; ++d)
              for (int j = 0; j < 3; ++j) {
                double s = 0.0;
                for (int e = 0; e < 3; ++e) s += C(ka, kb, d, e) * c[j][e];
                G[d][j] = s;
              }
            for (int i = 0; i < 3; ++i) {
              const bool identity = (i == 0 && penalty) || (i > 0 && sl);
              for (int j = 0; j < 3; ++j) {
                double s = 0.0;
                if (identity)
                  s = (a == b && i == j) ? 1.0 : 0.0;
                else
                  for (int d = 0; d < 3; ++d) s += basis(ka, i, d) * G[d][j];
                A(3 * a + i, 3 * b + j) = s;
              }
            }
          }
          sol(3 * a) = penalty ? kp * (-gap(ka)) : -gap(ka);
          for (int i = 1; i < 3; ++i) {
            double s = 0.0;
            if (!sl)
              for (int d = 0; d < 3; ++d) s -= basis(ka, i, d) * disp(ka, d);
            sol(3 * a + i) = s;
          }
        });
    Kokkos::fence();
    Kokkos::deep_copy(MCfH_, MCf_);
    Kokkos::deep_copy(solH_, sol_);
    const int m = 3 * nA;
    ipiv_.assign(static_cast<std::size_t>(m), 0);
    int info = 0;
    lapack.GESV(m, 1, MCfH_.data(), ld, ipiv_.data(), solH_.data(), m, &info);
    EPAPHE_REQUIRE(info == 0, "contact: the friction contact system of " << nA << " active nodes is singular (LAPACK info "
                                                                        << info << ")");
    Kokkos::deep_copy(sol_, solH_);
    if (!penalty) {  // release the nodes the surface would pull
      keep_.clear();
      for (int a = 0; a < nA; ++a)
        if (solH_(3 * a) >= 0.0) keep_.push_back(activeH_[a]);
      if (static_cast<int>(keep_.size()) < nA && releases < nc) {
        ++releases;
        activeH_.swap(keep_);
        nA = static_cast<int>(activeH_.size());
        if (nA == 0) break;
        continue;
      }
    }
    if (restored) break;
    // classify: proposed next state and direction per active node
    const auto nextState = nextState_;
    const auto nextTangent = nextTangent_;
    const auto returns = returns_;
    int changes = 0;
    Kokkos::parallel_reduce(
        "epaphe::contact::friction_classify", nA,
        KOKKOS_LAMBDA(const int a, int& count) {
          const int ka = active(a);
          const double lambda = sol(3 * a);
          double t[3];
          for (int e = 0; e < 3; ++e) t[e] = tangent(ka, e);
          int next = state(ka);
          if (state(ka) != slide) {
            double s[3], ss = 0.0;
            for (int e = 0; e < 3; ++e) {
              s[e] = sol(3 * a + 1) * basis(ka, 1, e) + sol(3 * a + 2) * basis(ka, 2, e);
              ss += s[e] * s[e];
            }
            ss = ::sqrt(ss);
            if (ss > mu * lambda) {  // outside the cone: slide, friction along the sticking force
              next = slide;
              for (int e = 0; e < 3; ++e) t[e] = s[e] / ss;
            }
          } else {
            // w = d_a + sum_b F_ab f_b, its tangential part
            double w[3];
            for (int e = 0; e < 3; ++e) w[e] = disp(ka, e);
            for (int b = 0; b < nA; ++b) {
              const int kb = active(b);
              double c[3][3];
              frictionColumns(basis, tangent, state, kb, mu, slide, c);
              double f[3];
              for (int e = 0; e < 3; ++e)
                f[e] = sol(3 * b) * c[0][e] + sol(3 * b + 1) * c[1][e] + sol(3 * b + 2) * c[2][e];
              for (int d = 0; d < 3; ++d)
                for (int e = 0; e < 3; ++e) w[d] += C(ka, kb, d, e) * f[e];
            }
            // radial return: the tangential force that would stop the node, the others' forces
            // fixed, s_trial = mu lambda t - K^{-1} w_t, K_ij = e_i^T F_aa e_j (2 x 2); inside the
            // cone it sticks, outside it slides along s_trial (stable when w is small)
            double w1 = 0.0, w2 = 0.0, K[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
            for (int e = 0; e < 3; ++e) {
              w1 += w[e] * basis(ka, 1, e);
              w2 += w[e] * basis(ka, 2, e);
            }
            for (int i = 0; i < 2; ++i)
              for (int j = 0; j < 2; ++j)
                for (int d = 0; d < 3; ++d)
                  for (int e = 0; e < 3; ++e) K[i][j] += basis(ka, 1 + i, d) * C(ka, ka, d, e) * basis(ka, 1 + j, e);
            const double det = K[0][0] * K[1][1] - K[0][1] * K[1][0];
            const double d1 = -(K[1][1] * w1 - K[0][1] * w2) / det, d2 = -(-K[1][0] * w1 + K[0][0] * w2) / det;
            double st[3], ss = 0.0;
            for (int e = 0; e < 3; ++e) {
              st[e] = mu * lambda * t[e] + d1 * basis(ka, 1, e) + d2 * basis(ka, 2, e);
              ss += st[e] * st[e];
            }
            ss = ::sqrt(ss);
            if (!(ss > mu * lambda) && returns(ka) < kMaxReturns) {
              next = kStick;
            } else if (ss > 0.0) {
              for (int e = 0; e < 3; ++e) t[e] = st[e] / ss;
            }
          }
          double dt = 0.0;
          for (int e = 0; e < 3; ++e) {
            dt += (t[e] - tangent(ka, e)) * (t[e] - tangent(ka, e));
            nextTangent(ka, e) = t[e];
          }
          nextState(ka) = next;
          if (next != state(ka) || (next == slide && dt > 1e-12)) ++count;  // |t change| > 1e-6
        },
        changes);
    if (changes == 0) break;
    if (bestChanges < 0 || changes < bestChanges) {
      bestChanges = changes;
      Kokkos::deep_copy(bestState_, state_);
      Kokkos::deep_copy(bestTangent_, tangent_);
    }
    if (++passes == kMaxFrictionPasses) {  // not settled: solve again with the best pass's states
      Kokkos::deep_copy(state_, bestState_);
      Kokkos::deep_copy(tangent_, bestTangent_);
      restored = true;
      continue;
    }
    const auto returns2 = returns_;
    Kokkos::parallel_for(
        "epaphe::contact::friction_commit", nA, KOKKOS_LAMBDA(const int a) {
          const int ka = active(a);
          if (state(ka) == slide && nextState(ka) != slide) ++returns2(ka);
          state(ka) = nextState(ka);
          for (int e = 0; e < 3; ++e) tangent(ka, e) = nextTangent(ka, e);
        });
    Kokkos::fence();
  }
  numActive_ = nA;
  lastFrictionPasses_ = passes + 1;
  // forces: lambda_a, and the direction c_a = n_a + mu_a t_a with mu_a t_a = s_a / lambda_a
  for (int k = 0; k < nc; ++k) forceH_(k) = 0.0;
  for (int a = 0; a < nA; ++a) forceH_(activeH_[a]) = solH_(3 * a);
  Kokkos::deep_copy(force_, forceH_);
  const auto active = uploadActive(nA);
  const auto normal = normal_;
  const auto basis = basis_;
  const auto tangent = tangent_;
  const auto state = state_;
  const auto dir = dir_;
  const auto muA = mu_;
  const auto sol = sol_;
  const auto force = force_;
  Kokkos::parallel_for(
      "epaphe::contact::friction_reset", nc, KOKKOS_LAMBDA(const int k) {
        for (int e = 0; e < 3; ++e) {
          dir(k, e) = normal(k, e);
          if (force(k) == 0.0) tangent(k, e) = 0.0;
        }
        muA(k) = 0.0;
      });
  Kokkos::fence();
  Kokkos::parallel_for(
      "epaphe::contact::friction_force", nA, KOKKOS_LAMBDA(const int a) {
        const int ka = active(a);
        const double l = sol(3 * a);
        if (state(ka) == kSlide) {
          muA(ka) = l > 0.0 ? mu : 0.0;
          for (int e = 0; e < 3; ++e) dir(ka, e) = normal(ka, e) + mu * tangent(ka, e);
          return;
        }
        double s[3], ss = 0.0;
        for (int e = 0; e < 3; ++e) {
          s[e] = sol(3 * a + 1) * basis(ka, 1, e) + sol(3 * a + 2) * basis(ka, 2, e);
          ss += s[e] * s[e];
        }
        ss = ::sqrt(ss);
        if (!(l > 0.0) || !(ss > 0.0)) {
          for (int e = 0; e < 3; ++e) tangent(ka, e) = 0.0;
          return;
        }
        muA(ka) = ss / l;
        for (int e = 0; e < 3; ++e) {
          tangent(ka, e) = s[e] / ss;
          dir(ka, e) = normal(ka, e) + s[e] / l;
        }
      });
  Kokkos::fence();
}

void SurfaceContact::solveLagrange(int nA) {
  // Active set iteration (frictionless: c_a = n_a): solve MC lambda = -g* (eq. 2.33), release
  // nodes pulled by the surface.
  Teuchos::LAPACK<int, double> lapack;
  std::vector<double>& lambda = lambda_;
  for (int pass = 0; pass <= numNodes() && nA > 0; ++pass) {
    const auto active = uploadActive(nA);
    const auto C = C_;
    const auto normal = normal_;
    const auto dir = dir_;
    const auto MC = MC_;
    // MC_ab = n_a^T C_ab c_b (eq. 2.32), C_ab = D_a F D_b^T, one row per active node.
    Kokkos::parallel_for(
        "epaphe::contact::matrix", nA, KOKKOS_LAMBDA(const int a) {
          const int ka = active(a);
          for (int b = 0; b < nA; ++b) {
            const int kb = active(b);
            double s = 0.0;
            for (int d = 0; d < 3; ++d)
              for (int e = 0; e < 3; ++e) {
                s += normal(ka, d) * C(ka, kb, d, e) * dir(kb, e);
              }
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
  for (int k = 0; k < numNodes(); ++k) forceH_(k) = 0.0;  // also nodes released on a former solve
  for (int a = 0; a < nA; ++a) forceH_(activeH_[a]) = lambda[a];
}

double SurfaceContact::workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const {
  double w = 0.0;
  if (numActive_ == 0) return w;
  const auto dir = dir_;
  const auto force = force_;
  const RelativeMotion D{entDof_, entW_, entN_, entRot_};
  const Difference<DenseVector> dq{qNext, qPrev};
  Kokkos::parallel_reduce(
      "epaphe::contact::work", numNodes(),
      KOKKOS_LAMBDA(const int k, double& s) {
        const double l = force(k);
        if (l == 0.0) return;
        double r[3];
        D.apply(k, dq, r);
        for (int d = 0; d < 3; ++d) s += 0.5 * l * dir(k, d) * r[d];
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
