#pragma once
// Solves A X = B for a sparse symmetric matrix factored once and reused for any number of
// right-hand sides (constraint modes, shift-invert inside Anasazi).
#include "Epaphe_TpetraTypes.hpp"

#include <Teuchos_RCP.hpp>

#include <memory>
#include <string>

namespace epaphe {

class SparseSolver {
public:
  virtual ~SparseSolver() = default;
  /// X = A^{-1} B.
  virtual void solve(const MultiVector& B, MultiVector& X) const = 0;
  virtual std::string name() const = 0;
};

/// Amesos2 direct solver: symbolic and numeric factorization happen here, once.
/// `solverName`: "MUMPS" (default; correct on any number of MPI ranks) or "KLU2" (one rank only:
/// in Trilinos 13.2 it returns wrong solutions when the matrix is distributed). `what` names the
/// matrix in error messages.
std::unique_ptr<SparseSolver> makeDirectSolver(const Teuchos::RCP<const CrsMatrix>& A,
                                               const std::string& solverName, const std::string& what);

}  // namespace epaphe
