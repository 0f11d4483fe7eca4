#pragma once
// A reduction method: what turns a body's full model and its retained nodes into the ReducedModel the
// loop steps, chosen by the deck's 'Reduction->Method'. Each method owns its deck keys in the body's
// Reduction sublist (getValidParameters(), merged into the deck schema), reads them (setParameters())
// and answers what the rest of Epaphe asks of it: whether it keeps retained nodes, what its cached
// model depends on, the frequency check, the checks made before any model is built, and over a speed
// range its parametric model (from a SpeedSampleSource, Epaphe_SpeedSampleSource.hpp).
//
// ReductionRegistry keys the methods by their deck name. The built-in ones (Craig-Bampton, Guyan,
// None, Full, lumped mass, Massless boundary; Epaphe_ReductionMethods.cpp) are registered on first
// use; an application adds its own with ReductionRegistry::add() before it reads a deck.
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SpeedParametricModel.hpp"
#include "Epaphe_SpeedSampleSource.hpp"

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace epaphe {

/// The frequency check of a body ('Reduction->Frequency check' = count > 0): the full model's lowest
/// `count` frequencies (Hz), at the cost of what the reduction has not computed yet. A lumped model's
/// own frequencies (it has no dense matrices to give them) come in `lumped`.
struct FrequencyCheck {
  /// the full model's lowest frequencies (Hz); a lumped model's own
  ///@{
  std::vector<double> full, lumped;
  ///@}
  bool reused = false;            ///< the reduction's own modes are the full model's (massless boundary)
  bool throughReduction = false;  ///< computed by the reduction through its factor (Craig-Bampton, Guyan)
  double seconds = 0;             ///< wall time (s)
};

/// What the checks made before any model is built know of a body with a built-in mesh.
struct ReductionMeshFacts {
  std::string context;  ///< the start of messages: the deck's path, ": body" and the body's name in single quotes
  const Teuchos::ParameterList* reduction;  ///< the body's Reduction sublist
  /// free DOFs of the full model, DOFs of the retained nodes
  ///@{
  int freeDofs = 0, retainedDofs = 0;
  ///@}
  std::string clampedSet;                  ///< 'Clamped node set' ("" for a free body)
  std::array<double, 3> gravity{0, 0, 0};  ///< the body's gravity (m/s^2)
};

/// A reduction method: what turns a body's full model into the model the loop steps, chosen by
/// 'Reduction->Method' (see the file's opening comment). Each owns its Reduction keys and answers the
/// checks, the cache and the frequency check.
class ReductionMethod {
public:
  virtual ~ReductionMethod() = default;

  /// The deck's name ('Reduction->Method').
  virtual std::string name() const = 0;
  /// What the method does, for the documentation of 'Reduction->Method'.
  virtual std::string documentation() const = 0;
  /// Its own keys in the body's Reduction sublist, with documentation, defaults and validators. Keys
  /// that several methods share carry the same entry (reductionKey() in Epaphe_ReductionMethods.cpp).
  virtual Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const = 0;
  /// Reads its keys from the body's validated Reduction sublist.
  virtual void setParameters(const Teuchos::ParameterList& reductionParams) = 0;

  /// The reduced model of `full` keeping `retained` (empty when !retainsNodes()); runs on every rank
  /// of the model's communicator, the result replicated on every rank. An Error names the body.
  virtual ReducedModel reduce(const FullModel& full, const std::vector<int>& retained,
                              ReductionReport* report) const = 0;

  /// True when it keeps nodes as physical DOFs: it needs 'Retained node set' (or a contact set).
  virtual bool retainsNodes() const { return true; }
  /// True when its model is worth storing in the reduced-model cache.
  virtual bool cacheable() const { return true; }
  /// The text of its parameters that the reduced model depends on, for the cache key.
  virtual std::string cacheKeyText() const = 0;
  /// The name of the method that made `model`, for messages and the history's 'reduction' attribute:
  /// by default its kind's (ReducedModel::method(), which a model of a built-in form made by a method of
  /// another name overrides here).
  virtual std::string modelName(const ReducedModel& model) const { return model.method(); }
  /// What reduce() did, one log line without the body's name ("" for none).
  virtual std::string describe(const ReducedModel& model, const ReductionReport& report, int ranks) const;
  /// The full model's lowest `count` frequencies, for 'Frequency check'. By default Anasazi on the
  /// full model, its shift placed by the reduced model's frequencies (reducedFrequencies).
  virtual FrequencyCheck frequencyCheck(const FullModel& full, const ReducedModel& model, int count,
                                        const ReductionReport& report) const;

  /// Non-empty when its model cannot take penalty contact: why, and the fix (SceneCheck).
  virtual std::string penaltyContactProblem() const { return ""; }
  /// True when its model is a dense projection u = V q of the full model (V: ReducedModel::recovery), so
  /// that a rotating body can keep its Coriolis terms as G_r = V^T G V ('Rotation->Coriolis', SceneCheck).
  virtual bool projectsCoriolis() const { return false; }
  /// True when its mass matrix is diagonal: damping must keep M/h^2 + D/2h diagonal (SceneCheck).
  virtual bool diagonalMass() const { return false; }
  /// Refusals of its parameters against a built-in mesh (mode counts, gravity on a held body), made
  /// by `epaphe-run --check` before any model is built; an Error names the deck key.
  virtual void checkMesh(const ReductionMeshFacts& facts) const;

  /// True when it builds a parametric model over a speed range ('Rotation->Speed range').
  virtual bool hasParametricModel() const { return false; }
  /// Refusals of its parameters over a speed range (`context` names the Rotation list).
  virtual void checkSpeedRange(const Teuchos::ParameterList& bodyParams, const std::string& context) const;
  /// The parametric model from `source`'s models at `speeds`.
  virtual SpeedParametricModel parametricModel(SpeedSampleSource& source, const std::vector<int>& retained,
                                               const std::vector<double>& speeds, ReductionReport* report) const;
  /// The modes the model taken from the parametric model at a speed keeps.
  virtual int parametricModes() const { return 0; }
};

/// The methods by their deck names, in the order they were added (the built-in ones first).
class ReductionRegistry {
public:
  /// Makes a new method.
  using Factory = std::function<std::unique_ptr<ReductionMethod>()>;
  /// Adds a method under `name`, its deck name; an Error when the name is taken.
  static void add(const std::string& name, Factory factory);
  /// A new method of that name, without parameters; an Error names `context` and the valid names.
  static std::unique_ptr<ReductionMethod> make(const std::string& name, const std::string& context);
  /// The registered deck names, in the order they were added.
  static std::vector<std::string> names();
  /// Changes with every add(), so that a schema built from the registry knows when to rebuild.
  static int version();
};

/// The method of a body's validated Reduction sublist ('Method'), its parameters read.
std::unique_ptr<ReductionMethod> reductionMethod(const Teuchos::ParameterList& reductionParams);

/// The Craig-Bampton options of a Reduction sublist's keys ('Fixed-interface modes', solver,
/// tolerance, frequency check, candidates, eigensolver, load direction); `modes` 0 for Guyan.
CraigBamptonOptions craigBamptonOptions(const Teuchos::ParameterList& reductionParams, bool guyan);

/// The methods of the Craig-Bampton family (Craig-Bampton, Guyan, Massless boundary): their options,
/// which epaphe-modes varies (the mode count) to show the convergence.
class ModalReduction : public ReductionMethod {
public:
  /// The options, which the deck's keys set (setParameters) and epaphe-modes varies.
  CraigBamptonOptions& options() { return options_; }
  /// The options.
  const CraigBamptonOptions& options() const { return options_; }

protected:
  CraigBamptonOptions options_;  ///< set by setParameters()
};

}  // namespace epaphe
