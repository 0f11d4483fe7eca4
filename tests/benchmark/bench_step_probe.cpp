// The two machine figures of the explicit step's bound (bench_step.py): the memory bandwidth one
// thread gets streaming a triad a = b + s c over arrays much larger than the caches, and the cost
// of one warm-started closest-point projection on a bicubic patch (a node moving a little between
// projections on a cylinder, like a blade tip in its casing). Prints "bandwidth_GBps X" and
// "projection_ns Y"; figures only.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_Runtime.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace epaphe;

namespace {

double seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double triadBandwidth() {
  const std::size_t n = std::size_t(1) << 24;  // 3 x 128 MiB
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double best = 1e300;
  for (int rep = 0; rep < 5; ++rep) {
    const double t0 = seconds();
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 0.5 * c[i];
    best = std::min(best, seconds() - t0);
    b[rep] = a[n - 1 - rep];  // keep the loop
  }
  return 3.0 * sizeof(double) * n / best / 1e9;
}

double projectionNs() {
  const int nu = 120, nv = 6;
  std::vector<double> g;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double th = 2 * M_PI * i / nu;
      g.insert(g.end(), {0.25 * std::cos(th), 0.25 * std::sin(th), -0.02 + 0.04 * j / (nv - 1)});
    }
  SurfaceOptions o;
  o.closureU = Closure::Periodic;
  o.closureV = Closure::Open;
  o.orientation = -1;
  BSplineSurface s("casing", nu, nv, g, o);
  const HostSurfaceView v = s.hostView();
  const int nodes = 16, steps = 20000;
  std::vector<double> uv(2 * nodes);
  double x[3];
  for (int k = 0; k < nodes; ++k) {
    x[0] = 0.2499 * std::cos(0.01 * k);
    x[1] = 0.2499 * std::sin(0.01 * k);
    x[2] = -0.01 + 0.02 * k / nodes;
    nearestGridPoint(v, x, uv[2 * k], uv[2 * k + 1]);
  }
  double sum = 0.0;
  const double t0 = seconds();
  for (int n = 0; n < steps; ++n) {
    const double th = 2 * M_PI * n / 1000.0;  // 1000 steps per revolution
    for (int k = 0; k < nodes; ++k) {
      x[0] = 0.2499 * std::cos(th + 0.01 * k);
      x[1] = 0.2499 * std::sin(th + 0.01 * k);
      x[2] = -0.01 + 0.02 * k / nodes;
      const Projection p = closestPoint(v, x, uv[2 * k], uv[2 * k + 1], 1e-8, 50);
      uv[2 * k] = p.u;
      uv[2 * k + 1] = p.v;
      sum += p.gap;
    }
  }
  const double t = seconds() - t0;
  if (!(sum == sum)) std::printf("NaN\n");
  return 1e9 * t / (double(steps) * nodes);
}

}  // namespace

int main(int argc, char** argv) {
  Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  std::printf("bandwidth_GBps %.3f\n", triadBandwidth());
  std::printf("projection_ns %.1f\n", projectionNs());
  return 0;
}
