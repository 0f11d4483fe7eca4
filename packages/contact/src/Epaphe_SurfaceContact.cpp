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

/// True when system DOF `dof` lies in block b, [offset, offset + size) of the blocks' host copy bH.
bool inBlock(const Kokkos::View<int* [2]>::HostMirror& bH, int dof, int b) {
  const int nb = static_cast<int>(bH.extent(0));
  return b >= 0 && b < nb && dof >= bH(b, 0) && dof < bH(b, 0) + bH(b, 1);
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
    : opt_(options),
      nodes_(std::move(nodes.labels)),
      nodeBlock_(std::move(nodes.block)),
      surfaces_(std::move(surfaces)),
      F_(flexibility.pack()) {
  const int nc = static_cast<int>(nodes_.size());
  const int N = flexibility.size();
  EPAPHE_REQUIRE(nc > 0, "contact: the contact node set is empty");
  EPAPHE_REQUIRE(!surfaces_.empty(), "contact: no surface to contact");
  const auto bH = initBlocks(blocks, flexibility);
  const auto blkH = initNodeBlocks(nodes, bH);
  initCarriedSurfaces(bH, blkH);
  controlColumns();
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

Kokkos::View<int* [2]>::HostMirror SurfaceContact::initBlocks(const std::vector<ContactBlock>& blocks,
                                                              const Flexibility& flexibility) {
  const int N = flexibility.size();
  EPAPHE_REQUIRE(flexibility.numBlocks() == static_cast<int>(blocks.size()),
                 "contact: the flexibility has " << flexibility.numBlocks() << " blocks, the bodies " << blocks.size());
  for (std::size_t b = 0; b < blocks.size(); ++b)
    EPAPHE_REQUIRE(flexibility.offset(b) == blocks[b].offset && flexibility.blockSize(b) == blocks[b].size,
                   "contact: block " << b << " of the flexibility is [" << flexibility.offset(b) << ", "
                                     << flexibility.offset(b) + flexibility.blockSize(b) << "), its body's ["
                                     << blocks[b].offset << ", " << blocks[b].offset + blocks[b].size << ")");
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
  return bH;
}

Kokkos::View<int*>::HostMirror SurfaceContact::initNodeBlocks(const ContactNodes& nodes,
                                                              const Kokkos::View<int* [2]>::HostMirror& bH) {
  const int nc = static_cast<int>(nodes_.size());
  nodeBlk_ = Kokkos::View<int*>("epaphe::contact::node_block", nc);
  auto blkH = Kokkos::create_mirror_view(nodeBlk_);
  EPAPHE_REQUIRE(nodes.dofs.size() == 3 * std::size_t(nc) && nodes.X.size() == 3 * std::size_t(nc) &&
                     nodeBlock_.size() == std::size_t(nc),
                 "contact: the node arrays disagree in size");
  for (int k = 0; k < nc; ++k) {
    blkH(k) = nodeBlock_[k];
    for (int d = 0; d < 3; ++d)
      EPAPHE_REQUIRE(inBlock(bH, nodes.dofs[3 * k + d], blkH(k)), "contact: node "
                                                                      << nodes_[k] << " DOF " << nodes.dofs[3 * k + d]
                                                                      << " is outside its body's block " << blkH(k));
  }
  Kokkos::deep_copy(nodeBlk_, blkH);
  return blkH;
}

void SurfaceContact::initCarriedSurfaces(const Kokkos::View<int* [2]>::HostMirror& bH,
                                         const Kokkos::View<int*>::HostMirror& blkH) {
  // Carried surfaces: grid DOFs and interpolation operators, concatenated.
  const int nc = static_cast<int>(nodes_.size());
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
    if (!cs.moving) continue;
    const std::size_t ng = std::size_t(S.inputNu()) * S.inputNv();
    EPAPHE_REQUIRE(cs.gridDofs.size() == 3 * ng && cs.gridX.size() == 3 * ng,
                   "contact: surface '" << S.name() << "' has " << ng << " grid nodes but " << cs.gridDofs.size() / 3
                                        << " grid DOF triples and " << cs.gridX.size() / 3 << " positions");
    for (std::size_t g = 0; g < 3 * ng; ++g)
      EPAPHE_REQUIRE(
          cs.gridDofs[g] < 0 || inBlock(bH, cs.gridDofs[g], cs.block),
          "contact: surface '" << S.name() << "' grid DOF " << cs.gridDofs[g] << " is outside its body's block");
    for (int k = 0; k < nc; ++k)
      EPAPHE_REQUIRE(blkH(k) != cs.block, "contact: node " << nodes_[k] << " belongs to the body that carries surface '"
                                                           << S.name() << "'; self-contact is not supported");
    gd.insert(gd.end(), cs.gridDofs.begin(), cs.gridDofs.end());
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
  Kokkos::deep_copy(opOff_, ooH);
}

void SurfaceContact::initDetection(const ContactNodes& nodes) {
  const DetectionOptions dopt = detectionOptions(opt_.complete());
  detection_ = std::make_unique<ContactDetection>(nodes.dofs, nodes.X, surfaces_, dopt);
  surfaces_ = detection_->surfaces();  // axes made unit
  const DetectionViews& dv = detection_->views();
  dof_ = dv.dof;
  x_ = dv.x;
  rot_ = dv.rot;
  turn_ = dv.turn;
  gap_ = dv.gap;
  surf_ = dv.selected;
  normal_ = dv.normal;
  foot_ = dv.foot;
  footX_ = dv.footX;
  skipped_ = dv.skipped;
  refine_ = dv.refine;
  bound_ = dv.bound;
}

void SurfaceContact::initWorkViews(const ContactNodes& nodes, int N) {
  const int nc = static_cast<int>(nodes_.size());
  wu_ = Kokkos::View<double**>("epaphe::contact::weights_u", nc, maxGrid_[0]);
  wv_ = Kokkos::View<double**>("epaphe::contact::weights_v", nc, maxGrid_[1]);
  pbasis_ = Kokkos::View<double* [8]>("epaphe::contact::patch_basis", nc);
  pcell_ = Kokkos::View<int* [2]>("epaphe::contact::patch_cell", nc);
  T_ = Kokkos::View<double**, Kokkos::LayoutLeft>("epaphe::contact::BuFDt", tRows_, 3 * nc);
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
  const int maxEntries = 1 + std::min(maxGrid_[0], 46) * std::min(maxGrid_[1], 46);
  entDof_ = Kokkos::View<int** [3]>("epaphe::contact::entry_dof", nc, maxEntries);
  entW_ = Kokkos::View<double**>("epaphe::contact::entry_weight", nc, maxEntries);
  entN_ = Kokkos::View<int*>("epaphe::contact::entries", nc);
  patch_ = Kokkos::View<int*>("epaphe::contact::patch_block", nc);
  entRot_ = Kokkos::View<double* [3][3]>("epaphe::contact::entry_rotation", nc);
  C_ = Kokkos::View<double** [3][3]>("epaphe::contact::relative_flexibility", nc, nc);
  known_ = Kokkos::View<int*>("epaphe::contact::known_rows", nc);
  fixedC_ = Kokkos::View<int**>("epaphe::contact::fixed_pairs", nc, nc);
  tangent_ = Kokkos::View<double* [3]>("epaphe::contact::tangent", nc);
  dir_ = Kokkos::View<double* [3]>("epaphe::contact::direction", nc);
  mu_ = Kokkos::View<double*>("epaphe::contact::friction", nc);
  muH_ = Kokkos::create_mirror_view(mu_);
  tangentH_ = Kokkos::create_mirror_view(tangent_);
  force_ = Kokkos::View<double*>("epaphe::contact::force", nc);
  active_ = Kokkos::View<int*>("epaphe::contact::active", nc);
  gapH_ = Kokkos::create_mirror_view(gap_);
  forceH_ = Kokkos::create_mirror_view(force_);
  surfH_ = Kokkos::create_mirror_view(surf_);
  activeH_.reserve(nc);
}

void SurfaceContact::initStepViews() {
  v_.gap = gap_;
  v_.surf = surf_;
  v_.normal = normal_;
  v_.x = x_;
  v_.footX = footX_;
  v_.turn = turn_;
  v_.D = RelativeMotion{entDof_, entW_, entN_, entRot_};
  v_.C = C_;
  v_.active = active_;
  v_.force = force_;
  v_.mu = mu_;
  v_.dir = dir_;
  v_.tangent = tangent_;
  v_.element = detection_->views().element;
  v_.coat = detection_->views().coat;
  v_.rows = coating_ != nullptr;
  if (v_.rows) v_.row = Kokkos::View<double* [3]>("epaphe::contact::normal_rows", numNodes());
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
  copy(gapH_, gap_);
  copy(surfH_, surf_);
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
  const int nc = numNodes();
  {
    ScopedPhase phase(cost, "projection");
    detect(q, false);
  }

  ScopedPhase phase(cost, "contact");
  // From here the step only copies views it owns into locals (kernel captures) and allocates none
  // (contact.step-budget): as inside a Kokkos region, the copies need not count references (two
  // atomic operations per copy, 4.6 % of a blade run with friction). No member view is assigned below.
  const parallel_detail::UntrackedViews untracked;
  activeH_.clear();
  for (int k = 0; k < nc; ++k) {
    forceH_(k) = 0.0;
    if (surfH_(k) >= 0 && gapH_(k) < 0.0) activeH_.push_back(k);
  }
  numActive_ = static_cast<int>(activeH_.size());
  const bool friction = frictional_;
  const long long ns = detection_->numSurfaces(), projected = detection_->lastProjected();
  projections_ += ns * projected;  // a node not skipped is projected on every surface
  projectionsSkipped_ += ns * (nc - projected);
  if (numActive_ == 0) {
    enforcement_->commit(v_, activeH_);
    const auto tangent = tangent_;
    fill(force_, 0.0);
    if (friction) {
      fill(mu_, 0.0);
      forEach(
          "epaphe::contact::no_friction", nc, 1, KOKKOS_LAMBDA(const int k) {
            for (int d = 0; d < 3; ++d) tangent(k, d) = 0.0;
          });
    }
    return;
  }
  motionEntries();
  fill(known_, 0);  // D (and so C) changed
  // Active set (Lagrange): the nodes the predictor made penetrate, less those the surface would
  // pull (lambda < 0, released inside the solves), plus those the correction of the others makes
  // penetrate through the coupling of F (their corrected gap g*_a + n_a . D_a dq < 0): solved
  // again until no node is added (at most kMaxAddPasses).
  const auto dq = dq_;
  for (int pass = 0;; ++pass) {
    numActive_ = static_cast<int>(activeH_.size());
    relativeColumns();
    enforcement_->enforce(v_, activeH_, q, qCurrent);  // lambda_a and c_a of the active nodes
    numActive_ = static_cast<int>(activeH_.size());
    lastFrictionPasses_ = enforcement_->lastPasses();
    // dq = F G lambda (eqs. 2.35-2.36), G_a = D_a^T c_a. On the dense rows of F: node a's own part,
    // F's columns at its DOFs, and a patch node's part on its surface's block, F (B_u x B_v) x, the
    // control columns times the control points' coefficients x summed over the nodes first. On a
    // diagonal block, dq_i = F_ii (sum_a D_a^T c_a lambda_a)_i, scattered from the entries of D (one
    // thread: the same sums in the same order on any number of threads).
    const auto F = F_;
    const auto dir = dir_;
    const auto force = force_;
    const auto act = v_.upload(activeH_);  // ascending: the sums below run in node order
    const int nA = numActive_;
    const int T = Kokkos::DefaultHostExecutionSpace().concurrency(), n = static_cast<int>(q.extent(0));
    const auto blocks = blocks_;
    const auto nodeBlk = nodeBlk_;
    const auto dof = dof_;
    const auto patch = patch_;
    const auto coefOff = coefOff_;
    const auto ctrlOff = ctrlOff_;
    const auto ctrlDim = ctrlDim_;
    const auto coef = coef_;
    const auto ctrl = ctrlF_;
    const auto info = info_;
    const int ns = static_cast<int>(surfaces_.size());
    const bool patches = coef_.extent(0) > 0;
    if (patches) {  // x = -sum_k lambda_k b_a b_b R_k^T c_k, over the patch nodes in node order
      const auto rot = entRot_;
      const auto surf = surf_;
      const auto pbasis = pbasis_;
      const auto pcell = pcell_;
      forEach(
          "epaphe::contact::control_coefficients", 1, 0, KOKKOS_LAMBDA(const int) {
            for (std::size_t x = 0; x < coef.extent(0); ++x) coef(x) = 0.0;
            for (int a = 0; a < nA; ++a) {
              const int k = act(a), s = surf(k);
              const double l = force(k);
              if (l == 0.0 || patch(k) < 0) continue;
              const int nuE = ctrlDim(s, 0), nvE = ctrlDim(s, 1), i = pcell(k, 0), j = pcell(k, 1);
              for (int e2 = 0; e2 < 3; ++e2) {
                const double c =
                    -l * (rot(k, 0, e2) * dir(k, 0) + rot(k, 1, e2) * dir(k, 1) + rot(k, 2, e2) * dir(k, 2));
                if (c == 0.0) continue;
                for (int r = 0; r < 4; ++r)
                  for (int t = 0; t < 4; ++t)
                    coef(coefOff(s) + (static_cast<long>(e2) * nuE + i + r) * nvE + j + t) +=
                        c * pbasis(k, r) * pbasis(k, 4 + t);
              }
            }
          });
    }
    // One block of rows per thread, each active node's three columns of F walked down it (F is
    // column-major); each dq_i sums its terms in node order on any number of threads
    forEach(
        "epaphe::contact::correction", T, 3L * n * nA / T, KOKKOS_LAMBDA(const int t) {
          const int i0 = static_cast<int>(static_cast<long>(n) * t / T),
                    i1 = static_cast<int>(static_cast<long>(n) * (t + 1) / T);
          for (int i = i0; i < i1; ++i) dq(i) = 0.0;
          for (int a = 0; a < nA; ++a) {
            const int k = act(a), blk = nodeBlk(k), b0 = blocks(blk, 0), n = blocks(blk, 1);
            const double l = force(k);
            if (l == 0.0 || F.denseRow(b0) < 0) continue;
            const double d0 = dir(k, 0), d1 = dir(k, 1), d2 = dir(k, 2);
            const double* f0 = &F.dense(F.start(blk) + static_cast<std::size_t>(dof(k, 0) - b0) * n);
            const double* f1 = &F.dense(F.start(blk) + static_cast<std::size_t>(dof(k, 1) - b0) * n);
            const double* f2 = &F.dense(F.start(blk) + static_cast<std::size_t>(dof(k, 2) - b0) * n);
            const int lo = i0 > b0 ? i0 : b0, hi = i1 < b0 + n ? i1 : b0 + n;
            for (int i = lo; i < hi; ++i) dq(i) += l * (f0[i - b0] * d0 + f1[i - b0] * d1 + f2[i - b0] * d2);
          }
          if (!patches) return;
          for (int s = 0; s < ns; ++s) {
            if (coefOff(s) < 0) continue;
            const int blk = info(s, 0), b0 = blocks(blk, 0), n = blocks(blk, 1);
            const int lo = i0 > b0 ? i0 : b0, hi = i1 < b0 + n ? i1 : b0 + n;
            const long nc = 3L * ctrlDim(s, 0) * ctrlDim(s, 1);
            for (long x = 0; x < nc; ++x) {
              const double c = coef(coefOff(s) + x);
              if (c == 0.0) continue;
              const double* g = &ctrl(ctrlOff(s) + x * n);
              for (int i = lo; i < hi; ++i) dq(i) += c * g[i - b0];
            }
          }
        });
    if (F.denseRows < F.size()) {
      const RelativeMotion Dk{entDof_, entW_, entN_, entRot_};
      forEach(
          "epaphe::contact::correction_diagonal", 1, 0, KOKKOS_LAMBDA(const int) {
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
    if (!enforcement_->closesGaps() || pass == kMaxAddPasses) break;
    // corrected gaps of the nodes outside the active set; a node whose projection was skipped is
    // out only if its gap's lower bound stays out, bound - |D_k dq| >= -eps (the corrected gap is
    // g + n . D_k dq >= bound - |D_k dq|); when the bound does not decide, it is projected (refine)
    // and tested again with its exact gap
    int added = 0;
    for (int attempt = 0;; ++attempt) {
      const RelativeMotion D{entDof_, entW_, entN_, entRot_};
      const auto normal = normal_;
      const auto gap = gap_;
      const auto surf = surf_;
      const auto corrected = corrected_;
      const auto skipped = skipped_;
      const auto refine = refine_;
      const auto bound = bound_;
      const double eps = gapTolerance_;
      added = 0;
      reduce(
          "epaphe::contact::corrected_gaps", nc, 20,
          KOKKOS_LAMBDA(const int k, int& n) {
            corrected(k) = 0;
            if (surf(k) < 0 || force(k) != 0.0 || !(gap(k) < 1e300)) return;
            double r[3];
            D.apply(k, dq, r);
            if (skipped(k)) {
              if (bound(k) - ::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) < -eps) refine(k) = 1;
              return;
            }
            double g = gap(k);
            for (int d = 0; d < 3; ++d) g += normal(k, d) * r[d];
            if (g < -eps) {
              corrected(k) = 1;
              ++n;
            }
          },
          Kokkos::Sum<int>(added));
      if (attempt > 0 || detection_->refine() == 0) break;
      motionEntries();  // the refined nodes' foot points
    }
    if (added == 0) break;
    auto addH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), corrected_);
    activeH_.clear();
    for (int k = 0; k < nc; ++k)
      if (forceH_(k) != 0.0 || addH(k)) activeH_.push_back(k);
    lastAddPasses_ = pass + 1;
  }
  enforcement_->commit(v_, activeH_);  // a coating's wear follows the step's final forces
  if (friction) {
    copy(muH_, mu_);
    copy(tangentH_, tangent_);
  }
  forEach(
      "epaphe::contact::apply_correction", q.extent(0), 1, KOKKOS_LAMBDA(const int i) { q(i) += dq(i); });
  fence();
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
  const auto patch = patch_;
  const auto ctrlOff = ctrlOff_;
  const int maxE = static_cast<int>(entW_.extent(1));
  forEach(
      "epaphe::contact::relative_motion", numNodes(),
      30L + 20L * (maxE > 1 ? 2 * (wu.extent(1) + wv.extent(1)) + maxE : 0), KOKKOS_LAMBDA(const int k) {
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
        patch(k) = s >= 0 && ctrlOff(s) >= 0 && m > 1 ? info(s, 0) : -1;
      });
}

void SurfaceContact::controlColumns() {
  // Per carried surface on a dense block, per direction e2 and control point (a, b) of the
  // extended grid: G(:, e2, a, b) = sum_pq B_u(a, p) B_v(b, q) F(:, grid DOF (p, q, e2)) over the
  // block's rows. The grid nodes' weights at a foot point are w_pq = sum_rs b_r b_s B_u(i + r, p)
  // B_v(j + s, q) (eqs. 2.22, 2.26), so a node's column F D^T on that block is -R sum_rs b_r b_s
  // G(:, ., i + r, j + s): 16 columns of the block instead of every grid node with a weight (up to
  // 46 x 46). F and the operators do not change: built once here.
  const int ns = static_cast<int>(surfaces_.size());
  ctrlOff_ = Kokkos::View<long*>("epaphe::contact::control_offset", ns);
  ctrlDim_ = Kokkos::View<int* [2]>("epaphe::contact::control_dims", ns);
  std::vector<double> G;
  for (int s = 0; s < ns; ++s) {
    ctrlOff_(s) = -1;
    const ContactSurface& cs = surfaces_[s];
    if (!cs.moving) continue;
    const int blk = cs.block, b0 = F_.blocks(blk, 0), n = F_.blocks(blk, 1);
    if (F_.denseRow(b0) < 0) continue;  // a diagonal block: the entries' path
    const BSplineSurface& S = *cs.surface;
    const int nu = S.nu(), nv = S.nv(), inNv = S.inputNv();
    const int nuE = static_cast<int>(S.operatorU().size()) / nu, nvE = static_cast<int>(S.operatorV().size()) / nv;
    const std::vector<double>&Bu = S.operatorU(), &Bv = S.operatorV();
    ctrlOff_(s) = static_cast<long>(G.size());
    ctrlDim_(s, 0) = nuE;
    ctrlDim_(s, 1) = nvE;
    G.resize(G.size() + 3 * static_cast<std::size_t>(nuE) * nvE * n, 0.0);
    std::vector<double> T(static_cast<std::size_t>(nuE) * nv * n);
    const std::size_t start = F_.start(blk);
    for (int e2 = 0; e2 < 3; ++e2) {
      std::fill(T.begin(), T.end(), 0.0);  // T(:, a, q) = sum_p B_u(a, p) F(:, (p, q, e2))
      for (int p = 0; p < nu; ++p)
        for (int q = 0; q < nv; ++q) {
          const int j = cs.gridDofs[3 * (static_cast<std::size_t>(p) * inNv + q) + e2];
          if (j < 0) continue;  // clamped
          const double* col = &F_.dense(start + static_cast<std::size_t>(j - b0) * n);
          for (int a = 0; a < nuE; ++a) {
            const double w = Bu[static_cast<std::size_t>(a) * nu + p];
            if (w == 0.0) continue;
            double* t = &T[(static_cast<std::size_t>(a) * nv + q) * n];
            for (int r = 0; r < n; ++r) t[r] += w * col[r];
          }
        }
      for (int a = 0; a < nuE; ++a)  // G(:, e2, a, b) = sum_q B_v(b, q) T(:, a, q)
        for (int b = 0; b < nvE; ++b) {
          double* g = &G[ctrlOff_(s) + ((static_cast<std::size_t>(e2) * nuE + a) * nvE + b) * n];
          for (int q = 0; q < nv; ++q) {
            const double w = Bv[static_cast<std::size_t>(b) * nv + q];
            if (w == 0.0) continue;
            const double* t = &T[(static_cast<std::size_t>(a) * nv + q) * n];
            for (int r = 0; r < n; ++r) g[r] += w * t[r];
          }
        }
    }
  }
  // T (relativeColumns), per carried surface with control columns: rows tOff_(s) + 3 nv A + 3 q + e2
  // (a patch's rows A = i..i+3 are one contiguous run); for P below, the dense rows of its grid DOFs
  // at gridRowOff[s] + (3 q + e2) nu + p (-1: clamped), and B_u transposed at buOff[s] + p nuE + A
  tOff_ = Kokkos::View<long*>("epaphe::contact::T_offset", ns);
  std::vector<long> gridRowOff(ns, -1), buOff(ns, -1);
  needRange_ = Kokkos::View<int* [2]>("epaphe::contact::needed_rows", ns);
  needRangeH_ = Kokkos::create_mirror_view(needRange_);
  std::vector<int> rows;
  std::vector<double> buT;
  long tRows = 0;
  for (int s = 0; s < ns; ++s) {
    tOff_(s) = -1;
    if (ctrlOff_(s) < 0) continue;
    const ContactSurface& cs = surfaces_[s];
    const BSplineSurface& S = *cs.surface;
    const int nu = S.nu(), nv = S.nv(), inNv = S.inputNv(), nuE = ctrlDim_(s, 0);
    tOff_(s) = tRows;
    tRows += 3L * nuE * nv;
    gridRowOff[s] = static_cast<long>(rows.size());
    for (int q = 0; q < nv; ++q)
      for (int e2 = 0; e2 < 3; ++e2)
        for (int p = 0; p < nu; ++p) {
          const int j = cs.gridDofs[3 * (static_cast<std::size_t>(p) * inNv + q) + e2];
          rows.push_back(j < 0 ? -1 : F_.denseRow(j));
        }
    buOff[s] = static_cast<long>(buT.size());
    for (int p = 0; p < nu; ++p)
      for (int a = 0; a < nuE; ++a) buT.push_back(S.operatorU()[static_cast<std::size_t>(a) * nu + p]);
  }
  tRows_ = tRows;
  ctrlF_ = Kokkos::View<double*>("epaphe::contact::control_columns", G.size());
  for (std::size_t i = 0; i < G.size(); ++i) ctrlF_(i) = G[i];
  // P(s2, s) for two surfaces with control columns on one block: s's control columns G on s2's grid
  // rows, contracted with s2's B_u as T is, P(:, c) = sum_p B_u(A, p) G(grid row (p, q, e2'), c). It
  // is about G's size (s2's grid rows are most of the block's).
  pOff_ = Kokkos::View<long**>("epaphe::contact::P_offset", ns, ns);
  coefOff_ = Kokkos::View<long*>("epaphe::contact::coefficient_offset", ns);
  std::vector<double> P;
  long coefs = 0;
  for (int s2 = 0; s2 < ns; ++s2) {
    coefOff_(s2) = -1;
    if (ctrlOff_(s2) >= 0) {
      coefOff_(s2) = coefs;
      coefs += 3L * ctrlDim_(s2, 0) * ctrlDim_(s2, 1);
    }
    for (int s = 0; s < ns; ++s) {
      pOff_(s2, s) = -1;
      if (tOff_(s2) < 0 || ctrlOff_(s) < 0 || surfaces_[s].block != surfaces_[s2].block) continue;
      const int blk = surfaces_[s].block, n = F_.blocks(blk, 1), r0 = F_.denseRow(F_.blocks(blk, 0));
      const int nu2 = surfaces_[s2].surface->nu(), nv2 = surfaces_[s2].surface->nv(), nuE2 = ctrlDim_(s2, 0);
      const long rowsP = 3L * nv2 * nuE2, cols = 3L * ctrlDim_(s, 0) * ctrlDim_(s, 1);
      pOff_(s2, s) = static_cast<long>(P.size());
      P.resize(P.size() + rowsP * cols, 0.0);
      for (long c = 0; c < cols; ++c) {
        const double* g = &G[ctrlOff_(s) + c * n];
        double* out = &P[pOff_(s2, s) + c * rowsP];
        for (int qe = 0; qe < 3 * nv2; ++qe)
          for (int p = 0; p < nu2; ++p) {
            const int j = rows[gridRowOff[s2] + static_cast<long>(qe) * nu2 + p];
            const double y = j >= 0 ? g[j - r0] : 0.0;
            if (y == 0.0) continue;
            const double* b = &buT[buOff[s2] + static_cast<long>(p) * nuE2];
            for (int A = 0; A < nuE2; ++A) out[static_cast<long>(A) * 3 * nv2 + qe] += b[A] * y;
          }
      }
    }
  }
  P_ = Kokkos::View<double*>("epaphe::contact::control_columns_on_grids", P.size());
  for (std::size_t i = 0; i < P.size(); ++i) P_(i) = P[i];
  coef_ = Kokkos::View<double*>("epaphe::contact::control_coefficients", coefs);
}

void SurfaceContact::relativeColumns() {
  // For the active nodes: what C_ab = D_a F D_b^T needs of F D_b^T beyond F itself. Its part on
  // node b's own (dense) block is F's columns at b's DOFs, read in place; a carried surface on a
  // diagonal block has no dense rows; so only a patch node (its surface's block has control
  // columns) has a part to form: T on the grids of that block (eq. 2.26), and its patch's basis.
  // Then C_ab = D_a (F D_b^T).
  const int nA = numActive_;
  const auto active = v_.upload(activeH_);
  const auto surf = surf_;
  const auto info = info_;
  const auto patch = patch_;
  const auto pbasis = pbasis_;
  const auto pcell = pcell_;
  const auto ctrlDim = ctrlDim_;
  const auto rot = entRot_;
  const auto T = T_;
  const auto tOff = tOff_;
  const auto need = needRange_;
  const auto Pm = P_;
  const auto pOff = pOff_;
  const int ns = static_cast<int>(surfaces_.size());
  if (tRows_ > 0) {
    // per patch node, its patch: the first control point (i, j) and the cubic basis of the foot
    // point (eq. 2.22), read below, by C and by the correction; per surface, the rows of B_u that
    // the patches of the active nodes read
    for (int s = 0; s < ns; ++s) {
      needRangeH_(s, 0) = 1 << 30;
      needRangeH_(s, 1) = -1;
    }
    for (int a = 0; a < nA; ++a) {
      const int k = activeH_[a], s = surfH_(k);
      if (patch_(k) < 0) continue;
      int i, j;
      double tu, tv, bu[4], bv[4], d1[4], d2[4];
      surface_detail::locate(foot_(k, 0), info_(s, 1), info_(s, 4) != 0, i, tu);
      surface_detail::locate(foot_(k, 1), info_(s, 2), info_(s, 5) != 0, j, tv);
      surface_detail::cubicBasis(tu, bu, d1, d2);
      surface_detail::cubicBasis(tv, bv, d1, d2);
      pcell_(k, 0) = i;
      pcell_(k, 1) = j;
      for (int r = 0; r < 4; ++r) {
        pbasis_(k, r) = bu[r];
        pbasis_(k, 4 + r) = bv[r];
      }
      needRangeH_(s, 0) = std::min(needRangeH_(s, 0), i);
      needRangeH_(s, 1) = std::max(needRangeH_(s, 1), i + 3);
    }
    copy(needRange_, needRangeH_);
    const long work = 600L * maxGrid_[1] + 10;
    forEach(
        "epaphe::contact::relative_columns", 3 * nA, work, KOKKOS_LAMBDA(const int ae) {
          const int k = active(ae / 3), e = ae % 3, c = 3 * k + e;
          const int s = surf(k), pb = patch(k);
          // a patch node's part on its surface's block comes from the 4 x 4 control points of its
          // patch, w_ab = -R(e, e2) b_a b_b (D_k's grid part: -R sum w_pq u_pq), instead of the grid
          // nodes' entries
          // T(:, c): column c on the grid of each carried surface s2 with control columns on the
          // block of node k's surface, contracted with the rows A of B_u that the active patches
          // read (eq. 2.26): T(s2; A, q, e2) = sum_p B_u(A, p) (F D_k^T)(grid DOF (p, q, e2), e),
          // 16 columns of P. (F D_k^T has no other part on a grid: no contact node is on a body
          // that carries a surface, so k's own block carries none.)
          for (int s2 = 0; s2 < ns; ++s2) {
            const int blk2 = info(s2, 0), lo = need(s2, 0), hi = need(s2, 1);
            if (tOff(s2) < 0 || hi < lo || !(s >= 0 && info(s, 0) == blk2)) continue;
            const int nv = info(s2, 2), nuE = ctrlDim(s2, 0);
            const int m = 3 * nv;  // T's rows A = lo..hi: one run of (hi - lo + 1) m
            double* t = &T(tOff(s2) + static_cast<long>(lo) * m, c);
            for (int x = 0; x < (hi - lo + 1) * m; ++x) t[x] = 0.0;
            if (pb != blk2) continue;
            const long rowsP = 3L * nv * nuE;
            const int nuEs = ctrlDim(s, 0), nvEs = ctrlDim(s, 1);
            for (int e2 = 0; e2 < 3; ++e2) {
              const double w = -rot(k, e, e2);
              if (w == 0.0) continue;
              for (int a = 0; a < 4; ++a)
                for (int b = 0; b < 4; ++b) {
                  const double wab = w * pbasis(k, a) * pbasis(k, 4 + b);
                  const double* pc =
                      &Pm(pOff(s2, s) +
                          ((static_cast<long>(e2) * nuEs + pcell(k, 0) + a) * nvEs + pcell(k, 1) + b) * rowsP) +
                      static_cast<long>(lo) * m;
                  for (int x = 0; x < (hi - lo + 1) * m; ++x) t[x] += wab * pc[x];
                }
            }
          }
        });
    fence();
  }
  relativeFlexibility(active);
}

void SurfaceContact::relativeFlexibility(const Kokkos::View<int*>& active) {
  const int nA = numActive_;
  const auto surf = surf_;
  const auto info = info_;
  const auto F = F_;
  const auto T = T_;
  const auto tOff = tOff_;
  const auto nodeBlk = nodeBlk_;
  const auto patch = patch_;
  const auto blocks = blocks_;
  const auto pcell = pcell_;
  const auto pbasis = pbasis_;
  const auto wv = wv_;
  const auto C = C_;
  const auto known = known_;
  const auto fixed = fixedC_;
  const RelativeMotion D{entDof_, entW_, entN_, entRot_};
  // C_ab = D_a (F D_b^T), one active node a per iteration, every b unless both were active at the
  // last pass of this step too (D and F do not change within a step: C_ab was made then).
  // Node a's own part reads F D_b^T at a's DOFs: F's block at (a's DOFs, b's) when both are in one
  // dense block, else 0 (a's body carries no surface: no patch of b's is on it), FlexibleColumn in
  // a diagonal block. On a carried surface with control columns its grid part is
  // -R_a sum_pq w_p w_q (F D_b^T)(grid node pq) = -R_a sum_r b_r sum_q w_q T_b(i + r, q), the cubic
  // basis b_r of the foot point's patch i (eqs. 2.22, 2.26); on one with none (a diagonal block)
  // D_a's entries are walked.
  // Two nodes whose D has its own entry alone (a body's node against a rigid or turning surface:
  // weight 1 on its DOFs, the turn applied to the gap's normal, not to D) have C_ab = F's block at
  // their DOFs, the same at every step: made once and kept (fixedC_), where it was made again at
  // every step with contact (rotor37-massless, frictionless: 7 % of its loop, 117 pairs a step).
  forEach(
      "epaphe::contact::relative_flexibility", nA, 30L * static_cast<long>(entW_.extent(1)) * nA,
      KOKKOS_LAMBDA(const int a) {
        const int ka = active(a), sa = surf(ka), pa = patch(ka);
        const bool direct = D.count(ka) == 1 || pa >= 0;
        const bool ownOnly = D.count(ka) == 1 && pa < 0;  // D_a is its own entry alone
        const double w0 = D.w(ka, 0);
        const int blk = nodeBlk(ka), b0 = blocks(blk, 0), n = blocks(blk, 1);
        int dof[3];
        double R[3][3];
        for (int d = 0; d < 3; ++d) {
          dof[d] = D.dof(ka, 0, d);
          for (int e = 0; e < 3; ++e) R[d][e] = D.rot(ka, d, e);
        }
        const bool dense = F.denseRow(dof[0]) >= 0;  // a's block is dense
        const int nv = pa >= 0 ? info(sa, 2) : 0;
        const long t0 = pa >= 0 ? tOff(sa) + 3L * nv * pcell(ka, 0) : 0;  // (its patch: relativeColumns)
        for (int b = 0; b < nA; ++b) {
          const int kb = active(b);
          const bool constant = ownOnly && D.count(kb) == 1 && patch(kb) < 0;
          if ((known(ka) && known(kb)) || (constant && fixed(ka, kb))) continue;
          fixed(ka, kb) = constant ? 1 : 0;
          if (!direct) {
            for (int e = 0; e < 3; ++e) {
              const FlexibleColumn col{F, D, nodeBlk, kb, e};
              double r[3];
              D.apply(ka, col, r);
              for (int d = 0; d < 3; ++d) C(ka, kb, d, e) = r[d];
            }
            continue;
          }
          double own[3][3];
          if (dense && nodeBlk(kb) == blk) {  // F's block
            const double wb = D.w(kb, 0);
            for (int e = 0; e < 3; ++e) {
              const double* col = &F.dense(F.start(blk) + static_cast<std::size_t>(D.dof(kb, 0, e) - b0) * n);
              for (int d = 0; d < 3; ++d) own[d][e] = w0 * (wb * col[dof[d] - b0]);
            }
          } else if (dense) {
            for (int e = 0; e < 3; ++e)
              for (int d = 0; d < 3; ++d) own[d][e] = 0.0;
          } else {
            for (int e = 0; e < 3; ++e)
              for (int d = 0; d < 3; ++d) own[d][e] = w0 * FlexibleColumn{F, D, nodeBlk, kb, e}(dof[d]);
          }
          if (pa >= 0) {                                                           // the grid part, R_a g
            double g[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};  // g[e][e2]
            if (surf(kb) >= 0 && info(surf(kb), 0) == pa) {
              for (int e = 0; e < 3; ++e) {  // T's rows of the patch, (r, q, e2), are one run of 12 nv
                const double* tc = &T(t0, 3 * kb + e);
                for (int r = 0; r < 4; ++r, tc += 3 * nv)
                  for (int q = 0; q < nv; ++q) {
                    const double w = pbasis(ka, r) * wv(ka, q);
                    g[e][0] -= w * tc[3 * q];
                    g[e][1] -= w * tc[3 * q + 1];
                    g[e][2] -= w * tc[3 * q + 2];
                  }
              }
            }
            for (int d = 0; d < 3; ++d)
              for (int e = 0; e < 3; ++e)
                own[d][e] = own[d][e] + R[d][0] * g[e][0] + R[d][1] * g[e][1] + R[d][2] * g[e][2];
          }
          for (int d = 0; d < 3; ++d)
            for (int e = 0; e < 3; ++e) C(ka, kb, d, e) = own[d][e];
        }
      });
  fence();
  // known: active at this pass (C_ab is reused only for two nodes active together at the last pass)
  for (int k = 0; k < numNodes(); ++k) known_(k) = 0;
  for (int a = 0; a < nA; ++a) known_(activeH_[a]) = 1;
}

double SurfaceContact::workIncrement(const DenseVector& qNext, const DenseVector& qPrev) const {
  double w = 0.0;
  if (numActive_ == 0) return w;
  const auto dir = dir_;
  const auto force = force_;
  const RelativeMotion D{entDof_, entW_, entN_, entRot_};
  const Difference<DenseVector> dq{qNext, qPrev};
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

std::array<double, 2> SurfaceContact::workIncrementSplit(const DenseVector& qNext, const DenseVector& qPrev) const {
  double friction = 0.0;
  if (numActive_ == 0) return {0.0, 0.0};
  const auto mu = mu_;
  const auto tangent = tangent_;
  const auto force = force_;
  const RelativeMotion D{entDof_, entW_, entN_, entRot_};
  const Difference<DenseVector> dq{qNext, qPrev};
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

double SurfaceContact::totalForce() const {
  double s = 0;
  for (int k = 0; k < numNodes(); ++k) s += forceH_(k);
  return s;
}

}  // namespace epaphe
