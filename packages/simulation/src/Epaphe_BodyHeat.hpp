#pragma once
// Heat from rubbing (docs/theory/heat.md, docs/user/heat.md): a body's 'Thermal' list, its reduced
// thermal model, and the observer that feeds it the frictional heat of its contact nodes.
//
// Per contact node a of a body with a thermal model, the heat friction makes over a step
// (SurfaceContact::frictionHeatByNode: the friction force times the slip, the surface's motion
// under the node less the node's) is split by the partition coefficient p: p enters the body at
// the node, 1 - p the counterface (the surface rubbed, not modelled). p = e_b / (e_b + e_c) by
// default, e = sqrt(k rho c) the thermal effusivities of the body and the counterface (two
// semi-infinite solids in perfect contact share a flux so; Blok 1937), or the deck's value.
// The thermal model advances every 'Sub-steps' mechanical steps (sub-cycling, eq. 60).
//
// Output, per body <b> with a thermal model:
//   /thermal/<b>                 attributes partition, modes, sub_steps, reference_temperature
//   /thermal/<b>/nodes, rates    the contact nodes' numbers, the reduced model's rates lambda_i (1/s)
//   /thermal/<b>/time            the record times (s), every 'Output->Every' steps and at the last
//   /thermal/<b>/temperature     (records x contact nodes): T at the contact nodes, as of the last thermal step
//   /thermal/<b>/max_temperature the largest T over the body's nodes
//   /thermal/<b>/friction_heat   the heat friction made at the body's contact nodes so far (J)
//   /thermal/<b>/coating_heat    with a coating, its plastic dissipation made at the body's contact nodes so far (J)
//   /thermal/<b>/heat            the part of the heat the body received (J): p (friction_heat + coating_heat)
//   /thermal/<b>/growth          (records x 3 contact nodes): the contact nodes' thermal growth (m), with an
//                                'Expansion coefficient'
//
// Thermal growth (eq. 61): with an 'Expansion coefficient' alpha, after every thermal step the contact
// nodes' reference positions become X_0 + G eta, their static thermal displacement: the tip grows and
// the clearance closes. The contact's work is the forces' on the motion D dq of the mechanical
// coordinates, so the energy balance is unchanged; the growth lags the heat by at most one thermal step.
// Checkpoints hold the thermal state (state()): a run with a thermal model restarts bit for bit.
//
// The energy record's heat term (eq. 63): every step, before the energy monitor (sources()), the heat friction
// made at every contact node, the normal forces' work and the counterface's work through friction go into the
// loop's accumulators (LoopAccumulators::frictionHeat, normalWork, counterfaceWork), and each thermal body's
// share p Q_b into heatReceived: the energy balance then reads E + D + Q - W_n - W_s - ... = E_0.
//
// A coating's plastic dissipation is a heat source too (eq. 64): the dissipation of the elements a contact node
// shortened over the step (CoatingContact::dissipationByNode) is added to the node's heat, split by the same
// partition; it stays in the balance's normal work (the coating takes it from the normal forces) and is kept
// apart as LoopAccumulators::coatingHeat.
#include "Epaphe_ExplicitLoop.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_ReducedThermal.hpp"
#include "Epaphe_SceneBody.hpp"
#include "Epaphe_SurfaceContact.hpp"
#include "Epaphe_ThermalParameters.hpp"

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace epaphe {

/// What the deck's 'Thermal' list of a body needs besides its validators, checked without a model:
/// contact nodes, the node sets it names, a definite K, the material (a CalculiX import's input or the
/// deck's keys). `mesh`: buildThermalMesh's; `ctx` names the body, `body` is its deck name.
void checkThermal(const Teuchos::ParameterList& bodyParams, const Mesh& mesh, const std::string& ctx,
                  const std::string& body, const std::string& deckPath);

/// A body's heat from rubbing: its reduced thermal model, its integrator and the share of the heat it takes.
struct BodyHeat {
  int body = 0;                                   ///< index in the scene's bodies
  ReducedThermalModel model;                      ///< the body's reduced thermal model
  std::unique_ptr<ThermalIntegrator> integrator;  ///< integrates it (sub-cycled)
  double partition = 1;  ///< p: the share of the friction heat the body takes (the rest goes to the counterface)
  int subSteps = 1;      ///< the mechanical steps per thermal step ('Sub-steps')
  double expansion = 0;  ///< alpha (1/K), 'Expansion coefficient'; 0: no thermal growth
  /// G (3 contact nodes x modes, row-major): the contact nodes' static thermal displacement per unit of
  /// each thermal coordinate (eq. 61; empty without thermal growth)
  std::vector<double> growth;
  ///@{
  int contactBegin = 0, contactEnd = 0;  ///< the body's nodes in the contact order
  ///@}
};

/// The thermal models of the bodies that have one (collective over `comm`: assembly and reduction).
std::vector<std::unique_ptr<BodyHeat>> buildBodyHeats(const Teuchos::ParameterList& deck, const std::string& origin,
                                                      const std::vector<std::unique_ptr<SceneBody>>& bodies,
                                                      const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                                      std::ostream& out);

/// Feeds each body's thermal model the friction heat of its contact nodes and writes the temperatures
/// (layout in the file's opening comment).
class HeatOutput : public LoopObserver {
public:
  /// `heats` non-empty; records every `every` steps. `restX`: the contact nodes' reference positions
  /// (3 per node, the contact's order), which the thermal growth moves.
  HeatOutput(io::Hdf5File& file, std::vector<std::unique_ptr<BodyHeat>> heats, SurfaceContact& contact,
             const std::vector<std::unique_ptr<SceneBody>>& bodies, long long every, std::vector<double> restX);
  ~HeatOutput() override;
  /// The observer that measures each step's friction heat and supplied work into the loop's accumulators (the
  /// energy record's heat term, eq. 63): register it before the energy monitor, and this one after the history
  /// (the growth it applies at a thermal step's end reaches the next step's correction, not this step's record).
  LoopObserver* sources();
  void afterCorrect(ExplicitLoop& loop) override;
  void endStep(ExplicitLoop& loop) override;
  void endRun(ExplicitLoop& loop) override;
  /// The bodies' thermal models.
  const std::vector<std::unique_ptr<BodyHeat>>& heats() const { return heats_; }

  /// Its series (those of /thermal), for checkpoints.
  std::vector<io::Series*> series();
  /// Everything the next steps depend on, for checkpoints: per body its integrator's state (eta, the window
  /// being summed, the heat received) and the friction and coating heat made at its nodes.
  std::vector<double> state() const;
  /// Restores what state() returned, and the contact nodes' grown positions (a restart continues bit for
  /// bit); `what` names the source for errors.
  void setState(const std::vector<double>& state, const std::string& what);

private:
  struct Record;
  class Sources;
  void measure(ExplicitLoop& loop);  // the step's heat by node and the heat term (Sources::afterCorrect)
  void record(ExplicitLoop& loop);
  std::unique_ptr<Sources> sources_;
  bool rubbing_ = false;  // this step's contact had active nodes (heat_ holds their heat)
  std::vector<std::unique_ptr<BodyHeat>> heats_;
  void grow(const BodyHeat& b);  // the body's contact nodes' grown positions, into X_
  SurfaceContact& contact_;
  long long every_;
  std::vector<double> restX_, X_;  // the contact nodes' reference positions, at rest and grown
  std::vector<double> heat_, power_, normalWork_, counterfaceWork_;  // per contact node, this step
  std::vector<double> coatingHeat_;           // per contact node: the coating's dissipation this step (J)
  std::vector<double> made_, coatingMadeBy_;  // per body, J: friction heat, coating dissipation
  std::vector<std::unique_ptr<Record>> records_;
};

}  // namespace epaphe
