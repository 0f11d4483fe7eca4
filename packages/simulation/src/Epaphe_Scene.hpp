#pragma once
// A scene built from a deck, on every MPI rank: the bodies (imported or built-in meshes, reduced by
// the factory or loaded from their cache, broadcast from rank 0), their initial state and
// integrators, the surfaces (rigid, or carried by a body), the contact and its run guards; checked
// at t = 0 (initial velocities and penetrations) and against each body's stable step. The run
// (Simulation::run) adds the loop and its observers.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ContactGuards.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_GuardedContact.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SceneBody.hpp"
#include "Epaphe_SpeedParametricModel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <string>
#include <vector>

namespace epaphe {

/// What the setup found, for the summary.
struct SetupReport {
  /// the time step, the critical step of the stiffest body (s) and the setup's wall time (s)
  ///@{
  double timeStep = 0, criticalStep = 0, setupSeconds = 0;
  ///@}
  int initialPenetrations = 0;         ///< resolved gently (count, deepest in m)
  double initialPenetrationDepth = 0;  ///< the deepest of them (m)
  std::vector<std::string> warnings;   ///< warnings of the setup (allowed large motions, ...)
};

/// A scene built from a deck (see the file's opening comment): the bodies, the surfaces, the contact and
/// its run guards.
class Scene {
public:
  /// `output`: the run's output file (cache files are named beside it); `restarting`: a restart
  /// (the output file exists).
  Scene(const Deck& deck, const Runtime& runtime, std::string output, bool restarting);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  /// Builds and reduces the bodies (collective over MPI), builds the surfaces and the contact,
  /// checks the start and the stable steps; Error on what would run to nonsense.
  void build();

  /// The bodies, in the deck's order.
  const std::vector<std::unique_ptr<SceneBody>>& bodies() const { return bodies_; }
  /// The surfaces, in the deck's order.
  const std::vector<std::unique_ptr<BSplineSurface>>& surfaces() const { return surfaces_; }
  /// Per surface: carried by a body (else rigid).
  const std::vector<bool>& surfaceCarried() const { return surfaceCarried_; }
  /// The size of the system coordinates (all bodies' coordinates, stacked).
  int systemSize() const { return systemSize_; }
  /// Null without contact nodes or surfaces.
  SurfaceContact* contact() const { return contact_.get(); }
  /// The contact nodes' reference positions at the start (3 per node, the contact's order).
  const std::vector<double>& contactPositions() const { return contactX_; }
  /// The run guards (null without contact).
  const ContactGuards* guards() const { return guards_.get(); }
  /// The contact and its guards as the explicit loop's ContactCorrector (null without contact).
  ContactCorrector* corrector() const { return corrector_.get(); }
  /// What the setup found.
  const SetupReport& report() const { return report_; }
  /// q_0 of 'Time->Initial state' = Static equilibrium (eqs. 71-72; system coordinates, all bodies
  /// stacked); empty: the bodies start at q_0 = 0.
  const std::vector<double>& initialState() const { return initialState_; }

private:
  using Body = SceneBody;
  // The steps of build(), in order.
  void loadOrReduce(Body* body, const Teuchos::ParameterList& bodyParams);
  std::string reducedModelKey(const Body& body, const Teuchos::ParameterList& bodyParams) const;
  void loadOrBuildReducedModel(Body* body, const Teuchos::ParameterList& bodyParams, const std::string& key,
                               const std::string& cacheFile, bool useCache, const RotationOptions& rotation);
  SpeedParametricModel parametricModel(Body* body, const Teuchos::ParameterList& bodyParams, const std::string& key,
                                       const std::string& cacheFile, bool useCache, const RotationOptions& rotation);
  void reportGrowth(const Body& body, const Teuchos::ParameterList& bodyParams, std::ostream& out) const;
  void reportCoriolis(const Body& body, std::ostream& out) const;
  void setInitialState(Body* body, const Teuchos::ParameterList& bodyParams, double h, const DampingOptions& damping);
  /// Builds the surfaces and the contact; returns, per body, the reduced DOFs of the surfaces it
  /// carries (penalty springs act on them too, for the stable step).
  std::vector<std::vector<int>> setupSurfacesAndContact(const ContactOptions& options);
  void checkContactAtStart(const Teuchos::ParameterList& contactParams, double h);
  void staticEquilibrium(const Teuchos::ParameterList& contactParams);
  void checkStableSteps(const std::vector<std::vector<int>>& carriedDofs, const ContactOptions& copt,
                        const DampingOptions& damping);

  const Deck& deck_;
  const Runtime& rt_;
  std::string output_;
  bool restarting_;
  std::vector<std::unique_ptr<Body>> bodies_;
  std::vector<std::unique_ptr<BSplineSurface>> surfaces_;
  std::vector<bool> surfaceCarried_;
  int systemSize_ = 0;  // all bodies' reduced coordinates, stacked
  std::unique_ptr<SurfaceContact> contact_;
  std::vector<double> contactX_;
  std::unique_ptr<ContactGuards> guards_;
  std::unique_ptr<GuardedContact> corrector_;
  SetupReport report_;
  std::vector<double> initialState_;
};

}  // namespace epaphe
