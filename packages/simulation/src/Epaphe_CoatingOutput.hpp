#pragma once
// The abradable coatings' output (Epaphe_AbradableCoating.hpp) as a loop observer. Layout, per coated
// surface <s>:
//   /coating/<s>                attributes thickness, youngs_modulus, yield_stress, hardening_modulus,
//                               elements {n_u, n_v}; at the end of a complete run max_wear (m),
//                               plastic_dissipation (J), lobes, lobe_angles (rad), dominant_order,
//                               harmonic_angles (rad) (the definition: wearLobes)
//   /coating/<s>/angle (n_u)    element columns' centre angle about the surface's axis (rad, its own frame)
//   /coating/<s>/axial (n_v)    element rows' centre along the axis (m)
//   /coating/<s>/area (n_u x n_v) each element's face area A_e (m^2)
//   /coating/<s>/mesh/{points, quads} (4 n_u n_v x 3, n_u n_v x 4): each element's quadrilateral at the unworn front
//                               (ParaView: <stem>.xmf draws it with the wear of each record)
//   /coating/<s>/time, /coating/<s>/wear (records x n_u x n_v, m): the plastic shortening of every
//                               element, every `wearEvery` steps and at the last step
//   /energy/plastic_dissipation, /energy/coating_elastic (J): at every history record
// The energy balance (/energy/balance_error) holds the coating through the contact work: the work
// of the contact forces on the bodies is what the coating stores and dissipates (and the rigid
// law's own impact loss); the two series above split it.
#include <memory>
#include <string>
#include <vector>

#include "Epaphe_EnergyMonitor.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_SurfaceContact.hpp"

namespace epaphe {

/// The abradable coatings' output, as a loop observer (layout in the file's opening comment).
class CoatingOutput : public LoopObserver {
public:
  /// `contact` has coatings (SurfaceContact::coating()); `wearEvery` > 0 (steps).
  CoatingOutput(io::Hdf5File& file, SurfaceContact& contact, const EnergyMonitor& monitor, long long wearEvery,
                bool fresh);
  ~CoatingOutput() override;
  /// Its series (dissipation, elastic energy, and per coated surface time and wear), for checkpoints.
  std::vector<io::Series*> series();
  void afterCorrect(ExplicitLoop& loop) override;
  /// Lobes of the final wear, as attributes and summary lines.
  void endRun(ExplicitLoop& loop) override;
  /// The summary lines of the coatings (wear, dissipation, lobes), after a complete run.
  const std::vector<std::string>& summary() const { return summary_; }

  /// The coated surfaces' names (for the XDMF file, FieldOutput::setCoatings).
  std::vector<std::string> surfaces() const;

private:
  struct Coated;
  void writeMesh(const BSplineSurface& surface, const CoatingMaterial& m, const std::string& group);
  io::Hdf5File& file_;
  SurfaceContact& contact_;
  const EnergyMonitor& monitor_;
  long long wearEvery_;
  io::Series plastic_, elastic_;
  std::vector<std::unique_ptr<Coated>> coated_;
  std::vector<std::string> summary_;
};

}  // namespace epaphe
