#include "Epaphe_Runtime.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Teuchos_GlobalMPISession.hpp>

#include <cstdio>
#include <dlfcn.h>
#include <iostream>

namespace epaphe {
namespace {
class NullBuffer : public std::streambuf {
protected:
  int overflow(int c) override { return c; }
};
NullBuffer nullBuffer;
std::ostream nullStream(&nullBuffer);
}  // namespace

Runtime::Runtime(int* argc, char*** argv)
    : mpi_(std::make_unique<Teuchos::GlobalMPISession>(argc, argv, nullptr)),
      comm_(Teuchos::DefaultComm<int>::getComm()) {}

Runtime::~Runtime() {
  if (kokkos_ && Kokkos::is_initialized()) Kokkos::finalize();
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
int Runtime::rank() const { return comm_->getRank(); }
int Runtime::size() const { return comm_->getSize(); }
Teuchos::RCP<const Teuchos::Comm<int>> Runtime::comm() const { return comm_; }
// An MpiComm, not a SerialComm: Amesos2's MUMPS adapter takes the raw MPI communicator.
void Runtime::useOwnCommunicator() {
  comm_ = Teuchos::rcp(new Teuchos::MpiComm<int>(Teuchos::opaqueWrapper<MPI_Comm>(MPI_COMM_SELF)));
}
Teuchos::RCP<const Teuchos::Comm<int>> Runtime::worldComm() const { return Teuchos::DefaultComm<int>::getComm(); }
std::ostream& Runtime::out() const { return rank() == 0 ? std::cout : nullStream; }

std::string formatDuration(double s) {
  char buf[64];
  if (s >= 3600) std::snprintf(buf, sizeof buf, "%d h %02d min", int(s / 3600), int(s / 60) % 60);
  else if (s >= 60) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s / 60), int(s) % 60);
  else if (s >= 1) std::snprintf(buf, sizeof buf, "%.2f s", s);
  else if (s >= 1e-3) std::snprintf(buf, sizeof buf, "%.2f ms", s * 1e3);
  else std::snprintf(buf, sizeof buf, "%.1f us", s * 1e6);
  return buf;
}

}  // namespace epaphe
