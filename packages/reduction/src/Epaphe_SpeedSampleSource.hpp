#pragma once
// Where the full model of a rotating body at a sample speed comes from, for the parametric model over
// a speed range (Epaphe_SpeedParametricModel.hpp): Epaphe's own elements (BuiltInSpeedSource, the
// model at speed of Epaphe_ModelAtSpeed.hpp) or matrices another code assembled at that speed (the
// CalculiX source of the simulation package reads a ccx run per speed). Every sample of a source
// shares the reference model's DOF numbering, mesh and mass matrix; only K(Omega) and the static
// displacement u_s(Omega) change with the speed.
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ModelAtSpeed.hpp"

#include <vector>

namespace epaphe {

/// The full model of a rotating body at one speed.
struct SpeedSample {
  FullModel model;                         ///< K(Omega) and M over the reference's DOF numbering
  std::vector<double> staticDisplacement;  ///< u_s(Omega), 3 per node (mesh order)
  double seconds = 0;                      ///< time to build or read it
  SpeedReport report;                      ///< Epaphe's elements: the static state's report (speed 0 otherwise)
};

/// Where the full models of a rotating body at the sample speeds come from (see the file's opening comment).
class SpeedSampleSource {
public:
  virtual ~SpeedSampleSource() = default;
  /// The model whose mesh, DOF numbering and mass matrix every sample shares.
  virtual const FullModel& reference() const = 0;
  /// The model at `speed` (rad/s); the parametric model asks for its samples from the fastest down.
  virtual SpeedSample sample(double speed) = 0;
  /// The static state of every sample (Epaphe's own elements: linear or stress-stiffened, an automatic
  /// choice resolved at the first, fastest, sample; imported: what the other code computed, reported
  /// as Linear).
  virtual StaticState staticState() const = 0;
  /// G / 2 per unit speed over the reference's free DOFs (Epaphe_Centrifugal.hpp) when the body keeps
  /// its Coriolis terms ('Rotation->Coriolis'); null otherwise, or when the source has no elements.
  virtual Teuchos::RCP<const CrsMatrix> coriolis() const { return Teuchos::null; }
};

/// The samples from Epaphe's elements: modelAtSpeed(rest, rotation at the speed). An automatic static
/// state is resolved at the first sample asked (the fastest, where the two states differ most) and
/// kept for the others, so that u_s(Omega) and K_sigma are interpolated across one model; a
/// stress-stiffened fixed point starts at the previous sample's state scaled by (Omega / Omega_prev)^2.
class BuiltInSpeedSource : public SpeedSampleSource {
public:
  /// Samples of `rest` (built-in elements) about `rotation`'s axis with its options (its speed is ignored).
  BuiltInSpeedSource(const FullModel& rest, const RotationOptions& rotation) : rest_(rest), common_(rotation) {}
  const FullModel& reference() const override { return rest_; }
  SpeedSample sample(double speed) override;
  StaticState staticState() const override {
    return common_.staticState == StaticState::Automatic ? StaticState::Linear : common_.staticState;
  }
  Teuchos::RCP<const CrsMatrix> coriolis() const override {
    return common_.coriolis ? terms().coriolis : Teuchos::null;
  }

private:
  /// The centrifugal terms, assembled once for every sample.
  const CentrifugalTerms& terms() const {
    if (terms_.load.is_null()) terms_ = assembleCentrifugal(rest_, common_.axis);
    return terms_;
  }

  const FullModel& rest_;
  RotationOptions common_;
  mutable CentrifugalTerms terms_;
  double previousSpeed_ = 0;
  std::vector<double> previousState_;
  bool first_ = true;
};

}  // namespace epaphe
