#pragma once
// Closest point of a bicubic B-spline surface to a node (thesis Leclere 2018, section 2.5.1):
// Newton-Raphson on f(u,v) = |S(u,v) - x|^2 / 2 in the global parameters, so the foot point moves
// from patch to patch by itself (clamped in open directions, wrapped in closed ones).
#include <Kokkos_Core.hpp>
#include <cmath>

#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_Error.hpp"

namespace epaphe {

/// The closest point of a point on a surface: the foot point, the normal, the gap and how Newton did.
struct Projection {
  ///@{
  double u, v;  ///< global parameters of the foot point
  ///@}
  double point[3];   ///< foot point S(u,v)
  double normal[3];  ///< unit normal at the foot point (orientation applied)
  double gap;        ///< (x - S) . normal; negative = penetration
  int iterations;    ///< Newton iterations performed
  bool converged;    ///< parameter step < tol, or zero (projected) gradient
  bool outside;      ///< foot point on the edge of an open direction with x beyond that edge
  double beyond;     ///< how far beyond that edge, in parameter units (patches; 0: not beyond)
};

namespace surface_detail {

KOKKOS_INLINE_FUNCTION double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// One Newton iterate: parameters, surface point and derivatives, d = S - x, f = |d|^2 / 2.
struct FootState {
  double u, v, S[3], Su[3], Sv[3], Suu[3], Suv[3], Svv[3], d[3], f;
};

template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void evalFoot(const BasicSurfaceView<MemorySpace>& s, const double x[3], double u, double v,
                                     FootState& st) {
  st.u = u;
  st.v = v;
  evaluate(s, u, v, st.S, st.Su, st.Sv, st.Suu, st.Suv, st.Svv);
  for (int c = 0; c < 3; ++c) st.d[c] = st.S[c] - x[c];
  st.f = 0.5 * dot3(st.d, st.d);
}

}  // namespace surface_detail

/// Initial guess by brute force: parameters (i, j) of the nearest grid node, the lowest i*nv + j
/// among equally near nodes. *evaluations (if given) receives the number of node distances
/// computed (nu*nv). Reference for nearestGridPoint().
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void nearestGridPointBruteForce(const BasicSurfaceView<MemorySpace>& s, const double x[3],
                                                       double& u, double& v, int* evaluations = nullptr) {
  double best = -1.0;
  u = v = 0.0;
  for (int i = 0; i < s.nu; ++i)
    for (int j = 0; j < s.nv; ++j) {
      const double dx = s.grid(i, j, 0) - x[0], dy = s.grid(i, j, 1) - x[1], dz = s.grid(i, j, 2) - x[2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (best < 0.0 || d2 < best) {
        best = d2;
        u = double(i);
        v = double(j);
      }
    }
  if (evaluations) *evaluations = s.nu * s.nv;
}

namespace surface_detail {

/// Broad phase: tests the nodes of one bucket cell against the best node so far (ties: lowest
/// node index, as the brute force).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void visitBin(const BasicSurfaceView<MemorySpace>& s, const double x[3], int cell, double& best,
                                     int& bestK, int& count) {
  const int end = s.binStart(cell + 1);
  for (int e = s.binStart(cell); e < end; ++e) {
    const int k = s.binNodes(e), i = k / s.nv, j = k - i * s.nv;
    const double dx = s.grid(i, j, 0) - x[0], dy = s.grid(i, j, 1) - x[1], dz = s.grid(i, j, 2) - x[2];
    const double d2 = dx * dx + dy * dy + dz * dz;
    ++count;
    if (bestK < 0 || d2 < best || (d2 == best && k < bestK)) {
      best = d2;
      bestK = k;
    }
  }
}

}  // namespace surface_detail

/// Initial guess: parameters (i, j) of the nearest grid node, the lowest i*nv + j among equally
/// near nodes: the same node as nearestGridPointBruteForce(), found with the bucket grid of the
/// surface (broad phase). The search starts in the cell of x (clamped to the grid of cells) and
/// visits shells of cells at Chebyshev cell distance r = 0, 1, 2, ... until the nearest node found
/// is strictly nearer than any node of an unvisited cell (lower bound: distance from x to the parts
/// of the node box beyond the faces of the visited block of cells). Falls back to the brute force
/// when the view has no bucket grid or x is not finite (or huge). *evaluations (if given) receives
/// the number of node distances computed.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void nearestGridPoint(const BasicSurfaceView<MemorySpace>& s, const double x[3], double& u,
                                             double& v, int* evaluations = nullptr) {
  double xmax = 0.0;
  for (int a = 0; a < 3; ++a) xmax = ::fabs(x[a]) > xmax ? ::fabs(x[a]) : xmax;
  if (s.binStart.extent(0) == 0 || !(xmax <= 1e150)) {
    nearestGridPointBruteForce(s, x, u, v, evaluations);
    return;
  }
  const int* dims = s.binDims;
  int c[3];
  double out2[3];  // squared distance from x to the node box along each axis
  int rmax = 0;
  for (int a = 0; a < 3; ++a) {
    c[a] = surface_detail::binCoord(s, x[a], a);
    const double o =
        x[a] < s.binOrigin[a] ? s.binOrigin[a] - x[a] : (x[a] > s.binUpper[a] ? x[a] - s.binUpper[a] : 0.0);
    out2[a] = o * o;
    const int reach = c[a] > dims[a] - 1 - c[a] ? c[a] : dims[a] - 1 - c[a];
    rmax = reach > rmax ? reach : rmax;
  }
  const double slack = s.binSlack + 1e-12 * xmax;
  double best = 0.0;
  int bestK = -1, count = 0;
  for (int r = 0; r <= rmax; ++r) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = c[a] - r > 0 ? c[a] - r : 0;
      hi[a] = c[a] + r < dims[a] - 1 ? c[a] + r : dims[a] - 1;
    }
    // Cells of the shell: Chebyshev distance exactly r from c.
    for (int a0 = lo[0]; a0 <= hi[0]; ++a0) {
      const bool face0 = a0 == c[0] - r || a0 == c[0] + r;
      for (int a1 = lo[1]; a1 <= hi[1]; ++a1) {
        const int base = (a0 * dims[1] + a1) * dims[2];
        if (face0 || a1 == c[1] - r || a1 == c[1] + r) {
          for (int a2 = lo[2]; a2 <= hi[2]; ++a2) surface_detail::visitBin(s, x, base + a2, best, bestK, count);
        } else {
          if (c[2] - r >= 0) surface_detail::visitBin(s, x, base + c[2] - r, best, bestK, count);
          if (c[2] + r < dims[2]) surface_detail::visitBin(s, x, base + c[2] + r, best, bestK, count);
        }
      }
    }
    if (bestK < 0) continue;
    // Lower bound of the distance to the nodes of the unvisited cells: they lie beyond one face
    // of the visited block [lo, hi], inside the node box.
    double bound2 = -1.0;
    for (int a = 0; a < 3; ++a) {
      const double side2 = out2[(a + 1) % 3] + out2[(a + 2) % 3];
      for (int side = 0; side < 2; ++side) {
        double gap;
        if (side == 0) {
          if (lo[a] == 0) continue;
          gap = x[a] - (s.binOrigin[a] + double(lo[a]) * s.binSize);
        } else {
          if (hi[a] == dims[a] - 1) continue;
          gap = s.binOrigin[a] + double(hi[a] + 1) * s.binSize - x[a];
        }
        gap = gap > 0.0 ? gap : 0.0;
        const double b2 = gap * gap + side2;
        if (bound2 < 0.0 || b2 < bound2) bound2 = b2;
      }
    }
    if (bound2 < 0.0) break;  // every cell visited
    const double bound = ::sqrt(bound2) * (1.0 - 1e-12) - slack;
    if (bound > 0.0 && best < bound * bound) break;
  }
  if (evaluations) *evaluations = count;
  u = double(bestK / s.nv);
  v = double(bestK % s.nv);
}

namespace surface_detail {

/// One Newton iteration's direction from the iterate `cur` (section 2.5.1), shared by closestPoint()
/// and closestPoints():
///  - gradient g = ((S-x).S_u, (S-x).S_v), Hessian H = [S_u.S_u + (S-x).S_uu, ...];
///  - H not positive definite: Gauss-Newton (second-derivative terms dropped);
///  - open directions are box constraints [0, n-1]: a bound whose gradient pushes outwards is held
///    fixed (1-D Newton in the other parameter);
///  - the step is capped at one patch; (un1, vn1) is the full step's point in the domain and step1
///    the squared length of the step actually taken to it (clamped in open directions): lengths are
///    only compared with tol, squares with tol^2 need no square root on the iteration's critical path.
struct NewtonDirection {
  double du, dv;     ///< the step (at most one patch along each parameter)
  double big;        ///< max(|du|, |dv|)
  double un1, vn1;   ///< cur + (du, dv) in the domain
  double step1;      ///< squared length of the step from cur to (un1, vn1)
  bool gaussNewton;  ///< H was not positive definite
  bool stationary;   ///< |projected gradient| <= 1e-14 |S_u| |S_v|: converged, no step
};

template <class MemorySpace>
KOKKOS_INLINE_FUNCTION NewtonDirection newtonDirection(const BasicSurfaceView<MemorySpace>& s, const FootState& cur) {
  const bool openU = !s.periodicU, openV = !s.periodicV;
  NewtonDirection r;
  const double gu = dot3(cur.d, cur.Su), gv = dot3(cur.d, cur.Sv);
  const double a = dot3(cur.Su, cur.Su), b = dot3(cur.Su, cur.Sv), c = dot3(cur.Sv, cur.Sv);
  double Huu = a + dot3(cur.d, cur.Suu), Huv = b + dot3(cur.d, cur.Suv), Hvv = c + dot3(cur.d, cur.Svv);
  r.gaussNewton = !(Huu > 0.0 && Hvv > 0.0 && Huu * Hvv - Huv * Huv > 1e-12 * Huu * Hvv);
  if (r.gaussNewton) {  // drop the second-derivative terms: J^T J, positive definite
    Huu = a;
    Huv = b;
    Hvv = c;
  }
  // Active bounds of the open directions (KKT: the gradient pushes out of the domain).
  const double umax = s.uMax(), vmax = s.vMax();
  const bool fixU = openU && ((cur.u <= 0.0 && gu > 0.0) || (cur.u >= umax && gu < 0.0));
  const bool fixV = openV && ((cur.v <= 0.0 && gv > 0.0) || (cur.v >= vmax && gv < 0.0));
  const double pgu = fixU ? 0.0 : gu, pgv = fixV ? 0.0 : gv;
  r.stationary = pgu * pgu + pgv * pgv <= 1e-28 * (a * c);
  double du = 0.0, dv = 0.0;
  if (fixU) {
    dv = -gv / (Hvv > 0.0 ? Hvv : c + 1e-300);
  } else if (fixV) {
    du = -gu / (Huu > 0.0 ? Huu : a + 1e-300);
  } else {
    const double det = Huu * Hvv - Huv * Huv;
    if (det > 1e-14 * Huu * Hvv) {
      du = -(Hvv * gu - Huv * gv) / det;
      dv = -(Huu * gv - Huv * gu) / det;
    } else {  // degenerate metric (S_u // S_v): steepest descent
      const double m = a + c + 1e-300;
      du = -gu / m;
      dv = -gv / m;
    }
  }
  double big = ::fabs(du) > ::fabs(dv) ? ::fabs(du) : ::fabs(dv);
  if (big > 1.0) {  // at most one patch per iteration
    du /= big;
    dv /= big;
    big = 1.0;
  }
  r.du = du;
  r.dv = dv;
  r.big = big;
  r.un1 = toDomain(cur.u + du, s.nu, s.periodicU);
  r.vn1 = toDomain(cur.v + dv, s.nv, s.periodicV);
  const double su = openU ? r.un1 - cur.u : du, sv = openV ? r.vn1 - cur.v : dv;
  r.step1 = su * su + sv * sv;
  return r;
}

/// The last step, shorter than tol, taken by Taylor's formula instead of a new evaluation. The point,
/// tangents and gap it gives differ from an evaluation at the new parameters by O(step^2) x the
/// surface's second and third derivatives (1e-12 of a patch at tol = 1e-6), and a warm-started
/// projection usually ends here after one or two iterations: it saves one of its two or three
/// evaluations.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void taylorStep(const BasicSurfaceView<MemorySpace>& s, const double x[3],
                                       const NewtonDirection& r, FootState& cur) {
  const double su = !s.periodicU ? r.un1 - cur.u : r.du, sv = !s.periodicV ? r.vn1 - cur.v : r.dv;
  for (int c = 0; c < 3; ++c) {
    cur.S[c] += cur.Su[c] * su + cur.Sv[c] * sv;
    cur.Su[c] += cur.Suu[c] * su + cur.Suv[c] * sv;
    cur.Sv[c] += cur.Suv[c] * su + cur.Svv[c] * sv;
    cur.d[c] = cur.S[c] - x[c];
  }
  cur.u = r.un1;
  cur.v = r.vn1;
  cur.f = 0.5 * dot3(cur.d, cur.d);
}

/// The projection of the last iterate: foot point, normal, gap, and whether it lies beyond an open
/// edge (on the bound, and the unconstrained Gauss-Newton step would leave the domain by more than tol).
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION Projection footProjection(const BasicSurfaceView<MemorySpace>& s, const FootState& cur,
                                                 double tol, int iterations, bool converged) {
  const bool openU = !s.periodicU, openV = !s.periodicV;
  const double umax = s.uMax(), vmax = s.vMax();
  Projection p;
  p.iterations = iterations;
  p.converged = converged;
  p.u = cur.u;
  p.v = cur.v;
  unitNormal(s, cur.Su, cur.Sv, p.normal);
  for (int k = 0; k < 3; ++k) p.point[k] = cur.S[k];
  p.gap = -dot3(cur.d, p.normal);  // (x - S) . n
  const double gu = dot3(cur.d, cur.Su), gv = dot3(cur.d, cur.Sv);
  const double a = dot3(cur.Su, cur.Su), c = dot3(cur.Sv, cur.Sv);
  const double bu = !openU ? 0.0 : (cur.u <= 0.0 && gu > 0.0 ? gu / a : (cur.u >= umax && gu < 0.0 ? -gu / a : 0.0));
  const double bv = !openV ? 0.0 : (cur.v <= 0.0 && gv > 0.0 ? gv / c : (cur.v >= vmax && gv < 0.0 ? -gv / c : 0.0));
  p.beyond = bu > bv ? bu : bv;
  p.outside = p.beyond > tol;
  return p;
}

}  // namespace surface_detail

/// Newton-Raphson closest point (eq. of section 2.5.1), warm-started from (u0, v0).
///  - each iteration's direction: surface_detail::newtonDirection() (Newton, or Gauss-Newton where
///    H is not positive definite; active bounds of open directions held; at most one patch);
///  - H not positive definite: the Gauss-Newton step is lengthened by doubling while f decreases
///    (flat or concave model far from the surface);
///  - steps are halved (at most 30 times) until f does not increase;
///  - converged when the parameter step norm < tol (thesis crit_NR; the last such step by Taylor's
///    formula) or the projected gradient is ~0 relative to |S_u||S_v|.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION Projection closestPoint(const BasicSurfaceView<MemorySpace>& s, const double x[3], double u0,
                                               double v0, double tol, int maxIter) {
  using surface_detail::dot3;
  using surface_detail::evalFoot;
  using surface_detail::toDomain;
  const bool openU = !s.periodicU, openV = !s.periodicV;
  surface_detail::FootState cur, trial;
  evalFoot(s, x, toDomain(u0, s.nu, s.periodicU), toDomain(v0, s.nv, s.periodicV), cur);
  auto stepLength2 = [&](double un, double vn, double du, double dv) {
    const double su = openU ? un - cur.u : du, sv = openV ? vn - cur.v : dv;
    return su * su + sv * sv;
  };
  const double tol2 = tol * tol;
  int iterations = 0;
  bool converged = false;
  for (int it = 0; it < maxIter; ++it) {
    iterations = it + 1;
    const surface_detail::NewtonDirection r = surface_detail::newtonDirection(s, cur);
    if (r.stationary) {
      converged = true;
      break;
    }
    if (r.step1 < tol2) {
      surface_detail::taylorStep(s, x, r, cur);
      converged = true;
      break;
    }
    // Line search: halve (at most 30 times) until f does not increase, with a slack for round-off
    // (made only when f did increase: f <= f_cur implies f <= f_cur + slack).
    double slack = -1.0;
    double alpha = 1.0, stepNorm = 0.0;  // (squared)
    bool accepted = false;
    for (int ls = 0; ls <= 30; ++ls) {
      const double un = ls == 0 ? r.un1 : toDomain(cur.u + alpha * r.du, s.nu, s.periodicU);
      const double vn = ls == 0 ? r.vn1 : toDomain(cur.v + alpha * r.dv, s.nv, s.periodicV);
      stepNorm = ls == 0 ? r.step1 : stepLength2(un, vn, alpha * r.du, alpha * r.dv);
      evalFoot(s, x, un, vn, trial);
      bool decrease = trial.f <= cur.f;
      if (!decrease) {
        if (slack < 0.0)
          slack = 8.0 * 2.2e-16 * (cur.f + ::sqrt(2.0 * cur.f) * (::sqrt(dot3(x, x)) + ::sqrt(dot3(cur.S, cur.S))));
        decrease = trial.f <= cur.f + slack;
      }
      if (decrease) {  // (a first step shorter than tol took Taylor's formula above)
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    if (!accepted) break;  // no decrease along a descent direction: stuck, not converged
    // Gauss-Newton on a flat or concave model (node beyond the centres of curvature): the step is
    // too short; extrapolate by doubling while f keeps decreasing, up to one patch.
    if (r.gaussNewton && alpha == 1.0 && stepNorm >= tol2) {
      surface_detail::FootState ext;
      for (double beta = 2.0; beta * r.big <= 1.0; beta *= 2.0) {
        const double un = toDomain(cur.u + beta * r.du, s.nu, s.periodicU);
        const double vn = toDomain(cur.v + beta * r.dv, s.nv, s.periodicV);
        evalFoot(s, x, un, vn, ext);
        if (!(ext.f < trial.f)) break;
        trial = ext;
        stepNorm = stepLength2(un, vn, beta * r.du, beta * r.dv);
      }
    }
    cur = trial;
    if (stepNorm < tol2) {
      converged = true;
      break;
    }
  }
  return surface_detail::footProjection(s, cur, tol, iterations, converged);
}

/// Lanes of closestPoints(): how many projections it interleaves.
constexpr int kProjectionLanes = 4;

/// closestPoint() of n <= kProjectionLanes nodes at once, their Newton iterations interleaved: a
/// warm-started projection is a chain of dependent operations (evaluate, direction, division, the
/// next evaluation's patch), and one node's chain leaves most of the core idle; the lanes' chains
/// are independent, and evaluated one after the other they overlap in the core. Each lane follows
/// closestPoint()'s path while it is the common one (full Newton steps accepted without a line
/// search, ended by Taylor's formula or a stationary point); a lane that would take another path (a
/// step that does not decrease f, a Gauss-Newton extrapolation, no convergence within maxIter) is
/// projected again by closestPoint() itself. A lane's result therefore depends on its own node
/// alone, never on the other lanes (the same bits wherever a node falls in a batch, on any number
/// of threads), and is closestPoint()'s.
template <class MemorySpace>
KOKKOS_INLINE_FUNCTION void closestPoints(const BasicSurfaceView<MemorySpace>& s, int n, const double (*x)[3],
                                          const double* u0, const double* v0, double tol, int maxIter,
                                          Projection* out) {
  using surface_detail::evalFoot;
  using surface_detail::toDomain;
  constexpr int W = kProjectionLanes;
  enum : int { kIterating, kDone, kAlone };
  surface_detail::FootState cur[W], trial[W];
  surface_detail::NewtonDirection dir[W];
  int lane[W], iterations[W];
  const double tol2 = tol * tol;
  for (int l = 0; l < W; ++l) {
    lane[l] = l < n ? kIterating : kDone;
    iterations[l] = 0;
  }
  for (int l = 0; l < n; ++l)
    evalFoot(s, x[l], toDomain(u0[l], s.nu, s.periodicU), toDomain(v0[l], s.nv, s.periodicV), cur[l]);
  for (int it = 0; it < maxIter; ++it) {
    bool trials = false;
    for (int l = 0; l < n; ++l) {
      if (lane[l] != kIterating) continue;
      iterations[l] = it + 1;
      dir[l] = surface_detail::newtonDirection(s, cur[l]);
      if (dir[l].stationary) {
        lane[l] = kDone;
      } else if (dir[l].step1 < tol2) {
        surface_detail::taylorStep(s, x[l], dir[l], cur[l]);
        lane[l] = kDone;
      } else if (dir[l].gaussNewton) {
        lane[l] = kAlone;  // closestPoint() extrapolates its step
      } else {
        trials = true;
      }
    }
    if (!trials) break;
    for (int l = 0; l < n; ++l)
      if (lane[l] == kIterating) evalFoot(s, x[l], dir[l].un1, dir[l].vn1, trial[l]);
    for (int l = 0; l < n; ++l) {
      if (lane[l] != kIterating) continue;
      if (trial[l].f <= cur[l].f)  // accepted at the full step, which is at least tol long
        cur[l] = trial[l];
      else
        lane[l] = kAlone;  // closestPoint()'s line search
    }
  }
  for (int l = 0; l < n; ++l) {
    if (lane[l] == kDone)
      out[l] = surface_detail::footProjection(s, cur[l], tol, iterations[l], true);
    else
      out[l] = closestPoint(s, x[l], u0[l], v0[l], tol, maxIter);  // another path, or maxIter reached
  }
}

/// Projects every node x(k) on the surface in one named kernel on the default execution space.
/// uv(k) is the warm start on input (NaN = cold start from nearestGridPoint) and the foot point
/// parameters on output. Asynchronous like any Kokkos kernel: fence before reading on the host.
inline void projectNodes(const SurfaceView& surface, Kokkos::View<const double* [3]> x, Kokkos::View<double* [2]> uv,
                         Kokkos::View<Projection*> out, double tol, int maxIter) {
  EPAPHE_REQUIRE(uv.extent(0) == x.extent(0) && out.extent(0) == x.extent(0),
                 "surface projection: " << x.extent(0) << " nodes but " << uv.extent(0) << " warm starts and "
                                        << out.extent(0) << " results; size uv and out like x");
  EPAPHE_REQUIRE(tol > 0.0 && maxIter > 0,
                 "surface projection: tol = " << tol << ", maxIter = " << maxIter << "; both must be > 0");
  const SurfaceView s = surface;
  Kokkos::parallel_for(
      "epaphe::surface::project", Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, x.extent(0)),
      KOKKOS_LAMBDA(const int k) {
        const double xk[3] = {x(k, 0), x(k, 1), x(k, 2)};
        double u0 = uv(k, 0), v0 = uv(k, 1);
        if (!(u0 == u0) || !(v0 == v0)) nearestGridPoint(s, xk, u0, v0);
        const Projection p = closestPoint(s, xk, u0, v0, tol, maxIter);
        uv(k, 0) = p.u;
        uv(k, 1) = p.v;
        out(k) = p;
      });
}

}  // namespace epaphe
