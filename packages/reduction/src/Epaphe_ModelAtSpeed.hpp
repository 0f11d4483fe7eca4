#pragma once
// A body turning at a steady speed Omega, modelled in its own frame (the casing turns around it):
// the centrifugal load is static there. The model at speed is the tangent about the static state,
//   (K_e - Omega^2 M_perp) u_s = Omega^2 f_c                          the linear static state
//                                                                     (or stress-stiffened: StaticState),
//   K(Omega) = K_e + K_sigma(u_s) - Omega^2 M_perp                    the tangent stiffness,
// M unchanged, and the nodes moved to x + u_s, so that contact and clearances start from the static
// position at speed (the tip growth). Terms: Epaphe_Centrifugal.hpp. The Coriolis matrix Omega G is
// assembled and its size reported (SpeedReport::coriolisRatio); with RotationOptions::coriolis the
// reduced model keeps it, G_r = V^T G V (reducedCoriolis), and the explicit step carries Omega G_r q'.
#include "Epaphe_Centrifugal.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_LinearSolver.hpp"

#include <vector>

namespace epaphe {

/// The static state at speed: linear ((K_e - Omega^2 M_perp) u_s = Omega^2 f_c), stress-stiffened
/// (K_sigma(u_s) added to the left side, by fixed point: the tension that untwists and straightens a
/// blade stiffens it against its own load, the dominant geometric nonlinearity of a centrifugal state),
/// or automatic: the stress-stiffened one where it moves the largest displacement by more than
/// `staticTolerance` of the linear one, else the linear one.
enum class StaticState { Linear = 0, StressStiffened = 1, Automatic = 2 };

/// The rotation of a body: its speed and axis and how its model at speed is made (see modelAtSpeed()).
struct RotationOptions {
  double speed = 0;              ///< Omega (rad/s); the sign gives the sense about the axis
  SpinAxis axis;                 ///< the rotation axis
  bool stressStiffening = true;  ///< K_sigma
  bool spinSoftening = true;     ///< -Omega^2 M_perp, in the static state and in K(Omega)
  bool coriolis = false;         ///< keep the Coriolis terms Omega G in the dynamics ('Rotation->Coriolis')
  StaticState staticState = StaticState::Automatic;  ///< which static state (see StaticState)
  double staticTolerance = 0.01;  ///< Automatic: the relative change of the largest displacement above which the
                                  ///< stress-stiffened state is kept
  LinearSolver solver = LinearSolver::Mumps;  ///< the solver of the static states
  /// A starting guess of the stress-stiffened state (3 per node), used with StaticState::StressStiffened
  /// only: the fixed point starts there instead of at the linear state, which is then not computed
  /// (SpeedReport::linearLargest and stiffenedChange are 0). Empty: start at the linear state.
  std::vector<double> initialState;
};

/// What making the model at speed found: the static state and what it cost.
struct SpeedReport {
  double speed = 0;                        ///< Omega (rad/s)
  std::vector<double> staticDisplacement;  ///< u_s, 3 per node (mesh order)
  double largestDisplacement = 0;          ///< max over nodes of |u_s| (m)
  int largestNode = -1;                    ///< the node of the largest displacement (-1: none moved)
  double linearLargest = 0;                ///< the linear static state's largest |u_s| (m)
  double stiffenedChange = 0;              ///< |largest stress-stiffened / largest linear - 1|, when computed
  bool stiffened = false;                  ///< u_s is the stress-stiffened state
  int passes = 0;                          ///< its fixed-point passes
  /// Omega ||G|| / sqrt(||K(Omega)|| ||M||) in the Frobenius norm (both kg/s): the size of the Coriolis
  /// terms against the stiffness and inertia they act beside (a ratio, not an error estimate).
  double coriolisRatio = 0;
  /// G / 2 = int rho N^T [a]_x N per unit speed over the free DOFs (CentrifugalTerms::coriolis), on the
  /// mesh at rest.
  Teuchos::RCP<const CrsMatrix> coriolis;
  double seconds = 0;  ///< wall time (s)
};

/// The model at speed (see above); `rest` must come from built-in elements (rest.material). The
/// report, when given, gets the static state.
FullModel modelAtSpeed(const FullModel& rest, const RotationOptions& options, SpeedReport* report);

/// The same with the centrifugal terms of `rest` about `options.axis` given (assembleCentrifugal): the
/// samples of a speed range share them.
FullModel modelAtSpeed(const FullModel& rest, const CentrifugalTerms& terms, const RotationOptions& options,
                       SpeedReport* report);

/// G_r = V^T G V (n x n, column-major, skew), G = 2 `halfG` (CentrifugalTerms::coriolis, over the free
/// DOFs of `full`), V the basis whose rows over every node's DOFs are `recovery` ((3 numNodes) x n,
/// row-major, a reduced model's u = R q): the reduced model's Coriolis matrix per unit speed. Its skew
/// part is kept (the projection's round-off removed). On every rank.
std::vector<double> reducedCoriolis(const CrsMatrix& halfG, const FullModel& full, const std::vector<double>& recovery,
                                    int n);

/// The frequencies (Hz, ascending) of the gyroscopic model M q'' + speed G q' + K q = 0 (n x n dense,
/// column-major; M positive definite): the moduli of the imaginary parts of the eigenvalues of the first
/// order form [0 I; -M^-1 K -M^-1 speed G] (LAPACK dgeev), each whirl once (a pair +-i w counted once).
/// With speed G = 0 they are the frequencies of (K, M).
std::vector<double> gyroscopicFrequencies(const std::vector<double>& K, const std::vector<double>& M,
                                          const std::vector<double>& G, double speed, int n);

}  // namespace epaphe
