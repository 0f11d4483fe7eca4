#pragma once
// A run-up: a rotating body whose speed follows a law in time (Epaphe_SpeedLaw.hpp), as Batailly et
// al. cross a critical speed with a time-dependent angular speed. Its reduced model is the
// parametric one (Epaphe_SpeedParametricModel.hpp) on a fixed basis, the Craig-Bampton basis at the
// law's start speed, where the stiffness and the static state are polynomials in xi = (Omega / Omega_max)^2:
//
//   K_r(xi) = sum_k xi^k R_k,   u_s(xi) = sum_k xi^k g_k   (contact nodes)
//
// Nothing is reduced during the run. The stiffness is refreshed on a grid of xi: at step n the body
// uses K_r(xi_l), l = round(xi(t_n) / dxi), and its contact nodes start from X + u_s(xi_l). With
// dxi = 1e-3 the xi used is within 5e-4 of the exact one; the stiffening of the blades Epaphe models
// changes omega^2 by less than 40 % over xi in [0, 1], so a frequency lags the speed by less than
// 1e-4 relative, well inside the width of a resonance (the modal damping ratio, 5e-3 in the decks).
// A refresh forms A = -P K once more (n^3); over a run-up from 0 to Omega_max there are 1000.
// The level depends on t_n only, so a restart refreshes as the uninterrupted run does.
//
// Energy. The scheme conserves E_{n+1/2} = 1/2 v^T M v + 1/2 q_n^T K q_{n+1} step by step with the
// step's K (Epaphe_CentralDifference.hpp); when step n uses K_l' instead of K_l, the stored energy
// changes by the drive's work
//
//   W_drive += 1/2 q_{n-1}^T (K_l' - K_l) q_n,
//
// the change of the strain energy at fixed q due to the changing speed; the energy balance counts it
// (Epaphe_EnergyMonitor.hpp). q is the motion about the static state: M d^2u_s/dt^2, the inertia of
// the static state's slow change, is neglected (a ramp much slower than the blade's periods).
// The damping matrix and hence the contact flexibility P are those of the start speed.
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_SpeedLaw.hpp"

#include <vector>

namespace epaphe {

/// One driven body's polynomials, as the scene builds them.
struct RunUpModel {
  SpeedLaw law;                                ///< the body's speed in time
  double maxSpeed = 1;                         ///< Omega_max of xi
  std::vector<std::vector<double>> stiffness;  ///< R_0 .. R_(S-1), n x n column-major
  std::vector<std::vector<double>> growth;     ///< g_0 .. g_(S-1) at its contact nodes, 3 per node
  std::vector<double> restX;                   ///< its contact nodes at rest, 3 per node
  int contactBegin = 0;                        ///< its first node in the contact's order
  double xiStep = 1e-3;                        ///< dxi

  /// The level l = round(xi(t) / dxi) of time `t` (s), xi = (speed(t) / maxSpeed)^2.
  long long level(double t) const;
  /// xi_l = l dxi.
  double xiOf(long long level) const { return xiStep * static_cast<double>(level); }
  /// K_r(xi_l), n x n column-major.
  std::vector<double> stiffnessAt(long long level) const;
  /// X + u_s(xi_l) at its contact nodes.
  std::vector<double> positionsAt(long long level) const;
};

/// The run-up of the driven bodies: refreshes each one's stiffness and contact nodes when its level
/// changes (see the file's opening comment) and counts the drive's work.
class RunUp : public LoopObserver {
public:
  /// A driven body.
  struct Driven {
    std::size_t body = 0;                     ///< its index among the loop's bodies
    CentralDifference* integrator = nullptr;  ///< its central difference (its stiffness is replaced)
    const RunUpModel* model = nullptr;        ///< its polynomials (not owned)
  };
  /// Puts every driven body at its level of t = 0 (its stiffness and contact nodes): construct it
  /// before the energy monitor takes E_0. `contactX`: all contact nodes' reference positions.
  RunUp(std::vector<Driven> driven, ContactCorrector* contact, std::vector<double> contactX);

  /// A restart: every body at the level of the last step done, without drive work (it is in the
  /// checkpoint); its first step then refreshes as the uninterrupted run did.
  void beginRun(ExplicitLoop& loop) override;
  /// A body whose level changed: K refreshed, the drive's work counted, the contact nodes moved.
  void beginStep(ExplicitLoop& loop) override;
  /// The stiffness refreshes made so far.
  long long refreshes() const { return refreshes_; }

private:
  void apply(std::size_t i, long long level);
  std::vector<Driven> driven_;
  ContactCorrector* contact_;
  std::vector<double> contactX_;
  std::vector<long long> level_;
  std::vector<std::vector<double>> K_;  // each body's current stiffness
  long long refreshes_ = 0;
};

}  // namespace epaphe
