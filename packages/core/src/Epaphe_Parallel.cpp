#include "Epaphe_Parallel.hpp"

#include "Epaphe_Error.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace epaphe {

namespace {
long readSerialWorkNs() {
  const char* e = std::getenv("EPAPHE_SERIAL_WORK_NS");
  if (!e || !*e) return kDefaultSerialWorkNs;
  char* end = nullptr;
  const long v = std::strtol(e, &end, 10);
  EPAPHE_REQUIRE(end && *end == '\0' && v >= 0,
                 "EPAPHE_SERIAL_WORK_NS = '" << e << "'; give a whole number of nanoseconds >= 0 (0: always parallel)");
  return v;
}
std::atomic<long> gSerialWorkNs{-1};
}  // namespace

long serialWorkNs() {
  long v = gSerialWorkNs.load(std::memory_order_relaxed);
  if (v < 0) gSerialWorkNs = v = readSerialWorkNs();
  return v;
}

namespace parallel_detail {
std::atomic<bool> gTimeKernels{false};
}  // namespace parallel_detail

namespace {
struct KernelTimes {
  std::mutex mutex;
  std::map<const char*, KernelTime> byName;  // by the name's address: the names are literals
};
KernelTimes& kernelTimesTable() {
  static KernelTimes t;
  return t;
}
}  // namespace

void parallel_detail::addKernelTime(const char* name, bool onTeam, double seconds) {
  KernelTimes& t = kernelTimesTable();
  const std::lock_guard<std::mutex> lock(t.mutex);
  KernelTime& k = t.byName[name];
  ++k.launches;
  if (onTeam) ++k.onTeam;
  k.seconds += seconds;
}

void timeKernels(bool on) {
  parallel_detail::gTimeKernels = on;
}

std::vector<KernelTime> kernelTimes() {
  KernelTimes& t = kernelTimesTable();
  std::map<std::string, KernelTime> merged;  // one name at two addresses (two translation units) is one kernel
  {
    const std::lock_guard<std::mutex> lock(t.mutex);
    for (const auto& [name, k] : t.byName) {
      KernelTime& m = merged[name];
      m.name = name;
      m.launches += k.launches;
      m.onTeam += k.onTeam;
      m.seconds += k.seconds;
    }
  }
  std::vector<KernelTime> out;
  for (auto& [name, k] : merged) out.push_back(k);
  std::stable_sort(out.begin(), out.end(),
                   [](const KernelTime& a, const KernelTime& b) { return a.seconds > b.seconds; });
  return out;
}

void clearKernelTimes() {
  KernelTimes& t = kernelTimesTable();
  const std::lock_guard<std::mutex> lock(t.mutex);
  t.byName.clear();
}

void setSerialWorkNs(long ns) {
  EPAPHE_REQUIRE(ns >= 0, "serial work threshold " << ns << " ns; give 0 or more");
  gSerialWorkNs = ns;
}

LargeTable largeTable(const std::string& label, std::size_t n) {
  LargeTable t;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::size_t kHuge = kHugePageBytes;
  if (std::is_same<Kokkos::DefaultExecutionSpace::memory_space, Kokkos::HostSpace>::value &&
      n * sizeof(double) >= kHuge) {
    const std::size_t bytes = (n * sizeof(double) + kHuge - 1) / kHuge * kHuge;
    const std::size_t length = bytes + kHuge;  // room to start on a 2 MiB boundary
    void* base = mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (base != MAP_FAILED) {
      const auto start = (reinterpret_cast<std::uintptr_t>(base) + kHuge - 1) / kHuge * kHuge;
      void* aligned = reinterpret_cast<void*>(start);
      // before the first touch, so that the pages are made huge as they are faulted in (fresh
      // anonymous pages are zero); refused (a kernel without THP): ordinary pages, the same table
      t.hugePagesAsked = madvise(aligned, bytes, MADV_HUGEPAGE) == 0;
      t.memory = std::shared_ptr<void>(base, [length](void* p) { munmap(p, length); });
      t.view = Kokkos::View<double*>(static_cast<double*>(aligned), n);
      return t;
    }
  }
#endif
  t.view = Kokkos::View<double*>(label, n);
  return t;
}

namespace {
std::atomic<std::int64_t> gLaunches{0}, gAllocations{0}, gDeepCopies{0};
std::atomic<bool> gActive{false};

std::mutex gNamesMutex;
std::map<std::string, std::int64_t> gNames;

void onBegin(const char* name, const std::uint32_t, std::uint64_t* id) {
  *id = 0;
  ++gLaunches;
  const std::lock_guard<std::mutex> lock(gNamesMutex);
  ++gNames[name ? name : "?"];
}
void onEnd(std::uint64_t) {}
void onAllocate(const Kokkos_Profiling_SpaceHandle, const char*, const void*, const std::uint64_t) {
  ++gAllocations;
}
void onDeepCopy(Kokkos_Profiling_SpaceHandle, const char*, const void*, Kokkos_Profiling_SpaceHandle, const char*,
                const void*, std::uint64_t) {
  ++gDeepCopies;
}
void onEndDeepCopy() {}

Kokkos::Tools::Experimental::EventSet gSaved;
}  // namespace

KernelCounter::KernelCounter() {
  EPAPHE_REQUIRE(!gActive.exchange(true), "KernelCounter: one counter at a time");
  namespace T = Kokkos::Tools::Experimental;
  gSaved = T::get_callbacks();
  T::set_begin_parallel_for_callback(onBegin);
  T::set_end_parallel_for_callback(onEnd);
  T::set_begin_parallel_reduce_callback(onBegin);
  T::set_end_parallel_reduce_callback(onEnd);
  T::set_begin_parallel_scan_callback(onBegin);
  T::set_end_parallel_scan_callback(onEnd);
  T::set_allocate_data_callback(onAllocate);
  T::set_begin_deep_copy_callback(onDeepCopy);
  T::set_end_deep_copy_callback(onEndDeepCopy);
  reset();
}

KernelCounter::~KernelCounter() {
  Kokkos::Tools::Experimental::set_callbacks(gSaved);
  gActive = false;
}

std::int64_t KernelCounter::launches() const {
  return gLaunches;
}
std::int64_t KernelCounter::allocations() const {
  return gAllocations;
}
std::int64_t KernelCounter::deepCopies() const {
  return gDeepCopies;
}
void KernelCounter::reset() {
  gLaunches = gAllocations = gDeepCopies = 0;
  const std::lock_guard<std::mutex> lock(gNamesMutex);
  gNames.clear();
}

std::map<std::string, std::int64_t> KernelCounter::byName() const {
  const std::lock_guard<std::mutex> lock(gNamesMutex);
  return gNames;
}

}  // namespace epaphe
