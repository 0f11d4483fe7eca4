// NodeRecovery::applyColumns (Epaphe_SceneBody.hpp): the watched nodes' displacements of a chunk of
// records, Y = R X, one dgemm per thread on its block of R's rows. Checked against the sums written
// out, and the same bits whether the product runs on one thread or split over the team (a history
// must not depend on the thread count through its recovery, nor a restart on how records group).
#include "Epaphe_Parallel.hpp"
#include "Epaphe_SceneBody.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <vector>

using namespace epaphe;

namespace {

/// A reduced model of `size` DOFs over `nodes` nodes with random recovery rows.
ReducedModel model(int size, int nodes) {
  ReducedModel rom;
  rom.kind = ReductionKind::CraigBampton;
  rom.size = size;
  rom.coords.assign(static_cast<std::size_t>(nodes), {0.0, 0.0, 0.0});
  rom.recovery.resize(3 * static_cast<std::size_t>(nodes) * size);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& r : rom.recovery) r = u(gen);
  return rom;
}

TEST(NodeRecovery, ColumnsMatchTheSumsAndDoNotDependOnTheThreads) {
  const int size = 131, nodes = 397, cols = 64;  // 1191 rows: not a multiple of the blocks' 16
  const ReducedModel rom = model(size, nodes);
  std::vector<int> watched(static_cast<std::size_t>(nodes));
  std::iota(watched.begin(), watched.end(), 0);
  const NodeRecovery R(rom, watched, "test::recovery");
  ASSERT_EQ(R.rows(), 3u * nodes);
  std::vector<double> X(static_cast<std::size_t>(size) * cols);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& x : X) x = u(gen);

  const int threads = Kokkos::DefaultHostExecutionSpace().concurrency();
  std::printf("%d threads\n", threads);
  const long threshold = serialWorkNs();
  std::vector<double> serial(R.rows() * cols), split(R.rows() * cols);
  setSerialWorkNs(1L << 60);  // every loop on the calling thread
  R.applyColumns(X.data(), cols, serial.data());
  setSerialWorkNs(0);  // every loop a Kokkos kernel over the team
  R.applyColumns(X.data(), cols, split.data());
  setSerialWorkNs(threshold);

  double worst = 0.0;
  for (int j = 0; j < cols; ++j)
    for (std::size_t i = 0; i < R.rows(); ++i) {
      double s = 0.0, scale = 0.0;
      for (int k = 0; k < size; ++k) {
        s += rom.recovery[i * size + k] * X[static_cast<std::size_t>(j) * size + k];
        scale += std::fabs(rom.recovery[i * size + k] * X[static_cast<std::size_t>(j) * size + k]);
      }
      worst = std::max(worst, std::fabs(serial[j * R.rows() + i] - s) / scale);
    }
  EXPECT_LT(worst, 1e-14) << "Y = R X differs from its sums written out";
  if (threads < 2) GTEST_SKIP() << "one thread: no split to compare (run with OMP_NUM_THREADS=2)";
  std::size_t differ = 0;
  for (std::size_t i = 0; i < serial.size(); ++i) differ += serial[i] != split[i];
  EXPECT_EQ(differ, 0u) << "the product split over " << threads << " threads gave other bits than on one";
}

}  // namespace
