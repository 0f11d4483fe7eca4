#pragma once
// The reduced thermal model of a body and its integration (plain data, no Tpetra).
//
// With a basis B that is C-orthonormal and K-orthogonal (B^T C B = I, B^T K B = diag(lambda);
// Epaphe_ThermalReduction.hpp builds it), theta = B eta turns C dtheta/dt + K theta = Q + g into
// independent equations
//
//   d eta_i / dt + lambda_i eta_i = f_i = B_i^T (Q + g),
//
// integrated exactly for a heat input constant over the step h (the exponential integrator,
// docs/theory/heat.md eq. 59):
//
//   eta_i(t + h) = exp(-lambda_i h) eta_i(t) + (1 - exp(-lambda_i h)) / lambda_i f_i,
//
// unconditionally stable and free of time-discretization error for a piecewise-constant input,
// so the thermal step is chosen for the input's variation, not for the model's fastest mode.
//
// Sub-cycling with the mechanical step (docs/theory/heat.md eq. 60): the heat of the mechanical steps of a
// window is summed (addHeat), and the window is advanced at once with the mean power
// (advanceWindow). Energy is conserved exactly: every joule the contact produced enters the model.
// What is lost is when, inside a window, it entered: for mode i the error of eta_i at the window's
// end is at most min(1, lambda_i H) times the window's input (f_i H), first order in the window
// length H for the slow modes that carry the growth of the temperature, and bounded for the fast
// ones, which forget the input within 1 / lambda_i anyway. The temperature the mechanics sees lags by
// at most one window.
#include <string>
#include <vector>

namespace epaphe {

/// A body's reduced thermal model: the rates and basis of its modes (B^T C B = I, B^T K B = diag(rate))
/// and the rows of the basis at the heated nodes.
struct ReducedThermalModel {
  std::string name;                 ///< the body's name
  double referenceTemperature = 0;  ///< T_ref: theta = T - T_ref
  int numNodes = 0;                 ///< nodes of the mesh
  std::vector<double> rate;         ///< lambda_i (1/s), ascending
  std::vector<double> basis;        ///< numNodes x numModes, row-major: theta_n = sum_i basis[n, i] eta_i
  std::vector<double> ambientLoad;  ///< B^T g (convection towards T_inf)
  std::vector<int> heatedNodes;     ///< the nodes heat enters through (contact nodes), in the input's order
  std::vector<double> heatedRows;   ///< heatedNodes.size() x numModes, row-major: the basis at them

  /// The number of modes (coordinates eta).
  int numModes() const { return static_cast<int>(rate.size()); }
  /// T at mesh node `node` for the coordinates eta.
  double temperature(int node, const std::vector<double>& eta) const;
};

/// Integrates a ReducedThermalModel exactly in time for piecewise-constant heat inputs, with
/// sub-cycling windows (see the file's opening comment).
class ThermalIntegrator {
public:
  /// The model is held by reference: it outlives the integrator. Starts at T_ref everywhere.
  explicit ThermalIntegrator(const ReducedThermalModel& model);

  /// Heat entering during a mechanical step dt: power[k] (W) at model.heatedNodes[k] (nullptr: none,
  /// the window only grows longer).
  void addHeat(const double* power, double dt);
  /// Advances over the window of the heat added since the last call, with its mean power. No-op on
  /// an empty window.
  void advanceWindow();
  /// Advances h with power[k] (W) at the heated nodes (nullptr: none), constant over h.
  void advance(double h, const double* power);

  /// The time integrated so far (s).
  double time() const { return time_; }
  /// The heat that entered so far (J), windows not yet advanced included.
  double heatReceived() const { return received_; }
  /// The length of the window being summed (s; 0 after advanceWindow()).
  double windowTime() const { return windowTime_; }
  /// The modal coordinates eta.
  const std::vector<double>& coordinates() const { return eta_; }
  /// T at mesh node `node` now.
  double temperature(int node) const { return model_.temperature(node, eta_); }
  /// The nodes of the model's mesh.
  int numNodes() const { return model_.numNodes; }

  /// Everything the next steps depend on, for checkpoints: the time, the window's length, the heat received,
  /// the coordinates eta and the window's summed heat per heated node (2 + 1 + modes + heated nodes values).
  std::vector<double> state() const;
  /// Restores what state() returned (a restart continues bit for bit); `what` names its source for errors.
  void setState(const std::vector<double>& state, const std::string& what);

private:
  void integrate(double h, const double* power);

  const ReducedThermalModel& model_;
  std::vector<double> eta_, force_, window_;
  std::vector<double> decay_, gain_;  // exp(-lambda_i h) and (1 - exp(-lambda_i h)) / lambda_i for h = step_
  double step_ = -1;
  double time_ = 0, windowTime_ = 0, received_ = 0;
};

}  // namespace epaphe
