#include "Epaphe_EigenSolver.hpp"

#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <AnasaziBasicEigenproblem.hpp>
#include <AnasaziBlockKrylovSchurSolMgr.hpp>
#include <AnasaziTpetraAdapter.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <numeric>

namespace epaphe {
namespace {

/// Y = (K - sigma M)^{-1} M X.
class ShiftInvertOperator final : public Operator {
public:
  ShiftInvertOperator(Teuchos::RCP<const CrsMatrix> M, const SparseSolver& solver)
      : M_(std::move(M)), solver_(solver) {}
  Teuchos::RCP<const Map> getDomainMap() const override { return M_->getDomainMap(); }
  Teuchos::RCP<const Map> getRangeMap() const override { return M_->getRangeMap(); }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp = Teuchos::NO_TRANS, double alpha = 1.0,
             double beta = 0.0) const override {
    const auto t0 = std::chrono::steady_clock::now();
    ++applications;
    vectors += static_cast<long>(X.getNumVectors());
    struct Tally {
      std::chrono::steady_clock::time_point t0;
      double& s;
      ~Tally() { s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
    } tally{t0, seconds};
    MultiVector MX(M_->getRangeMap(), X.getNumVectors());
    M_->apply(X, MX);
    if (alpha == 1.0 && beta == 0.0) {
      solver_.solve(MX, Y);
      return;
    }
    MultiVector Z(Y.getMap(), Y.getNumVectors());
    solver_.solve(MX, Z);
    Y.update(alpha, Z, beta);
  }

  mutable long applications = 0, vectors = 0;
  mutable double seconds = 0;

private:
  Teuchos::RCP<const CrsMatrix> M_;
  const SparseSolver& solver_;
};

}  // namespace

EigenResult lowestEigenpairs(const Teuchos::RCP<const CrsMatrix>& K, const Teuchos::RCP<const CrsMatrix>& M,
                             const SparseSolver& factorOfShifted, const EigenOptions& opt) {
  using OP = Operator;
  using MV = MultiVector;
  const int n = static_cast<int>(K->getGlobalNumRows());
  EPAPHE_REQUIRE(opt.count >= 1 && opt.count < n,
                 "asked for " << opt.count << " eigenpairs of a system with " << n << " DOFs; ask for 1 to " << n - 1);
  // Block Krylov-Schur on (K - sigma M)^{-1} M, self-adjoint in the M inner product; its largest
  // eigenvalues theta = 1 / (lambda - sigma) are the lowest lambda. A block of several vectors:
  // structures have repeated eigenvalues (6 rigid-body modes, bending pairs of symmetric
  // sections) and a single-vector Krylov space holds one vector per distinct eigenvalue.
  // Measured on a 64,500-DOF C3D20 plate, 50 modes: blocks of 6 beat 12 and 24 (fewer, larger
  // solves, but more Anasazi work on the larger basis), and a space of 3 nev beats 2 nev.
  const int blockSize = std::min(6, opt.count);
  auto op = Teuchos::rcp(new ShiftInvertOperator(M, factorOfShifted));
  // A search space of 3 nev (at least nev + 60) vectors: restarts are rare, and a restart that
  // splits a cluster of (numerically) repeated eigenvalues is what trips Krylov-Schur. When one
  // still does (Anasazi 13.2 then throws from a column range past its basis: measured on a free
  // 40 x 1 x 1 bar, 26 and 30 pairs, its six rigid modes and square section's bending pairs), the
  // solve starts again from a new random block with a space twice as large, up to the whole space.
  const int wanted = std::max(3 * opt.count, opt.count + 60);
  int numBlocks = std::max(3, std::min((n - 1) / blockSize, wanted / blockSize + 1));
  Teuchos::RCP<Anasazi::BasicEigenproblem<double, MV, OP>> problem;
  std::unique_ptr<Anasazi::BlockKrylovSchurSolMgr<double, MV, OP>> mgr;
  for (int attempt = 0;; ++attempt) {
    auto x0 = Teuchos::rcp(new MV(K->getDomainMap(), blockSize));
    x0->randomize();
    if (attempt == 0 && !opt.start.is_null() && opt.start->getLocalLength() == x0->getLocalLength()) {
      auto a = x0->getLocalViewHost(Tpetra::Access::ReadWrite);
      auto b = opt.start->getLocalViewHost(Tpetra::Access::ReadOnly);
      const int k = std::min<int>(blockSize, static_cast<int>(opt.start->getNumVectors()));
      for (int j = 0; j < k; ++j)
        for (std::size_t i = 0; i < x0->getLocalLength(); ++i) a(i, j) = b(i, j);
    }
    problem = Teuchos::rcp(new Anasazi::BasicEigenproblem<double, MV, OP>(op, M, x0));
    problem->setHermitian(true);
    problem->setNEV(opt.count);
    EPAPHE_REQUIRE(problem->setProblem(), "Anasazi could not set up the eigenvalue problem");

    Teuchos::ParameterList pl;
    pl.set("Which", "LM");
    pl.set("Block Size", blockSize);
    pl.set("Num Blocks", numBlocks);
    pl.set("Maximum Restarts", opt.maxRestarts);
    // Ritz values and residuals after every block, not only when the space is full: the solve stops
    // as soon as the wanted pairs converge. Measured on the 64,500-DOF C3D20 blade (1 rank): 50
    // fixed-interface modes 6.4 -> 4.2-4.5 s, the 10-mode frequency check 72 -> 48 solves.
    pl.set("Step Size", 1);
    pl.set("Convergence Tolerance", opt.tolerance);
    pl.set("Verbosity", Anasazi::Errors);
    mgr = std::make_unique<Anasazi::BlockKrylovSchurSolMgr<double, MV, OP>>(problem, pl);
    const int largest = std::max(3, (n - 1) / blockSize);
    try {
      const Anasazi::ReturnType ret = mgr->solve();
      EPAPHE_REQUIRE(ret == Anasazi::Converged && problem->getSolution().numVecs >= opt.count,
                     "Anasazi found " << problem->getSolution().numVecs << " of " << opt.count << " eigenpairs after "
                                      << mgr->getNumIters() << " iterations; try fewer modes or a larger tolerance");
      break;
    } catch (const Error&) {
      throw;
    } catch (const std::exception& e) {
      EPAPHE_REQUIRE(attempt < 3 && numBlocks < largest, "Anasazi's Krylov-Schur failed for "
                                                             << opt.count << " eigenpairs with a space of " << numBlocks
                                                             << " blocks of " << blockSize << " (" << e.what()
                                                             << "); try a few modes more or fewer");
      numBlocks = std::min(largest, 2 * numBlocks);
    }
  }
  const auto& sol = problem->getSolution();
  // theta = 1 / (lambda - sigma)  ->  lambda = sigma + 1/theta; sort ascending.
  std::vector<double> lambda(static_cast<std::size_t>(sol.numVecs));
  for (int i = 0; i < sol.numVecs; ++i) lambda[i] = opt.shift + 1.0 / sol.Evals[i].realpart;
  std::vector<int> order(lambda.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return lambda[a] < lambda[b]; });
  EigenResult r;
  r.vectors = Teuchos::rcp(new MV(K->getDomainMap(), opt.count));
  for (int i = 0; i < opt.count; ++i) {
    const int src = order[i];  // Evecs column i belongs to Evals[i] (real symmetric problem)
    r.lambda.push_back(lambda[order[i]]);
    r.vectors->getVectorNonConst(i)->update(1.0, *sol.Evecs->getVector(src), 0.0);
  }
  r.restarts = mgr->getNumIters();
  r.operatorApplications = op->applications;
  r.operatorVectors = op->vectors;
  r.operatorSeconds = op->seconds;
  return r;
}

EigenResult denseLowestEigenpairs(const CrsMatrix& K, const CrsMatrix& M, int count, const std::string& what) {
  const int n = static_cast<int>(K.getGlobalNumRows());
  EPAPHE_REQUIRE(n <= 6000, what << ": the dense eigensolver holds two " << n << " x " << n
                                 << " matrices; above 6000 DOFs use 'Eigensolver' = Anasazi");
  EPAPHE_REQUIRE(count >= 1 && count <= n, what << ": " << count << " eigenpairs asked of " << n << " DOFs");
  std::vector<double> V;
  const std::vector<double> w = denseEigenpairs(gatherDense(K), gatherDense(M), n, &V);
  EigenResult r;
  r.lambda.assign(w.begin(), w.begin() + count);
  const auto map = K.getRowMap();
  r.vectors = Teuchos::rcp(new MultiVector(map, static_cast<std::size_t>(count)));
  auto v = r.vectors->getLocalViewHost(Tpetra::Access::ReadWrite);
  for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
    const GO g = map->getGlobalElement(l);
    for (int k = 0; k < count; ++k) v(l, k) = V[static_cast<std::size_t>(k) * n + g];
  }
  return r;
}

}  // namespace epaphe
