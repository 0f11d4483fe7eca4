#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_GlobalMPISession.hpp>

#include <cstdio>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <dlfcn.h>
#include <iostream>
#include <sys/stat.h>
#include <unistd.h>

namespace epaphe {
namespace {
class NullBuffer : public std::streambuf {
protected:
  int overflow(int c) override { return c; }
};
NullBuffer nullBuffer;
std::ostream nullStream(&nullBuffer);

// A process started without a launcher (no mpiexec, srun: an MPI singleton) talks to no other
// process, yet Open MPI 4.1 starts its runtime daemon and initialises UCX for it: 0.31 s of the
// 0.35 s that `epaphe-run --check` took (a bare MPI_Init + MPI_Finalize: 0.31 s). An isolated
// singleton (ess_singleton_isolated: no daemon, hence no MPI_Comm_spawn, which Epaphe never calls)
// with the ob1 messaging layer (no UCX) starts in 0.02 s. Isolated singletons all name their session
// directory <tmp>/ompi.<host>.<uid>/jf.0/1/0, so concurrent ones race for it (2 of 200 simultaneous
// starts failed in mkdir): each gets its own base directory, epaphe-mpi-<pid>-XXXXXX, removed after
// MPI_Finalize (and, for a process killed before, by the next start: the directories of this user
// whose process no longer exists). Set only when no launcher's variable is there, and never over a
// value the user set; other MPI libraries ignore these variables. Returns the directory to remove
// ("" for none).
void removeStaleSessionDirs(const std::string& tmp) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(tmp, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("epaphe-mpi-", 0) != 0) continue;
    const long pid = std::strtol(name.c_str() + 11, nullptr, 10);
    struct stat st;
    if (pid <= 0 || stat(entry.path().c_str(), &st) != 0 || st.st_uid != getuid()) continue;
    if (kill(static_cast<pid_t>(pid), 0) == -1 && errno == ESRCH) std::filesystem::remove_all(entry.path(), ec);
  }
}

std::string lightSingletonStart() {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "SLURM_PROCID"})
    if (std::getenv(launched)) return "";
  if (std::getenv("OMPI_MCA_ess_singleton_isolated") || std::getenv("OMPI_MCA_orte_tmpdir_base")) return "";
  const char* env = std::getenv("TMPDIR");
  const std::string tmp = env && *env ? env : "/tmp";
  removeStaleSessionDirs(tmp);
  std::string base = tmp + "/epaphe-mpi-" + std::to_string(getpid()) + "-XXXXXX";
  if (!mkdtemp(base.data())) return "";  // no private directory: the default start, slower but safe
  setenv("OMPI_MCA_orte_tmpdir_base", base.c_str(), 1);
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 1);
  setenv("OMPI_MCA_pml", "ob1", 0);
  return base;
}

std::unique_ptr<Teuchos::GlobalMPISession> startMpi(int* argc, char*** argv, std::string& sessionBase) {
  sessionBase = lightSingletonStart();
  return std::make_unique<Teuchos::GlobalMPISession>(argc, argv, nullptr);
}
}  // namespace

Runtime::Runtime(int* argc, char*** argv)
    : mpi_(startMpi(argc, argv, sessionBase_)), comm_(Teuchos::DefaultComm<int>::getComm()) {}

Runtime::~Runtime() {
  if (kokkos_ && Kokkos::is_initialized()) Kokkos::finalize();
  comm_ = Teuchos::null;
  mpi_.reset();  // MPI_Finalize
  if (!sessionBase_.empty()) {
    std::error_code ec;
    std::filesystem::remove_all(sessionBase_, ec);
  }
}

void Runtime::initializeKokkos(int threads) {
  if (Kokkos::is_initialized()) return;
  Kokkos::InitArguments args;
  args.num_threads = threads > 0 ? threads : -1;
  args.disable_warnings = true;
  Kokkos::initialize(args);
  kokkos_ = true;
  // One pool of threads: Kokkos' OpenMP threads. OpenBLAS (Debian's BLAS, with its own pthreads)
  // is set to one thread: its threads and Kokkos' spinning ones would share the same cores, and
  // the per-step products of a reduced model are too small to split anyway (measured on the
  // 112-DOF bar: with 2 Kokkos threads 44k -> 133k steps/s; one 112 x 112 dgemv 2.2 -> 1.2 us).
  // Looked up at run time: another BLAS behind libblas.so simply has no such function.
  if (void* f = dlsym(RTLD_DEFAULT, "openblas_set_num_threads")) reinterpret_cast<void (*)(int)>(f)(1);
}

int Runtime::threads() const {
  return Kokkos::is_initialized() ? Kokkos::DefaultHostExecutionSpace::concurrency() : 0;
}
int Runtime::rank() const {
  return comm_->getRank();
}
int Runtime::size() const {
  return comm_->getSize();
}
Teuchos::RCP<const Teuchos::Comm<int>> Runtime::comm() const {
  return comm_;
}
// An MpiComm, not a SerialComm: Amesos2's MUMPS adapter takes the raw MPI communicator.
void Runtime::useOwnCommunicator() {
  comm_ = Teuchos::rcp(new Teuchos::MpiComm<int>(Teuchos::opaqueWrapper<MPI_Comm>(MPI_COMM_SELF)));
}
Teuchos::RCP<const Teuchos::Comm<int>> Runtime::worldComm() const {
  return Teuchos::DefaultComm<int>::getComm();
}
std::ostream& Runtime::out() const {
  return rank() == 0 ? std::cout : nullStream;
}

std::string formatDuration(double s) {
  char buf[64];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%d h %02d min", int(s / 3600), int(s / 60) % 60);
  else if (s >= 60)
    std::snprintf(buf, sizeof buf, "%d min %02d s", int(s / 60), int(s) % 60);
  else if (s >= 1)
    std::snprintf(buf, sizeof buf, "%.2f s", s);
  else if (s >= 1e-3)
    std::snprintf(buf, sizeof buf, "%.2f ms", s * 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.1f us", s * 1e6);
  return buf;
}

}  // namespace epaphe
