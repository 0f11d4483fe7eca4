#include "Epaphe_Parallel.hpp"

#include "Epaphe_Error.hpp"

#include <atomic>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>

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

void setSerialWorkNs(long ns) {
  EPAPHE_REQUIRE(ns >= 0, "serial work threshold " << ns << " ns; give 0 or more");
  gSerialWorkNs = ns;
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
