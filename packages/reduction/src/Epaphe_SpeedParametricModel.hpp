#pragma once
// One reduced model of a rotating body over a speed range [Omega_min, Omega_max], built from a few
// Craig-Bampton reductions at sample speeds Omega_s (Epaphe_ModelAtSpeed.hpp for each):
//
//   T = [ I      0   ]   a common basis: the boundary columns are the constraint modes at the first
//       [ Psi_1  V   ]   sample; V orthonormalises every sample's fixed-interface modes Phi_s, the
//                        changes of its constraint modes Psi_s - Psi_1 and its static state's interior
//                        part u_s - Psi_1 u_s,b (all vanish on the retained DOFs)
//
//   K_T(Omega) = sum_k xi^k C_k,   xi = (Omega / Omega_max)^2,   k = 0 .. S-1,   M_T = T^T M T,
//
// the C_k interpolating T^T K(Omega_s) T at the S samples exactly (a polynomial in Omega^2: K(Omega) is
// K_e - Omega^2 M_perp + K_sigma(u_s(Omega)) with u_s a series in Omega^2; with S = 3 and a sample at
// rest this is the classical K_0 + Omega^2 K_1 + Omega^4 K_2). The static state is the Galerkin
// solution on T, u_s(Omega) = T K_T(Omega)^-1 b(Omega), with the reduced load b interpolated through
// the samples' T^T K(Omega_s) u_s: u_s at a sample, and between samples it follows the stiffness, where
// a polynomial through the samples' u_s misses its curvature in Omega^2. It is stored as a polynomial
// in xi fitted to the Galerkin solutions, u_s(Omega) = sum_k xi^k g_k (degree 2 to 8).
//
// At a speed, at() reduces this model once more by Craig-Bampton on its own interior block, dense:
// the model handed to a run has today's size (retained DOFs + the deck's modes). At a sample speed the
// common basis contains that speed's constraint and fixed-interface modes, so the result is the direct
// reduction at that speed (Rayleigh-Ritz recovers eigenvectors its space contains); between samples
// it is an interpolation, whose error against direct reductions the tests and epaphe-modes --campbell
// measure.
//
// The massless boundary (Epaphe_ReducedModel.hpp) the same way: T is an orthonormal basis of every
// sample's static responses K(Omega_s)^-1 E_b to forces on the retained DOFs and its modes Phi_s (the
// span of its recovery columns), K_T(Omega) and u_s(Omega) interpolated as above, and at() builds the
// massless-boundary model of the dense model on T: its lowest modes (Rayleigh-Ritz) and the static
// responses (Galerkin), both exact at a sample, whose basis contains them.
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_ModelAtSpeed.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SpeedSampleSource.hpp"

#include <vector>

namespace epaphe {

/// One reduced model of a rotating body over a speed range (see the file's opening comment).
struct SpeedParametricModel {
  /// The model on the common basis T: K = C_0 (the stiffness at rest), M = T^T M T, recovery = T,
  /// coords at rest; its size N, numModes = N - retained DOFs; its kind says the method. A massless
  /// boundary's T has no identity block: nodeDof names the rows of T at the retained DOFs, and
  /// modalTranslation holds T^T M e_d (N x 3).
  ReducedModel base;
  std::vector<double> speeds;                  ///< the samples, ascending (rad/s)
  std::vector<std::vector<double>> stiffness;  ///< C_1 .. C_(S-1), N x N column-major each
  std::vector<std::vector<double>> growth;     ///< g_0 .. g_P, 3 per node each: u_s(Omega) = sum_k xi^k g_k
  double growthFitError = 0;  ///< the polynomial's largest difference from the Galerkin static state, relative
  int boundarySize = 0;       ///< retained DOFs, the first columns of T
  /// The static state of every sample (an Automatic choice resolved at the highest speed).
  StaticState staticState = StaticState::Linear;

  /// The slowest sample speed (rad/s).
  double minSpeed() const { return speeds.front(); }
  /// The fastest sample speed, Omega_max (rad/s).
  double maxSpeed() const { return speeds.back(); }
  /// T^T K(Omega) T.
  std::vector<double> stiffnessAt(double speed) const;
  /// u_s(Omega), 3 per node.
  std::vector<double> staticDisplacementAt(double speed) const;
  /// The lowest frequencies (Hz) of the common-basis model at `speed`, with the retained DOFs free.
  std::vector<double> frequenciesAt(double speed, int count) const;
  /// The Craig-Bampton model at `speed` with `modes` fixed-interface modes (see above); its coords are
  /// the static position at that speed. An Error names `context` when the speed is outside
  /// [minSpeed, maxSpeed] (by more than 1e-9 of the range) or `modes` exceeds the interior size.
  /// `basis`, when given, receives the N x n basis S of that reduction (column-major).
  ReducedModel at(double speed, int modes, const std::string& context, std::vector<double>* basis = nullptr) const;
  /// For a run-up: the model at `speed` as at(), and its stiffness over the whole range on that fixed
  /// basis S, K_r(xi) = sum_k xi^k R_k with R_k = S^T C_k S (R_0 from C_0, the stiffness at rest): the
  /// same polynomial in xi as the common-basis model, of the run's size, evaluated without a reduction.
  struct FixedBasis {
    ReducedModel model;                          ///< the model at the speed, as at()
    std::vector<std::vector<double>> stiffness;  ///< R_0 .. R_(S-1), n x n column-major each
  };
  /// The model at `speed` with `modes` modes and its stiffness over the range on that basis (see FixedBasis).
  FixedBasis onFixedBasis(double speed, int modes, const std::string& context) const;
  /// xi = (speed / maxSpeed)^2, the variable of the polynomials.
  double xiOf(double speed) const { return (speed / maxSpeed()) * (speed / maxSpeed()); }

private:
  ReducedModel masslessAt(double speed, int modes, const std::string& context) const;
};

/// Builds the parametric model of `rest` (built-in elements) from Craig-Bampton reductions at
/// `speeds` (at least 2, distinct; sorted here), each with `options.modes` modes, about `rotation`'s
/// axis (its speed is ignored). Cost: one static state and one reduction per sample.
SpeedParametricModel parametricCraigBampton(const FullModel& rest, const std::vector<int>& retained,
                                            const CraigBamptonOptions& options, const RotationOptions& rotation,
                                            std::vector<double> speeds, ReductionReport* report = nullptr);

/// The same from the models of `source` at `speeds` (at least 2, distinct; sorted here): Epaphe's
/// elements or matrices imported at each speed (Epaphe_SpeedSampleSource.hpp). The interpolation is
/// exact at the samples whatever the source.
SpeedParametricModel parametricCraigBampton(SpeedSampleSource& source, const std::vector<int>& retained,
                                            const CraigBamptonOptions& options, std::vector<double> speeds,
                                            ReductionReport* report = nullptr);

/// The same by massless-boundary reductions (masslessBoundary) at the samples, each with `options.modes`
/// lowest modes; the body must be held (a clamped node set) and keep the lowest modes (no candidates).
SpeedParametricModel parametricMasslessBoundary(const FullModel& rest, const std::vector<int>& retained,
                                                const CraigBamptonOptions& options, const RotationOptions& rotation,
                                                std::vector<double> speeds, ReductionReport* report = nullptr);
/// The same from the models of `source` at `speeds`.
SpeedParametricModel parametricMasslessBoundary(SpeedSampleSource& source, const std::vector<int>& retained,
                                                const CraigBamptonOptions& options, std::vector<double> speeds,
                                                ReductionReport* report = nullptr);

/// `count` sample speeds spread over [min, max] at Chebyshev-Lobatto points in Omega^2 (both ends
/// included): the interpolation in Omega^2 is then well conditioned.
std::vector<double> sampleSpeeds(double minSpeed, double maxSpeed, int count);

}  // namespace epaphe
