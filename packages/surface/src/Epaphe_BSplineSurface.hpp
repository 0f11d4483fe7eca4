#pragma once
// Uniform bicubic interpolating B-spline surface through an ordered grid of nodes
// (thesis Leclere 2018, section 2.4, eqs 2.14-2.27), open or closed in each direction.
//
// Parametrisation (global parameters, uniform knots, one unit per patch):
//   open direction  : n passing points, u in [0, n-1], patch i = floor(u) clamped to [0, n-2]
//   closed direction: N passing points, u in [0, N) and wraps, patch i = floor(u) in [0, N-1]
// Patch i reads the 4 consecutive extended control points Qext[i..i+3] (eq. 2.21, 2.22):
//   open  : Qext = [Q_0, Q_1, ..., Q_{n+1}]                 (n+2 control points)
//   closed: Qext = [Q_{N-1}, Q_0, ..., Q_{N-1}, Q_0, Q_1]    (N control points, N+3 stored)
// so that S(u = i) = (Qext[i] + 4 Qext[i+1] + Qext[i+2]) / 6 = P_i in both cases.
#include <Kokkos_Core.hpp>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace epaphe {

/// Device-copyable description of one surface: copy it by value into a KOKKOS_LAMBDA.
template <class MemorySpace>
struct BasicSurfaceView {
  /// Kokkos' name of the memory space the views live in.
  using memory_space = MemorySpace;
  /// A view of 3-D points, [i][j][3].
  using Points = Kokkos::View<double***, Kokkos::LayoutRight, MemorySpace>;
  Points ctrl;             ///< extended control points [nu_ext][nv_ext][3] (see top of file)
  Points grid;             ///< passing points (grid nodes) [nu][nv][3], duplicate closing row dropped
  int nu = 0;              ///< number of distinct passing points along u
  int nv = 0;              ///< number of distinct passing points along v
  bool periodicU = false;  ///< closed (C2 across the seam) along u
  bool periodicV = false;  ///< closed along v
  int orientation = 1;     ///< unit normal = orientation * (S_u x S_v) / |S_u x S_v|
  int id = 0;              ///< user id of the surface

  /// Broad phase of the cold-start closest-point search: uniform bucket grid of cubic cells of side
  /// binSize over the grid nodes. Cell (a,b,c) (a along x) has flat index (a*binDims[1] + b) *
  /// binDims[2] + c and holds the nodes binNodes[binStart[cell] .. binStart[cell+1]), node (i,j)
  /// stored as i*nv + j, ascending within a cell. Empty views (hand-built view): no broad phase.
  using Indices = Kokkos::View<int*, MemorySpace>;
  Indices binStart;                       ///< [cells + 1] offsets into binNodes
  Indices binNodes;                       ///< [nu*nv] node indices sorted by cell
  double binOrigin[3] = {0.0, 0.0, 0.0};  ///< lower corner of cell (0,0,0) = min of the nodes
  double binUpper[3] = {0.0, 0.0, 0.0};   ///< max of the nodes (node box = [binOrigin, binUpper])
  double binSize = 1.0;                   ///< side of a cell
  double binSlack = 0.0;                  ///< absolute round-off margin of the pruning bounds
  int binDims[3] = {0, 0, 0};             ///< cells along x, y, z

  /// Upper end of the parameter range: n-1 (open) or N (closed, excluded).
  KOKKOS_INLINE_FUNCTION double uMax() const { return periodicU ? double(nu) : double(nu - 1); }
  /// Upper end of the v range: n-1 (open) or N (closed, excluded).
  KOKKOS_INLINE_FUNCTION double vMax() const { return periodicV ? double(nv) : double(nv - 1); }
};

/// The surface view in the default execution space's memory, for kernels.
using SurfaceView = BasicSurfaceView<Kokkos::DefaultExecutionSpace::memory_space>;
/// The surface view in host memory.
using HostSurfaceView = BasicSurfaceView<Kokkos::HostSpace>;

namespace surface_detail {

/// Eq. 2.22 uniform cubic B-spline basis on one patch, local t in [0, 1], and its derivatives.
KOKKOS_INLINE_FUNCTION void cubicBasis(double t, double b[4], double db[4], double ddb[4]) {
  const double s = 1.0 - t, t2 = t * t, t3 = t2 * t;
  constexpr double sixth = 1.0 / 6.0;  // a product, not four divisions (a closest point evaluates this often)
  b[0] = s * s * s * sixth;
  b[1] = (3.0 * t3 - 6.0 * t2 + 4.0) * sixth;
  b[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) * sixth;
  b[3] = t3 * sixth;
  db[0] = -0.5 * s * s;
  db[1] = 1.5 * t2 - 2.0 * t;
  db[2] = -1.5 * t2 + t + 0.5;
  db[3] = 0.5 * t2;
  ddb[0] = s;
  ddb[1] = 3.0 * t - 2.0;
  ddb[2] = -3.0 * t + 1.0;
  ddb[3] = t;
}

/// Maps a global parameter to the domain: clamp to [0, n-1] (open) or wrap into [0, N) (closed).
KOKKOS_INLINE_FUNCTION double toDomain(double u, int n, bool periodic) {
  if (periodic) {
    const double N = double(n);
    if (u >= 0.0 && u < N) return u;  // already inside: the wrap below would leave it unchanged
    u -= N * ::floor(u / N);
    if (u >= N) u -= N;  // rounding of a tiny negative u
    return u < 0.0 ? 0.0 : u;
  }
  const double umax = double(n - 1);
  return u < 0.0 ? 0.0 : (u > umax ? umax : u);
}

/// Patch index and local parameter t = u - i. Open: i = floor(u) clamped to [0, n-2] (t may leave
/// [0, 1] outside the domain: polynomial extrapolation). Closed: u is wrapped first.
KOKKOS_INLINE_FUNCTION void locate(double u, int n, bool periodic, int& i, double& t) {
  if (periodic) {
    u = toDomain(u, n, true);
    i = int(u);
    if (i > n - 1) i = n - 1;
  } else {
    const double f = ::floor(u);
    i = f < 0.0 ? 0 : (f > double(n - 2) ? n - 2 : int(f));
  }
  t = u - double(i);
}

/// Broad phase: cell coordinate of x along axis a, clamped to [0, binDims[a]-1] (NaN -> 0).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION int binCoord(const BasicSurfaceView<MemorySpace>& s, double x, int a) {
  const double t = (x - s.binOrigin[a]) / s.binSize;
  if (!(t >= 0.0)) return 0;
  if (t >= double(s.binDims[a] - 1)) return s.binDims[a] - 1;
  return int(t);
}

}  // namespace surface_detail

/// Surface point and first and second derivatives w.r.t. the global parameters (eq. 2.21-2.22).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void evaluate(const BasicSurfaceView<MemorySpace>& s, double u, double v, double S[3],
                                     double Su[3], double Sv[3], double Suu[3], double Suv[3], double Svv[3]) {
  int i, j;
  double t, w;
  surface_detail::locate(u, s.nu, s.periodicU, i, t);
  surface_detail::locate(v, s.nv, s.periodicV, j, w);
  double bu[4], dbu[4], ddbu[4], bv[4], dbv[4], ddbv[4];
  surface_detail::cubicBasis(t, bu, dbu, ddbu);
  surface_detail::cubicBasis(w, bv, dbv, ddbv);
  // The patch's 4 rows (along u) of 4 control points: each row's 12 coordinates are contiguous
  // (LayoutRight [nu_ext][nv_ext][3]), rows stride(0) apart. The rows are first combined along u,
  // 12 coordinates at a time (a loop the compiler vectorises), then along v.
  const double* P = &s.ctrl(i, j, 0);
  const std::size_t rowStride = s.ctrl.stride(0);
  double r[12], ru[12], ruu[12];  // the 4 rows combined along u: value, d/du, d2/du2
  for (int e = 0; e < 12; ++e) {
    const double q0 = P[e], q1 = P[rowStride + e], q2 = P[2 * rowStride + e], q3 = P[3 * rowStride + e];
    r[e] = bu[0] * q0 + bu[1] * q1 + bu[2] * q2 + bu[3] * q3;
    ru[e] = dbu[0] * q0 + dbu[1] * q1 + dbu[2] * q2 + dbu[3] * q3;
    ruu[e] = ddbu[0] * q0 + ddbu[1] * q1 + ddbu[2] * q2 + ddbu[3] * q3;
  }
  for (int c = 0; c < 3; ++c) {
    S[c] = bv[0] * r[c] + bv[1] * r[3 + c] + bv[2] * r[6 + c] + bv[3] * r[9 + c];
    Sv[c] = dbv[0] * r[c] + dbv[1] * r[3 + c] + dbv[2] * r[6 + c] + dbv[3] * r[9 + c];
    Svv[c] = ddbv[0] * r[c] + ddbv[1] * r[3 + c] + ddbv[2] * r[6 + c] + ddbv[3] * r[9 + c];
    Su[c] = bv[0] * ru[c] + bv[1] * ru[3 + c] + bv[2] * ru[6 + c] + bv[3] * ru[9 + c];
    Suv[c] = dbv[0] * ru[c] + dbv[1] * ru[3 + c] + dbv[2] * ru[6 + c] + dbv[3] * ru[9 + c];
    Suu[c] = bv[0] * ruu[c] + bv[1] * ruu[3 + c] + bv[2] * ruu[6 + c] + bv[3] * ruu[9 + c];
  }
}

/// Surface point only (cheaper than evaluate()).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void evaluatePoint(const BasicSurfaceView<MemorySpace>& s, double u, double v, double S[3]) {
  int i, j;
  double t, w, bu[4], bv[4], d1[4], d2[4];
  surface_detail::locate(u, s.nu, s.periodicU, i, t);
  surface_detail::locate(v, s.nv, s.periodicV, j, w);
  surface_detail::cubicBasis(t, bu, d1, d2);
  surface_detail::cubicBasis(w, bv, d1, d2);
  S[0] = S[1] = S[2] = 0.0;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 3; ++c) S[c] += bu[a] * bv[b] * s.ctrl(i + a, j + b, c);
}

/// Unit normal orientation * (Su x Sv) / |Su x Sv|; zero vector on a degenerate point.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void unitNormal(const BasicSurfaceView<MemorySpace>& s, const double Su[3], const double Sv[3],
                                       double n[3]) {
  n[0] = Su[1] * Sv[2] - Su[2] * Sv[1];
  n[1] = Su[2] * Sv[0] - Su[0] * Sv[2];
  n[2] = Su[0] * Sv[1] - Su[1] * Sv[0];
  const double len = ::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double f = len > 0.0 ? double(s.orientation) / len : 0.0;
  for (int c = 0; c < 3; ++c) n[c] *= f;
}

/// How the closure of one direction is decided.
enum class Closure {
  Detect,   ///< closed when the last row of nodes repeats the first (within 1e-9 x grid size)
  Open,     ///< always open (natural end conditions)
  Periodic  ///< always closed; a repeated closing row, if present, is dropped
};

/// How a BSplineSurface is built from its grid: the closure of each direction, the orientation and an id.
struct SurfaceOptions {
  Closure closureU = Closure::Detect;  ///< closure along u
  Closure closureV = Closure::Detect;  ///< closure along v
  int orientation = 1;                 ///< +1 or -1, see BasicSurfaceView::orientation
  int id = 0;                          ///< user id of the surface
};

/// Host-side owner of a bicubic interpolating surface (thesis 2.4).
/// Requires Kokkos to be initialised; destroy it before Kokkos::finalize().
class BSplineSurface {
public:
  /// points: nu x nv grid nodes, 3 doubles each, node (i,j) at points[3*(i*nv + j)],
  /// i along u, j along v. nu, nv >= 4.
  BSplineSurface(std::string name, int nu, int nv, const double* points, SurfaceOptions options = {});
  /// Same, from a vector of 3 nu nv doubles.
  BSplineSurface(std::string name, int nu, int nv, const std::vector<double>& points, SurfaceOptions options = {});

  /// Recomputes the control points for moved nodes (flexible surface), same layout and size as the
  /// constructor input (a repeated closing row/column is read but ignored: the first one wins).
  /// Reuses the interpolation operators B_u, B_v (eq. 2.26): no factorisation. `bins`: rebuild the
  /// broad phase's bucket grid; false drops it (the views then have none, and a cold-start
  /// nearestGridPoint() takes the brute force, the same node): a surface carried by a body is
  /// updated at every step and warm-started almost always, and the grid cost more than its use.
  void update(const double* points, bool bins = true);
  /// Same, from a vector laid out as the constructor's.
  void update(const std::vector<double>& points);

  /// The surface's name (the deck's).
  const std::string& name() const { return name_; }
  /// The user id (SurfaceOptions::id).
  int id() const { return view_.id; }
  int nu() const { return view_.nu; }  ///< distinct nodes along u (closing duplicate dropped)
  /// Distinct nodes along v (closing duplicate dropped).
  int nv() const { return view_.nv; }
  int inputNu() const { return inNu_; }  ///< nodes along u as given to the constructor
  /// Nodes along v as given to the constructor.
  int inputNv() const { return inNv_; }
  /// Closed along u.
  bool periodicU() const { return view_.periodicU; }
  /// Closed along v.
  bool periodicV() const { return view_.periodicV; }
  /// Upper end of the u range (nu() - 1 open, nu() closed).
  double uMax() const { return view_.uMax(); }
  /// Upper end of the v range (nv() - 1 open, nv() closed).
  double vMax() const { return view_.vMax(); }
  /// +1 or -1: the sign of the unit normal relative to S_u x S_v.
  int orientation() const { return view_.orientation; }
  /// Sets the orientation (+1 or -1).
  void setOrientation(int orientation);

  /// Current grid node (i,j), 0 <= i < nu(), 0 <= j < nv(); S(i, j) equals it.
  std::array<double, 3> gridPoint(int i, int j) const;

  /// Views in the default execution space's memory (for kernels) and on the host.
  const SurfaceView& view() const { return view_; }
  /// A copy of the views in host memory.
  HostSurfaceView hostView() const;

  /// Dense 1-D interpolation operators (row-major): extended control points = B * passing points.
  /// B_u is nu_ext x nu (nu_ext = nu+2 open, nu+3 closed).
  const std::vector<double>& operatorU() const { return Bu_; }
  /// B_v, nv_ext x nv (row-major).
  const std::vector<double>& operatorV() const { return Bv_; }

private:
  void loadGrid(const double* points, const char* where);
  void computeControlPoints();
  void buildBins();  ///< (re)builds the broad-phase bucket grid from hostGrid_ (O(nodes))

  std::string name_;
  int inNu_ = 0, inNv_ = 0;
  int nuExt_ = 0, nvExt_ = 0;
  std::vector<double> Bu_, Bv_;
  std::vector<double> work_;  ///< computeControlPoints' B_u P
  SurfaceView view_;
  SurfaceView::Points::HostMirror hostCtrl_, hostGrid_;
  SurfaceView::Indices binStart_, binNodes_;  // the bucket grid's storage (view_'s when it has one)
  SurfaceView::Indices::HostMirror hostBinStart_, hostBinNodes_;
};

}  // namespace epaphe
