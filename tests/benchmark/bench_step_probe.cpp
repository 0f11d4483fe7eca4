// The two machine figures of the explicit step's bound (bench_step.py): the memory bandwidth one
// thread gets streaming a triad a = b + s c over arrays much larger than the caches, and the cost
// of one warm-started closest-point projection on a bicubic patch (a node moving a little between
// projections on a cylinder, like a blade tip in its casing). Prints "bandwidth_GBps X" and
// "projection_ns Y"; figures only. And what two threads pay to share data: the time a cache line
// written on one CPU takes to be read on another ("core_to_core_ns Z", half a round trip of a flag
// between two threads on the first two CPUs the process may use; -1 with one CPU). Each kernel of
// the step on the thread team reads what the other thread wrote in the kernels before it.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ClosestPoint.hpp"
#include "Epaphe_Runtime.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>
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

// ns per projection of 16 nodes on a casing, 20,000 times, one revolution in 1000: each node alone
// (closestPoint) or kProjectionLanes at a time, their iterations interleaved (closestPoints).
double projectionNs(bool lanes) {
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
  constexpr int nodes = 16, W = kProjectionLanes;
  const int steps = 20000;
  std::vector<double> u(nodes), w(nodes);
  double x[nodes][3];
  auto place = [&](double th) {
    for (int k = 0; k < nodes; ++k) {
      x[k][0] = 0.2499 * std::cos(th + 0.01 * k);
      x[k][1] = 0.2499 * std::sin(th + 0.01 * k);
      x[k][2] = -0.01 + 0.02 * k / nodes;
    }
  };
  place(0.0);
  for (int k = 0; k < nodes; ++k) nearestGridPoint(v, x[k], u[k], w[k]);
  double sum = 0.0;
  Projection p[nodes];
  const double t0 = seconds();
  for (int n = 0; n < steps; ++n) {
    place(2 * M_PI * n / 1000.0);  // 1000 steps per revolution
    if (lanes) {
      for (int k = 0; k < nodes; k += W) closestPoints(v, std::min(W, nodes - k), x + k, &u[k], &w[k], 1e-8, 50, p + k);
    } else {
      for (int k = 0; k < nodes; ++k) p[k] = closestPoint(v, x[k], u[k], w[k], 1e-8, 50);
    }
    for (int k = 0; k < nodes; ++k) {
      u[k] = p[k].u;
      w[k] = p[k].v;
      sum += p[k].gap;
    }
  }
  const double t = seconds() - t0;
  if (!(sum == sum)) std::printf("NaN\n");
  return 1e9 * t / (double(steps) * nodes);
}

// Half the round trip of a flag between two threads pinned to the first two CPUs of this process
// (ns, the fastest of 5 rounds of 100,000 trips); -1 when it may use fewer than 2 CPUs.
double coreToCoreNs() {
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0 || CPU_COUNT(&allowed) < 2) return -1;
  int cpus[2], found = 0;
  for (int c = 0; c < CPU_SETSIZE && found < 2; ++c)
    if (CPU_ISSET(c, &allowed)) cpus[found++] = c;
  auto pin = [](int cpu) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    pthread_setaffinity_np(pthread_self(), sizeof one, &one);
  };
  constexpr int trips = 100000;
  alignas(64) std::atomic<long> flag{0};
  double best = 1e300;
  for (int round = 0; round < 5; ++round) {
    flag = 0;
    std::thread echo([&] {
      pin(cpus[1]);
      for (long i = 0; i < trips; ++i) {
        while (flag.load(std::memory_order_acquire) != 2 * i + 1) {
        }
        flag.store(2 * i + 2, std::memory_order_release);
      }
    });
    pin(cpus[0]);
    const double t0 = seconds();
    for (long i = 0; i < trips; ++i) {
      flag.store(2 * i + 1, std::memory_order_release);
      while (flag.load(std::memory_order_acquire) != 2 * i + 2) {
      }
    }
    best = std::min(best, seconds() - t0);
    echo.join();
  }
  return 1e9 * best / trips / 2;
}

}  // namespace

int main(int argc, char** argv) {
  Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  std::printf("bandwidth_GBps %.3f\n", triadBandwidth());
  std::printf("projection_ns %.1f\n", projectionNs(true));
  std::printf("projection_alone_ns %.1f\n", projectionNs(false));
  std::printf("core_to_core_ns %.1f\n", coreToCoreNs());
  return 0;
}
