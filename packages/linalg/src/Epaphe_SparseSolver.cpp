#include "Epaphe_SparseSolver.hpp"

#include "Epaphe_Error.hpp"

#include <Amesos2.hpp>
#include <BelosBlockCGSolMgr.hpp>
#include <BelosLinearProblem.hpp>
#include <BelosTpetraAdapter.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include <algorithm>

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

/// Y = alpha D^{-1} X + beta Y, D the diagonal of A.
class JacobiOperator final : public Operator {
public:
  explicit JacobiOperator(const CrsMatrix& A) : inv_(A.getRowMap()) {
    A.getLocalDiagCopy(inv_);
    inv_.reciprocal(inv_);
  }
  Teuchos::RCP<const Map> getDomainMap() const override { return inv_.getMap(); }
  Teuchos::RCP<const Map> getRangeMap() const override { return inv_.getMap(); }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp = Teuchos::NO_TRANS, double alpha = 1.0,
             double beta = 0.0) const override {
    Y.elementWiseMultiply(alpha, inv_, X, beta);
  }

private:
  Tpetra::Vector<double, LO, GO> inv_;
};

class BelosCgSolver final : public SparseSolver {
public:
  BelosCgSolver(const Teuchos::RCP<const CrsMatrix>& A, double tolerance, const std::string& what)
      : A_(A), prec_(Teuchos::rcp(new JacobiOperator(*A))), tolerance_(tolerance), what_(what) {
    EPAPHE_REQUIRE(tolerance > 0 && tolerance < 1,
                   "Belos CG tolerance " << tolerance << " for " << what << "; use a value in (0, 1), e.g. 1e-12");
  }

  void solve(const MultiVector& B, MultiVector& X) const override {
    using MV = MultiVector;
    using OP = Operator;
    X.putScalar(0.0);
    auto Xr = Teuchos::rcpFromRef(X);
    auto Br = Teuchos::rcpFromRef(B);
    auto problem = Teuchos::rcp(new Belos::LinearProblem<double, MV, OP>(A_, Xr, Br));
    problem->setLeftPrec(prec_);
    EPAPHE_REQUIRE(problem->setProblem(), "Belos could not set up the solve with " << what_);
    auto pl = Teuchos::rcp(new Teuchos::ParameterList());
    const int n = static_cast<int>(A_->getGlobalNumRows());
    pl->set("Block Size", static_cast<int>(std::min<std::size_t>(B.getNumVectors(), 16)));
    pl->set("Maximum Iterations", std::max(1000, 20 * n));
    pl->set("Convergence Tolerance", tolerance_);
    pl->set("Verbosity", Belos::Errors);
    Belos::BlockCGSolMgr<double, MV, OP> mgr(problem, pl);
    const Belos::ReturnType ret = mgr.solve();
    iterations_ += mgr.getNumIters();
    EPAPHE_REQUIRE(ret == Belos::Converged, "Belos CG on "
                                                << what_ << " (" << n << " rows) did not reach the relative "
                                                << "residual " << tolerance_ << " in " << mgr.getNumIters()
                                                << " iterations (reached " << mgr.achievedTol()
                                                << "); use a direct solver (MUMPS) or a larger 'Iterative tolerance'");
  }
  std::string name() const override { return "Belos CG"; }
  long iterations() const override { return iterations_; }

private:
  Teuchos::RCP<const CrsMatrix> A_;
  Teuchos::RCP<const Operator> prec_;
  double tolerance_;
  std::string what_;
  mutable long iterations_ = 0;
};

}  // namespace

std::unique_ptr<SparseSolver> makeBelosCgSolver(const Teuchos::RCP<const CrsMatrix>& A, double tolerance,
                                                const std::string& what) {
  return std::make_unique<BelosCgSolver>(A, tolerance, what);
}

std::string solverName(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::Mumps:
      return "MUMPS";
    case LinearSolver::Klu2:
      return "KLU2";
    case LinearSolver::BelosCg:
      return "Belos CG";
  }
  return "?";
}

LinearSolver linearSolverNamed(const std::string& name) {
  for (LinearSolver s : {LinearSolver::Mumps, LinearSolver::Klu2, LinearSolver::BelosCg})
    if (solverName(s) == name) return s;
  throw Error("linear solver '" + name + "': give MUMPS, KLU2 or Belos CG");
}

std::unique_ptr<SparseSolver> makeSolver(const Teuchos::RCP<const CrsMatrix>& A, LinearSolver solver,
                                         const std::string& what, double tolerance) {
  if (solver == LinearSolver::BelosCg) return makeBelosCgSolver(A, tolerance, what);
  return makeDirectSolver(A, solverName(solver), what);
}

std::unique_ptr<SparseSolver> makeDirectSolver(const Teuchos::RCP<const CrsMatrix>& A, const std::string& solverName,
                                               const std::string& what) {
  return std::make_unique<Amesos2Solver>(A, solverName, what);
}

}  // namespace epaphe
