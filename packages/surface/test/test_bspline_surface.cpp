// Unit tests of the surface package: bicubic interpolating B-spline (thesis 2.4) and the
// Newton-Raphson closest point (thesis 2.5.1).
#include <gtest/gtest.h>

#include <Kokkos_Core.hpp>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_Error.hpp"

namespace {

using epaphe::BSplineSurface;
using epaphe::Closure;
using epaphe::HostSurfaceView;
using epaphe::Projection;
using epaphe::SurfaceOptions;
using Vec3 = std::array<double, 3>;

const double kPi = std::acos(-1.0);

std::vector<double> makeGrid(int nu, int nv, const std::function<Vec3(int, int)>& f) {
  std::vector<double> p;
  p.reserve(std::size_t(nu) * nv * 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const Vec3 x = f(i, j);
      p.insert(p.end(), x.begin(), x.end());
    }
  return p;
}

// Open curved grid: z = sin(x) cos(y), 12 x 10 nodes.
constexpr int kWaveNu = 12, kWaveNv = 10;
Vec3 waveNode(int i, int j) {
  const double x = 0.4 * i, y = 0.35 * j;
  return {x, y, std::sin(x) * std::cos(y)};
}
std::vector<double> waveGrid() {
  return makeGrid(kWaveNu, kWaveNv, waveNode);
}

// Cylinder of radius 1 around z: u = angle (N = 16 distinct nodes), v = height (6 nodes).
constexpr int kCylN = 16, kCylNv = 6;
Vec3 cylNode(int i, int j) {
  const double t = 2.0 * kPi * i / kCylN;
  return {std::cos(t), std::sin(t), 0.4 * j};
}
// withSeam: the last row repeats the first one (i = N), as a mesh that closes on itself.
std::vector<double> cylinderGrid(bool withSeam) {
  return makeGrid(withSeam ? kCylN + 1 : kCylN, kCylNv, cylNode);
}

struct Eval {
  double S[3], Su[3], Sv[3], Suu[3], Suv[3], Svv[3];
};
Eval eval(const HostSurfaceView& s, double u, double v) {
  Eval e;
  epaphe::evaluate(s, u, v, e.S, e.Su, e.Sv, e.Suu, e.Suv, e.Svv);
  return e;
}

double dist(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}
double maxDiff(const double* a, const double* b) {
  double m = 0.0;
  for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(a[c] - b[c]));
  return m;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const epaphe::Error& e) {
    return e.what();
  }
  return "<no epaphe::Error thrown>";
}

// ---- 1. interpolation -------------------------------------------------------------------------

TEST(BSplineSurface, InterpolatesEveryGridPointOpen) {
  const std::vector<double> P = waveGrid();
  BSplineSurface s("wave", kWaveNu, kWaveNv, P);
  EXPECT_EQ(s.nu(), kWaveNu);
  EXPECT_EQ(s.nv(), kWaveNv);
  EXPECT_DOUBLE_EQ(s.uMax(), kWaveNu - 1);
  const HostSurfaceView h = s.hostView();
  for (int i = 0; i < kWaveNu; ++i)
    for (int j = 0; j < kWaveNv; ++j) {
      double S[3];
      epaphe::evaluatePoint(h, i, j, S);
      EXPECT_LT(maxDiff(S, &P[3 * (i * kWaveNv + j)]), 1e-12) << "node (" << i << "," << j << ")";
      const Vec3 g = s.gridPoint(i, j);
      EXPECT_EQ(g[2], P[3 * (i * kWaveNv + j) + 2]);
    }
}

TEST(BSplineSurface, InterpolatesEveryGridPointClosedCylinder) {
  const std::vector<double> P = cylinderGrid(true);
  BSplineSurface s("cylinder", kCylN + 1, kCylNv, P);
  ASSERT_TRUE(s.periodicU());
  const HostSurfaceView h = s.hostView();
  for (int i = 0; i <= kCylN; ++i)  // i = N is the seam: u wraps to 0
    for (int j = 0; j < kCylNv; ++j) {
      const Eval e = eval(h, i, j);
      EXPECT_LT(maxDiff(e.S, &P[3 * (i * kCylNv + j)]), 1e-12) << "node (" << i << "," << j << ")";
    }
  // Between nodes the spline stays close to the unit cylinder (16 nodes per turn).
  for (double u = 0.25; u < kCylN; u += 0.5) {
    const Eval e = eval(h, u, 2.5);
    EXPECT_NEAR(std::hypot(e.S[0], e.S[1]), 1.0, 2e-3);
  }
}

// ---- 2. planar grids -------------------------------------------------------------------------

TEST(BSplineSurface, AffineGridReproducesThePlaneExactly) {
  const Vec3 o{0.3, -1.2, 2.0}, a{0.5, 0.1, -0.2}, b{-0.1, 0.4, 0.3};
  const int nu = 7, nv = 5;
  const auto P = makeGrid(nu, nv, [&](int i, int j) {
    return Vec3{o[0] + a[0] * i + b[0] * j, o[1] + a[1] * i + b[1] * j, o[2] + a[2] * i + b[2] * j};
  });
  BSplineSurface s("plane", nu, nv, P);
  const HostSurfaceView h = s.hostView();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0.0, nu - 1), V(0.0, nv - 1);
  for (int k = 0; k < 200; ++k) {
    const double u = U(rng), v = V(rng);
    const Eval e = eval(h, u, v);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(e.S[c], o[c] + a[c] * u + b[c] * v, 1e-12);
      EXPECT_NEAR(e.Su[c], a[c], 1e-12);
      EXPECT_NEAR(e.Sv[c], b[c], 1e-12);
      EXPECT_NEAR(e.Suu[c], 0.0, 1e-12);
      EXPECT_NEAR(e.Suv[c], 0.0, 1e-12);
      EXPECT_NEAR(e.Svv[c], 0.0, 1e-12);
    }
  }
}

TEST(BSplineSurface, IrregularPlanarGridStaysInThePlane) {
  // Unevenly spaced nodes in the plane z = 0.5 x - 0.25 y + 1: every control point is an affine
  // combination of the nodes, so the whole surface lies in the plane.
  const int nu = 8, nv = 6;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  std::vector<double> xs(nu), ys(nv);
  for (int i = 0; i < nu; ++i) xs[i] = i + jitter(rng);
  for (int j = 0; j < nv; ++j) ys[j] = 0.8 * j + jitter(rng);
  const auto P = makeGrid(nu, nv, [&](int i, int j) {
    return Vec3{xs[i], ys[j] + 0.1 * xs[i], 0.5 * xs[i] - 0.25 * (ys[j] + 0.1 * xs[i]) + 1.0};
  });
  BSplineSurface s("tilted", nu, nv, P);
  const HostSurfaceView h = s.hostView();
  const double n[3] = {0.5, -0.25, -1.0};
  const double len = std::sqrt(0.25 + 0.0625 + 1.0);
  for (double u = 0.0; u <= nu - 1; u += 0.37)
    for (double v = 0.0; v <= nv - 1; v += 0.29) {
      const Eval e = eval(h, u, v);
      EXPECT_NEAR((n[0] * e.S[0] + n[1] * e.S[1] + n[2] * e.S[2] + 1.0) / len, 0.0, 1e-12);
      double nn[3];
      epaphe::unitNormal(h, e.Su, e.Sv, nn);
      EXPECT_NEAR(std::fabs(n[0] * nn[0] + n[1] * nn[1] + n[2] * nn[2]) / len, 1.0, 1e-12);
    }
}

// ---- 3. derivatives and C2 continuity ----------------------------------------------------------

TEST(BSplineSurface, DerivativesMatchFiniteDifferences) {
  BSplineSurface s("wave", kWaveNu, kWaveNv, waveGrid());
  const HostSurfaceView h = s.hostView();
  const double d = 1e-5;
  // Sample points away from the knots (the third derivative jumps there).
  for (double u = 0.33; u < kWaveNu - 1; u += 1.71)
    for (double v = 0.21; v < kWaveNv - 1; v += 1.33) {
      const Eval e = eval(h, u, v), pu = eval(h, u + d, v), mu = eval(h, u - d, v), pv = eval(h, u, v + d),
                 mv = eval(h, u, v - d);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(e.Su[c], (pu.S[c] - mu.S[c]) / (2 * d), 1e-8);
        EXPECT_NEAR(e.Sv[c], (pv.S[c] - mv.S[c]) / (2 * d), 1e-8);
        EXPECT_NEAR(e.Suu[c], (pu.Su[c] - mu.Su[c]) / (2 * d), 1e-8);
        EXPECT_NEAR(e.Suv[c], (pv.Su[c] - mv.Su[c]) / (2 * d), 1e-8);
        EXPECT_NEAR(e.Svv[c], (pv.Sv[c] - mv.Sv[c]) / (2 * d), 1e-8);
      }
    }
}

void expectC2(const HostSurfaceView& h, double u1, double v1, double u2, double v2, const std::string& where) {
  const Eval a = eval(h, u1, v1), b = eval(h, u2, v2);
  EXPECT_LT(maxDiff(a.S, b.S), 1e-8) << where;
  EXPECT_LT(maxDiff(a.Su, b.Su), 1e-7) << where;
  EXPECT_LT(maxDiff(a.Sv, b.Sv), 1e-7) << where;
  EXPECT_LT(maxDiff(a.Suu, b.Suu), 1e-7) << where;
  EXPECT_LT(maxDiff(a.Suv, b.Suv), 1e-7) << where;
  EXPECT_LT(maxDiff(a.Svv, b.Svv), 1e-7) << where;
}

TEST(BSplineSurface, C2AcrossInteriorKnots) {
  BSplineSurface s("wave", kWaveNu, kWaveNv, waveGrid());
  const HostSurfaceView h = s.hostView();
  const double e = 1e-9;
  for (int k = 1; k < kWaveNu - 1; ++k)
    for (double v : {0.0, 0.5, 3.3, 9.0})
      expectC2(h, k - e, v, k + e, v, "u knot " + std::to_string(k) + " v " + std::to_string(v));
  for (int k = 1; k < kWaveNv - 1; ++k)
    for (double u : {0.0, 2.7, 11.0})
      expectC2(h, u, k - e, u, k + e, "v knot " + std::to_string(k) + " u " + std::to_string(u));
}

TEST(BSplineSurface, C2AcrossTheSeamOfAClosedSurface) {
  BSplineSurface s("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  const HostSurfaceView h = s.hostView();
  const double e = 1e-9;
  for (double v : {0.0, 1.5, 2.0, 5.0}) {
    expectC2(h, kCylN - e, v, e, v, "seam, v " + std::to_string(v));
    expectC2(h, kCylN - e, v, 0.0, v, "seam at 0, v " + std::to_string(v));
    expectC2(h, -e, v, e, v, "seam from below, v " + std::to_string(v));
  }
  for (int k = 1; k < kCylN; ++k) expectC2(h, k - e, 1.7, k + e, 1.7, "u knot " + std::to_string(k));
  // Wrapping: u and u + N are the same point.
  const Eval a = eval(h, 3.25, 2.5), b = eval(h, 3.25 + kCylN, 2.5), c = eval(h, 3.25 - kCylN, 2.5);
  EXPECT_LT(maxDiff(a.S, b.S), 1e-12);
  EXPECT_LT(maxDiff(a.S, c.S), 1e-12);
}

// ---- 4. closed-ness --------------------------------------------------------------------------

TEST(BSplineSurface, DetectsClosedDirections) {
  BSplineSurface cyl("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  EXPECT_TRUE(cyl.periodicU());
  EXPECT_FALSE(cyl.periodicV());
  EXPECT_EQ(cyl.nu(), kCylN);  // duplicate row dropped
  EXPECT_EQ(cyl.inputNu(), kCylN + 1);
  EXPECT_DOUBLE_EQ(cyl.uMax(), kCylN);
  EXPECT_EQ(cyl.operatorU().size(), std::size_t(kCylN + 3) * kCylN);

  BSplineSurface wave("wave", kWaveNu, kWaveNv, waveGrid());
  EXPECT_FALSE(wave.periodicU());
  EXPECT_FALSE(wave.periodicV());
  EXPECT_EQ(wave.operatorU().size(), std::size_t(kWaveNu + 2) * kWaveNu);

  // Torus: closed in both directions.
  const int nu = 13, nv = 9;
  const auto T = makeGrid(nu, nv, [&](int i, int j) {
    const double a = 2 * kPi * i / (nu - 1), b = 2 * kPi * j / (nv - 1), r = 3.0 + std::cos(b);
    return Vec3{r * std::cos(a), r * std::sin(a), std::sin(b)};
  });
  BSplineSurface torus("torus", nu, nv, T);
  EXPECT_TRUE(torus.periodicU());
  EXPECT_TRUE(torus.periodicV());
  EXPECT_EQ(torus.nu(), nu - 1);
  EXPECT_EQ(torus.nv(), nv - 1);
}

TEST(BSplineSurface, ClosureCanBeForced) {
  SurfaceOptions periodic;
  periodic.closureU = Closure::Periodic;
  BSplineSurface noSeam("cylinder", kCylN, kCylNv, cylinderGrid(false), periodic);
  EXPECT_TRUE(noSeam.periodicU());
  EXPECT_EQ(noSeam.nu(), kCylN);

  // Same surface whether or not the mesh repeats its first row.
  BSplineSurface seam("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  const HostSurfaceView a = noSeam.hostView(), b = seam.hostView();
  for (double u = 0.0; u < kCylN; u += 0.61) {
    const Eval ea = eval(a, u, 1.3), eb = eval(b, u, 1.3);
    EXPECT_LT(maxDiff(ea.S, eb.S), 1e-13);
  }

  SurfaceOptions open;
  open.closureU = Closure::Open;
  BSplineSurface forcedOpen("cylinder", kCylN + 1, kCylNv, cylinderGrid(true), open);
  EXPECT_FALSE(forcedOpen.periodicU());
  EXPECT_EQ(forcedOpen.nu(), kCylN + 1);
}

// ---- flexible surfaces: update() -------------------------------------------------------------

TEST(BSplineSurface, UpdateMatchesAFreshSurface) {
  BSplineSurface s("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  // Ovalise and twist the cylinder.
  const auto moved = makeGrid(kCylN + 1, kCylNv, [](int i, int j) {
    const Vec3 p = cylNode(i, j);
    return Vec3{1.2 * p[0] + 0.05 * j, 0.9 * p[1], p[2] + 0.1 * p[0]};
  });
  s.update(moved);
  BSplineSurface fresh("cylinder", kCylN + 1, kCylNv, moved);
  ASSERT_TRUE(fresh.periodicU());
  const HostSurfaceView a = s.hostView(), b = fresh.hostView();
  for (int i = 0; i < kCylN; ++i)
    for (int j = 0; j < kCylNv; ++j) {
      double S[3];
      epaphe::evaluatePoint(a, i, j, S);
      EXPECT_LT(maxDiff(S, &moved[3 * (i * kCylNv + j)]), 1e-12);
      EXPECT_EQ(s.gridPoint(i, j)[0], moved[3 * (i * kCylNv + j)]);
    }
  for (double u = 0.1; u < kCylN; u += 0.7)
    for (double v = 0.0; v <= kCylNv - 1; v += 0.45) {
      const Eval ea = eval(a, u, v), eb = eval(b, u, v);
      EXPECT_LT(maxDiff(ea.S, eb.S), 1e-13);
      EXPECT_LT(maxDiff(ea.Suv, eb.Suv), 1e-12);
    }
}

// ---- 5. closest point ------------------------------------------------------------------------

// Brute force: dense sampling of the parameter domain, then compass search around the best sample.
double bruteForceDistance(const HostSurfaceView& h, const double x[3], int samples = 400) {
  const double umax = h.uMax(), vmax = h.vMax();
  auto f = [&](double u, double v) {
    u = epaphe::surface_detail::toDomain(u, h.nu, h.periodicU);
    v = epaphe::surface_detail::toDomain(v, h.nv, h.periodicV);
    double S[3];
    epaphe::evaluatePoint(h, u, v, S);
    return dist(S, x);
  };
  double bu = 0, bv = 0, best = std::numeric_limits<double>::max();
  for (int a = 0; a < samples; ++a)
    for (int b = 0; b < samples; ++b) {
      const double u = umax * a / (h.periodicU ? samples : samples - 1);
      const double v = vmax * b / (h.periodicV ? samples : samples - 1);
      const double d = f(u, v);
      if (d < best) {
        best = d;
        bu = u;
        bv = v;
      }
    }
  for (double step = umax / samples; step > 1e-12;) {
    bool moved = false;
    for (int du = -1; du <= 1; ++du)
      for (int dv = -1; dv <= 1; ++dv) {
        const double u = epaphe::surface_detail::toDomain(bu + du * step, h.nu, h.periodicU);
        const double v = epaphe::surface_detail::toDomain(bv + dv * step, h.nv, h.periodicV);
        const double d = f(u, v);
        if (d < best) {
          best = d;
          bu = u;
          bv = v;
          moved = true;
        }
      }
    if (!moved) step *= 0.5;
  }
  return best;
}

// Random nodes x = S(u,v) + r n(u,v), 0.05 <= |r| <= 0.3, away from open edges.
struct Probe {
  double x[3];
  double r;
};
std::vector<Probe> probesNear(const HostSurfaceView& h, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(h.periodicU ? 0.0 : 1.0, h.periodicU ? h.uMax() : h.uMax() - 1.0);
  std::uniform_real_distribution<double> V(h.periodicV ? 0.0 : 1.0, h.periodicV ? h.vMax() : h.vMax() - 1.0);
  std::uniform_real_distribution<double> R(0.05, 0.3);
  std::bernoulli_distribution side(0.5);
  std::vector<Probe> probes;
  for (int k = 0; k < count; ++k) {
    const Eval e = eval(h, U(rng), V(rng));
    double n[3];
    epaphe::unitNormal(h, e.Su, e.Sv, n);
    Probe p;
    p.r = side(rng) ? R(rng) : -R(rng);
    for (int c = 0; c < 3; ++c) p.x[c] = e.S[c] + p.r * n[c];
    probes.push_back(p);
  }
  return probes;
}

void checkAgainstBruteForce(const BSplineSurface& s, unsigned seed) {
  const HostSurfaceView h = s.hostView();
  int totalIterations = 0;
  for (const Probe& pr : probesNear(h, 25, seed)) {
    double u0, v0;
    epaphe::nearestGridPoint(h, pr.x, u0, v0);
    const Projection p = epaphe::closestPoint(h, pr.x, u0, v0, 1e-10, 50);
    ASSERT_TRUE(p.converged) << s.name();
    EXPECT_GE(p.iterations, 1);
    // Full Newton (not Gauss-Newton, whose rate here is ~|r| x curvature) from a grid node.
    EXPECT_LE(p.iterations, 8) << s.name() << " r = " << pr.r;
    totalIterations += p.iterations;
    EXPECT_FALSE(p.outside);
    const double dNewton = dist(p.point, pr.x);
    const double dBrute = bruteForceDistance(h, pr.x);
    EXPECT_NEAR(dNewton, dBrute, 1e-8 * dBrute) << s.name() << " r = " << pr.r;
    // x was built on the normal at a foot point: the gap is r itself.
    EXPECT_NEAR(p.gap, pr.r, 1e-9) << s.name();
    double S[3];
    epaphe::evaluatePoint(h, p.u, p.v, S);
    EXPECT_LT(maxDiff(S, p.point), 1e-14);
  }
  EXPECT_GT(totalIterations, 25);
}

TEST(ClosestPoint, MatchesBruteForceOnAnOpenCurvedSurface) {
  BSplineSurface s("wave", kWaveNu, kWaveNv, waveGrid());
  checkAgainstBruteForce(s, 11);
}

TEST(ClosestPoint, MatchesBruteForceOnACylinder) {
  BSplineSurface s("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  checkAgainstBruteForce(s, 12);
}

TEST(ClosestPoint, SafeguardsFarFromTheSurfaceAndNearTheAxis) {
  // Far nodes (beyond the centres of curvature: indefinite Hessian) and nodes near the axis of the
  // cylinder (almost equidistant from every foot point): the iteration must still converge to a
  // stationary point no farther than the starting grid node.
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> X(0.0, 4.4), Y(0.0, 3.15), Z(-5.0, 5.0), A(0.0, 2 * kPi), small(0.0, 0.05),
      H(0.2, 1.8);
  BSplineSurface wave("wave", kWaveNu, kWaveNv, waveGrid());
  BSplineSurface cyl("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  for (int k = 0; k < 200; ++k) {
    const bool onCylinder = k % 2 == 1;
    const HostSurfaceView h = onCylinder ? cyl.hostView() : wave.hostView();
    double x[3];
    if (onCylinder) {
      const double a = A(rng), r = small(rng);
      x[0] = r * std::cos(a);
      x[1] = r * std::sin(a);
      x[2] = H(rng);
    } else {
      x[0] = X(rng);
      x[1] = Y(rng);
      x[2] = Z(rng);
    }
    double u0, v0;
    epaphe::nearestGridPoint(h, x, u0, v0);
    const Projection p = epaphe::closestPoint(h, x, u0, v0, 1e-10, 100);
    ASSERT_TRUE(p.converged) << (onCylinder ? "cylinder" : "wave") << " node " << x[0] << " " << x[1] << " " << x[2];
    const Eval e = eval(h, p.u, p.v);
    double d[3], n0[3];
    for (int c = 0; c < 3; ++c) d[c] = x[c] - e.S[c];
    const double dn = dist(x, e.S), su = std::sqrt(e.Su[0] * e.Su[0] + e.Su[1] * e.Su[1] + e.Su[2] * e.Su[2]),
                 sv = std::sqrt(e.Sv[0] * e.Sv[0] + e.Sv[1] * e.Sv[1] + e.Sv[2] * e.Sv[2]);
    if (!p.outside) {
      EXPECT_LT(std::fabs(d[0] * e.Su[0] + d[1] * e.Su[1] + d[2] * e.Su[2]) / (dn * su), 1e-7);
      EXPECT_LT(std::fabs(d[0] * e.Sv[0] + d[1] * e.Sv[1] + d[2] * e.Sv[2]) / (dn * sv), 1e-7);
      EXPECT_NEAR(std::fabs(p.gap), dn, 1e-9 * dn);
    }
    epaphe::evaluatePoint(h, u0, v0, n0);
    EXPECT_LE(dn, dist(x, n0) * (1 + 1e-14));
  }
}

TEST(ClosestPoint, KernelColdAndWarmStarts) {
  BSplineSurface s("wave", kWaveNu, kWaveNv, waveGrid());
  const HostSurfaceView h = s.hostView();
  const std::vector<Probe> probes = probesNear(h, 64, 5);
  const int n = int(probes.size());
  Kokkos::View<double* [3]> x("x", n);
  Kokkos::View<double* [2]> uv("uv", n);
  Kokkos::View<Projection*> cold("cold", n), warm("warm", n);
  auto xh = Kokkos::create_mirror_view(x);
  auto uvh = Kokkos::create_mirror_view(uv);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) xh(k, c) = probes[k].x[c];
    uvh(k, 0) = uvh(k, 1) = nan;
  }
  Kokkos::deep_copy(x, xh);
  Kokkos::deep_copy(uv, uvh);
  epaphe::projectNodes(s.view(), x, uv, cold, 1e-10, 50);
  Kokkos::fence();
  auto coldh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cold);
  Kokkos::deep_copy(uvh, uv);
  int coldIterations = 0;
  for (int k = 0; k < n; ++k) {
    ASSERT_TRUE(coldh(k).converged);
    EXPECT_EQ(uvh(k, 0), coldh(k).u);
    EXPECT_EQ(uvh(k, 1), coldh(k).v);
    EXPECT_NEAR(coldh(k).gap, probes[k].r, 1e-9);
    // Same answer as the host function.
    double u0, v0;
    epaphe::nearestGridPoint(h, probes[k].x, u0, v0);
    const Projection p = epaphe::closestPoint(h, probes[k].x, u0, v0, 1e-10, 50);
    EXPECT_NEAR(p.u, coldh(k).u, 1e-12);
    EXPECT_NEAR(p.v, coldh(k).v, 1e-12);
    EXPECT_EQ(p.iterations, coldh(k).iterations);
    coldIterations += coldh(k).iterations;
  }

  // Next "time step": the nodes move a little; warm start from the previous foot points.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> small(-2e-3, 2e-3);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) xh(k, c) += small(rng);
  Kokkos::deep_copy(x, xh);
  Kokkos::View<double* [2]> uvCold("uvCold", n);
  Kokkos::deep_copy(uvCold, nan);
  Kokkos::View<Projection*> cold2("cold2", n);
  epaphe::projectNodes(s.view(), x, uv, warm, 1e-10, 50);
  epaphe::projectNodes(s.view(), x, uvCold, cold2, 1e-10, 50);
  Kokkos::fence();
  auto warmh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), warm);
  auto cold2h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cold2);
  int warmIterations = 0, cold2Iterations = 0;
  for (int k = 0; k < n; ++k) {
    ASSERT_TRUE(warmh(k).converged);
    EXPECT_NEAR(warmh(k).gap, cold2h(k).gap, 1e-12);
    warmIterations += warmh(k).iterations;
    cold2Iterations += cold2h(k).iterations;
  }
  EXPECT_LT(warmIterations, cold2Iterations);
  std::printf("[          ] iterations over %d nodes: cold %d, cold after motion %d, warm %d\n", n, coldIterations,
              cold2Iterations, warmIterations);
}

TEST(ClosestPoint, KernelChecksSizes) {
  BSplineSurface s("wave", kWaveNu, kWaveNv, waveGrid());
  Kokkos::View<double* [3]> x("x", 4);
  Kokkos::View<double* [2]> uv("uv", 3);
  Kokkos::View<Projection*> out("out", 4);
  const std::string m = errorOf([&] { epaphe::projectNodes(s.view(), x, uv, out, 1e-8, 20); });
  EXPECT_NE(m.find("4 nodes but 3 warm starts"), std::string::npos) << m;
}

// ---- 6. gap sign and orientation --------------------------------------------------------------

TEST(ClosestPoint, GapSignFollowsTheOrientation) {
  const auto P = makeGrid(6, 5, [](int i, int j) { return Vec3{0.5 * i, 0.5 * j, 0.0}; });
  BSplineSurface s("floor", 6, 5, P);
  const double above[3] = {1.1, 0.7, 0.2}, below[3] = {1.3, 1.2, -0.1};
  auto project = [&](const double* x) {
    const HostSurfaceView h = s.hostView();
    double u, v;
    epaphe::nearestGridPoint(h, x, u, v);
    return epaphe::closestPoint(h, x, u, v, 1e-10, 30);
  };
  Projection a = project(above), b = project(below);
  EXPECT_NEAR(a.normal[2], 1.0, 1e-14);  // (S_u x S_v) = +z
  EXPECT_NEAR(a.gap, 0.2, 1e-13);
  EXPECT_NEAR(b.gap, -0.1, 1e-13);
  EXPECT_NEAR(a.u, 2.2, 1e-12);
  EXPECT_NEAR(a.v, 1.4, 1e-12);
  EXPECT_FALSE(a.outside);

  s.setOrientation(-1);
  EXPECT_EQ(s.view().orientation, -1);
  a = project(above);
  b = project(below);
  EXPECT_NEAR(a.normal[2], -1.0, 1e-14);
  EXPECT_NEAR(a.gap, -0.2, 1e-13);
  EXPECT_NEAR(b.gap, 0.1, 1e-13);
  EXPECT_NE(errorOf([&] { s.setOrientation(0); }).find("must be +1 or -1"), std::string::npos);
}

TEST(ClosestPoint, CylinderGapIsRadialDistance) {
  BSplineSurface s("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  const HostSurfaceView h = s.hostView();
  for (double r : {0.6, 0.9, 1.1, 1.5}) {
    const double x[3] = {r * std::cos(0.3), r * std::sin(0.3), 1.1};
    double u, v;
    epaphe::nearestGridPoint(h, x, u, v);
    const Projection p = epaphe::closestPoint(h, x, u, v, 1e-10, 30);
    ASSERT_TRUE(p.converged);
    const double rs = std::hypot(p.point[0], p.point[1]);
    EXPECT_NEAR(p.gap, r - rs, 1e-4);  // outward normal: outside positive, inside negative
    EXPECT_EQ(p.gap > 0.0, r > 1.0);
    EXPECT_NEAR(rs, 1.0, 2e-3);
    EXPECT_NEAR(p.v, 1.1 / 0.4, 1e-3);
  }
  // Across the seam: a node at angle -0.05 rad starts from the node at u = 0 and ends at u ~ N.
  const double x[3] = {1.2 * std::cos(-0.05), 1.2 * std::sin(-0.05), 0.9};
  const Projection p = epaphe::closestPoint(h, x, 0.0, 2.0, 1e-10, 30);
  ASSERT_TRUE(p.converged);
  EXPECT_NEAR(p.u, kCylN - 0.05 * kCylN / (2 * kPi), 1e-2);
  EXPECT_GT(p.gap, 0.19);
}

// ---- 7. nodes beyond the edge of an open surface ----------------------------------------------

TEST(ClosestPoint, NodesBeyondAnOpenEdgeAreOutside) {
  const auto P = makeGrid(6, 5, [](int i, int j) { return Vec3{0.5 * i, 0.5 * j, 0.0}; });
  BSplineSurface s("floor", 6, 5, P);  // x in [0, 2.5], y in [0, 2]
  const HostSurfaceView h = s.hostView();
  auto project = [&](double x0, double x1, double x2) {
    const double x[3] = {x0, x1, x2};
    double u, v;
    epaphe::nearestGridPoint(h, x, u, v);
    return epaphe::closestPoint(h, x, u, v, 1e-10, 30);
  };
  const Projection beyondU0 = project(-0.3, 1.0, 0.1), beyondUmax = project(2.9, 1.0, -0.1),
                   beyondV = project(1.0, 2.4, 0.05), corner = project(-0.2, -0.2, 0.1),
                   inside = project(0.05, 1.95, 0.1);
  EXPECT_TRUE(beyondU0.outside);
  EXPECT_DOUBLE_EQ(beyondU0.u, 0.0);
  EXPECT_NEAR(beyondU0.v, 2.0, 1e-10);
  EXPECT_TRUE(beyondU0.converged);
  EXPECT_TRUE(beyondUmax.outside);
  EXPECT_DOUBLE_EQ(beyondUmax.u, 5.0);
  EXPECT_TRUE(beyondV.outside);
  EXPECT_DOUBLE_EQ(beyondV.v, 4.0);
  EXPECT_TRUE(corner.outside);
  EXPECT_FALSE(inside.outside);
  EXPECT_NEAR(inside.gap, 0.1, 1e-13);

  // Cylinder: closed around, open along its axis.
  BSplineSurface cyl("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  const HostSurfaceView c = cyl.hostView();
  const double below[3] = {1.05, 0.0, -0.5}, within[3] = {1.05, 0.0, 0.3};
  double u, v;
  epaphe::nearestGridPoint(c, below, u, v);
  EXPECT_TRUE(epaphe::closestPoint(c, below, u, v, 1e-10, 30).outside);
  epaphe::nearestGridPoint(c, within, u, v);
  EXPECT_FALSE(epaphe::closestPoint(c, within, u, v, 1e-10, 30).outside);
}

// closestPoints() interleaves kProjectionLanes projections: a node's result must not depend on the
// other lanes nor on where it falls in the batch (the same bits: the detection's result on any
// number of threads), and must be closestPoint()'s: the same iterations and outcome, the same
// numbers to round-off (the compiler may fuse a multiply and an add in one place and not in the
// other). Nodes warm-started near the surface (the lanes' common path), far ones (Gauss-Newton
// extrapolation), ones beyond an open edge (bounds held), started far from their foot (line search)
// and a maxIter too small to converge.
TEST(ClosestPoint, LanesGiveEachNodeItsOwnProjection) {
  BSplineSurface wave("wave", kWaveNu, kWaveNv, waveGrid());
  BSplineSurface cyl("cylinder", kCylN + 1, kCylNv, cylinderGrid(true));
  constexpr int W = epaphe::kProjectionLanes;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const BSplineSurface* surf : {&wave, &cyl}) {
    const HostSurfaceView h = surf->hostView();
    struct Node {
      double x[3], u0, v0;
      int maxIter;
    };
    std::vector<Node> nodes;
    int kinds[5] = {0, 0, 0, 0, 0};
    for (const Probe& pr : probesNear(h, 40, 7)) {  // near: started at a nearby foot, or far from it
      Node n{{pr.x[0], pr.x[1], pr.x[2]}, 0.0, 0.0, 30};
      epaphe::nearestGridPoint(h, n.x, n.u0, n.v0);
      const int kind = nodes.size() % 4;
      if (kind == 1) n.u0 += 0.3 * (unit(rng) - 0.5);               // a warm start's small miss
      if (kind == 2) n.u0 += 2.5 * (unit(rng) < 0.5 ? -1.0 : 1.0);  // far from the foot
      if (kind == 3) n.maxIter = 1;                                 // stopped before converging
      const Projection ref = epaphe::closestPoint(h, n.x, n.u0, n.v0, 1e-10, n.maxIter);
      ++kinds[ref.converged ? (ref.iterations > 2 ? 1 : 0) : 2];
      nodes.push_back(n);
    }
    for (int k = 0; k < 30; ++k) {  // far from the surface, and beyond its open edges
      Node n{{6.0 * unit(rng) - 1.5, 5.0 * unit(rng) - 1.0, 8.0 * unit(rng) - 4.0}, 0.0, 0.0, 30};
      epaphe::nearestGridPoint(h, n.x, n.u0, n.v0);
      const Projection ref = epaphe::closestPoint(h, n.x, n.u0, n.v0, 1e-10, n.maxIter);
      ++kinds[ref.outside ? 3 : 4];
      nodes.push_back(n);
    }
    EXPECT_GT(kinds[1], 0) << "no projection needed more than 2 iterations";
    EXPECT_GT(kinds[2], 0) << "no projection stopped at maxIter";
    if (!h.periodicU || !h.periodicV) {
      EXPECT_GT(kinds[3], 0) << "no node beyond an edge";
    }
    // Every offset of the list against the batches, and batches of every size up to W.
    std::vector<Projection> first(nodes.size());
    std::vector<bool> seen(nodes.size(), false);
    for (int n = 1; n <= W; ++n)
      for (int offset = 0; offset < n; ++offset)
        for (std::size_t k0 = offset; k0 < nodes.size(); k0 += n) {
          const int m = static_cast<int>(std::min<std::size_t>(n, nodes.size() - k0));
          double x[W][3], u0[W], v0[W];
          Projection out[W];
          for (int l = 0; l < m; ++l) {
            for (int c = 0; c < 3; ++c) x[l][c] = nodes[k0 + l].x[c];
            u0[l] = nodes[k0 + l].u0;
            v0[l] = nodes[k0 + l].v0;
          }
          const int maxIter = nodes[k0].maxIter;  // (a batch shares it: the others' is 30 or 1)
          epaphe::closestPoints(h, m, x, u0, v0, 1e-10, maxIter, out);
          for (int l = 0; l < m; ++l) {
            if (nodes[k0 + l].maxIter != maxIter) continue;
            const std::size_t k = k0 + l;
            const Projection& p = out[l];
            if (!seen[k]) {
              seen[k] = true;
              first[k] = p;
              const Projection ref = epaphe::closestPoint(h, x[l], u0[l], v0[l], 1e-10, maxIter);
              ASSERT_EQ(ref.iterations, p.iterations) << surf->name() << " node " << k;
              ASSERT_EQ(ref.converged, p.converged);
              ASSERT_EQ(ref.outside, p.outside);
              const double scale = 1.0 + std::fabs(ref.u) + std::fabs(ref.v);
              EXPECT_NEAR(ref.u, p.u, 1e-14 * scale) << surf->name() << " node " << k;
              EXPECT_NEAR(ref.v, p.v, 1e-14 * scale);
              EXPECT_NEAR(ref.gap, p.gap, 1e-14 * (1.0 + std::fabs(ref.gap)));
              EXPECT_NEAR(ref.beyond, p.beyond, 1e-14 * (1.0 + ref.beyond));
              for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(ref.point[c], p.point[c], 1e-14 * (1.0 + std::fabs(ref.point[c])));
                EXPECT_NEAR(ref.normal[c], p.normal[c], 1e-14);
              }
              continue;
            }
            const Projection& q = first[k];
            ASSERT_EQ(std::memcmp(&q.u, &p.u, sizeof(double)), 0)
                << surf->name() << " node " << k << ", lane " << l << " of " << m;
            ASSERT_EQ(std::memcmp(&q.v, &p.v, sizeof(double)), 0);
            ASSERT_EQ(std::memcmp(q.point, p.point, sizeof q.point), 0);
            ASSERT_EQ(std::memcmp(q.normal, p.normal, sizeof q.normal), 0);
            ASSERT_EQ(std::memcmp(&q.gap, &p.gap, sizeof(double)), 0);
            ASSERT_EQ(std::memcmp(&q.beyond, &p.beyond, sizeof(double)), 0);
            ASSERT_EQ(q.iterations, p.iterations);
          }
        }
    for (std::size_t k = 0; k < nodes.size(); ++k) EXPECT_TRUE(seen[k]) << "node " << k << " never projected";
  }
}

// ---- 7b. broad phase of the cold start (bucket grid) ------------------------------------------

// Large open wavy grid, 200 x 50 nodes, and a closed cylinder 120 x 40.
constexpr int kBigNu = 200, kBigNv = 50;
Vec3 bigWaveNode(int i, int j) {
  const double x = 0.1 * i, y = 0.12 * j;
  return {x, y, 0.5 * std::sin(0.7 * x) * std::cos(1.3 * y) + 0.02 * x};
}
constexpr int kBigCylN = 120, kBigCylNv = 40;
Vec3 bigCylNode(int i, int j) {
  const double t = 2.0 * kPi * i / kBigCylN;
  return {2.0 * std::cos(t), 2.0 * std::sin(t), 0.1 * j};
}

// Random points inside the node box, near the surface (within a few spacings), on the nodes and
// far outside the box (up to 100 box sizes away).
std::vector<Vec3> broadPhaseProbes(const HostSurfaceView& h, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
  double lo[3] = {h.binOrigin[0], h.binOrigin[1], h.binOrigin[2]};
  double hi[3] = {h.binUpper[0], h.binUpper[1], h.binUpper[2]};
  const double size = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                (hi[2] - lo[2]) * (hi[2] - lo[2]));
  std::vector<Vec3> probes;
  for (int k = 0; k < count; ++k) {
    Vec3 x;
    const int kind = k % 4;
    if (kind == 0) {  // inside the box
      for (int c = 0; c < 3; ++c) x[c] = lo[c] + (hi[c] - lo[c]) * unit(rng);
    } else if (kind == 1 || kind == 2) {  // near the surface (kind 2: on a node)
      double S[3];
      epaphe::evaluatePoint(h, h.uMax() * unit(rng), h.vMax() * unit(rng), S);
      if (kind == 2) {
        const int i = int(unit(rng) * h.nu) % h.nu, j = int(unit(rng) * h.nv) % h.nv;
        for (int c = 0; c < 3; ++c) x[c] = h.grid(i, j, c);
      } else {
        for (int c = 0; c < 3; ++c) x[c] = S[c] + 0.3 * sym(rng);
      }
    } else {  // outside the box, near or far
      const double reach = size * std::pow(100.0, unit(rng));
      for (int c = 0; c < 3; ++c) x[c] = 0.5 * (lo[c] + hi[c]) + 0.5 * reach * sym(rng);
    }
    probes.push_back(x);
  }
  return probes;
}

void expectSameNodeAsBruteForce(const HostSurfaceView& h, const std::vector<Vec3>& probes, const std::string& name) {
  int mismatches = 0;
  for (const Vec3& x : probes) {
    double u, v, ub, vb;
    epaphe::nearestGridPoint(h, x.data(), u, v);
    epaphe::nearestGridPointBruteForce(h, x.data(), ub, vb);
    if (u != ub || v != vb) {
      if (++mismatches <= 5)
        ADD_FAILURE() << name << ": x = " << x[0] << " " << x[1] << " " << x[2] << " bucket (" << u << "," << v
                      << ") brute force (" << ub << "," << vb << ")";
    }
  }
  EXPECT_EQ(mismatches, 0) << name;
}

TEST(BroadPhase, SameNodeAsBruteForceOnALargeOpenGridAndACylinder) {
  BSplineSurface wave("bigwave", kBigNu, kBigNv, makeGrid(kBigNu, kBigNv, bigWaveNode));
  const HostSurfaceView hw = wave.hostView();
  EXPECT_GT(hw.binDims[0] * hw.binDims[1] * hw.binDims[2], 1);
  expectSameNodeAsBruteForce(hw, broadPhaseProbes(hw, 4000, 31), "bigwave");

  BSplineSurface cyl("bigcyl", kBigCylN + 1, kBigCylNv, makeGrid(kBigCylN + 1, kBigCylNv, bigCylNode));
  ASSERT_TRUE(cyl.periodicU());
  const HostSurfaceView hc = cyl.hostView();
  expectSameNodeAsBruteForce(hc, broadPhaseProbes(hc, 4000, 32), "bigcyl");
  // Near the axis: almost every node is nearly equidistant.
  std::vector<Vec3> axis;
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> small(-1e-3, 1e-3), H(-0.5, 4.5);
  for (int k = 0; k < 500; ++k) axis.push_back({small(rng), small(rng), H(rng)});
  axis.push_back({0.0, 0.0, 1.0});  // exactly on the axis: ties
  expectSameNodeAsBruteForce(hc, axis, "bigcyl axis");

  // Flat regular grid, probes at cell centres and edge midpoints: exact ties, lowest index wins.
  const auto P = makeGrid(30, 20, [](int i, int j) { return Vec3{0.5 * i, 0.25 * j, 0.0}; });
  BSplineSurface flat("flat", 30, 20, P);
  std::vector<Vec3> ties;
  for (int i = 0; i < 29; ++i)
    for (int j = 0; j < 19; ++j) {
      ties.push_back({0.5 * i + 0.25, 0.25 * j + 0.125, 0.0});
      ties.push_back({0.5 * i + 0.25, 0.25 * j, 0.3});
      ties.push_back({0.5 * i, 0.25 * j + 0.125, -0.7});
    }
  expectSameNodeAsBruteForce(flat.hostView(), ties, "flat ties");
}

TEST(BroadPhase, RebuiltByUpdate) {
  // Flexible surface: the grid moves far and changes its shape; the bucket grid follows.
  BSplineSurface wave("bigwave", kBigNu, kBigNv, makeGrid(kBigNu, kBigNv, bigWaveNode));
  const auto moved = makeGrid(kBigNu, kBigNv, [](int i, int j) {
    const Vec3 p = bigWaveNode(i, j);
    return Vec3{10.0 + 0.5 * p[0], -3.0 + 2.0 * p[1], 4.0 * p[2] + 0.3 * p[1]};
  });
  wave.update(moved);
  const HostSurfaceView h = wave.hostView();
  EXPECT_NEAR(h.binOrigin[0], 10.0, 1e-12);
  EXPECT_NEAR(h.binOrigin[1], -3.0, 1e-12);
  expectSameNodeAsBruteForce(h, broadPhaseProbes(h, 2000, 34), "moved bigwave");
  // The device view sees the rebuilt bucket grid too.
  EXPECT_EQ(wave.view().binOrigin[0], h.binOrigin[0]);
  EXPECT_EQ(wave.view().binStart.extent(0), h.binStart.extent(0));
}

TEST(BroadPhase, DroppedByAnUpdateWithoutIt) {
  // A carried surface's update at every step leaves the bucket grid out: the views have none, the
  // cold start then takes the brute force (the same node); a later update with it brings it back.
  BSplineSurface wave("bigwave", kBigNu, kBigNv, makeGrid(kBigNu, kBigNv, bigWaveNode));
  const auto moved = makeGrid(kBigNu, kBigNv, [](int i, int j) {
    const Vec3 p = bigWaveNode(i, j);
    return Vec3{10.0 + 0.5 * p[0], -3.0 + 2.0 * p[1], 4.0 * p[2] + 0.3 * p[1]};
  });
  wave.update(moved.data(), false);
  const HostSurfaceView h = wave.hostView();
  EXPECT_EQ(h.binStart.extent(0), 0u);
  EXPECT_EQ(wave.view().binStart.extent(0), 0u);
  EXPECT_EQ(wave.view().binNodes.extent(0), 0u);
  for (const Vec3& x : broadPhaseProbes(h, 200, 35)) {
    double u, v, ub, vb;
    int evaluations = 0;
    epaphe::nearestGridPoint(h, x.data(), u, v, &evaluations);
    epaphe::nearestGridPointBruteForce(h, x.data(), ub, vb);
    EXPECT_EQ(u, ub);
    EXPECT_EQ(v, vb);
    EXPECT_EQ(evaluations, kBigNu * kBigNv);  // the brute force
  }
  wave.update(moved);
  const HostSurfaceView g = wave.hostView();
  EXPECT_GT(g.binStart.extent(0), 1u);
  EXPECT_EQ(wave.view().binStart.extent(0), g.binStart.extent(0));
  expectSameNodeAsBruteForce(g, broadPhaseProbes(g, 500, 36), "moved bigwave, grid back");
}

TEST(BroadPhase, TestsFewNodesNearTheSurface) {
  BSplineSurface wave("bigwave", kBigNu, kBigNv, makeGrid(kBigNu, kBigNv, bigWaveNode));
  const HostSurfaceView h = wave.hostView();
  const std::vector<Probe> probes = probesNear(h, 2000, 35);
  long total = 0;
  int worst = 0;
  for (const Probe& pr : probes) {
    double u, v, ub, vb;
    int count = 0, countBrute = 0;
    epaphe::nearestGridPoint(h, pr.x, u, v, &count);
    epaphe::nearestGridPointBruteForce(h, pr.x, ub, vb, &countBrute);
    EXPECT_EQ(u, ub);
    EXPECT_EQ(v, vb);
    EXPECT_EQ(countBrute, kBigNu * kBigNv);
    total += count;
    worst = std::max(worst, count);
  }
  const double mean = double(total) / double(probes.size());
  std::printf(
      "[          ] broad phase, %d x %d grid, %d cells: %.1f node distances per point on "
      "average (%.2f %%), at most %d\n",
      kBigNu, kBigNv, h.binDims[0] * h.binDims[1] * h.binDims[2], mean, 100.0 * mean / (kBigNu * kBigNv), worst);
  EXPECT_LT(mean, 0.05 * kBigNu * kBigNv);
  EXPECT_LT(worst, 0.05 * kBigNu * kBigNv);
  // A view without bucket grid (hand-built) falls back to the brute force.
  HostSurfaceView bare = h;
  bare.binStart = HostSurfaceView::Indices();
  int count = 0;
  double u, v;
  epaphe::nearestGridPoint(bare, probes[0].x, u, v, &count);
  EXPECT_EQ(count, kBigNu * kBigNv);
}

// Cold-start batch in a kernel, with the brute-force or the bucket initial guess.
double coldBatchSeconds(const epaphe::SurfaceView& s, Kokkos::View<const double* [3]> x, Kokkos::View<Projection*> out,
                        bool brute) {
  Kokkos::fence();
  Kokkos::Timer timer;
  Kokkos::parallel_for(
      "test::coldBatch", Kokkos::RangePolicy<>(0, x.extent(0)), KOKKOS_LAMBDA(const int k) {
        const double xk[3] = {x(k, 0), x(k, 1), x(k, 2)};
        double u0, v0;
        if (brute)
          epaphe::nearestGridPointBruteForce(s, xk, u0, v0);
        else
          epaphe::nearestGridPoint(s, xk, u0, v0);
        out(k) = epaphe::closestPoint(s, xk, u0, v0, 1e-10, 50);
      });
  Kokkos::fence();
  return timer.seconds();
}

TEST(BroadPhase, ColdStartBatchTiming) {
  BSplineSurface wave("bigwave", kBigNu, kBigNv, makeGrid(kBigNu, kBigNv, bigWaveNode));
  const std::vector<Probe> probes = probesNear(wave.hostView(), 20000, 36);
  const int n = int(probes.size());
  Kokkos::View<double* [3]> x("x", n);
  auto xh = Kokkos::create_mirror_view(x);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) xh(k, c) = probes[k].x[c];
  Kokkos::deep_copy(x, xh);
  Kokkos::View<Projection*> a("brute", n), b("bucket", n);
  double tBrute = 1e300, tBucket = 1e300;
  for (int rep = 0; rep < 3; ++rep) {
    tBrute = std::min(tBrute, coldBatchSeconds(wave.view(), x, a, true));
    tBucket = std::min(tBucket, coldBatchSeconds(wave.view(), x, b, false));
  }
  auto ah = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  auto bh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(ah(k).u, bh(k).u);
    EXPECT_EQ(ah(k).v, bh(k).v);
  }
  std::printf(
      "[          ] cold-start projection of %d points on the %d x %d grid: brute-force "
      "guess %.4f s, bucket guess %.4f s\n",
      n, kBigNu, kBigNv, tBrute, tBucket);
}

// ---- 8. user errors --------------------------------------------------------------------------

TEST(BSplineSurface, RejectsBadGrids) {
  std::string m = errorOf([] { BSplineSurface("short", 3, 5, makeGrid(3, 5, waveNode)); });
  EXPECT_NE(m.find("surface 'short': grid has 3 points along u, at least 4 are needed"), std::string::npos) << m;
  m = errorOf([] { BSplineSurface("narrow", 6, 2, makeGrid(6, 2, waveNode)); });
  EXPECT_NE(m.find("surface 'narrow': grid has 2 points along v, at least 4 are needed"), std::string::npos) << m;

  std::vector<double> dup = waveGrid();
  for (int c = 0; c < 3; ++c) dup[3 * (3 * kWaveNv + 4) + c] = dup[3 * (2 * kWaveNv + 4) + c];
  m = errorOf([&] { BSplineSurface("dup", kWaveNu, kWaveNv, dup); });
  EXPECT_NE(m.find("surface 'dup'"), std::string::npos) << m;
  EXPECT_NE(m.find("(2,4) and (3,4) coincide"), std::string::npos) << m;

  std::vector<double> dupV = waveGrid();
  for (int c = 0; c < 3; ++c) dupV[3 * (5 * kWaveNv + 7) + c] = dupV[3 * (5 * kWaveNv + 6) + c];
  m = errorOf([&] { BSplineSurface("dupv", kWaveNu, kWaveNv, dupV); });
  EXPECT_NE(m.find("(5,6) and (5,7) coincide"), std::string::npos) << m;

  std::vector<double> bad = waveGrid();
  bad[3 * (1 * kWaveNv + 2) + 2] = std::numeric_limits<double>::quiet_NaN();
  m = errorOf([&] { BSplineSurface("nan", kWaveNu, kWaveNv, bad); });
  EXPECT_NE(m.find("grid point (1,2) coordinate z = nan is not finite"), std::string::npos) << m;

  m = errorOf([] { BSplineSurface("size", 5, 5, std::vector<double>(70, 0.0)); });
  EXPECT_NE(m.find("70 coordinates given for a 5 x 5 grid"), std::string::npos) << m;

  m = errorOf([] {
    SurfaceOptions o2;
    o2.orientation = 2;
    BSplineSurface("orient", kWaveNu, kWaveNv, waveGrid(), o2);
  });
  EXPECT_NE(m.find("orientation = 2"), std::string::npos) << m;

  BSplineSurface s("wave", kWaveNu, kWaveNv, waveGrid());
  m = errorOf([&] { s.update(bad); });
  EXPECT_NE(m.find("update: grid point (1,2) coordinate z = nan"), std::string::npos) << m;
  m = errorOf([&] { s.update(std::vector<double>(3, 0.0)); });
  EXPECT_NE(m.find("update with 3 coordinates"), std::string::npos) << m;
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  Kokkos::initialize(argc, argv);
  int result = 0;
  result = RUN_ALL_TESTS();
  Kokkos::finalize();
  return result;
}
