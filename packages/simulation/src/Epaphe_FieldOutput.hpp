#pragma once
// Frames of the whole bodies for ParaView as a loop observer (Output->Fields every > 0): every
// `every` steps (and the last) /fields/time and each body's /bodies/<b>/fields/{position,
// displacement} (u = R q, eq. 2.5), and temperature for a body with a thermal model; fresh runs also
// get the meshes and the rigid surfaces' grids.
// writeXdmf() then describes the frames in an XDMF file beside the HDF5 one.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_SceneBody.hpp"

#include <memory>
#include <string>
#include <vector>

namespace epaphe {

class ThermalIntegrator;

/// Frames of the whole bodies for ParaView, as a loop observer (see the file's opening comment).
class FieldOutput : public LoopObserver {
public:
  /// `drawn[s]`: surface s is drawn on its own (rigid); carried surfaces move with their body.
  FieldOutput(io::Hdf5File& file, const std::vector<std::unique_ptr<SceneBody>>& bodies,
              const std::vector<const BSplineSurface*>& drawn, int every, bool fresh);
  ~FieldOutput() override;

  /// Its series (per body position and displacement, then the frames' times), for checkpoints.
  std::vector<io::Series*> series();
  /// Frames written (and buffered).
  long long frames() const { return static_cast<long long>(time_.size()); }

  void afterCorrect(ExplicitLoop& loop) override;

  /// `<stem>.xmf` for `h5path` (closed): a temporal collection per body whose frames pick one record
  /// of the fields by hyperslab, and the rigid surfaces as quads.
  void writeXdmf(const std::string& h5path, const std::string& xmfPath) const;
  /// Coated surfaces (Epaphe_CoatingOutput.hpp): writeXdmf adds each coating's elements with the
  /// wear of every wear record (a temporal collection).
  void setCoatings(std::vector<std::string> surfaces) { coatings_ = std::move(surfaces); }
  /// Body `body`'s temperature field from its thermal model (Epaphe_BodyHeat.hpp, heat from rubbing):
  /// every frame then also holds `/bodies/<b>/fields/temperature`, T at each node (as of the last thermal
  /// step), and writeXdmf adds it as the scalar 'temperature'. `integrator` outlives this observer.
  void setTemperature(int body, const ThermalIntegrator* integrator);

private:
  struct BodyFields;
  io::Hdf5File& file_;
  const std::vector<std::unique_ptr<SceneBody>>& bodies_;
  std::vector<const BSplineSurface*> drawn_;
  std::vector<std::string> coatings_;
  int every_;
  std::vector<std::unique_ptr<BodyFields>> perBody_;
  io::Series time_;
};

}  // namespace epaphe
