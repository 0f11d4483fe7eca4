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

#include <Teuchos_ParameterList.hpp>

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
