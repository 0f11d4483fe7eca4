// Kernel times (timeKernels, Epaphe_Parallel.hpp): each forEach and reduce launch counted and timed
// by its name, on the thread team or on the calling thread, while timing is on, and nothing otherwise.
#include "Epaphe_Parallel.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <climits>
#include <thread>

namespace epaphe {
namespace {

// A kernel of 64 items whose item 0 sleeps `ms` milliseconds: its launch lasts at least that long
void sleepy(const char* name, int ms) {
  forEach(name, 64, 1, [=](const int i) {
    if (i == 0) std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  });
}

TEST(KernelTimes, NothingWhileOff) {
  clearKernelTimes();
  sleepy("epaphe::test::off", 1);
  EXPECT_TRUE(kernelTimes().empty());
}

TEST(KernelTimes, EachLaunchByItsName) {
  const bool team = Kokkos::DefaultExecutionSpace().concurrency() > 1;
  clearKernelTimes();
  timeKernels(true);
  setSerialWorkNs(LONG_MAX);  // on the calling thread
  for (int k = 0; k < 3; ++k) sleepy("epaphe::test::sleepy", 4);
  setSerialWorkNs(0);  // on the team (with 2 threads)
  for (int k = 0; k < 2; ++k) sleepy("epaphe::test::sleepy", 4);
  double sum = 0;
  reduce(
      "epaphe::test::sum", 1000, 1, [](const int i, double& s) { s += i; }, Kokkos::Sum<double>(sum));
  forEach("epaphe::test::empty", 0, 1, [](int) {});  // no item: no launch
  timeKernels(false);
  sleepy("epaphe::test::sleepy", 1);  // not counted
  setSerialWorkNs(kDefaultSerialWorkNs);
  EXPECT_EQ(sum, 999.0 * 1000 / 2);

  const std::vector<KernelTime> k = kernelTimes();
  ASSERT_EQ(k.size(), 2u);
  EXPECT_EQ(k[0].name, "epaphe::test::sleepy");  // the longest first
  EXPECT_EQ(k[0].launches, 5);
  EXPECT_EQ(k[0].onTeam, team ? 2 : 0);
  EXPECT_GE(k[0].seconds, 5 * 4e-3);
  EXPECT_LT(k[0].seconds, 5.0) << "the launches' wall time, not a sum over threads or items";
  EXPECT_EQ(k[1].name, "epaphe::test::sum");
  EXPECT_EQ(k[1].launches, 1);
  EXPECT_EQ(k[1].onTeam, team ? 1 : 0);
  EXPECT_GE(k[1].seconds, 0.0);
  EXPECT_LT(k[1].seconds, k[0].seconds);
  clearKernelTimes();
  EXPECT_TRUE(kernelTimes().empty());
}

}  // namespace
}  // namespace epaphe
