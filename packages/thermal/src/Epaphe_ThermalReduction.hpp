#pragma once
// Reduction of the full thermal model (Epaphe_ThermalModel.hpp) to a ReducedThermalModel
// (docs/theory/heat.md eq. 58):
//
//   V = [ Phi | K^{-1} E | K^{-1} C K^{-1} E | K^{-1} g ],
//
// Phi the `modes` lowest modes of K phi = lambda C phi (the slow, body-wide heating and cooling),
// K^{-1} E the static responses to unit heat inputs at the heated nodes (E: one column per heated
// node; what a hot spot looks like once conduction has spread it, which no handful of modes
// represents: the modes' sum converges like sum 1/lambda_i), K^{-1} C K^{-1} E their first Krylov
// correction (the "static + dynamic correction" of modal truncation: the part of a fresh input that
// has not spread yet; `krylovBlocks` sets how many such blocks), and K^{-1} g the steady state of the
// convection alone. Each input's static response in the basis makes the reduced model's steady state
// the full model's, exactly. The static and Krylov vectors are scaled to a unit C-norm, made
// C-orthogonal to the modes (which are kept whole: a static response is mostly the slowest mode, and
// dropping directions of the mixed Gram matrix would lose part of it) and C-orthonormal among
// themselves (what is left of one below 1e-10 of its C-norm^2 is in the others' span and dropped); on
// [Phi | S] the Rayleigh-Ritz problem of K is solved: B^T C B = I and B^T K B = diag(lambda), the form
// ThermalIntegrator integrates exactly.
#include "Epaphe_LinearSolver.hpp"
#include "Epaphe_ReducedThermal.hpp"
#include "Epaphe_ThermalModel.hpp"

#include <vector>

namespace epaphe {

/// How reduceThermal() builds the reduced basis.
struct ThermalReductionOptions {
  int modes = 10;  ///< lowest modes of (K, C) kept
  /// Krylov blocks per heated node: 1, its static response K^{-1} e; 2 adds K^{-1} C K^{-1} e; k adds
  /// up to (K^{-1} C)^{k-1} K^{-1} e.
  int krylovBlocks = 2;
  LinearSolver solver = LinearSolver::Mumps;  ///< the solver of K in the static responses
  double eigenTolerance = 1e-10;              ///< Anasazi's relative residual tolerance
  /// Up to this many free nodes, every eigenpair by LAPACK on the dense matrices, else Anasazi's
  /// lowest ones.
  int denseUpTo = 3000;
};

/// K must be definite: a face held at T_ref or a convection (an insulated body has no static
/// response to a heat input). Runs on every rank; the result is replicated.
ReducedThermalModel reduceThermal(const ThermalFullModel& full, const std::vector<int>& heatedNodes,
                                  const ThermalReductionOptions& options);

/// The full model as a ReducedThermalModel: every mode of (K, C) by LAPACK (small models; the
/// reference the reduction's error is measured against).
ReducedThermalModel fullThermalModel(const ThermalFullModel& full, const std::vector<int>& heatedNodes);

}  // namespace epaphe
