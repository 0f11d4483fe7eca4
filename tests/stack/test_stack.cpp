// Proves the dependency stack is what Epaphe needs:
//   mumps N   Amesos2 over MUMPS solves a 1000 x 1000 SPD tridiagonal system with a known solution
//             (residual and error checked) on however many MPI ranks run it;
//   klu2      on more than one rank, Epaphe refuses KLU2 (wrong answers in Trilinos 13.2) with a
//             clear message; on one rank KLU2 solves correctly;
//   kokkos N  the default execution space is OpenMP and N threads really run a kernel.
#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SparseSolver.hpp"
#include "Epaphe_TpetraTypes.hpp"

#include <Kokkos_Core.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <set>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace epaphe;

namespace {

int solveTridiagonal(const Runtime& rt, const std::string& solverName) {
  const GO n = 1000;
  auto map = Teuchos::rcp(new Map(n, 0, rt.comm()));
  auto A = Teuchos::rcp(new CrsMatrix(map, 3));
  for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
    const GO i = map->getGlobalElement(l);
    std::vector<GO> c;
    std::vector<double> v;
    if (i > 0) {
      c.push_back(i - 1);
      v.push_back(-1.0);
    }
    c.push_back(i);
    v.push_back(2.5);
    if (i < n - 1) {
      c.push_back(i + 1);
      v.push_back(-1.0);
    }
    A->insertGlobalValues(i, Teuchos::ArrayView<const GO>(c), Teuchos::ArrayView<const double>(v));
  }
  A->fillComplete();
  // x_exact(i) = sin(i / 10) + 1; b = A x_exact
  MultiVector xe(map, 1), b(map, 1), x(map, 1), r(map, 1);
  {
    auto h = xe.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l)
      h(l, 0) = std::sin(map->getGlobalElement(l) / 10.0) + 1.0;
  }
  A->apply(xe, b);
  auto solver = makeDirectSolver(A, solverName, "the test matrix");
  solver->solve(b, x);
  A->apply(x, r);
  r.update(-1.0, b, 1.0);
  Teuchos::Array<double> rn(1), bn(1), en(1);
  r.norm2(rn());
  b.norm2(bn());
  x.update(-1.0, xe, 1.0);
  x.norm2(en());
  const double rel = rn[0] / bn[0];
  rt.out() << solverName << " on " << rt.size() << " rank(s): relative residual " << rel << ", error norm " << en[0]
           << "\n";
  return (rel < 1e-10 && en[0] < 1e-8) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  Runtime rt(&argc, &argv);
  const std::string what = argc > 1 ? argv[1] : "";
  const int threads = argc > 2 ? std::atoi(argv[2]) : 2;
  rt.initializeKokkos(threads);
  int failed = 0;
  try {
    if (what == "mumps") {
      failed = solveTridiagonal(rt, "MUMPS");
    } else if (what == "klu2") {
      if (rt.size() == 1) {
        failed = solveTridiagonal(rt, "KLU2");
      } else {
        try {
          solveTridiagonal(rt, "KLU2");
          rt.out() << "KLU2 was not refused on " << rt.size() << " ranks\n";
          failed = 1;
        } catch (const Error& e) {
          rt.out() << "refused as expected: " << e.what() << "\n";
          failed = std::string(e.what()).find("use MUMPS") == std::string::npos;
        }
      }
    } else if (what == "kokkos") {
      const std::string space = Kokkos::DefaultExecutionSpace::name();
      const int conc = Kokkos::DefaultExecutionSpace::concurrency();
      // Count the distinct OpenMP threads that execute iterations of a kernel.
      Kokkos::View<int*> who("who", 1 << 16);
      Kokkos::parallel_for(
          "epaphe::test::threads",
          Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace, Kokkos::Schedule<Kokkos::Static>>(0, who.extent(0)),
          KOKKOS_LAMBDA(const int i) {
            double s = 0;
            for (int k = 0; k < 2000; ++k) s += std::sin(i + k);
            who(i) = omp_get_thread_num() + (s > 1e300 ? 1 : 0);
          });
      auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), who);
      std::set<int> ids(h.data(), h.data() + h.extent(0));
      rt.out() << "execution space " << space << ", concurrency " << conc << ", threads seen " << ids.size() << "\n";
      failed = !(space == "OpenMP" && conc == threads && static_cast<int>(ids.size()) == threads);
    } else {
      std::cerr << "usage: test_stack mumps|klu2|kokkos [threads]\n";
      return 2;
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    failed = 1;
  }
  int global = 0;
  Teuchos::reduceAll(*rt.comm(), Teuchos::REDUCE_MAX, failed, Teuchos::outArg(global));
  rt.out() << (global ? "FAILED" : "PASSED") << "\n";
  return global;
}
