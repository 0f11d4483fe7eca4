#pragma once
// The valid parameters of an Epaphe deck, with documentation, defaults and validators.
#include "Epaphe_Mesh.hpp"  // ClearanceLaw
#include "Epaphe_LinearSolver.hpp"

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <string>

namespace epaphe {

/// The kind of a deck surface (`Surfaces-><s>->Type`).
enum class SurfaceType { Plane = 0, CylinderArc = 1, BodyFace = 2, Casing = 3 };

/// The whole deck: lists Run, Bodies (one sublist per body), Surfaces (one per surface),
/// Contact, Time, Output.
Teuchos::RCP<const Teuchos::ParameterList> validDeckParameters();

/// Reads, validates and completes a deck with defaults. Errors name the file, line and key.
struct Deck {
  Teuchos::RCP<Teuchos::ParameterList> params;  ///< the validated deck with its defaults
  std::string text;                             ///< the file as read, stored in the output
  std::string origin;                           ///< its path
};
/// Reads the deck file `path` (Errors name the file, the line and the key).
Deck readDeck(const std::string& path);
/// Reads a deck from its text; `origin` names it in messages.
Deck readDeckFromString(const std::string& xml, const std::string& origin);

/// The deck run at another rotation speed (a point of a speed sweep): every surface that turns
/// turns at `omega` rad/s instead, with its own sign; `revolutions` > 0 replaces the end time by
/// that many revolutions; the output goes to `outputFile`. The text is rewritten to match, so the
/// output's /run/deck is the deck that ran. A deck where no surface turns is an error.
Deck deckAtSpeed(const Deck& deck, double omega, double revolutions, const std::string& outputFile);

/// 'Output->File' without its extension, the stem of the cache, XDMF and other files of a run.
std::string stem(const std::string& path);

/// The reduced-model cache file of a body: 'Reduction->Cache file', else `<output stem>.<body>.rom.h5`.
std::string cacheFileOf(const Teuchos::ParameterList& reductionParams, const std::string& outputPath,
                        const std::string& body);

}  // namespace epaphe
