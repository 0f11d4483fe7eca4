// largeTable(): the step's large tables on huge pages where the kernel grants them.
#include "Epaphe_Parallel.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

namespace {

// Transparent huge pages are available on request: /sys/kernel/mm/transparent_hugepage/enabled reads
// "always [madvise] never" or "[always] madvise never".
bool hugePagesOnRequest() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(f, s);
  return s.find("[madvise]") != std::string::npos || s.find("[always]") != std::string::npos;
}

// The VmFlags of the mapping holding `p` in /proc/self/smaps ("" when none is found).
std::string vmFlags(const void* p) {
  std::ifstream f("/proc/self/smaps");
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  bool inside = false;
  for (std::string line; std::getline(f, line);) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
      inside = lo <= a && a < hi;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line;
  }
  return "";
}

TEST(LargeTable, ZeroedAndWritable) {
  for (const std::size_t n : {std::size_t(1000), std::size_t(3) << 20}) {
    epaphe::LargeTable t = epaphe::largeTable("test::table", n);
    ASSERT_EQ(t.view.extent(0), n);
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += t.view(i) * t.view(i);
    EXPECT_EQ(sum, 0.0) << n;
    t.view(n - 1) = 2.5;
    const epaphe::LargeTable copy = t;  // shares the table
    EXPECT_EQ(copy.view(n - 1), 2.5);
  }
}

TEST(LargeTable, SmallTablesAreOrdinaryViews) {
  const epaphe::LargeTable t = epaphe::largeTable("test::small", epaphe::kHugePageBytes / sizeof(double) - 1);
  EXPECT_FALSE(t.memory);
  EXPECT_FALSE(t.hugePagesAsked);
  EXPECT_TRUE(t.view.use_count() > 0);  // managed
}

TEST(LargeTable, LargeTablesAskForHugePages) {
  if (!hugePagesOnRequest()) GTEST_SKIP() << "this kernel gives no transparent huge pages on request";
  const std::size_t n = 5 * epaphe::kHugePageBytes / sizeof(double) + 7;
  const epaphe::LargeTable t = epaphe::largeTable("test::large", n);
  ASSERT_TRUE(t.memory);
  EXPECT_TRUE(t.hugePagesAsked);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(t.view.data()) % epaphe::kHugePageBytes, 0u);
  // madvise(MADV_HUGEPAGE) shows as the flag "hg" of the table's mapping
  const std::string flags = vmFlags(t.view.data() + n / 2);
  EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
}

}  // namespace
