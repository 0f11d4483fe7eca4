#include "Epaphe_SparseSolver.hpp"

#include "Epaphe_Error.hpp"

#include <Amesos2.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

namespace epaphe {
namespace {

class Amesos2Solver final : public SparseSolver {
public:
  Amesos2Solver(const Teuchos::RCP<const CrsMatrix>& A, const std::string& solverName, const std::string& what)
      : name_(solverName) {
    EPAPHE_REQUIRE(Amesos2::query(solverName),
                   "sparse direct solver '" << solverName << "' is not available in this Trilinos build; use MUMPS");
    EPAPHE_REQUIRE(!(solverName == "KLU2" && A->getComm()->getSize() > 1),
                   "KLU2 cannot factor " << what << " distributed over " << A->getComm()->getSize()
                                         << " MPI ranks: Trilinos 13.2's Amesos2-KLU2 returns wrong solutions "
                                            "there; use MUMPS (the default)");
    try {
      solver_ = Amesos2::create<CrsMatrix, MultiVector>(solverName, A);
      if (solverName == "MUMPS") {
        Teuchos::ParameterList params("Amesos2");
        auto& mumps = params.sublist("MUMPS");
        mumps.set("ICNTL(14)", 100);  // 100 % more working space than the estimate: robust on shells
        solver_->setParameters(Teuchos::rcpFromRef(params));
      }
      solver_->symbolicFactorization();
      solver_->numericFactorization();
    } catch (const std::exception& e) {
      throw Error("factorization of " + what + " (" + std::to_string(A->getGlobalNumRows()) + " rows) by " +
                  solverName + " failed: " + e.what() +
                  ". The matrix may be singular: check that the boundary conditions remove every "
                  "rigid-body motion of the condensed part");
    }
  }

  void solve(const MultiVector& B, MultiVector& X) const override {
    solver_->solve(Teuchos::ptrFromRef(X), Teuchos::ptrFromRef(B));
  }
  std::string name() const override { return name_; }

private:
  std::string name_;
  Teuchos::RCP<Amesos2::Solver<CrsMatrix, MultiVector>> solver_;
};

}  // namespace

std::unique_ptr<SparseSolver> makeDirectSolver(const Teuchos::RCP<const CrsMatrix>& A,
                                               const std::string& solverName, const std::string& what) {
  return std::make_unique<Amesos2Solver>(A, solverName, what);
}

}  // namespace epaphe
