#include "Epaphe_Damping.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_Parallel.hpp"

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace epaphe {

void rayleighFromRatios(double f1, double xi1, double f2, double xi2, double& alpha, double& beta) {
  EPAPHE_REQUIRE(f1 > 0 && f2 > f1, "Rayleigh damping: frequencies " << f1 << " and " << f2 << " Hz; give 0 < f1 < f2");
  const double w1 = 2 * M_PI * f1, w2 = 2 * M_PI * f2;
  beta = 2 * (xi2 * w2 - xi1 * w1) / (w2 * w2 - w1 * w1);
  alpha = 2 * w1 * w2 * (xi1 * w2 - xi2 * w1) / (w2 * w2 - w1 * w1);
  EPAPHE_REQUIRE(alpha >= 0 && beta >= 0,
                 "Rayleigh damping: ratios "
                     << xi1 << " at " << f1 << " Hz and " << xi2 << " at " << f2 << " Hz give alpha = " << alpha
                     << ", beta = " << beta
                     << "; a negative coefficient would feed energy into some modes: choose closer ratios");
}

std::vector<double> modalDamping(const ReducedModel& model, const DampingOptions& damping) {
  std::vector<double> d;
  for (double w2 : model.modalStiffness()) {
    if (damping.type == DampingType::Rayleigh)
      d.push_back(damping.alpha + damping.beta * w2);
    else if (damping.type == DampingType::Modal)
      d.push_back(2 * damping.ratio * std::sqrt(w2));
    else
      d.push_back(0.0);
  }
  return d;
}

std::vector<double> dampingMatrix(const ReducedModel& model, const DampingOptions& damping) {
  const int n = model.size;
  std::vector<double> D(static_cast<std::size_t>(n) * n, 0.0);
  if (model.massless()) {
    const std::vector<double> d = modalDamping(model, damping);
    const int nb = model.boundarySize();
    for (int k = 0; k < model.numModes; ++k) D[static_cast<std::size_t>(nb + k) * n + nb + k] = d[k];
  } else if (damping.type == DampingType::Rayleigh) {
    for (std::size_t k = 0; k < D.size(); ++k) D[k] = damping.alpha * model.M[k] + damping.beta * model.K[k];
  } else if (damping.type == DampingType::Modal) {
    std::vector<double> V;
    const std::vector<double> w = denseEigenpairs(model.K, model.M, n, &V);
    // MV = M V; D = (MV) diag(2 xi omega) (MV)^T
    std::vector<double> MV(D.size()), MVs(D.size());
    Teuchos::BLAS<int, double> blas;
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, 1.0, model.M.data(), n, V.data(), n, 0.0, MV.data(), n);
    for (int j = 0; j < n; ++j) {
      const double c = 2 * damping.ratio * std::sqrt(std::max(w[j], 0.0));
      for (int i = 0; i < n; ++i)
        MVs[static_cast<std::size_t>(j) * n + i] = c * MV[static_cast<std::size_t>(j) * n + i];
    }
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, n, n, n, 1.0, MVs.data(), n, MV.data(), n, 0.0, D.data(), n);
  }
  return D;
}

std::string fullModelDampingProblem(const DampingOptions& damping) {
  if (damping.type == DampingType::Modal)
    return "modal damping needs every mode of the full model; use Rayleigh damping with Beta = 0 (D = Alpha M), "
           "or reduce the body";
  if (damping.type == DampingType::Rayleigh && damping.beta != 0.0) {
    std::ostringstream os;
    os << "Rayleigh Beta = " << damping.beta << " makes M/h^2 + D/2h non-diagonal (a linear solve per step); set "
       << "Beta = 0 (and no 'Rayleigh frequencies', which give Beta > 0), or reduce the body";
    return os.str();
  }
  return "";
}

}  // namespace epaphe
