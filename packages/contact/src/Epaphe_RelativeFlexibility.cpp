#include "Epaphe_RelativeFlexibility.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace epaphe {

namespace {

/// True when system DOF `dof` lies in block b, [offset, offset + size) of the blocks' host copy bH.
bool inBlock(const Kokkos::View<int* [2]>::HostMirror& bH, int dof, int b) {
  const int nb = static_cast<int>(bH.extent(0));
  return b >= 0 && b < nb && dof >= bH(b, 0) && dof < bH(b, 0) + bH(b, 1);
}

/// Appends to `win` the windows of one direction of a surface (CarriedSurfaceViews::window): B its
/// interpolation operator (row-major, nExt x n), one window {first, count} per interval i, the rows
/// i..i+3 a foot point there reads. Why a node p outside it has no entry: with the cubic basis b_r >= 0,
/// sum b_r = 1 (eq. 2.22), the weight w_p = sum_r b_r B(i + r, p) has |w_p| <= max_r |B(i + r, p)|, and
/// sum_p w_p = sum_r b_r rowsum(i + r) >= min_r rowsum(i + r) (1: the spline of constant data is that
/// constant), so max_p |w_p| >= min_r rowsum / n. Outside the window max_r |B(i + r, p)| < 0.5e-12
/// min_r rowsum / n, so |w_p| < 0.5e-12 max |w|, below the 1e-12 at which motionEntries zeroes a weight:
/// the window loses no entry. (The rows decay like 0.27^distance: about 56 nodes of a closed direction.)
void appendWindows(const std::vector<double>& B, int n, bool periodic, std::vector<int>& win, int& maxLen) {
  const int nExt = static_cast<int>(B.size()) / n;
  std::vector<char> in(n);
  for (int i = 0; i + 3 < nExt; ++i) {
    double least = HUGE_VAL;
    for (int r = 0; r < 4; ++r) {
      double sum = 0.0;
      for (int p = 0; p < n; ++p) sum += B[std::size_t(i + r) * n + p];
      least = std::min(least, sum);
    }
    int first = 0, count = n;
    if (least > 0.0) {
      const double cut = 0.5e-12 * least / n;
      for (int p = 0; p < n; ++p) {
        double big = 0.0;
        for (int r = 0; r < 4; ++r) big = std::max(big, std::fabs(B[std::size_t(i + r) * n + p]));
        in[p] = big >= cut;
      }
      if (!periodic) {
        int lo = 0, hi = n - 1;
        while (lo < hi && !in[lo]) ++lo;
        while (hi > lo && !in[hi]) --hi;
        first = lo;
        count = hi - lo + 1;
      } else {  // the complement of the longest run of nodes out, round the circle
        int bestStart = 0, bestLen = 0;
        for (int p = 0; p < n; ++p) {
          if (in[p] || in[(p + n - 1) % n] == 0) continue;  // a run of nodes out starts at p
          int len = 0;
          while (len < n && !in[(p + len) % n]) ++len;
          if (len > bestLen) {
            bestLen = len;
            bestStart = p;
          }
        }
        if (bestLen > 0) {
          first = (bestStart + bestLen) % n;
          count = n - bestLen;
        }
      }
    }
    win.push_back(first);
    win.push_back(count);
    maxLen = std::max(maxLen, count);
  }
}

}  // namespace

RelativeFlexibility::RelativeFlexibility(const Flexibility& flexibility, const std::vector<ContactBlock>& blocks,
                                         const ContactNodes& nodes, std::vector<ContactSurface>& surfaces)
    : F_(flexibility.pack()) {
  initBlocks(blocks, flexibility);
  initNodeBlocks(nodes);
  initCarriedSurfaces(nodes, surfaces);
  controlColumns(surfaces);
  const int nc = static_cast<int>(nodes.labels.size());
  {  // U's map over the canonical surfaces with H; Y holds at most every control point or 16 per node
    const int ns = static_cast<int>(surfaces.size());
    uMapOff_ = Kokkos::View<long*>("epaphe::contact::U_map_offset", ns);
    long points = 0;
    for (int s = 0; s < ns; ++s) {
      uMapOff_(s) = -1;
      if (ctrl_.hOff(s, s) < 0 || ctrl_.canon(s) != s) continue;
      uMapOff_(s) = points;
      points += static_cast<long>(ctrl_.dim(s, 0)) * ctrl_.dim(s, 1);
    }
    uMap_ = Kokkos::View<int*>("epaphe::contact::U_map", points);
    uPoint_ = Kokkos::View<int* [2]>("epaphe::contact::U_point", points);
    uEnd_ = Kokkos::View<int*>("epaphe::contact::U_end", nc);
    fill(uMap_, -1);
    Y_ = Kokkos::View<double**>("epaphe::contact::Y", points > 0 ? nc : 0, 9 * std::min(points, 16L * nc));
  }
  wu_ = Kokkos::View<double**>("epaphe::contact::weights_u", nc, carried_.maxWindow[0]);
  wv_ = Kokkos::View<double**>("epaphe::contact::weights_v", nc, carried_.maxWindow[1]);
  pbasis_ = Kokkos::View<double* [8]>("epaphe::contact::patch_basis", nc);
  pcell_ = Kokkos::View<int* [2]>("epaphe::contact::patch_cell", nc);
  pweight_ = Kokkos::View<double* [16]>("epaphe::contact::patch_weight", nc);
  ppoint_ = Kokkos::View<int* [16]>("epaphe::contact::patch_point", nc);
  rowWeight_ = Kokkos::View<double* [48]>("epaphe::contact::row_weight", nc);
  groupNode_ = Kokkos::View<int*>("epaphe::contact::group_node", nc);
  groupStart_ = Kokkos::View<int*>("epaphe::contact::group_start", nc + 1);
  groupEnd_ = Kokkos::View<int*>("epaphe::contact::group_end", nc);
  groupOf_.reserve(static_cast<std::size_t>(nc));
  groupFirst_.reserve(static_cast<std::size_t>(nc));
  D_.own = Kokkos::View<int* [3]>("epaphe::contact::node_dof", nc);
  D_.grid = Kokkos::View<int* [4]>("epaphe::contact::node_grid", nc);
  D_.pu = Kokkos::View<int**>("epaphe::contact::grid_u", nc, carried_.maxWindow[0]);
  D_.pv = Kokkos::View<int**>("epaphe::contact::grid_v", nc, carried_.maxWindow[1]);
  D_.wu = Kokkos::View<double**>("epaphe::contact::grid_weight_u", nc, carried_.maxWindow[0]);
  D_.wv = Kokkos::View<double**>("epaphe::contact::grid_weight_v", nc, carried_.maxWindow[1]);
  D_.gridDof = carried_.gridDof;
  patch_ = Kokkos::View<int*>("epaphe::contact::patch_block", nc);
  D_.rot = Kokkos::View<double* [3][3]>("epaphe::contact::entry_rotation", nc);
  C_ = Kokkos::View<double** [3][3]>("epaphe::contact::relative_flexibility", nc, nc);
  rowEdge_ =
      Kokkos::View<int*>("epaphe::contact::correction_rows", Kokkos::DefaultHostExecutionSpace().concurrency() + 1);
  known_ = Kokkos::View<int*>("epaphe::contact::known_rows", nc);
  fixedC_ = Kokkos::View<int**>("epaphe::contact::fixed_pairs", nc, nc);
  // F symmetric (every body but one with gyroscopic terms): relativePairs makes half the pairs
  symmetric_ = true;
  for (std::size_t b = 0; b < F_.blocks.extent(0) && symmetric_; ++b) {
    const int n = F_.blocks(b, 1);
    if (F_.denseRow(F_.blocks(b, 0)) < 0) continue;  // a diagonal block
    const double* f = &F_.dense(F_.start(b));
    double largest = 0.0, skew = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        largest = std::max(largest, std::fabs(f[static_cast<std::size_t>(j) * n + i]));
        skew =
            std::max(skew, std::fabs(f[static_cast<std::size_t>(j) * n + i] - f[static_cast<std::size_t>(i) * n + j]));
      }
    symmetric_ = skew <= 1e-12 * largest;
  }
}

void RelativeFlexibility::update(const std::vector<int>& activeH, const Kokkos::View<int*>& active,
                                 const Kokkos::View<int*>::HostMirror& surfH, const DetectionViews& dv) {
  patchBases(activeH, surfH, dv);
  relativeColumns(active, static_cast<int>(activeH.size()), dv);
  relativePairs(activeH, active);
}

void RelativeFlexibility::forgetPairs() {
  fill(known_, 0);
}

void RelativeFlexibility::initBlocks(const std::vector<ContactBlock>& blocks, const Flexibility& flexibility) {
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
  auto bH = Kokkos::create_mirror_view(blocks_);  // (host memory: the same view)
  for (int b = 0; b < nb; ++b) {
    EPAPHE_REQUIRE(blocks[b].offset >= 0 && blocks[b].size > 0 && blocks[b].offset + blocks[b].size <= N,
                   "contact: block " << b << " [" << blocks[b].offset << ", " << blocks[b].offset + blocks[b].size
                                     << ") does not fit the " << N << " system coordinates");
    bH(b, 0) = blocks[b].offset;
    bH(b, 1) = blocks[b].size;
  }
  Kokkos::deep_copy(blocks_, bH);
}

void RelativeFlexibility::initNodeBlocks(const ContactNodes& nodes) {
  const int nc = static_cast<int>(nodes.labels.size());
  const auto bH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), blocks_);
  nodeBlk_ = Kokkos::View<int*>("epaphe::contact::node_block", nc);
  auto blkH = Kokkos::create_mirror_view(nodeBlk_);
  EPAPHE_REQUIRE(nodes.dofs.size() == 3 * std::size_t(nc) && nodes.X.size() == 3 * std::size_t(nc) &&
                     nodes.block.size() == std::size_t(nc),
                 "contact: the node arrays disagree in size");
  for (int k = 0; k < nc; ++k) {
    blkH(k) = nodes.block[k];
    for (int d = 0; d < 3; ++d)
      EPAPHE_REQUIRE(inBlock(bH, nodes.dofs[3 * k + d], blkH(k)),
                     "contact: node " << nodes.labels[k] << " DOF " << nodes.dofs[3 * k + d]
                                      << " is outside its body's block " << blkH(k));
  }
  Kokkos::deep_copy(nodeBlk_, blkH);
}

void RelativeFlexibility::initCarriedSurfaces(const ContactNodes& nodes, std::vector<ContactSurface>& surfaces) {
  // Carried surfaces: grid DOFs and interpolation operators, concatenated.
  const auto bH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), blocks_);
  const auto blkH = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), nodeBlk_);
  const int nc = static_cast<int>(nodes.labels.size());
  const int ns = static_cast<int>(surfaces.size());
  carried_.info = Kokkos::View<int* [6]>("epaphe::contact::surface_info", ns);
  carried_.gridOff = Kokkos::View<int*>("epaphe::contact::grid_offset", ns);
  carried_.opOff = Kokkos::View<int* [2]>("epaphe::contact::operator_offset", ns);
  auto infoH = Kokkos::create_mirror_view(carried_.info);
  auto goH = Kokkos::create_mirror_view(carried_.gridOff);
  auto ooH = Kokkos::create_mirror_view(carried_.opOff);
  std::vector<int> gd, win;
  std::vector<double> ops;
  std::vector<std::array<int, 2>> woH(ns, {-1, -1});
  for (int s = 0; s < ns; ++s) {
    ContactSurface& cs = surfaces[s];
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
    woH[s][0] = static_cast<int>(win.size() / 2);
    appendWindows(S.operatorU(), S.nu(), S.periodicU(), win, carried_.maxWindow[0]);
    woH[s][1] = static_cast<int>(win.size() / 2);
    appendWindows(S.operatorV(), S.nv(), S.periodicV(), win, carried_.maxWindow[1]);
    const std::size_t ng = std::size_t(S.inputNu()) * S.inputNv();
    EPAPHE_REQUIRE(cs.gridDofs.size() == 3 * ng && cs.gridX.size() == 3 * ng,
                   "contact: surface '" << S.name() << "' has " << ng << " grid nodes but " << cs.gridDofs.size() / 3
                                        << " grid DOF triples and " << cs.gridX.size() / 3 << " positions");
    for (std::size_t g = 0; g < 3 * ng; ++g)
      EPAPHE_REQUIRE(
          cs.gridDofs[g] < 0 || inBlock(bH, cs.gridDofs[g], cs.block),
          "contact: surface '" << S.name() << "' grid DOF " << cs.gridDofs[g] << " is outside its body's block");
    for (int k = 0; k < nc; ++k)
      EPAPHE_REQUIRE(blkH(k) != cs.block, "contact: node " << nodes.labels[k]
                                                           << " belongs to the body that carries surface '" << S.name()
                                                           << "'; self-contact is not supported");
    gd.insert(gd.end(), cs.gridDofs.begin(), cs.gridDofs.end());
    carried_.maxGrid[0] = std::max(carried_.maxGrid[0], S.nu());
    carried_.maxGrid[1] = std::max(carried_.maxGrid[1], S.nv());
  }
  carried_.gridDof = Kokkos::View<int* [3]>("epaphe::contact::grid_dof", gd.size() / 3);
  auto gdH = Kokkos::create_mirror_view(carried_.gridDof);
  for (std::size_t g = 0; g < gd.size() / 3; ++g)
    for (int d = 0; d < 3; ++d) gdH(g, d) = gd[3 * g + d];
  Kokkos::deep_copy(carried_.gridDof, gdH);
  carried_.ops = Kokkos::View<double*>("epaphe::contact::operators", ops.size());
  Kokkos::deep_copy(
      carried_.ops,
      Kokkos::View<const double*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>(ops.data(), ops.size()));
  Kokkos::deep_copy(carried_.info, infoH);
  Kokkos::deep_copy(carried_.gridOff, goH);
  Kokkos::deep_copy(carried_.opOff, ooH);
  carried_.window = Kokkos::View<int* [2]>("epaphe::contact::weight_window", win.size() / 2);
  carried_.winOff = Kokkos::View<int* [2]>("epaphe::contact::weight_window_offset", ns);
  auto wH = Kokkos::create_mirror_view(carried_.window);
  auto wOffH = Kokkos::create_mirror_view(carried_.winOff);
  for (std::size_t w = 0; w < win.size() / 2; ++w)
    for (int d = 0; d < 2; ++d) wH(w, d) = win[2 * w + d];
  for (int s = 0; s < ns; ++s)
    for (int d = 0; d < 2; ++d) wOffH(s, d) = woH[s][d];
  Kokkos::deep_copy(carried_.window, wH);
  Kokkos::deep_copy(carried_.winOff, wOffH);
}

void RelativeFlexibility::controlColumns(const std::vector<ContactSurface>& surfaces) {
  // Per carried surface on a dense block, per direction e2 and control point (a, b) of the
  // extended grid: G(:, e2, a, b) = sum_pq B_u(a, p) B_v(b, q) F(:, grid DOF (p, q, e2)) over the
  // block's rows. The grid nodes' weights at a foot point are w_pq = sum_rs b_r b_s B_u(i + r, p)
  // B_v(j + s, q) (eqs. 2.22, 2.26), so a node's column F D^T on that block is -R sum_rs b_r b_s
  // G(:, ., i + r, j + s): 16 columns of the block instead of every grid node with a weight (up to
  // 46 x 46). F and the operators do not change: built once here.
  const int ns = static_cast<int>(surfaces.size());
  ctrl_.off = Kokkos::View<long*>("epaphe::contact::control_offset", ns);
  ctrl_.dim = Kokkos::View<int* [2]>("epaphe::contact::control_dims", ns);
  ctrl_.canon = Kokkos::View<int*>("epaphe::contact::canonical_surface", ns);
  std::vector<double> G;
  for (int s = 0; s < ns; ++s) {
    ctrl_.off(s) = -1;
    const ContactSurface& cs = surfaces[s];
    int first = 0;  // a copy of a carried surface (a stage's instances) shares the first one's columns
    while (first < s && !(cs.moving && surfaces[first].moving == cs.moving && surfaces[first].block == cs.block))
      ++first;
    ctrl_.canon(s) = first;
    if (first < s) {
      ctrl_.off(s) = ctrl_.off(first);
      ctrl_.dim(s, 0) = ctrl_.dim(first, 0);
      ctrl_.dim(s, 1) = ctrl_.dim(first, 1);
      continue;
    }
    if (!cs.moving) continue;
    const int blk = cs.block, b0 = F_.blocks(blk, 0), n = F_.blocks(blk, 1);
    if (F_.denseRow(b0) < 0) continue;  // a diagonal block: the entries' path
    const BSplineSurface& S = *cs.surface;
    const int nu = S.nu(), nv = S.nv(), inNv = S.inputNv();
    const int nuE = static_cast<int>(S.operatorU().size()) / nu, nvE = static_cast<int>(S.operatorV().size()) / nv;
    const std::vector<double>&Bu = S.operatorU(), &Bv = S.operatorV();
    ctrl_.off(s) = static_cast<long>(G.size());
    ctrl_.dim(s, 0) = nuE;
    ctrl_.dim(s, 1) = nvE;
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
          double* g = &G[ctrl_.off(s) + ((static_cast<std::size_t>(e2) * nuE + a) * nvE + b) * n];
          for (int q = 0; q < nv; ++q) {
            const double w = Bv[static_cast<std::size_t>(b) * nv + q];
            if (w == 0.0) continue;
            const double* t = &T[(static_cast<std::size_t>(a) * nv + q) * n];
            for (int r = 0; r < n; ++r) g[r] += w * t[r];
          }
        }
    }
  }
  gridColumns(surfaces, G);
}

void RelativeFlexibility::gridColumns(const std::vector<ContactSurface>& surfaces, const std::vector<double>& G) {
  const int ns = static_cast<int>(surfaces.size());
  LargeTable g = largeTable("epaphe::contact::control_columns", G.size());
  ctrl_.G = g.view;
  ctrl_.memoryG = g.memory;
  for (std::size_t i = 0; i < G.size(); ++i) ctrl_.G(i) = G[i];
  // H(s, s2) for two surfaces with control columns on one block, from s's control columns G on s2's
  // grid rows interpolated as s2's control points are (eq. 2.26): M(:, c) = sum_pq B_u(A, p) B_v(B, q)
  // G(grid row (p, q, e2'), c), B_u first (into one column Y(A, q, e2') at a time), then B_v; stored
  // transposed, H(s, s2) = M^T = (B_u x B_v)_s F^T (B_u x B_v)_s2^T, so that relativeColumns reads a
  // column of s2 at a patch of s as contiguous runs (the transpose of what it needs, H(s2, s), for any
  // F). It is about G's size (s2's grid rows are most of the block's).
  ctrl_.hOff = Kokkos::View<long**>("epaphe::contact::H_offset", ns, ns);
  ctrl_.coefOff = Kokkos::View<long*>("epaphe::contact::coefficient_offset", ns);
  std::vector<double> H, Y, M;
  long coefs = 0;
  for (int s2 = 0; s2 < ns; ++s2) {
    ctrl_.coefOff(s2) = -1;
    if (ctrl_.off(s2) >= 0) {
      if (ctrl_.canon(s2) != s2) {
        ctrl_.coefOff(s2) = ctrl_.coefOff(ctrl_.canon(s2));
      } else {
        ctrl_.coefOff(s2) = coefs;
        coefs += 3L * ctrl_.dim(s2, 0) * ctrl_.dim(s2, 1);
      }
    }
  }
  for (int s2 = 0; s2 < ns; ++s2)
    for (int s = 0; s < ns; ++s) ctrl_.hOff(s, s2) = -1;
  for (int s2 = 0; s2 < ns; ++s2) {
    for (int s = 0; s < ns; ++s) {
      if (ctrl_.off(s2) < 0 || ctrl_.off(s) < 0 || surfaces[s].block != surfaces[s2].block) continue;
      if (ctrl_.canon(s2) != s2 || ctrl_.canon(s) != s) continue;  // copies: the first ones' H (below)
      const ContactSurface& cs2 = surfaces[s2];
      const BSplineSurface& S2 = *cs2.surface;
      const int blk = surfaces[s].block, n = F_.blocks(blk, 1), r0 = F_.denseRow(F_.blocks(blk, 0));
      const int nu2 = S2.nu(), nv2 = S2.nv(), inNv2 = S2.inputNv(), nuE2 = ctrl_.dim(s2, 0), nvE2 = ctrl_.dim(s2, 1);
      const int nuE = ctrl_.dim(s, 0), nvE = ctrl_.dim(s, 1);
      const std::vector<double>&Bu = S2.operatorU(), &Bv = S2.operatorV();
      const long rows = 3L * nuE * nvE, cols = 3L * nuE2 * nvE2;  // H(s, s2)'s
      ctrl_.hOff(s, s2) = static_cast<long>(H.size());
      H.resize(H.size() + rows * cols, 0.0);
      Y.assign(3L * nuE2 * nv2, 0.0);
      M.assign(static_cast<std::size_t>(cols), 0.0);
      for (long c = 0; c < rows; ++c) {  // c: s's control column (e2, a, b) as in G
        const double* g = &G[ctrl_.off(s) + c * n];
        std::fill(Y.begin(), Y.end(), 0.0);  // Y(A, q, e2') = sum_p B_u(A, p) G((p, q, e2'), c)
        for (int p = 0; p < nu2; ++p)
          for (int q = 0; q < nv2; ++q)
            for (int e2 = 0; e2 < 3; ++e2) {
              const int j = cs2.gridDofs[3 * (static_cast<std::size_t>(p) * inNv2 + q) + e2];
              const double y = j >= 0 ? g[F_.denseRow(j) - r0] : 0.0;  // (-1: clamped)
              if (y == 0.0) continue;
              for (int A = 0; A < nuE2; ++A)
                Y[(static_cast<long>(A) * nv2 + q) * 3 + e2] += Bu[static_cast<long>(A) * nu2 + p] * y;
            }
        std::fill(M.begin(), M.end(), 0.0);  // M(A, B, e2') = sum_q B_v(B, q) Y(A, q, e2')
        for (int A = 0; A < nuE2; ++A)
          for (int B = 0; B < nvE2; ++B)
            for (int q = 0; q < nv2; ++q) {
              const double w = Bv[static_cast<long>(B) * nv2 + q];
              if (w == 0.0) continue;
              for (int e2 = 0; e2 < 3; ++e2)
                M[(static_cast<long>(A) * nvE2 + B) * 3 + e2] += w * Y[(static_cast<long>(A) * nv2 + q) * 3 + e2];
            }
        // H(s, s2): row 3 nvE a + 3 b + e2 of s's point (c = (e2 nuE + a) nvE + b), column (e2', A, B) of s2
        const long e2 = c / (static_cast<long>(nuE) * nvE), a = (c / nvE) % nuE, b = c % nvE;
        const long row = 3 * (a * nvE + b) + e2;
        for (int A = 0; A < nuE2; ++A)
          for (int B = 0; B < nvE2; ++B)
            for (int e2p = 0; e2p < 3; ++e2p)
              H[ctrl_.hOff(s, s2) + ((static_cast<long>(e2p) * nuE2 + A) * nvE2 + B) * rows + row] =
                  M[(static_cast<long>(A) * nvE2 + B) * 3 + e2p];
      }
    }
  }
  for (int s2 = 0; s2 < ns; ++s2)  // copies: the first ones' H
    for (int s = 0; s < ns; ++s)
      if (ctrl_.hOff(s, s2) < 0 && ctrl_.off(s2) >= 0 && ctrl_.off(s) >= 0 && surfaces[s].block == surfaces[s2].block)
        ctrl_.hOff(s, s2) = ctrl_.hOff(ctrl_.canon(s), ctrl_.canon(s2));
  LargeTable h = largeTable("epaphe::contact::control_flexibility", H.size());
  ctrl_.H = h.view;
  ctrl_.memoryH = h.memory;
  for (std::size_t i = 0; i < H.size(); ++i) ctrl_.H(i) = H[i];
  ctrl_.coef = Kokkos::View<double*>("epaphe::contact::control_coefficients", coefs);
}

void RelativeFlexibility::motionEntries(const DetectionViews& dv) {
  // For every node on a surface: the entries of D_k, i.e. the spline weights of its foot point on
  // a carried surface.
  const auto foot = dv.foot;
  const auto ops = unmanaged(carried_.ops);
  const auto opOff = unmanaged(carried_.opOff);
  const auto info = unmanaged(carried_.info);
  const auto surf = dv.selected;
  const auto gridOff = unmanaged(carried_.gridOff);
  const auto dof = dv.dof;
  const auto wu = unmanaged(wu_), wv = unmanaged(wv_);
  const auto own = unmanaged(D_.own);
  const auto grid = unmanaged(D_.grid);
  const auto pu = unmanaged(D_.pu), pv = unmanaged(D_.pv);
  const auto gu = unmanaged(D_.wu), gv = unmanaged(D_.wv);
  const auto entRot = unmanaged(D_.rot);
  const auto rot = dv.rot;
  const auto patch = unmanaged(patch_);
  const auto ctrlOff = unmanaged(ctrl_.off);
  const auto window = unmanaged(carried_.window);
  const auto winOff = unmanaged(carried_.winOff);
  forEach(
      "epaphe::contact::relative_motion", static_cast<long>(dv.gap.extent(0)),
      30L + 40L * (carried_.maxWindow[0] + carried_.maxWindow[1]), KOKKOS_LAMBDA(const int k) {
        for (int d = 0; d < 3; ++d) own(k, d) = dof(k, d);
        for (int x = 0; x < 4; ++x) grid(k, x) = 0;
        const int s = surf(k);
        for (int d = 0; d < 3; ++d)  // R of the surface at this detection (identity when it does not turn)
          for (int e = 0; e < 3; ++e) entRot(k, d, e) = s >= 0 ? rot(s, d, e) : (d == e ? 1.0 : 0.0);
        if (s >= 0 && info(s, 0) >= 0) {
          // w_p = sum_r b_r B(i + r, p): the cubic basis (eq. 2.22) contracted with the rows of the
          // interpolation operator (eq. 2.26, row-major n_ext x n) the patch reads, on the grid nodes of
          // the interval's window (the others' weights count as zero: appendWindows); wgt(k, j) holds
          // node first + j (mod n). Those above 1e-12 of the largest are kept, in ascending order
          for (int dir = 0; dir < 2; ++dir) {
            const int n = info(s, 1 + dir);
            const auto& wgt = dir == 0 ? wu : wv;
            const auto& keptP = dir == 0 ? pu : pv;
            const auto& keptW = dir == 0 ? gu : gv;
            int i;
            double t, bs[4], db[4], ddb[4], wmax = 0.0;
            surface_detail::locate(foot(k, dir), n, info(s, 4 + dir) != 0, i, t);
            surface_detail::cubicBasis(t, bs, db, ddb);
            int first = 0, count = n;
            if (t >= 0.0 && t <= 1.0) {  // (b_r >= 0: the window's premise)
              first = window(winOff(s, dir) + i, 0);
              count = window(winOff(s, dir) + i, 1);
            }
            const double* B = &ops(opOff(s, dir) + i * n);
            for (int j = 0; j < count; ++j) {
              const int p = first + j < n ? first + j : first + j - n;
              double x = 0.0;
              for (int r = 0; r < 4; ++r) x += bs[r] * B[r * n + p];
              wgt(k, j) = x;
              wmax = ::fabs(x) > wmax ? ::fabs(x) : wmax;
            }
            const int shift = first + count > n ? n - first : 0;  // node order: j = idx + shift (mod count)
            int kept = 0;
            for (int idx = 0; idx < count; ++idx) {  // they decay like 0.27^distance: at most 46 are kept
              const int j = idx + shift < count ? idx + shift : idx + shift - count;
              if (::fabs(wgt(k, j)) < 1e-12 * wmax || wgt(k, j) == 0.0) continue;
              keptP(k, kept) = first + j < n ? first + j : first + j - n;
              keptW(k, kept) = wgt(k, j);
              ++kept;
            }
            grid(k, 2 + dir) = kept;
          }
          grid(k, 0) = gridOff(s);
          grid(k, 1) = info(s, 3);
        }
        const int m = 1 + grid(k, 2) * grid(k, 3);
        patch(k) = s >= 0 && ctrlOff(s) >= 0 && m > 1 ? info(s, 0) : -1;
      });
}

void RelativeFlexibility::patchBases(const std::vector<int>& activeH, const Kokkos::View<int*>::HostMirror& surfH,
                                     const DetectionViews& dv) {
  // per active patch node, its patch: the first control point (i, j) and the cubic basis of the foot
  // point (eq. 2.22), read by C and by the correction; and U, the control points of the patches
  const int ns = static_cast<int>(carried_.info.extent(0));
  for (std::size_t x = 0; x < uMap_.extent(0); ++x) uMap_(x) = -1;
  for (const int k : activeH) {
    const int s = surfH(k);
    if (patch_(k) < 0) continue;
    int i, j;
    double tu, tv, bu[4], bv[4], d1[4], d2[4];
    surface_detail::locate(dv.foot(k, 0), carried_.info(s, 1), carried_.info(s, 4) != 0, i, tu);
    surface_detail::locate(dv.foot(k, 1), carried_.info(s, 2), carried_.info(s, 5) != 0, j, tv);
    surface_detail::cubicBasis(tu, bu, d1, d2);
    surface_detail::cubicBasis(tv, bv, d1, d2);
    pcell_(k, 0) = i;
    pcell_(k, 1) = j;
    for (int r = 0; r < 4; ++r) {
      pbasis_(k, r) = bu[r];
      pbasis_(k, 4 + r) = bv[r];
    }
  }
  // U in the order the active nodes' patches first read its points, so that the points of nodes 0..a
  // are U's first uEnd_(a) (relativeColumns)
  int u = 0;
  std::vector<int> uOf(static_cast<std::size_t>(ns), 0);  // |U_s|
  for (std::size_t a = 0; a < activeH.size(); ++a) {
    const int k = activeH[a], c = patch_(k) >= 0 ? ctrl_.canon(surfH(k)) : 0;
    if (patch_(k) >= 0 && uMapOff_(c) >= 0) {
      const int nvE = ctrl_.dim(c, 1);
      for (int r = 0; r < 4; ++r)
        for (int t = 0; t < 4; ++t) {
          const int point = (pcell_(k, 0) + r) * nvE + pcell_(k, 1) + t;
          int& m = uMap_(uMapOff_(c) + point);
          if (m >= 0) continue;
          m = u;
          uPoint_(u, 0) = c;
          uPoint_(u, 1) = point;
          ++uOf[c];
          ++u;
        }
    }
    uEnd_(a) = u;
  }
  nU_ = u;                       // at most every control point and 16 a node: Y_'s room (constructor)
  for (const int k : activeH) {  // a patch's 16 points: b_r b_s and their indices in U (relativePairs)
    if (patch_(k) < 0) continue;
    for (int r = 0; r < 4; ++r)
      for (int t = 0; t < 4; ++t) pweight_(k, 4 * r + t) = pbasis_(k, r) * pbasis_(k, 4 + t);
    for (int x = 0; x < 48; ++x) rowWeight_(k, x) = pweight_(k, x / 3);  // (r', 3 s' + e2'): b_r' b_s'
    const int c = ctrl_.canon(surfH(k));
    if (uMapOff_(c) < 0) continue;
    const int nvE = ctrl_.dim(c, 1);
    for (int r = 0; r < 4; ++r)
      for (int t = 0; t < 4; ++t)
        ppoint_(k, 4 * r + t) = uMap_(uMapOff_(c) + (pcell_(k, 0) + r) * nvE + pcell_(k, 1) + t);
  }
  patchGroups(activeH, surfH);
  // leastBytes(): H on U x U, F's columns at U, and the own columns of the active nodes of dense blocks
  double entries = 0;
  for (int s = 0; s < ns; ++s) {
    if (uOf[s] == 0) continue;
    const int blk = carried_.info(s, 0);
    entries += 3.0 * uOf[s] * blocks_(blk, 1);
    for (int s2 = 0; s2 < ns; ++s2)
      if (uOf[s2] > 0 && carried_.info(s2, 0) == blk) entries += 9.0 * uOf[s] * uOf[s2];
  }
  std::vector<int> own(blocks_.extent(0), 0);  // active nodes of each dense block
  for (const int k : activeH)
    if (F_.denseRow(blocks_(nodeBlk_(k), 0)) >= 0) ++own[nodeBlk_(k)];
  for (std::size_t b = 0; b < own.size(); ++b)
    entries += static_cast<double>(std::min(3 * own[b], blocks_(b, 1))) * blocks_(b, 1);
  leastBytes_ = entries * sizeof(double);
  // The correction's blocks of rows, one a thread, of equal work rather than equal size: a row of a
  // dense block costs 3 multiply-adds per active node of its body and 3 per point of U on its carried
  // surfaces (the columns with a coefficient), 1 otherwise (set to 0). A stage's casing rows weigh
  // several times its blades', and a split by rows gives one thread most of the casing while the
  // other waits for it
  const int T = static_cast<int>(rowEdge_.extent(0)) - 1, N = F_.size();
  rowEdge_(0) = 0;
  rowEdge_(T) = N;
  if (T > 1) {
    std::vector<long> perRow(blocks_.extent(0), 1);
    for (std::size_t b = 0; b < own.size(); ++b) perRow[b] += 3L * own[b];
    for (int s = 0; s < ns; ++s)
      if (uOf[s] > 0) perRow[carried_.info(s, 0)] += 3L * uOf[s];
    std::vector<std::array<long, 3>> seg;  // {first row, rows, work a row}, ascending
    for (std::size_t b = 0; b < perRow.size(); ++b) seg.push_back({blocks_(b, 0), blocks_(b, 1), perRow[b]});
    std::sort(seg.begin(), seg.end());
    double total = 0.0;
    for (const auto& g : seg) total += static_cast<double>(g[1]) * g[2];
    double sum = 0.0;
    std::size_t g = 0;
    for (int t = 1; t < T; ++t) {
      const double target = total * t / T;
      for (; g < seg.size() && sum + static_cast<double>(seg[g][1]) * seg[g][2] < target; ++g)
        sum += static_cast<double>(seg[g][1]) * seg[g][2];
      const long row = g < seg.size() ? seg[g][0] + static_cast<long>(std::ceil((target - sum) / seg[g][2])) : N;
      rowEdge_(t) = static_cast<int>(std::clamp(row, static_cast<long>(rowEdge_(t - 1)), static_cast<long>(N)));
    }
  }
}

void RelativeFlexibility::patchGroups(const std::vector<int>& activeH, const Kokkos::View<int*>::HostMirror& surfH) {
  // The active nodes by patch, in the order of their first nodes; a group's nodes ascending. The nodes
  // of a blade's tip on one patch of the casing share its 48 rows of H: relativeColumns reads them once
  // for the group (rotating stage: 52 active nodes on 14 patches on average)
  const int nA = static_cast<int>(activeH.size());
  std::vector<int>& of = groupOf_;  // per active node: its group
  of.assign(static_cast<std::size_t>(nA), -1);
  std::vector<int>& first = groupFirst_;  // per group: its first node
  first.clear();
  for (int a = 0; a < nA; ++a) {
    const int k = activeH[a];
    if (patch_(k) >= 0)
      for (std::size_t g = 0; g < first.size(); ++g) {
        const int f = activeH[first[g]];
        if (patch_(f) >= 0 && surfH(f) == surfH(k) && pcell_(f, 0) == pcell_(k, 0) && pcell_(f, 1) == pcell_(k, 1)) {
          of[a] = static_cast<int>(g);
          break;
        }
      }
    if (of[a] < 0) {
      of[a] = static_cast<int>(first.size());
      first.push_back(a);
    }
  }
  nGroups_ = static_cast<int>(first.size());
  for (int g = 0; g <= nGroups_; ++g) groupStart_(g) = 0;
  for (int a = 0; a < nA; ++a) ++groupStart_(of[a] + 1);
  for (int g = 0; g < nGroups_; ++g) {
    groupStart_(g + 1) += groupStart_(g);
    groupEnd_(g) = 0;
  }
  std::vector<int>& next = groupFirst_;  // (reused: per group, where its next node goes)
  for (int g = 0; g < nGroups_; ++g) next[g] = groupStart_(g);
  for (int a = 0; a < nA; ++a) {
    const int g = of[a];
    groupNode_(next[g]++) = a;
    groupEnd_(g) = std::max(groupEnd_(g), symmetric_ ? uEnd_(a) : nU_);
  }
}

void RelativeFlexibility::relativeColumns(const Kokkos::View<int*>& active, int nA, const DetectionViews& dv) {
  // Y_b(u, e2', e2) = sum_r's' b_r' b_s' (B_s2 F B_sb^T)((u, e2), (e2', i_b + r', j_b + s')) of every active
  // patch node b, on the points u of U on a surface s2 of b's block, read from its transpose H(s_b, s2)
  // (gridColumns): in the column (u, e2), b's patch is 4 runs of 12 (s', e2'). One group of nodes on one
  // patch an iteration (patchGroups): the group's 48 entries of a column are read once, from memory,
  // and weighed by each node's basis. With F symmetric, node b's pairs with the nodes a <= b read Y_b at
  // their patches alone (relativePairs): U's first uEnd_(b) points (patchBases' order), about half of U
  // on average; a group makes its nodes' Y on the most of them
  if (Y_.extent(0) == 0) return;
  const auto surf = dv.selected;
  const auto patch = unmanaged(patch_);
  const auto pcell = unmanaged(pcell_);
  const auto rowWeight = unmanaged(rowWeight_);
  const auto ctrlDim = unmanaged(ctrl_.dim);
  const auto H = unmanaged(ctrl_.H);
  const auto hOff = unmanaged(ctrl_.hOff);
  const auto uPoint = unmanaged(uPoint_);
  const auto groupNode = unmanaged(groupNode_);
  const auto groupStart = unmanaged(groupStart_);
  const auto groupEnd = unmanaged(groupEnd_);
  const auto Y = unmanaged(Y_);
  const int nG = nGroups_;
  const bool symmetric = symmetric_;
  forEach(
      "epaphe::contact::relative_columns", nG, (16L * 3 * nU_ / 2 + 10) * nA / std::max(nG, 1),
      KOKKOS_LAMBDA(const int i) {
        // (with F symmetric, the groups from both ends of the list in turn: the threads' blocks of i
        // then hold as many columns)
        const int g = symmetric ? (i % 2 == 0 ? i / 2 : nG - 1 - i / 2) : i;
        const int m0 = groupStart(g), m1 = groupStart(g + 1);
        const int k0 = active(groupNode(m0)), sb = surf(k0);
        if (patch(k0) < 0) return;
        const int end = groupEnd(g);
        const int nuEb = ctrlDim(sb, 0), nvEb = ctrlDim(sb, 1);
        const long rowsB = 3L * nuEb * nvEb;  // rows of H(s_b, s2): s_b's control points
        // the rows of column u + ahead asked for from memory while column u is weighed: the columns are
        // 3 nuEb nvEb entries apart, each read at 4 runs of 12 entries, which the hardware's prefetch
        // does not foresee (without it, the loads of H waited for memory on a third of the kernel's samples)
        constexpr int ahead = 2;
        auto prefetch = [&](int v) {
          const int s2 = uPoint(v, 0);
          if (hOff(sb, s2) < 0) return;
          const long nE2 = static_cast<long>(ctrlDim(s2, 0)) * ctrlDim(s2, 1);
          const double* rows = &H(hOff(sb, s2) + 3L * nvEb * pcell(k0, 0) + 3L * pcell(k0, 1));
          for (int e2 = 0; e2 < 3; ++e2)
            for (int rp = 0; rp < 4; ++rp) {
              const double* run = rows + (e2 * nE2 + uPoint(v, 1)) * rowsB + 3L * nvEb * rp;
              __builtin_prefetch(run);
              __builtin_prefetch(run + 11);
            }
        };
        for (int v = 0; v < ahead && v < end; ++v) prefetch(v);
        for (int u = 0; u < end; ++u) {
          if (u + ahead < end) prefetch(u + ahead);
          const int s2 = uPoint(u, 0), point = uPoint(u, 1);
          if (hOff(sb, s2) < 0) {  // another block: no flexibility between them
            for (int m = m0; m < m1; ++m)
              for (int x = 0; x < 9; ++x) Y(active(groupNode(m)), 9L * u + x) = 0.0;
            continue;
          }
          const long nE2 = static_cast<long>(ctrlDim(s2, 0)) * ctrlDim(s2, 1);
          // the patch in a column of H(s_b, s2): rows 3 nvEb (i + r') + 3 j + (3 s' + e2'), read once for
          // the group's nodes
          const double* patchRows = &H(hOff(sb, s2) + 3L * nvEb * pcell(k0, 0) + 3L * pcell(k0, 1));
          for (int e2 = 0; e2 < 3; ++e2) {
            const double* col = patchRows + (e2 * nE2 + point) * rowsB;
            double h[4][12];
            for (int rp = 0; rp < 4; ++rp)
              for (int x = 0; x < 12; ++x) h[rp][x] = col[3L * nvEb * rp + x];
            for (int m = m0; m < m1; ++m) {
              const int k = active(groupNode(m));
              const double* w = &rowWeight(k, 0);
              double acc[12] = {};
              for (int rp = 0; rp < 4; ++rp)
                for (int x = 0; x < 12; ++x) acc[x] += w[12 * rp + x] * h[rp][x];
              double* yu = &Y(k, 9L * u);
              for (int e2p = 0; e2p < 3; ++e2p)
                yu[3 * e2p + e2] = acc[e2p] + acc[3 + e2p] + acc[6 + e2p] + acc[9 + e2p];
            }
          }
        }
      });
  fence();
}

void RelativeFlexibility::relativePairs(const std::vector<int>& activeH, const Kokkos::View<int*>& active) {
  const int nA = static_cast<int>(activeH.size());
  const auto F = F_.untracked();
  const auto Y = unmanaged(Y_);
  const Kokkos::View<int*> nodeBlk = unmanaged(nodeBlk_);  // (FlexibleColumn refers to it)
  const auto patch = unmanaged(patch_);
  const auto blocks = unmanaged(blocks_);
  const auto C = unmanaged(C_);
  const auto known = unmanaged(known_);
  const auto fixed = unmanaged(fixedC_);
  const RelativeMotion D = motion();
  // C_ab = D_a (F D_b^T), every pair unless both were active at the last pass of this step too (D and
  // F do not change within a step: C_ab was made then).
  // Node a's own part reads F D_b^T at a's DOFs: F's block at (a's DOFs, b's) when both are in one
  // dense block, else 0 (a's body carries no surface: no patch of b's is on it), FlexibleColumn in
  // a diagonal block. On a carried surface with control columns its grid part is
  // -R_a sum_pq w_p w_q (F D_b^T)(grid node pq), w_p w_q = sum_rs b_r b_s B_u(i + r, p) B_v(j + s, q)
  // (eqs. 2.22, 2.26), and F D_b^T on that grid is nonzero only for a patch node b of the same block,
  // -sum_r's' b_r' b_s' F (B_u x B_v)^T(:, ., i_b + r', j_b + s') R_b^T: so the part is
  // R_a X R_b^T with X = sum b_r b_s b_r' b_s' H((i_a + r, j_a + s), (i_b + r', j_b + s')) =
  // sum_rs b_r b_s Y_b(i_a + r, j_a + s) (relativeColumns); on a surface with none (a diagonal block)
  // D_a's entries are walked.
  // Two nodes whose D has its own entry alone (a body's node against a rigid or turning surface:
  // weight 1 on its DOFs, the turn applied to the gap's normal, not to D) have C_ab = F's block at
  // their DOFs, the same at every step: made once and kept (fixedC_), where it was made again at
  // every step with contact (rotor37-massless, frictionless: 7 % of its loop, 117 pairs a step).
  // One group of nodes b an iteration (patchGroups), with their pairs (a, b): the group whose Y_b
  // relativeColumns made at the same iteration (the same groups, the same split of the iterations over
  // the threads), so each thread reads the Y it wrote, from its own cache, and Y_b is read for all of
  // b's pairs while it is there. With F symmetric, C_ba = C_ab^T: node b makes its pairs with a <= b
  // and writes both (groups taken from both ends of the list in turn, as relativeColumns takes them:
  // the threads' blocks hold as many pairs)
  const auto pweight = unmanaged(pweight_);
  const auto ppoint = unmanaged(ppoint_);
  const auto groupNode = unmanaged(groupNode_);
  const auto groupStart = unmanaged(groupStart_);
  const int nG = nGroups_;
  const bool symmetric = symmetric_;
  forEach(
      "epaphe::contact::relative_flexibility", nG,
      (30L * (1 + carried_.maxWindow[0] * carried_.maxWindow[1]) + 160) * nA * nA / std::max(nG, 1),
      KOKKOS_LAMBDA(const int i) {
        const int g = symmetric ? (i % 2 == 0 ? i / 2 : nG - 1 - i / 2) : i;
        for (int m = groupStart(g); m < groupStart(g + 1); ++m) {
          const int b = groupNode(m);
          const int kb = active(b), pb = patch(kb), blkB = nodeBlk(kb);
          const bool ownOnlyB = D.count(kb) == 1 && pb < 0;  // D_b is its own entry alone
          // X of b's pairs with the patch nodes a of its block first, into C_ab (the pair's own, made
          // below), in a loop of nothing else: the 16 multiply-adds of one X wait for each other, and
          // the processor overlaps those of the next pairs only in a short loop
          if (pb >= 0)
            for (int a = 0; a < (symmetric ? b + 1 : nA); ++a) {
              const int ka = active(a);
              if (patch(ka) != pb || (known(ka) && known(kb))) continue;  // (made: kept, as below)
              double X[9] = {};  // X[3 e2' + e2], as Y stores it (one vector of 9 a point)
              for (int x = 0; x < 16; ++x) {
                const double* y = &Y(kb, 9 * ppoint(ka, x));
                const double wa = pweight(ka, x);
                for (int e = 0; e < 9; ++e) X[e] += wa * y[e];
              }
              double* c = &C(ka, kb, 0, 0);
              for (int e = 0; e < 9; ++e) c[e] = X[e];
            }
          for (int a = 0; a < (symmetric ? b + 1 : nA); ++a) {
            const int ka = active(a), pa = patch(ka);
            const bool ownOnly = D.count(ka) == 1 && pa < 0;  // D_a is its own entry alone
            const bool constant = ownOnly && ownOnlyB;
            if ((known(ka) && known(kb)) || (constant && fixed(ka, kb))) continue;
            fixed(ka, kb) = constant ? 1 : 0;
            if (symmetric) fixed(kb, ka) = fixed(ka, kb);
            if (!(D.count(ka) == 1 || pa >= 0)) {  // D_a's entries walked
              for (int e = 0; e < 3; ++e) {
                const FlexibleColumn col{F, D, nodeBlk, kb, e};
                double r[3];
                D.apply(ka, col, r);
                for (int d = 0; d < 3; ++d) {
                  C(ka, kb, d, e) = r[d];
                  if (symmetric && b != a) C(kb, ka, e, d) = r[d];
                }
              }
              continue;
            }
            const int blk = nodeBlk(ka), b0 = blocks(blk, 0), n = blocks(blk, 1);
            const bool denseA = F.denseRow(D.ownDof(ka, 0)) >= 0;  // a's block is dense
            double own[3][3];
            if (denseA && blkB == blk) {     // F's block
              for (int e = 0; e < 3; ++e) {  // (D's own entries have weight 1)
                const double* col = &F.dense(F.start(blk) + static_cast<std::size_t>(D.ownDof(kb, e) - b0) * n);
                for (int d = 0; d < 3; ++d) own[d][e] = col[D.ownDof(ka, d) - b0];
              }
            } else if (denseA) {
              for (int e = 0; e < 3; ++e)
                for (int d = 0; d < 3; ++d) own[d][e] = 0.0;
            } else {
              for (int e = 0; e < 3; ++e)
                for (int d = 0; d < 3; ++d) own[d][e] = FlexibleColumn{F, D, nodeBlk, kb, e}(D.ownDof(ka, d));
            }
            if (pa >= 0 && pb == pa) {             // the grid part, R_a X R_b^T
              const double* X = &C(ka, kb, 0, 0);  // (made above)
              double g[3][3];                      // g[d][e2'] = (R_a X)[d][e2']
              for (int d = 0; d < 3; ++d)
                for (int e2p = 0; e2p < 3; ++e2p)
                  g[d][e2p] = D.rot(ka, d, 0) * X[3 * e2p] + D.rot(ka, d, 1) * X[3 * e2p + 1] +
                              D.rot(ka, d, 2) * X[3 * e2p + 2];
              for (int d = 0; d < 3; ++d)
                for (int e = 0; e < 3; ++e)
                  own[d][e] += g[d][0] * D.rot(kb, e, 0) + g[d][1] * D.rot(kb, e, 1) + g[d][2] * D.rot(kb, e, 2);
            }
            for (int d = 0; d < 3; ++d)
              for (int e = 0; e < 3; ++e) {
                C(ka, kb, d, e) = own[d][e];
                if (symmetric && b != a) C(kb, ka, e, d) = own[d][e];
              }
          }
        }
      });
  fence();
  // known: active at this pass (C_ab is reused only for two nodes active together at the last pass)
  for (std::size_t k = 0; k < known_.extent(0); ++k) known_(k) = 0;
  for (int a = 0; a < nA; ++a) known_(activeH[a]) = 1;
}

void RelativeFlexibility::correction(const Kokkos::View<int*>& active, int nA, const Kokkos::View<double*>& force,
                                     const Kokkos::View<double* [3]>& dir, const Kokkos::View<int*>& surf,
                                     const DenseVector& dqOut, int n) const {
  // dq = F G lambda (eqs. 2.35-2.36), G_a = D_a^T c_a. On the dense rows of F: node a's own part,
  // F's columns at its DOFs, and a patch node's part on its surface's block, F (B_u x B_v) x, the
  // control columns times the control points' coefficients x summed over the nodes first. On a
  // diagonal block, dq_i = F_ii (sum_a D_a^T c_a lambda_a)_i, scattered from the entries of D (one
  // thread: the same sums in the same order on any number of threads).
  const auto F = F_.untracked();
  const auto dq = unmanaged(dqOut);
  const auto act = active;  // ascending: the sums below run in node order
  const int T = Kokkos::DefaultHostExecutionSpace().concurrency();
  const auto blocks = unmanaged(blocks_);
  const Kokkos::View<int*> nodeBlk = unmanaged(nodeBlk_);  // (FlexibleColumn refers to it)
  const auto dof = unmanaged(D_.own);                      // the node's own DOFs
  const auto patch = unmanaged(patch_);
  const auto coefOff = unmanaged(ctrl_.coefOff);
  const auto ctrlOff = unmanaged(ctrl_.off);
  const auto ctrlDim = unmanaged(ctrl_.dim);
  const auto coef = unmanaged(ctrl_.coef);
  const auto ctrl = unmanaged(ctrl_.G);
  const auto canon = unmanaged(ctrl_.canon);
  const auto info = unmanaged(carried_.info);
  const int ns = static_cast<int>(carried_.info.extent(0));
  const bool patches = ctrl_.coef.extent(0) > 0;
  if (patches) {  // x = -sum_k lambda_k b_a b_b R_k^T c_k, over the patch nodes in node order
    const auto rot = unmanaged(D_.rot);
    const auto pbasis = unmanaged(pbasis_);
    const auto pcell = unmanaged(pcell_);
    forEach(
        "epaphe::contact::control_coefficients", 1, 0, KOKKOS_LAMBDA(const int) {
          for (std::size_t x = 0; x < coef.extent(0); ++x) coef(x) = 0.0;
          for (int a = 0; a < nA; ++a) {
            const int k = act(a), s = surf(k);
            const double l = force(k);
            if (l == 0.0 || patch(k) < 0) continue;
            const int nuE = ctrlDim(s, 0), nvE = ctrlDim(s, 1), i = pcell(k, 0), j = pcell(k, 1);
            for (int e2 = 0; e2 < 3; ++e2) {
              const double c = -l * (rot(k, 0, e2) * dir(k, 0) + rot(k, 1, e2) * dir(k, 1) + rot(k, 2, e2) * dir(k, 2));
              if (c == 0.0) continue;
              for (int r = 0; r < 4; ++r)
                for (int t = 0; t < 4; ++t)
                  coef(coefOff(s) + (static_cast<long>(e2) * nuE + i + r) * nvE + j + t) +=
                      c * pbasis(k, r) * pbasis(k, 4 + t);
            }
          }
        });
  }
  // One block of rows per thread (patchBases cut the flexibility's n rows for the T threads), each
  // active node's three columns of F walked down it (F is column-major); each dq_i sums its terms in
  // node order on any number of threads
  const auto edge = unmanaged(rowEdge_);
  forEach(
      "epaphe::contact::correction", T, 3L * n * nA / T, KOKKOS_LAMBDA(const int t) {
        const int i0 = edge(t), i1 = edge(t + 1);
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
          if (coefOff(s) < 0 || canon(s) != s) continue;  // a copy's coefficients are summed into the first's
          const int blk = info(s, 0), b0 = blocks(blk, 0), n = blocks(blk, 1);
          const int lo = i0 > b0 ? i0 : b0, hi = i1 < b0 + n ? i1 : b0 + n;
          const long nc = 3L * ctrlDim(s, 0) * ctrlDim(s, 1);
          // the columns with a coefficient, four at a time: dq_i is loaded and stored once per four
          // (the same sum, in the same order, as column by column)
          double c[4];
          const double* g[4];
          int m = 0;
          auto add = [&](int count) {
            for (int i = lo; i < hi; ++i) {
              double y = dq(i);
              for (int q = 0; q < count; ++q) y += c[q] * g[q][i - b0];
              dq(i) = y;
            }
          };
          for (long x = 0; x < nc; ++x) {
            const double cx = coef(coefOff(s) + x);
            if (cx == 0.0) continue;
            c[m] = cx;
            g[m] = &ctrl(ctrlOff(s) + x * n);
            if (++m == 4) {
              add(4);
              m = 0;
            }
          }
          if (m > 0) add(m);
        }
      });
  if (F.denseRows < F.size()) {
    const RelativeMotion Dk = motion();
    forEach(
        "epaphe::contact::correction_diagonal", 1, 0, KOKKOS_LAMBDA(const int) {
          for (std::size_t k = 0; k < force.extent(0); ++k) {
            const double l = force(k);
            if (l == 0.0) continue;
            // (D_k^T c)_i at DOF i = (m, e)
            Dk.forEachEntry(static_cast<int>(k), [&](int m, const int* dof, double w) {
              for (int e = 0; e < 3; ++e) {
                const int i = dof[e];
                if (i < 0 || F.denseRow(i) >= 0) continue;
                const int kk = static_cast<int>(k);
                const double c = Dk.coefficient(kk, m, w, 0, e) * dir(k, 0) +
                                 Dk.coefficient(kk, m, w, 1, e) * dir(k, 1) +
                                 Dk.coefficient(kk, m, w, 2, e) * dir(k, 2);
                dq(i) += F.diag(i) * l * c;
              }
            });
          }
        });
  }
}

}  // namespace epaphe
