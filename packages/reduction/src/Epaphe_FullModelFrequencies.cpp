// The full model's lowest frequencies (Epaphe_CraigBampton.hpp, fullModelFrequencies).
#include "Epaphe_CraigBampton.hpp"

#include "Epaphe_EigenSolver.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ReductionShared.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <numeric>
#include <array>
#include <memory>
#include <cmath>

namespace epaphe {

std::vector<double> fullModelFrequencies(const FullModel& full, int count, LinearSolver solver,
                                         double iterativeTolerance, const std::vector<double>& upperBoundsHz) {
  double sigma = 0;
  // The lowest elastic bound: above 1e-6 of the highest (rigid-body modes of a reduced model are
  // round-off, many orders below); the shift halfway from it to minus itself.
  const double top = upperBoundsHz.empty() ? 0.0 : *std::max_element(upperBoundsHz.begin(), upperBoundsHz.end());
  double elastic = 0;
  for (double f : upperBoundsHz)
    if (f > 1e-6 * top && (elastic == 0 || f < elastic)) elastic = f;
  if (elastic > 0) {
    const double omega = 2 * M_PI * elastic;
    sigma = -0.5 * omega * omega;
  } else {
    sigma = -1e-4 * largestDiagonalRatio(*full.K, *full.M);
  }
  auto shifted = Tpetra::MatrixMatrix::add(1.0, false, *full.K, -sigma, false, *full.M);
  auto factor = makeSolver(shifted, solver, "K - sigma M of body '" + full.name + "'", iterativeTolerance);
  EigenOptions eo;
  eo.count = count;
  eo.shift = sigma;
  EigenResult er = lowestEigenpairs(full.K, full.M, *factor, eo);
  std::vector<double> f;
  for (double l : er.lambda) f.push_back(std::sqrt(std::max(l, 0.0)) / (2 * M_PI));
  return f;
}

}  // namespace epaphe
