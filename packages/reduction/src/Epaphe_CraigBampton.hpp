#pragma once
// Craig-Bampton reduction (thesis section 2.3.3, eq. 2.12):
//
//   x = R q,   R = [ I      0   ]     Psi = -K_CC^{-1} K_CR   (constraint modes, eq. 2.10)
//                  [ Psi   Phi  ]     K_CC Phi = M_CC Phi Omega^2 (fixed-interface modes, eq. 2.13)
//
// with K_red = R^T K R and M_red = R^T M R (eqs. 2.6-2.7). K_CC is factored once by Amesos2
// (MUMPS by default; or Belos CG, Jacobi-preconditioned, with no factor); the constraint modes are one multi-RHS solve
// with that factor, and the fixed-interface modes come from Anasazi with shift-invert through the same factor. Guyan is
// Craig-Bampton with zero modes (eq. 2.11).
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <array>
#include <string>
#include <vector>

namespace epaphe {

/// The options of a Craig-Bampton, Guyan or massless-boundary reduction.
struct CraigBamptonOptions {
  int modes = 0;                              ///< fixed-interface modes kept
  LinearSolver solver = LinearSolver::Mumps;  ///< K_CC: Amesos2 MUMPS or KLU2 (one factor), or Belos CG (iterative)
  double iterativeTolerance = 1e-12;          ///< Belos CG: relative residual of each solve
  double eigenTolerance = 1e-10;              ///< Anasazi's relative residual tolerance of the fixed-interface modes
  /// Craig-Bampton and Guyan: the full model's lowest `checkFrequencies` frequencies, computed
  /// through the reduction's K_CC factor (no second factorization) into ReducedModel::fullFrequencies
  /// (left empty when the body has a free rigid motion; fullModelFrequencies then serves). 0: none.
  int checkFrequencies = 0;
  /// Anasazi's relative residual tolerance tau for the check: a symmetric problem's Ritz values err
  /// by about tau^2 / (relative gap), so 1e-6 gives the frequencies to about 1e-11 (measured on the
  /// 64,500-DOF blade: equal to 1e-10's to 11 digits, with 48 solves instead of 66).
  double checkTolerance = 1e-6;
  /// Massless boundary: keep, of the lowest `candidates` elastic modes (0: just the lowest `modes`),
  /// the `modes` that a load spread evenly over the retained nodes along `loadDirection` excites most
  /// (selectByParticipation in Epaphe_MasslessBoundary.cpp).
  int candidates = 0;
  /// Massless boundary: every eigenpair at once by LAPACK on the dense matrices (small models)
  /// instead of Anasazi's lowest ones.
  bool denseEigen = false;
  /// Massless boundary: the direction of the load that selects the modes (candidates > 0).
  std::array<double, 3> loadDirection{0.0, 0.0, 0.0};
  /// Craig-Bampton: the basis only (recovery, modeFrequencies); K and M are not projected (left
  /// empty), for callers that project on a basis of their own (Epaphe_SpeedParametricModel.hpp).
  bool basisOnly = false;
  /// Craig-Bampton: a reduction of a nearby model of the same body and retained nodes (another speed)
  /// whose fixed-interface modes start Anasazi's search; null: a random start.
  const ReducedModel* startModes = nullptr;
};

/// What a reduction did and what it cost (wall times in s).
struct ReductionReport {
  double seconds = 0;  ///< wall time of the whole reduction
  /// wall times of the phases: factorization of K_CC, constraint modes, eigenmodes, projection
  ///@{
  double factorSeconds = 0, constraintSeconds = 0, eigenSeconds = 0, projectSeconds = 0;
  ///@}
  double checkSeconds = 0;  ///< the frequency check (checkFrequencies), not part of `seconds`
  /// a parametric model over a speed range: the static states at its samples (part of `seconds`;
  /// projectSeconds is then the common basis and the projections)
  double staticSeconds = 0;
  /// retained DOFs (kept physical) and condensed DOFs (the interior)
  ///@{
  int retainedDofs = 0, condensedDofs = 0;
  ///@}
  int eigenIterations = 0;       ///< Anasazi iterations
  long eigenSolves = 0;          ///< vectors through the shift-invert operator
  double eigenSolveSeconds = 0;  ///< of eigenSeconds, the time in the operator (M products and solves)
  long solverIterations = 0;     ///< Belos CG: iterations of all solves (constraint modes and Anasazi)
};

/// `retained`: nodes whose DOFs stay physical (interface, contact nodes). Runs on every rank of
/// the model's communicator; the result is replicated on every rank.
ReducedModel craigBampton(const FullModel& full, const std::vector<int>& retained, const CraigBamptonOptions& opt,
                          ReductionReport* report = nullptr);

/// Massless-boundary reduction (MacNeal's residual flexibility; Monjaraz-Tec, Gross & Krack 2022;
/// the model is described in Epaphe_ReducedModel.hpp): the body's `opt.modes` lowest normal modes
/// with the retained nodes free, and the static response to forces on the retained DOFs, from one
/// factor of the full K. A free body (no constrained DOF) keeps its six rigid-body modes besides
/// (numModes = opt.modes + 6, Omega = 0) and the inertia-relief static response, from one factor of
/// K + sigma M. The retained DOFs carry no mass, so the highest frequency is the last kept mode's,
/// not the boundary's.
ReducedModel masslessBoundary(const FullModel& full, const std::vector<int>& retained, const CraigBamptonOptions& opt,
                              ReductionReport* report = nullptr);

/// The lowest `count` natural frequencies (Hz) of the full model, by Anasazi's shift-invert on
/// (K, M) with a negative shift sigma, so that K - sigma M is positive definite also with rigid-body
/// modes. The shift-invert spectrum 1/(lambda - sigma) separates the lowest modes only when sigma
/// is not far below them: `upperBoundsHz`, frequencies of a reduced model of the same body (Rayleigh-
/// Ritz values, upper bounds of the full model's; a lumped-mass model's are close estimates), give
/// sigma = -omega_e^2 / 2 with omega_e the lowest elastic one of them. Without them, sigma = -1e-4 max_i K_ii / M_ii,
/// which a fine mesh (large K_ii / M_ii) puts so far below the lowest modes that Anasazi needs minutes.
std::vector<double> fullModelFrequencies(const FullModel& full, int count, LinearSolver solver = LinearSolver::Mumps,
                                         double iterativeTolerance = 1e-12,
                                         const std::vector<double>& upperBoundsHz = {});

}  // namespace epaphe
