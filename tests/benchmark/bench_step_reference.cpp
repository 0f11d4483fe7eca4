// The reference kernel of bench_step.py's guard: a fixed amount of work of the explicit step's kinds,
// written here and sharing no code with Epaphe, so that its time measures how fast the machine runs
// at the moment and nothing else. bench_step.py divides a deck's 1-thread loop time by it (timed right
// before and after the deck's runs) to compare the loop with the figure recorded on the same machine
// class another day: a busy or throttled machine slows both alike. A kernel that called Epaphe (the
// probe's closest point, say) would slow down with Epaphe and hide the slowdown it is there to show.
//
// Each part is timed in the thread's CPU time (CLOCK_THREAD_CPUTIME_ID), which stands still while
// other processes have the core: on this project's shared 2-core VM the wall time of a few ms of work
// doubled at times, its CPU time did not. Three parts, each the fastest of 7 repetitions (the machine
// at its best, as the loop's best run):
//   dense   y = A x on a 98 x 98 matrix (the 98-DOF blade's reduced operators, in cache), 1200 times
//   sparse  a 7-point stencil product in CSR on a 16^3 grid (4,096 rows, 27,136 entries), 300 times
//   scalar  Newton's closest point on an analytic cylinder patch (sin, cos, a 2 x 2 solve, a square
//           root per iteration), 40,000 warm-started points, 4 iterations each
// Prints "dense_ms X", "sparse_ms Y", "scalar_ms Z" and "reference_ms" (their sum). The work is fixed:
// changing it changes every figure recorded in step_reference.json, which must then be recorded again.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <vector>

namespace {

double seconds() {  // this thread's CPU time
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

volatile double sink = 0.0;  // keeps every result alive

template <class F>
double best(F&& work) {
  double t = 1e300;
  for (int rep = 0; rep < 7; ++rep) {
    const double t0 = seconds();
    sink = sink + work();
    t = std::min(t, seconds() - t0);
  }
  return t;
}

double dense() {
  const int n = 98, times = 1200;
  static std::vector<double> a = [] {
    std::vector<double> m(98 * 98);
    for (int i = 0; i < 98; ++i)
      for (int j = 0; j < 98; ++j) m[i * 98 + j] = (i == j ? 1.0 : 0.0) + 1e-3 * std::sin(i + 2.0 * j);
    return m;
  }();
  std::vector<double> x(n, 1.0), y(n);
  for (int k = 0; k < times; ++k) {
    for (int i = 0; i < n; ++i) {
      double s = 0.0;
      for (int j = 0; j < n; ++j) s += a[i * n + j] * x[j];
      y[i] = s;
    }
    for (int i = 0; i < n; ++i) x[i] = 0.5 * (x[i] + y[i]);  // stays near 1
  }
  return x[n / 2];
}

double sparse() {
  const int m = 16, n = m * m * m, times = 300;
  static std::vector<int> ptr, col;
  static std::vector<double> val;
  if (ptr.empty()) {
    ptr.push_back(0);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        for (int k = 0; k < m; ++k) {
          const int r = (i * m + j) * m + k;
          const int nb[7][3] = {{i - 1, j, k}, {i, j - 1, k}, {i, j, k - 1}, {i, j, k},
                                {i, j, k + 1}, {i, j + 1, k}, {i + 1, j, k}};
          for (const auto& c : nb) {
            if (c[0] < 0 || c[0] >= m || c[1] < 0 || c[1] >= m || c[2] < 0 || c[2] >= m) continue;
            const int cc = (c[0] * m + c[1]) * m + c[2];
            col.push_back(cc);
            val.push_back(cc == r ? 6.0 : -1.0);
          }
          ptr.push_back(int(col.size()));
        }
  }
  std::vector<double> x(n), y(n);
  for (int i = 0; i < n; ++i) x[i] = std::cos(0.01 * i);
  for (int k = 0; k < times; ++k) {
    for (int r = 0; r < n; ++r) {
      double s = 0.0;
      for (int e = ptr[r]; e < ptr[r + 1]; ++e) s += val[e] * x[col[e]];
      y[r] = s;
    }
    for (int r = 0; r < n; ++r) x[r] = x[r] + 0.1 * y[r];  // the stencil's spectrum is in [0, 12]: keep it small
    for (int r = 0; r < n; ++r) x[r] *= 1.0 / (1.0 + 1e-3 * std::abs(x[r]));
  }
  return x[n / 3];
}

double scalar() {
  // p(u, v) = (R cos u, R sin u, v): the closest point to x by Newton on |p - x|^2 / 2
  const double radius = 0.25;
  const int points = 40000, iterations = 4;
  double u = 0.0, v = 0.0, sum = 0.0;
  for (int n = 0; n < points; ++n) {
    const double th = 2 * M_PI * n / 1000.0;
    const double x[3] = {0.2499 * std::cos(th), 0.2499 * std::sin(th), -0.01 + 0.02 * (n % 16) / 16.0};
    for (int it = 0; it < iterations; ++it) {
      const double c = std::cos(u), s = std::sin(u);
      const double d[3] = {radius * c - x[0], radius * s - x[1], v - x[2]};
      const double pu[3] = {-radius * s, radius * c, 0.0}, puu[3] = {-radius * c, -radius * s, 0.0};
      const double gu = d[0] * pu[0] + d[1] * pu[1], gv = d[2];
      const double huu = pu[0] * pu[0] + pu[1] * pu[1] + d[0] * puu[0] + d[1] * puu[1], hvv = 1.0, huv = 0.0;
      const double det = huu * hvv - huv * huv;
      u -= (hvv * gu - huv * gv) / det;
      v -= (huu * gv - huv * gu) / det;
    }
    const double c = std::cos(u), s = std::sin(u);
    sum += std::sqrt((radius * c - x[0]) * (radius * c - x[0]) + (radius * s - x[1]) * (radius * s - x[1]) +
                     (v - x[2]) * (v - x[2]));
  }
  return sum;
}

}  // namespace

int main() {
  const double d = best(dense), s = best(sparse), c = best(scalar);
  std::printf("dense_ms %.4f\nsparse_ms %.4f\nscalar_ms %.4f\nreference_ms %.4f\n", 1e3 * d, 1e3 * s, 1e3 * c,
              1e3 * (d + s + c));
  return 0;
}
