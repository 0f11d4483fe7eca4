#pragma once
// Process-wide runtime: MPI (through Teuchos), Kokkos on its OpenMP execution space, rank-0
// output, and wall-clock accounting of the phases of a run.
#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <chrono>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>
#include <memory>
#include <ostream>
#include <string>
#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

namespace Teuchos {
class GlobalMPISession;
}

namespace epaphe {

/// The process-wide runtime: MPI (through Teuchos) for the program's lifetime, Kokkos once initialized,
/// the communicator the runs use and rank-0 output. One per program, made first in main().
class Runtime {
public:
  /// Initializes MPI. Kokkos is initialized separately, once the deck gives the thread count.
  Runtime(int* argc, char*** argv);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  /// Initializes Kokkos with `threads` OpenMP threads (0: OMP_NUM_THREADS or all cores).
  void initializeKokkos(int threads);
  /// The OpenMP threads Kokkos runs on (0 before initializeKokkos()).
  int threads() const;

  /// Rank and size in the communicator the runs use: MPI_COMM_WORLD, or this process alone
  /// after useOwnCommunicator().
  int rank() const;
  /// The number of ranks in comm().
  int size() const;
  /// The communicator the runs use (MPI_COMM_WORLD, or this process alone after useOwnCommunicator()).
  Teuchos::RCP<const Teuchos::Comm<int>> comm() const;
  /// From now on the runs of this process use a communicator of this process alone, so that each
  /// MPI rank runs its own decks (a speed sweep distributed over ranks). worldComm() still sees all.
  void useOwnCommunicator();
  /// MPI_COMM_WORLD, whatever useOwnCommunicator() did.
  Teuchos::RCP<const Teuchos::Comm<int>> worldComm() const;
  /// std::cout on rank 0, a sink elsewhere.
  std::ostream& out() const;

private:
  std::string sessionBase_;  // a private directory for Open MPI's session files ("" : none), removed at the end
  std::unique_ptr<Teuchos::GlobalMPISession> mpi_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  bool kokkos_ = false;
};

/// A cheap monotonic tick count for timing the phases of a step: x86's time-stamp counter (constant
/// rate and synchronized across cores on the CPUs and VMs of the last 15 years; 10 ns a read on this
/// project's machines against steady_clock's 26 ns, and a step reads it about ten times), else
/// steady_clock's count. CostSplit turns ticks into seconds.
inline std::uint64_t phaseTicks() {
#if defined(__x86_64__) || defined(__i386__)
  return __rdtsc();
#else
  return static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
}

/// Accumulates wall time per named phase (projection, contact, integration, output, ...), in
/// phaseTicks(), turned into seconds by the tick rate measured against steady_clock over the split's
/// own lifetime (from its construction to the reading). A phase is a slot found by the address of its
/// name first (the string literals of ScopedPhase: a few pointer comparisons a phase, where a std::map
/// of strings cost a string and its comparisons, 2 % of rotor37-massless' instructions), by its
/// characters when that address is new.
class CostSplit {
public:
  CostSplit() : t0_(std::chrono::steady_clock::now()), k0_(phaseTicks()) {}
  /// The slot of `phase`, a name of static storage (a string literal): its address is kept.
  int slot(const char* phase) {
    for (const auto& [key, i] : keys_)
      if (key == phase) return i;
    int i = 0;
    while (i < static_cast<int>(names_.size()) && names_[i] != phase) ++i;
    if (i == static_cast<int>(names_.size())) {
      names_.emplace_back(phase);
      ticks_.push_back(0);
    }
    keys_.emplace_back(phase, i);
    return i;
  }
  /// Adds phaseTicks() elapsed (a difference of two readings; a negative one, from a counter that is
  /// not synchronized across cores, counts 0).
  void add(int slot, std::uint64_t from, std::uint64_t to) { ticks_[slot] += to > from ? to - from : 0; }
  /// The seconds accumulated in `phase` (0 for a phase never added to).
  double get(const std::string& phase) const {
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == phase) return static_cast<double>(ticks_[i]) * secondsPerTick();
    return 0.0;
  }
  /// Every phase and its seconds, by name.
  std::map<std::string, double> all() const {
    std::map<std::string, double> m;
    const double rate = secondsPerTick();
    for (std::size_t i = 0; i < names_.size(); ++i) m[names_[i]] = static_cast<double>(ticks_[i]) * rate;
    return m;
  }

private:
  double secondsPerTick() const {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const std::uint64_t k = phaseTicks();
    return k > k0_ ? seconds / static_cast<double>(k - k0_) : 0.0;
  }
  std::chrono::steady_clock::time_point t0_;
  std::uint64_t k0_;
  std::vector<std::pair<const char*, int>> keys_;  // name addresses seen, and their slot
  std::vector<std::string> names_;
  std::vector<std::uint64_t> ticks_;
};

/// Wall time since construction or the last restart() (std::chrono::steady_clock).
class Stopwatch {
public:
  Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
  /// Seconds since construction or the last restart().
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  /// Starts counting again from now.
  void restart() { t0_ = std::chrono::steady_clock::now(); }

private:
  std::chrono::steady_clock::time_point t0_;
};

/// RAII: adds the lifetime of the scope to a phase of a CostSplit.
class ScopedPhase {
public:
  /// Starts timing `phase` of `split`; the destructor adds the elapsed time to it.
  ScopedPhase(CostSplit& split, const char* phase) : split_(split), slot_(split.slot(phase)), start_(phaseTicks()) {}
  ~ScopedPhase() { split_.add(slot_, start_, phaseTicks()); }

private:
  CostSplit& split_;
  int slot_;
  std::uint64_t start_;
};

/// "1 h 02 min", "3 min 12 s", "4.21 s", "812 us".
std::string formatDuration(double seconds);

}  // namespace epaphe
