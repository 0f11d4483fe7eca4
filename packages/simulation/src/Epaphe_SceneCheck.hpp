#pragma once
// Every check of a scene that needs no reduced model, in one place: the deck's cross-key and
// cross-section checks (bodies, reductions against damping and contact, surfaces), the built-in
// meshes with the node sets and grids the deck names, and the files the run will create.
// Simulation::setup() runs it before any work and `epaphe-run --check` runs it alone, so a deck is
// refused by both with the same message. What needs the reduced model or the contact detection
// is checked in the setup only: the critical time step (the reduced model's highest frequency),
// gravity on a held imported model, bodies that start inside a surface, a step longer than a
// surface patch (tests/badinput/check_bad_decks.py lists them).
#include "Epaphe_SpeedLaw.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_LoadTimeFunction.hpp"

#include <Teuchos_ParameterList.hpp>

#include <array>
#include <string>
#include <vector>

namespace epaphe {

/// The checks above; `outputPath` is the history file the run will write (the deck's or the
/// command line's), `restart` true when the run continues an existing one. Throws an Error naming
/// the deck, the key, the value and the fix.
void checkScene(const Deck& scene, const std::string& outputPath, bool restart);

/// |Rotation speed| of the fastest turning surface of the deck (rad/s), 0 when none turns.
double fastestRotation(const Teuchos::ParameterList& deck);
/// A body's 'Rotation->Speed law' (ramp = false: constant at 'Speed'), checked by checkScene.
SpeedLaw speedLawOf(const Teuchos::ParameterList& rotation);
/// The run-up of the deck: the speed law of its driven body (ramp = false: none).
SpeedLaw runUpOf(const Teuchos::ParameterList& deck);
/// The run's number of steps: 'Time->End time', or 'End revolutions' of the fastest turning surface
/// (an Error when none turns).
long long numberOfSteps(const Teuchos::ParameterList& deck, const std::string& origin);

/// A load of a body's 'Loads' list (docs/theory/forced-response.md, eqs. 65-66): the force F on every
/// node of a node set, or forces on chosen coordinates of the body's model (its reduced DOFs), times g(t).
struct BodyLoad {
  std::string name;                   ///< its name in the deck
  std::string path;                   ///< its deck path, "Bodies->B->Loads->L", for messages
  std::string nodeSet;                ///< the nodes it acts on (empty: a load on reduced DOFs)
  std::array<double, 3> force{};      ///< F, per node (N)
  std::vector<int> reducedDofs;       ///< 'Reduced DOFs': indices j of the model's coordinates q_j
  std::vector<double> reducedForces;  ///< 'Reduced forces': f_j on each of them (the model's units)
  LoadTimeFunction g;                 ///< its time function
};
/// The loads of body list `body` (its deck list), checked: a node set or reduced DOFs (not both; as many
/// reduced forces as DOFs, indices >= 0), a harmonic's frequency > 0, a table's increasing times, a ramp's
/// time > 0 (the node set's existence is checked against the mesh, the DOFs against the model's size).
std::vector<BodyLoad> bodyLoads(const Teuchos::ParameterList& body, const std::string& origin);

/// The stiffness factors of a body's instances ('Instances', Count of them): the given ones, the random
/// pattern 1 + delta_k (delta_k normal: Box-Muller on mt19937_64, whose sequence the C++ standard fixes,
/// so the pattern is the same on every machine), or all 1. `ctx` names the body in errors.
std::vector<double> instanceFactors(const Teuchos::ParameterList& body, const std::string& ctx);

/// The damping of the deck's 'Time->Damping' list (Rayleigh from two frequencies and ratios when given).
DampingOptions dampingOptions(const Teuchos::ParameterList& timeParams, const std::string& origin);

/// The point grid of a rigid surface (Plane, Cylinder, Casing) from its deck list: nu x nv points
/// (i along u, j along v), a Casing's first row repeated (closed). `towardsAxis`: a Casing's normal
/// points inwards (flip its orientation).
struct RigidGrid {
  /// grid nodes along u and along v
  ///@{
  int nu = 0, nv = 0;
  ///@}
  std::vector<double> points;  ///< nu x nv points, 3 each, (i, j) at 3 (i nv + j) (m)
  bool towardsAxis = false;    ///< a Casing: its normal points towards the axis
};
/// The point grid of a rigid surface's deck list (see RigidGrid); `origin` names the deck.
RigidGrid rigidSurfaceGrid(const Teuchos::ParameterList& surface, const std::string& origin);

}  // namespace epaphe
