#pragma once
// Loops of the explicit step over nodes, pairs or DOFs: a Kokkos parallel region when the loop has
// enough work to pay for waking the thread team, the same functor on the calling thread otherwise.
//
// Why: an OpenMP parallel region costs a fork and a join (a few microseconds on 2 threads, see
// benchmark.launch-overhead), while most loops of a contact step do well under a microsecond of
// work (16 tip nodes of a blade, 100 DOFs of a bar). Run in parallel, they made 2 threads slower
// than 1 (bar-on-wall: 0.44x). Every loop states its work per item in nanoseconds (measured on one
// thread, rounded up); a loop whose total is below serialWorkNs() runs serially. Nothing depends on
// the choice, to the bit: the functors write per item, and reduce() adds in fixed chunks of items
// joined in index order whichever thread ran a chunk, so the floating-point sums of the outputs
// (epaphe::dot for energies and momenta, SurfaceContact::workIncrement) are the same on 1 and 2
// threads, serial or parallel. A run can therefore switch between the two while it runs
// (ParallelChooser, Epaphe_ParallelChooser.hpp) without changing a bit of its results.
//
// The serial path calls the functor on the host, so the views must be host-accessible: with a
// device backend (CUDA) every loop goes to Kokkos.
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <type_traits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace epaphe {

/// Work (ns) below which a loop runs on the calling thread: EPAPHE_SERIAL_WORK_NS if set, else
/// kDefaultSerialWorkNs (4x the fork-join cost measured on this project's 2-core machines).
long serialWorkNs();
/// The default of serialWorkNs() (ns).
constexpr long kDefaultSerialWorkNs = 20000;
/// Sets the threshold for this process (tests and benchmarks: 0 makes every loop a Kokkos kernel).
void setSerialWorkNs(long ns);

/// The unmanaged view type of a view type V: the same data, layout and memory, no reference count.
template <class V>
using Unmanaged = Kokkos::View<typename V::data_type, typename V::array_layout, typename V::device_type,
                               Kokkos::MemoryTraits<Kokkos::Unmanaged>>;

/// An unmanaged view of v's memory: nothing allocated, no reference counted, and neither are they by
/// the copies of it or of a view assigned from it. The explicit step copies views into locals and
/// kernel captures, and kernels copy structs of views per item; counting references costs two atomic
/// operations per view and copy (measured 6.7 % of a blade run's instructions), so the step copies
/// unmanaged views of the views their owner keeps (allocated at setup, alive as long as the step).
template <class V>
Unmanaged<V> unmanaged(const V& v) {
  return Unmanaged<V>(v);
}

/// One kernel's launches while kernel timing was on (timeKernels): how many, how many of them on the
/// thread team, and their wall time in all (s).
struct KernelTime {
  std::string name;      ///< the kernel's name, as forEach or reduce was given it
  long launches = 0;     ///< launches timed
  long onTeam = 0;       ///< ...of which on the thread team (the others on the calling thread)
  double seconds = 0.0;  ///< wall time of the timed launches (s)
};
/// Starts (true) or stops timing each forEach and reduce by its name: a launch on the team is timed
/// from its fork to its join, one on the calling thread from its first item to its last. Off by
/// default, when a launch pays one test of a flag. The times gather over every thread that launches.
/// (KernelCounter, below, counts Kokkos' own parallel regions, allocations and copies instead.)
void timeKernels(bool on);
/// The kernels timed since the last clearKernelTimes(), the longest first.
std::vector<KernelTime> kernelTimes();
/// Forgets the times gathered so far.
void clearKernelTimes();

namespace parallel_detail {
/// Kernel timing is on (timeKernels).
extern std::atomic<bool> gTimeKernels;
/// Adds one launch of kernel `name` (a literal: its address is the key) to the kernel times.
void addKernelTime(const char* name, bool onTeam, double seconds);
/// Times the scope as a launch of kernel `name` when kernel timing is on.
class KernelTimer {
public:
  KernelTimer(const char* name, bool onTeam)
      : name_(gTimeKernels.load(std::memory_order_relaxed) ? name : nullptr), onTeam_(onTeam) {
    if (name_) start_ = std::chrono::steady_clock::now();
  }
  ~KernelTimer() {
    if (name_)
      addKernelTime(name_, onTeam_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  KernelTimer(const KernelTimer&) = delete;
  KernelTimer& operator=(const KernelTimer&) = delete;

private:
  const char* name_;
  bool onTeam_;
  std::chrono::steady_clock::time_point start_;
};

constexpr bool kHostAccessible =
    Kokkos::SpaceAccessibility<Kokkos::HostSpace, Kokkos::DefaultExecutionSpace::memory_space>::accessible;
inline bool serial(long n, long nsPerItem) {
  return kHostAccessible && (Kokkos::DefaultExecutionSpace().concurrency() == 1 || n * nsPerItem < serialWorkNs());
}
/// A kernel launched by forEach and not yet waited for by fence().
inline bool& launched() {
  static bool pending = false;
  return pending;
}
}  // namespace parallel_detail

/// Waits for the kernels forEach launched since the last wait (Kokkos::fence), and only then: a step
/// whose loops all ran on the calling thread pays no fence (each one calls Kokkos Tools' hooks:
/// measured 6.6 % of a blade run with friction). Reductions into a host value have waited already.
inline void fence() {
  if (!parallel_detail::launched()) return;
  Kokkos::fence();
  parallel_detail::launched() = false;
}

/// dst = src for two views of one shape: a plain copy when both are host memory, contiguous and of
/// one layout (after fence(); nothing when they are the same memory, as a host mirror of a host
/// view is), else Kokkos::deep_copy. The same values either way, without deep_copy's fences and
/// hooks in the explicit step.
template <class D, class S>
void copy(const D& dst, const S& src) {
  constexpr bool host = Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename D::memory_space>::accessible &&
                        Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename S::memory_space>::accessible;
  constexpr bool sameLayout =
      std::is_same<typename D::array_layout, typename S::array_layout>::value || (D::rank <= 1 && S::rank <= 1);
  if constexpr (host && sameLayout) {
    if (dst.span_is_contiguous() && src.span_is_contiguous() && dst.span() == src.span()) {
      bool sameShape = true;
      for (unsigned r = 0; r < D::rank; ++r) sameShape = sameShape && dst.extent(r) == src.extent(r);
      if (sameShape) {
        fence();
        if (dst.data() != src.data()) std::copy(src.data(), src.data() + src.span(), dst.data());
        return;
      }
    }
  }
  Kokkos::deep_copy(dst, src);
}

/// f(i) for i in [0, n): in parallel (named kernel `name`) when n * nsPerItem >= serialWorkNs().
template <class F>
void forEach(const char* name, long n, long nsPerItem, const F& f) {
  if (n <= 0) return;
  const bool serial = parallel_detail::serial(n, nsPerItem);
  const parallel_detail::KernelTimer timer(name, !serial);
  if (serial) {
    for (long i = 0; i < n; ++i) f(static_cast<int>(i));
  } else {
    Kokkos::parallel_for(name, Kokkos::RangePolicy<>(0, n), f);
    parallel_detail::launched() = true;
  }
}

/// f(r0, r1) on one block of rows [r0, r1) of an n-row product per thread of the team, as one
/// parallel region when the product's estimated work `ns` pays for it (forEach), else every block
/// on the calling thread. Blocks start at multiples of `align` rows (a BLAS kernel's row tile: a
/// row's sum then does not depend on the block it falls in, so 1 and 2 threads give the same bits).
/// Used for the dense and sparse operators of the step, stored by rows so that a block is one
/// contiguous piece of memory (Epaphe_CentralDifference.cpp), and the history's node recovery.
template <class F>
void forRowBlocks(const char* name, int n, long ns, int align, const F& f) {
  const int T = Kokkos::DefaultHostExecutionSpace().concurrency();
  forEach(name, T, ns / T, [=](const int t) {
    auto edge = [&](int u) { return u == T ? n : static_cast<int>(static_cast<long>(n) * u / T) / align * align; };
    const int r0 = edge(t), r1 = edge(t + 1);
    if (r1 > r0) f(r0, r1);
  });
}

namespace parallel_detail {
/// Items per chunk of reduce(): each chunk is reduced in index order, the chunks joined in order.
constexpr long kReduceChunk = 256;
/// A buffer of a chunk's partial results per calling thread, grown as needed and kept (no
/// allocation in the explicit step once it has the size).
template <class V>
V* partials(long chunks) {
  thread_local std::vector<V> buffer;
  if (static_cast<long>(buffer.size()) < chunks) buffer.resize(static_cast<std::size_t>(chunks));
  return buffer.data();
}
}  // namespace parallel_detail

/// result = reduction over i of f(i, partial), with Kokkos' reducer R (Kokkos::Max<T>, Sum<T>...):
/// items in chunks of kReduceChunk, each chunk in index order, the chunks' results joined in order.
/// The association is the same on any number of threads, serial or parallel (a floating-point sum
/// has the same bits); in parallel (a kernel per chunk) when n * nsPerItem >= serialWorkNs(). A
/// device backend (not host-accessible) uses Kokkos' parallel_reduce and its own order.
template <class F, class R>
void reduce(const char* name, long n, long nsPerItem, const F& f, const R& reducer) {
  using V = typename R::value_type;
  constexpr long C = parallel_detail::kReduceChunk;
  if constexpr (!parallel_detail::kHostAccessible) {
    Kokkos::parallel_reduce(name, Kokkos::RangePolicy<>(0, n), f, reducer);
  } else {
    V total;
    reducer.init(total);
    const long chunks = (std::max(n, 0L) + C - 1) / C;
    const bool serial = chunks <= 1 || parallel_detail::serial(n, nsPerItem);
    const parallel_detail::KernelTimer timer(name, !serial);
    if (serial) {
      for (long c = 0; c < chunks; ++c) {
        V v;
        reducer.init(v);
        for (long i = c * C, e = std::min(n, i + C); i < e; ++i) f(static_cast<int>(i), v);
        reducer.join(total, v);
      }
    } else {
      V* part = parallel_detail::partials<V>(chunks);
      const R r = reducer;
      Kokkos::parallel_for(name, Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace>(0, chunks), [=](const int c) {
        V v;
        r.init(v);
        for (long i = c * C, e = std::min(n, c * C + C); i < e; ++i) f(static_cast<int>(i), v);
        part[c] = v;
      });
      Kokkos::DefaultHostExecutionSpace().fence();
      for (long c = 0; c < chunks; ++c) reducer.join(total, part[c]);
    }
    reducer.reference() = total;
  }
}

/// x . y of two 1-D views (serial below the threshold, as forEach; on one thread in index order).
template <class X, class Y>
double dot(const X& x, const Y& y) {
  double s = 0.0;
  reduce(
      "epaphe::dot", static_cast<long>(x.extent(0)), 2, KOKKOS_LAMBDA(const int i, double& t) { t += x(i) * y(i); },
      Kokkos::Sum<double>(s));
  return s;
}

/// y = a x + b y for 1-D views.
template <class X, class Y>
void axpby(double a, const X& x, double b, const Y& y) {
  forEach(
      "epaphe::axpby", static_cast<long>(y.extent(0)), 1, KOKKOS_LAMBDA(const int i) { y(i) = a * x(i) + b * y(i); });
}

/// x(i) = value for a 1-D view.
template <class X, class T>
void fill(const X& x, T value) {
  forEach(
      "epaphe::fill", static_cast<long>(x.extent(0)), 1, KOKKOS_LAMBDA(const int i) { x(i) = value; });
}

/// The size of a huge page (x86-64 Linux's transparent huge pages): a LargeTable's alignment.
constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;

/// A table of megabytes that the step reads in short runs at scattered places (a body's flexibility,
/// the control columns of a carried surface and the flexibility between its control points): n
/// doubles, zeroed. On host memory, from kHugePageBytes up, it is mapped on its own, aligned to 2 MiB
/// and marked for transparent huge pages (Linux madvise), which the kernel grants where it can: on
/// 4 KiB pages such a table spans more pages than the TLB holds, and its scattered reads pay page
/// walks (docs/performance.md). `view` is then unmanaged and `memory` keeps the table (copies share
/// it). Smaller, or elsewhere (a device backend, another system), `view` is an ordinary view and
/// `memory` empty.
struct LargeTable {
  Kokkos::View<double*> view;    ///< the n doubles
  std::shared_ptr<void> memory;  ///< owns the mapping (empty: `view` owns its memory)
  /// Whether the kernel was asked for huge pages for this table and agreed to try (it may still
  /// give fewer, when it has no free 2 MiB of contiguous memory).
  bool hugePagesAsked = false;
};
/// A zeroed LargeTable of n doubles (`label`: its name where it is an ordinary view).
LargeTable largeTable(const std::string& label, std::size_t n);

/// Counts, while alive, the Kokkos parallel regions (for, reduce, scan), allocations and deep
/// copies of this process through Kokkos Tools callbacks: the budget tests of the explicit step use
/// it. One at a time; restores the callbacks it found.
class KernelCounter {
public:
  KernelCounter();
  ~KernelCounter();
  KernelCounter(const KernelCounter&) = delete;
  KernelCounter& operator=(const KernelCounter&) = delete;
  /// Parallel regions (for, reduce, scan) launched since construction or reset().
  std::int64_t launches() const;
  /// Kokkos allocations since construction or reset().
  std::int64_t allocations() const;
  /// Kokkos deep copies since construction or reset().
  std::int64_t deepCopies() const;
  /// Launches per kernel name.
  std::map<std::string, std::int64_t> byName() const;
  /// Sets every count to zero.
  void reset();
};

}  // namespace epaphe
