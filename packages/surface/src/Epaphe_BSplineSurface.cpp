#include "Epaphe_BSplineSurface.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>
#include <algorithm>
#include <cmath>
#include <utility>

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

namespace epaphe {
namespace {

// Two grid nodes closer than kCoincide x (bounding-box diagonal) are the same node.
constexpr double kCoincide = 1e-9;

double distance(const double* a, const double* b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

/// Inverse of the n x n 1-D interpolation matrix, row-major (eq. 2.25: [A C]^-1).
/// Open : row 0 and n-1 read Q_1 = P_0 and Q_n = P_{n-1} (end condition Q_0 = 2Q_1 - Q_2 folded
/// in),
///        row k: (Q_k + 4 Q_{k+1} + Q_{k+2}) / 6 = P_k, unknowns Q_1..Q_n.
/// Closed: row k: (Q_{k-1} + 4 Q_k + Q_{k+1}) / 6 = P_k cyclic, unknowns Q_0..Q_{N-1}.
std::vector<double> inverseInterpolation(int n, bool periodic, const std::string& surface, char dir) {
  std::vector<double> A(std::size_t(n) * n, 0.0), X(std::size_t(n) * n, 0.0);  // column-major
  auto a = [&](int r, int c) -> double& { return A[std::size_t(c) * n + r]; };
  for (int k = 0; k < n; ++k) {
    X[std::size_t(k) * n + k] = 1.0;
    if (periodic) {
      a(k, (k + n - 1) % n) += 1.0 / 6.0;
      a(k, k) += 4.0 / 6.0;
      a(k, (k + 1) % n) += 1.0 / 6.0;
    } else if (k == 0 || k == n - 1) {
      a(k, k) = 1.0;
    } else {
      a(k, k - 1) = 1.0 / 6.0;
      a(k, k) = 4.0 / 6.0;
      a(k, k + 1) = 1.0 / 6.0;
    }
  }
  Teuchos::LAPACK<int, double> lapack;
  std::vector<int> ipiv(n);
  int info = 0;
  lapack.GESV(n, n, A.data(), n, ipiv.data(), X.data(), n, &info);
  EPAPHE_REQUIRE(info == 0, "surface '" << surface << "': LAPACK GESV failed (info = " << info << ") on the " << dir
                                        << "-interpolation matrix of size " << n
                                        << "; this is a bug, please report it");
  std::vector<double> inv(std::size_t(n) * n);  // back to row-major
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) inv[std::size_t(r) * n + c] = X[std::size_t(c) * n + r];
  return inv;
}

/// Extended operator B (eq. 2.26, B = C [A C]^-1): rows are the control points every patch reads.
std::vector<double> extendedOperator(int n, bool periodic, const std::string& surface, char dir, int& nExt) {
  const std::vector<double> inv = inverseInterpolation(n, periodic, surface, dir);
  nExt = periodic ? n + 3 : n + 2;
  std::vector<double> B(std::size_t(nExt) * n, 0.0);
  auto row = [&](int r) { return inv.data() + std::size_t(r) * n; };
  auto put = [&](int e, double ca, int ra, double cb, int rb) {
    for (int c = 0; c < n; ++c) B[std::size_t(e) * n + c] = ca * row(ra)[c] + (rb >= 0 ? cb * row(rb)[c] : 0.0);
  };
  if (periodic) {
    // Qext = [Q_{N-1}, Q_0, ..., Q_{N-1}, Q_0, Q_1]
    put(0, 1.0, n - 1, 0.0, -1);
    for (int k = 0; k < n; ++k) put(k + 1, 1.0, k, 0.0, -1);
    put(n + 1, 1.0, 0, 0.0, -1);
    put(n + 2, 1.0, 1, 0.0, -1);
  } else {
    // Qext = [Q_0, Q_1..Q_n, Q_{n+1}], thesis "symmetry" end conditions (C matrix, open surface):
    // Q_0 = 2 Q_1 - Q_2 and Q_{n+1} = 2 Q_n - Q_{n-1} (zero second derivative at the ends).
    put(0, 2.0, 0, -1.0, 1);
    for (int k = 0; k < n; ++k) put(k + 1, 1.0, k, 0.0, -1);
    put(n + 1, 2.0, n - 1, -1.0, n - 2);
  }
  return B;
}

const double* checkedData(const std::vector<double>& points, int nu, int nv, const std::string& surface) {
  EPAPHE_REQUIRE(points.size() == std::size_t(std::max(nu, 0)) * std::size_t(std::max(nv, 0)) * 3,
                 "surface '" << surface << "': " << points.size() << " coordinates given for a " << nu << " x " << nv
                             << " grid, expected " << nu << " * " << nv
                             << " * 3; pass the nodes as x,y,z triplets, i (u) major");
  return points.data();
}

}  // namespace

BSplineSurface::BSplineSurface(std::string name, int nu, int nv, const std::vector<double>& points,
                               SurfaceOptions options)
    : BSplineSurface(name, nu, nv, checkedData(points, nu, nv, name), options) {}

BSplineSurface::BSplineSurface(std::string name, int nu, int nv, const double* points, SurfaceOptions options)
    : name_(std::move(name)), inNu_(nu), inNv_(nv) {
  EPAPHE_REQUIRE(Kokkos::is_initialized(), "surface '" << name_
                                                       << "': Kokkos is not initialised; call Kokkos::initialize "
                                                          "(or create the Epaphe runtime) before building surfaces");
  EPAPHE_REQUIRE(nu >= 4, "surface '" << name_ << "': grid has " << nu
                                      << " points along u, at least 4 are needed (refine the "
                                         "contact surface grid along u)");
  EPAPHE_REQUIRE(nv >= 4, "surface '" << name_ << "': grid has " << nv
                                      << " points along v, at least 4 are needed (refine the "
                                         "contact surface grid along v)");
  EPAPHE_REQUIRE(points != nullptr, "surface '" << name_ << "': null grid point array");
  EPAPHE_REQUIRE(options.orientation == 1 || options.orientation == -1,
                 "surface '" << name_ << "': orientation = " << options.orientation << ", must be +1 or -1");

  auto P = [&](int i, int j) { return points + 3 * (std::size_t(i) * nv + j); };
  double lo[3], hi[3];
  for (int c = 0; c < 3; ++c) {
    lo[c] = P(0, 0)[c];
    hi[c] = P(0, 0)[c];
  }
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      for (int c = 0; c < 3; ++c) {
        const double x = P(i, j)[c];
        EPAPHE_REQUIRE(std::isfinite(x), "surface '" << name_ << "': grid point (" << i << "," << j << ") coordinate "
                                                     << "xyz"[c] << " = " << x
                                                     << " is not finite; check the node "
                                                        "coordinates of the contact surface");
        lo[c] = std::min(lo[c], x);
        hi[c] = std::max(hi[c], x);
      }
  const double size = distance(lo, hi);
  const double tol = kCoincide * size;

  // Closed-ness: the last row (column) repeats the first one.
  double gapU = 0.0, gapV = 0.0;
  for (int j = 0; j < nv; ++j) gapU = std::max(gapU, distance(P(nu - 1, j), P(0, j)));
  for (int i = 0; i < nu; ++i) gapV = std::max(gapV, distance(P(i, nv - 1), P(i, 0)));
  const bool repeatU = gapU <= tol, repeatV = gapV <= tol;
  const bool perU = options.closureU == Closure::Periodic || (options.closureU == Closure::Detect && repeatU);
  const bool perV = options.closureV == Closure::Periodic || (options.closureV == Closure::Detect && repeatV);
  const int mu = (perU && repeatU) ? nu - 1 : nu;
  const int mv = (perV && repeatV) ? nv - 1 : nv;

  // Duplicated consecutive nodes (including across the seam of a closed direction).
  for (int i = 0; i < mu; ++i)
    for (int j = 0; j < mv; ++j) {
      const int in = i + 1 < mu ? i + 1 : (perU ? 0 : -1);
      const int jn = j + 1 < mv ? j + 1 : (perV ? 0 : -1);
      if (in >= 0) {
        const double d = distance(P(i, j), P(in, j));
        EPAPHE_REQUIRE(d > tol, "surface '" << name_ << "': grid points (" << i << "," << j << ") and (" << in << ","
                                            << j << ") coincide (distance " << d << " <= " << tol
                                            << " = 1e-9 x grid size"
                                            << ")"
                                            << "; remove the duplicated node or fix the ordering of "
                                               "the grid along u");
      }
      if (jn >= 0) {
        const double d = distance(P(i, j), P(i, jn));
        EPAPHE_REQUIRE(d > tol, "surface '" << name_ << "': grid points (" << i << "," << j << ") and (" << i << ","
                                            << jn << ") coincide (distance " << d << " <= " << tol
                                            << " = 1e-9 x grid size"
                                            << ")"
                                            << "; remove the duplicated node or fix the ordering of "
                                               "the grid along v");
      }
    }

  view_.nu = mu;
  view_.nv = mv;
  view_.periodicU = perU;
  view_.periodicV = perV;
  view_.orientation = options.orientation;
  view_.id = options.id;

  // 1-D operators built and factorised once (eq. 2.23-2.26); Q = B_u P B_v^T per coordinate.
  Bu_ = extendedOperator(mu, perU, name_, 'u', nuExt_);
  Bv_ = extendedOperator(mv, perV, name_, 'v', nvExt_);

  view_.ctrl = SurfaceView::Points("epaphe::surface::" + name_ + "::ctrl", nuExt_, nvExt_, 3);
  view_.grid = SurfaceView::Points("epaphe::surface::" + name_ + "::grid", mu, mv, 3);
  hostCtrl_ = Kokkos::create_mirror_view(view_.ctrl);
  hostGrid_ = Kokkos::create_mirror_view(view_.grid);
  loadGrid(points, "constructor");
  computeControlPoints();
  buildBins();
}

void BSplineSurface::loadGrid(const double* points, const char* where) {
  EPAPHE_REQUIRE(points != nullptr, "surface '" << name_ << "': null grid point array in " << where);
  const int mu = view_.nu, mv = view_.nv;
  for (int i = 0; i < mu; ++i)
    for (int j = 0; j < mv; ++j)
      for (int c = 0; c < 3; ++c) {
        const double x = points[3 * (std::size_t(i) * inNv_ + j) + c];
        EPAPHE_REQUIRE(std::isfinite(x), "surface '" << name_ << "': " << where << ": grid point (" << i << "," << j
                                                     << ") coordinate "
                                                     << "xyz"[c] << " = " << x
                                                     << " is not finite; check the displacement "
                                                        "of the contact surface nodes");
        hostGrid_(i, j, c) = x;
      }
}

void BSplineSurface::computeControlPoints() {
  const int mu = view_.nu, mv = view_.nv;
  // T = B_u P  (nuExt x nv x 3), then Qext = T B_v^T (nuExt x nvExt x 3); T is kept between updates
  // (a carried surface is updated at every step: no allocation there).
  // T (row-major nuExt x 3 nv) = B_u (row-major nuExt x nu) P (row-major nu x 3 nv): one GEMM, read
  // column-major as T^T = P^T B_u^T (B_u is dense for a closed direction: nuExt nu 3 nv multiply-adds,
  // 66,000 on the stage's casing at every step)
  std::vector<double>& T = work_;
  T.resize(std::size_t(nuExt_) * mv * 3);
  Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 3 * mv, nuExt_, mu, 1.0, hostGrid_.data(),
                                    3 * mv, Bu_.data(), mu, 0.0, T.data(), 3 * mv);
  for (int a = 0; a < nuExt_; ++a)
    for (int b = 0; b < nvExt_; ++b) {
      double q[3] = {0.0, 0.0, 0.0};
      for (int j = 0; j < mv; ++j) {
        const double w = Bv_[std::size_t(b) * mv + j];
        for (int c = 0; c < 3; ++c) q[c] += w * T[(std::size_t(a) * mv + j) * 3 + c];
      }
      for (int c = 0; c < 3; ++c) hostCtrl_(a, b, c) = q[c];
    }
  copy(view_.ctrl, hostCtrl_);  // every step for a carried surface: no deep_copy fences and hooks
  copy(view_.grid, hostGrid_);
}

void BSplineSurface::update(const double* points, bool bins) {
  loadGrid(points, "update");
  computeControlPoints();
  if (bins) {
    buildBins();
  } else {
    view_.binStart = SurfaceView::Indices();
    view_.binNodes = SurfaceView::Indices();
  }
}

void BSplineSurface::buildBins() {
  const int mu = view_.nu, mv = view_.nv, n = mu * mv;
  auto node = [&](int k, int c) { return hostGrid_(k / mv, k % mv, c); };
  // Node box.
  double lo[3], hi[3];
  for (int c = 0; c < 3; ++c) lo[c] = hi[c] = node(0, c);
  for (int k = 1; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], node(k, c));
      hi[c] = std::max(hi[c], node(k, c));
    }
  // Cell side: mean distance between neighbouring nodes (a cell holds O(1) nodes of the surface),
  // enlarged if the box would need more than max(64, 2 nodes) cells (e.g. a large closed surface).
  double sum = 0.0;
  long edges = 0;
  for (int i = 0; i < mu; ++i)
    for (int j = 0; j < mv; ++j) {
      const double* p = &hostGrid_(i, j, 0);
      if (i + 1 < mu || view_.periodicU) {
        sum += distance(p, &hostGrid_((i + 1) % mu, j, 0));
        ++edges;
      }
      if (j + 1 < mv || view_.periodicV) {
        sum += distance(p, &hostGrid_(i, (j + 1) % mv, 0));
        ++edges;
      }
    }
  double h = edges > 0 ? sum / double(edges) : 0.0;
  const double diag = distance(lo, hi);
  if (!(h > 0.0)) h = diag > 0.0 ? diag : 1.0;
  const double maxCells = std::max(64.0, 2.0 * n);
  double dims[3];
  for (int pass = 0; pass < 64; ++pass) {
    double cells = 1.0;
    for (int c = 0; c < 3; ++c) {
      dims[c] = std::max(1.0, std::ceil((hi[c] - lo[c]) / h));
      cells *= dims[c];
    }
    if (cells <= maxCells) break;
    h *= std::cbrt(cells / maxCells) * (1.0 + 1e-6);
  }
  double scale = h;
  for (int c = 0; c < 3; ++c) {
    view_.binOrigin[c] = lo[c];
    view_.binUpper[c] = hi[c];
    view_.binDims[c] = int(dims[c]);
    scale = std::max({scale, std::fabs(lo[c]), std::fabs(hi[c])});
  }
  view_.binSize = h;
  view_.binSlack = 1e-12 * scale;
  const int cells = view_.binDims[0] * view_.binDims[1] * view_.binDims[2];

  if (hostBinStart_.extent(0) != std::size_t(cells) + 1) {
    binStart_ = SurfaceView::Indices("epaphe::surface::" + name_ + "::binStart", cells + 1);
    hostBinStart_ = Kokkos::create_mirror_view(binStart_);
  }
  if (hostBinNodes_.extent(0) != std::size_t(n)) {
    binNodes_ = SurfaceView::Indices("epaphe::surface::" + name_ + "::binNodes", n);
    hostBinNodes_ = Kokkos::create_mirror_view(binNodes_);
  }
  view_.binStart = binStart_;
  view_.binNodes = binNodes_;
  // Counting sort by cell, stable: nodes ascending within a cell.
  std::vector<int> cellOf(n);
  for (int c = 0; c <= cells; ++c) hostBinStart_(c) = 0;
  for (int k = 0; k < n; ++k) {
    int a[3];
    for (int c = 0; c < 3; ++c) a[c] = surface_detail::binCoord(view_, node(k, c), c);
    cellOf[k] = (a[0] * view_.binDims[1] + a[1]) * view_.binDims[2] + a[2];
    ++hostBinStart_(cellOf[k] + 1);
  }
  for (int c = 0; c < cells; ++c) hostBinStart_(c + 1) += hostBinStart_(c);
  std::vector<int> fill(hostBinStart_.data(), hostBinStart_.data() + cells);
  for (int k = 0; k < n; ++k) hostBinNodes_(fill[cellOf[k]]++) = k;
  Kokkos::deep_copy(view_.binStart, hostBinStart_);
  Kokkos::deep_copy(view_.binNodes, hostBinNodes_);
}

void BSplineSurface::update(const std::vector<double>& points) {
  EPAPHE_REQUIRE(points.size() == std::size_t(inNu_) * inNv_ * 3,
                 "surface '" << name_ << "': update with " << points.size() << " coordinates, expected " << inNu_
                             << " * " << inNv_ << " * 3 (same grid as at construction)");
  update(points.data());
}

void BSplineSurface::setOrientation(int orientation) {
  EPAPHE_REQUIRE(orientation == 1 || orientation == -1,
                 "surface '" << name_ << "': orientation = " << orientation
                             << ", must be +1 or -1 (the side of the surface where bodies are)");
  view_.orientation = orientation;
}

std::array<double, 3> BSplineSurface::gridPoint(int i, int j) const {
  EPAPHE_REQUIRE(i >= 0 && i < view_.nu && j >= 0 && j < view_.nv, "surface '" << name_ << "': grid point (" << i << ","
                                                                               << j << ") out of range [0," << view_.nu
                                                                               << ") x [0," << view_.nv << ")");
  return {hostGrid_(i, j, 0), hostGrid_(i, j, 1), hostGrid_(i, j, 2)};
}

HostSurfaceView BSplineSurface::hostView() const {
  HostSurfaceView h;
  h.ctrl = hostCtrl_;
  h.grid = hostGrid_;
  h.nu = view_.nu;
  h.nv = view_.nv;
  h.periodicU = view_.periodicU;
  h.periodicV = view_.periodicV;
  h.orientation = view_.orientation;
  h.id = view_.id;
  if (view_.binStart.extent(0) > 0) {  // (none after an update without it)
    h.binStart = hostBinStart_;
    h.binNodes = hostBinNodes_;
  }
  for (int c = 0; c < 3; ++c) {
    h.binOrigin[c] = view_.binOrigin[c];
    h.binUpper[c] = view_.binUpper[c];
    h.binDims[c] = view_.binDims[c];
  }
  h.binSize = view_.binSize;
  h.binSlack = view_.binSlack;
  return h;
}

}  // namespace epaphe
