#pragma once
// The solvers of K in the reductions, as the deck names them ('Reduction->Linear solver'): plain
// data, no Tpetra, so that the deck schema compiles without it (tests/fuzz).
#include <string>

namespace epaphe {

/// A solver of K in the reductions: Amesos2 MUMPS, Amesos2 KLU2 or Belos CG.
enum class LinearSolver { Mumps = 0, Klu2 = 1, BelosCg = 2 };

/// "MUMPS", "KLU2" or "Belos CG".
std::string solverName(LinearSolver solver);

/// The solver named "MUMPS", "KLU2" or "Belos CG"; an Error lists them for any other name.
LinearSolver linearSolverNamed(const std::string& name);

}  // namespace epaphe
