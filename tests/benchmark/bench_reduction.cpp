// Large-model reduction benchmark: imports a CalculiX model (MATRIXSTORAGE run), reduces it by
// Craig-Bampton and prints the time of each phase and the peak memory (getrusage maxrss, largest
// rank and sum over ranks), as one "BENCH {json}" line for bench_reduction.py. Asserts nothing.
//
//   bench_reduction INPUT.inp JOB RETAINED_SET MODES SOLVER [TOLERANCE]
#include "Epaphe_CalculixImport.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_Runtime.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <sys/resource.h>

#include <cstdlib>
#include <iostream>
#include <sstream>

int main(int argc, char** argv) {
  epaphe::Runtime rt(&argc, &argv);
  if (argc < 6) {
    if (rt.rank() == 0) std::cerr << "usage: bench_reduction INPUT.inp JOB RETAINED_SET MODES SOLVER [TOLERANCE]\n";
    return 2;
  }
  try {
    rt.initializeKokkos(1);
    const auto comm = rt.comm();
    epaphe::Stopwatch total, sw;
    const epaphe::FullModel full = epaphe::importCalculix({argv[1], argv[2]}, "blade", comm);
    const double importSeconds = sw.seconds();
    epaphe::CraigBamptonOptions o;
    o.modes = std::atoi(argv[4]);
    o.solver = epaphe::linearSolverNamed(argv[5]);
    if (argc > 6) o.iterativeTolerance = std::atof(argv[6]);
    epaphe::ReductionReport rep;
    const epaphe::ReducedModel red = epaphe::craigBampton(full, full.mesh.nodeSets.at(argv[3]), o, &rep);
    const double totalSeconds = total.seconds();
    const auto fr = epaphe::denseFrequencies(red.K, red.M, red.size);
    struct rusage ru {};
    getrusage(RUSAGE_SELF, &ru);
    const double mb = ru.ru_maxrss / 1024.0;
    // CPU time of this rank (user + system): a figure less sensitive than wall time to a loaded machine.
    const double cpu =
        ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec + 1e-6 * ru.ru_stime.tv_usec;
    double cpuMax = 0;
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, cpu, Teuchos::outArg(cpuMax));
    double maxMb = 0, sumMb = 0;
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, mb, Teuchos::outArg(maxMb));
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, mb, Teuchos::outArg(sumMb));
    std::ostringstream js;
    js.precision(17);
    js << "{\"ranks\": " << comm->getSize() << ", \"solver\": \"" << epaphe::solverName(o.solver)
       << "\", \"free_dofs\": " << full.numFree << ", \"nnz_K\": " << full.K->getGlobalNumEntries()
       << ", \"retained_dofs\": " << rep.retainedDofs << ", \"modes\": " << o.modes
       << ", \"import_s\": " << importSeconds << ", \"factor_s\": " << rep.factorSeconds
       << ", \"constraint_s\": " << rep.constraintSeconds << ", \"eigen_s\": " << rep.eigenSeconds
       << ", \"project_s\": " << rep.projectSeconds << ", \"reduction_s\": " << rep.seconds
       << ", \"total_s\": " << totalSeconds << ", \"cpu_s_max\": " << cpuMax
       << ", \"iterations\": " << rep.solverIterations << ", \"eigen_iterations\": " << rep.eigenIterations
       << ", \"eigen_solves\": " << rep.eigenSolves << ", \"eigen_operator_s\": " << rep.eigenSolveSeconds
       << ", \"maxrss_mb_max\": " << maxMb << ", \"maxrss_mb_sum\": " << sumMb << ", \"f_hz\": [";
    for (std::size_t i = 0; i < fr.size() && i < 10; ++i) js << (i ? ", " : "") << fr[i];
    js << "]}";
    rt.out() << "BENCH " << js.str() << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "bench_reduction: error: " << e.what() << "\n";
    return 1;
  }
}
