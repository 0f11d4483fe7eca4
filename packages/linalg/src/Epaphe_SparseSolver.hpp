#pragma once
// Solves A X = B for a sparse symmetric matrix factored once and reused for any number of
// right-hand sides (constraint modes, shift-invert inside Anasazi).
#include "Epaphe_LinearSolver.hpp"
#include "Epaphe_TpetraTypes.hpp"

#include <Teuchos_RCP.hpp>

#include <memory>
#include <string>

namespace epaphe {

/// A sparse symmetric matrix A factored once (or solved iteratively), solving A X = B for any B.
class SparseSolver {
public:
  virtual ~SparseSolver() = default;
  /// X = A^{-1} B.
  virtual void solve(const MultiVector& B, MultiVector& X) const = 0;
  /// The solver's name ("MUMPS", "KLU2", "Belos CG"), for reports.
  virtual std::string name() const = 0;
  /// Iterations of all solves so far (0 for direct solvers).
  virtual long iterations() const { return 0; }
};

/// Amesos2 direct solver: symbolic and numeric factorization happen here, once.
/// `solverName`: "MUMPS" (default; correct on any number of MPI ranks) or "KLU2" (one rank only:
/// in Trilinos 13.2 it returns wrong solutions when the matrix is distributed). `what` names the
/// matrix in error messages.
std::unique_ptr<SparseSolver> makeDirectSolver(const Teuchos::RCP<const CrsMatrix>& A, const std::string& solverName,
                                               const std::string& what);

/// Belos block conjugate gradients preconditioned by Jacobi (the inverse diagonal of A, a Tpetra
/// operator: this Trilinos has no Ifpack2). A must be symmetric positive definite. Nothing is
/// factored: each solve iterates until the relative residual of every column is below
/// `tolerance` (an Error names A, the iterations and the residual reached otherwise).
std::unique_ptr<SparseSolver> makeBelosCgSolver(const Teuchos::RCP<const CrsMatrix>& A, double tolerance,
                                                const std::string& what);

/// MUMPS, KLU2 (Amesos2, makeDirectSolver) or Belos CG (makeBelosCgSolver with `tolerance`).
std::unique_ptr<SparseSolver> makeSolver(const Teuchos::RCP<const CrsMatrix>& A, LinearSolver solver,
                                         const std::string& what, double tolerance = 1e-12);

}  // namespace epaphe
