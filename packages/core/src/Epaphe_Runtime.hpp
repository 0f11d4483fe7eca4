#pragma once
// Process-wide runtime: MPI (through Teuchos), Kokkos on its OpenMP execution space, rank-0
// output, and wall-clock accounting of the phases of a run.
#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include <chrono>
#include <map>
#include <memory>
#include <ostream>
#include <string>

namespace Teuchos { class GlobalMPISession; }

namespace epaphe {

class Runtime {
public:
  /// Initializes MPI. Kokkos is initialized separately, once the deck gives the thread count.
  Runtime(int* argc, char*** argv);
  ~Runtime();
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  /// Initializes Kokkos with `threads` OpenMP threads (0: OMP_NUM_THREADS or all cores).
  void initializeKokkos(int threads);
  int threads() const;

  /// Rank and size in the communicator the runs use: MPI_COMM_WORLD, or this process alone
  /// after useOwnCommunicator().
  int rank() const;
  int size() const;
  Teuchos::RCP<const Teuchos::Comm<int>> comm() const;
  /// From now on the runs of this process use a communicator of this process alone, so that each
  /// MPI rank runs its own decks (a speed sweep distributed over ranks). worldComm() still sees all.
  void useOwnCommunicator();
  Teuchos::RCP<const Teuchos::Comm<int>> worldComm() const;
  /// std::cout on rank 0, a sink elsewhere.
  std::ostream& out() const;

private:
  std::string sessionBase_;  // a private directory for Open MPI's session files ("" : none), removed at the end
  std::unique_ptr<Teuchos::GlobalMPISession> mpi_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  bool kokkos_ = false;
};

/// Accumulates wall time per named phase (projection, contact, integration, output, ...).
class CostSplit {
public:
  void add(const std::string& phase, double seconds) { seconds_[phase] += seconds; }
  double get(const std::string& phase) const {
    auto it = seconds_.find(phase);
    return it == seconds_.end() ? 0.0 : it->second;
  }
  const std::map<std::string, double>& all() const { return seconds_; }

private:
  std::map<std::string, double> seconds_;
};

class Stopwatch {
public:
  Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
  void restart() { t0_ = std::chrono::steady_clock::now(); }

private:
  std::chrono::steady_clock::time_point t0_;
};

/// RAII: adds the lifetime of the scope to a phase of a CostSplit.
class ScopedPhase {
public:
  ScopedPhase(CostSplit& split, const char* phase) : split_(split), phase_(phase) {}
  ~ScopedPhase() { split_.add(phase_, watch_.seconds()); }

private:
  CostSplit& split_;
  const char* phase_;
  Stopwatch watch_;
};

/// "1 h 02 min", "3 min 12 s", "4.21 s", "812 us".
std::string formatDuration(double seconds);

}  // namespace epaphe
