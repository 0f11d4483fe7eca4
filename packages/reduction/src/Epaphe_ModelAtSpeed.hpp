#pragma once
// A body turning at a steady speed Omega, modelled in its own frame (the casing turns around it):
// the centrifugal load is static there. The model at speed is the tangent about the static state,
//   (K_e - Omega^2 M_perp) u_s = Omega^2 f_c                          the linear static state
//                                                                     (or stress-stiffened: StaticState),
//   K(Omega) = K_e + K_sigma(u_s) - Omega^2 M_perp                    the tangent stiffness,
// M unchanged, and the nodes moved to x + u_s, so that contact and clearances start from the static
// position at speed (the tip growth). Terms: Epaphe_Centrifugal.hpp. The Coriolis matrix Omega G is
// assembled and its size reported (SpeedReport::coriolisRatio), not kept in the model.
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

struct RotationOptions {
  double speed = 0;  // Omega (rad/s); the sign gives the sense about the axis
  SpinAxis axis;
  bool stressStiffening = true;  // K_sigma
  bool spinSoftening = true;     // -Omega^2 M_perp, in the static state and in K(Omega)
  StaticState staticState = StaticState::Automatic;
  double staticTolerance = 0.01;
  LinearSolver solver = LinearSolver::Mumps;
  /// A starting guess of the stress-stiffened state (3 per node), used with StaticState::StressStiffened
  /// only: the fixed point starts there instead of at the linear state, which is then not computed
  /// (SpeedReport::linearLargest and stiffenedChange are 0). Empty: start at the linear state.
  std::vector<double> initialState;
};

struct SpeedReport {
  double speed = 0;
  std::vector<double> staticDisplacement;  // u_s, 3 per node (mesh order)
  double largestDisplacement = 0;          // max over nodes of |u_s| (m)
  int largestNode = -1;
  double linearLargest = 0;    // the linear static state's largest |u_s| (m)
  double stiffenedChange = 0;  // |largest stress-stiffened / largest linear - 1|, when computed
  bool stiffened = false;      // u_s is the stress-stiffened state
  int passes = 0;              // its fixed-point passes
  /// Omega ||G|| / sqrt(||K(Omega)|| ||M||) in the Frobenius norm (both kg/s): the size of the Coriolis
  /// terms against the stiffness and inertia they act beside (a ratio, not an error estimate).
  double coriolisRatio = 0;
  double seconds = 0;
};

/// The model at speed (see above); `rest` must come from built-in elements (rest.material). The
/// report, when given, gets the static state.
FullModel modelAtSpeed(const FullModel& rest, const RotationOptions& options, SpeedReport* report);

}  // namespace epaphe
