// The solvers of K behind one enum: each solves the clamped steel bar's K x = b to its accuracy
// (the direct ones to round-off, Belos CG to its tolerance), and they agree with each other.
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_SparseSolver.hpp"

#include "TestBar.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace epaphe;

namespace {

/// ||K x - b|| / ||b|| and x for the solver `s` on the clamped bar, under a unit load on every DOF.
std::pair<double, std::vector<double>> solveBar(LinearSolver s, double tolerance) {
  const FullModel bar = test::bar(10, true);
  MultiVector b(bar.K->getRowMap(), 1), x(bar.K->getRowMap(), 1), r(bar.K->getRowMap(), 1);
  b.putScalar(1.0);  // the same load for every solver
  makeSolver(bar.K, s, "K of the test bar", tolerance)->solve(b, x);
  bar.K->apply(x, r);
  r.update(-1.0, b, 1.0);
  std::vector<double> nr(1), nb(1);
  r.norm2(Teuchos::ArrayView<double>(nr));
  b.norm2(Teuchos::ArrayView<double>(nb));
  auto xh = x.getLocalViewHost(Tpetra::Access::ReadOnly);
  std::vector<double> xs(xh.data(), xh.data() + xh.extent(0));
  return {nr[0] / nb[0], xs};
}

}  // namespace

TEST(Linalg, SolverNamesRoundTripAndAnUnknownOneListsTheValidOnes) {
  for (LinearSolver s : {LinearSolver::Mumps, LinearSolver::Klu2, LinearSolver::BelosCg})
    EXPECT_EQ(linearSolverNamed(solverName(s)), s);
  try {
    linearSolverNamed("SuperLU");
    FAIL() << "an unknown solver was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("MUMPS, KLU2 or Belos CG"), std::string::npos) << e.what();
  }
}

TEST(Linalg, EverySolverSolvesTheBarAndTheyAgree) {
  // Direct: a backward-stable factor leaves a residual of order eps cond(K) at worst; 1e-9 is
  // 1e7 eps, far above round-off here and far below an error of the factor or of the data.
  const auto [rm, xm] = solveBar(LinearSolver::Mumps, 0);
  EXPECT_LT(rm, 1e-9);
  const auto [rk, xk] = solveBar(LinearSolver::Klu2, 0);
  EXPECT_LT(rk, 1e-9);
  // Belos CG stops at a relative residual of 1e-10; the solution then differs from MUMPS's by at
  // most cond(K) times that (the bar's cond(K) is below 1e6: 1e-4 relative bounds it).
  const auto [rc, xc] = solveBar(LinearSolver::BelosCg, 1e-10);
  EXPECT_LT(rc, 1e-10 * 1.01);
  double dk = 0, dc = 0, scale = 0;
  for (std::size_t i = 0; i < xm.size(); ++i) {
    scale = std::max(scale, std::abs(xm[i]));
    dk = std::max(dk, std::abs(xk[i] - xm[i]));
    dc = std::max(dc, std::abs(xc[i] - xm[i]));
  }
  EXPECT_LT(dk, 1e-8 * scale);
  EXPECT_LT(dc, 1e-4 * scale);
}
