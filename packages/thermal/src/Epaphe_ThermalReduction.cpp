#include "Epaphe_ThermalReduction.hpp"

#include "Epaphe_EigenSolver.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ReducedModel.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace epaphe {
namespace {

/// A^T B as a dense column-major (colsA x colsB) array on every rank.
std::vector<double> transposeProduct(const MultiVector& A, const MultiVector& B) {
  const int m = static_cast<int>(A.getNumVectors()), n = static_cast<int>(B.getNumVectors());
  std::vector<double> out(static_cast<std::size_t>(m) * n, 0.0);
  auto local = Tpetra::createLocalMap<LO, GO>(m, A.getMap()->getComm());
  MultiVector P(local, n);
  P.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, A, B, 0.0);
  auto h = P.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) out[static_cast<std::size_t>(j) * m + i] = h(i, j);
  return out;
}

/// X^T A X for a sparse A.
std::vector<double> project(const CrsMatrix& A, const MultiVector& X) {
  MultiVector AX(A.getRangeMap(), X.getNumVectors());
  A.apply(X, AX);
  return transposeProduct(X, AX);
}

/// The rows of X (numRows x numVectors, row-major) on every rank.
std::vector<double> gatherRows(const MultiVector& X) {
  const std::size_t n = X.getGlobalLength(), p = X.getNumVectors();
  std::vector<double> local(n * p, 0.0), global(n * p, 0.0);
  auto h = X.getLocalViewHost(Tpetra::Access::ReadOnly);
  const auto map = X.getMap();
  for (LO l = 0; l < static_cast<LO>(X.getLocalLength()); ++l)
    for (std::size_t j = 0; j < p; ++j) local[static_cast<std::size_t>(map->getGlobalElement(l)) * p + j] = h(l, j);
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  return global;
}

/// The identity, n x n column-major.
std::vector<double> identity(int n) {
  std::vector<double> I(static_cast<std::size_t>(n) * n, 0.0);
  for (int i = 0; i < n; ++i) I[static_cast<std::size_t>(i) * n + i] = 1.0;
  return I;
}

/// T (n x p, column-major) with T^T G T = I from the eigenvectors of a Gram matrix G (n x n):
/// directions whose eigenvalue is below 1e-10 `scale` are dropped as dependent.
std::vector<double> orthonormalizer(const std::vector<double>& G, int n, double scale, int& p) {
  std::vector<double> U;
  const std::vector<double> mu = denseEigenpairs(G, identity(n), n, &U);
  std::vector<double> T;
  p = 0;
  for (int j = 0; j < n; ++j) {
    if (!(mu[j] > 1e-10 * scale)) continue;
    for (int i = 0; i < n; ++i) T.push_back(U[static_cast<std::size_t>(j) * n + i] / std::sqrt(mu[j]));
    ++p;
  }
  return T;
}

/// A dense column-major (rows x cols) array as a MultiVector on a locally replicated map.
MultiVector replicated(const std::vector<double>& A, int rows, int cols,
                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  MultiVector M(Tpetra::createLocalMap<LO, GO>(rows, comm), static_cast<std::size_t>(cols));
  auto h = M.getLocalViewHost(Tpetra::Access::ReadWrite);
  for (int c = 0; c < cols; ++c)
    for (int r = 0; r < rows; ++r) h(r, c) = A[static_cast<std::size_t>(c) * rows + r];
  return M;
}

/// W with the columns of A, then those of B.
MultiVector joined(const MultiVector* A, const MultiVector& B) {
  const int a = A ? static_cast<int>(A->getNumVectors()) : 0, b = static_cast<int>(B.getNumVectors());
  MultiVector W(B.getMap(), static_cast<std::size_t>(a + b));
  for (int j = 0; j < a; ++j) W.getVectorNonConst(j)->update(1.0, *A->getVector(j), 0.0);
  for (int j = 0; j < b; ++j) W.getVectorNonConst(a + j)->update(1.0, *B.getVector(j), 0.0);
  return W;
}

/// B = [Phi | S_1 | S_2 ...] Y. The blocks X_b, in order (the static responses, then each Krylov
/// block), are each scaled to unit C-norms (their units differ), made C-orthogonal to everything before
/// them (Phi, C-orthonormal, and the earlier blocks' S; twice, which is enough in floating point) and
/// C-orthonormal among themselves through the eigenvectors of their Gram matrix, dropping what is left
/// below 1e-10 of a unit C-norm^2 as in the span of the rest: a Krylov block then never costs a static
/// response its place, and the steady state stays exact. The modes are kept whole, however close to
/// them the static responses are (a static response is mostly the slowest mode). On the whole
/// C-orthonormal set the Rayleigh-Ritz problem of K is a standard one: B^T C B = I, B^T K B =
/// diag(rates).
MultiVector orthogonalBasis(const ThermalFullModel& full, const MultiVector* Phi,
                            const std::vector<MultiVector*>& blocks, std::vector<double>& rates) {
  const auto map = full.K->getRowMap();
  const auto comm = map->getComm();
  std::unique_ptr<MultiVector> W;
  if (Phi) W = std::make_unique<MultiVector>(joined(nullptr, *Phi));
  for (MultiVector* X : blocks) {
    const int ns = static_cast<int>(X->getNumVectors());
    if (ns == 0) continue;
    {
      const std::vector<double> G0 = project(*full.C, *X);
      std::vector<double> unit(static_cast<std::size_t>(ns));
      for (int j = 0; j < ns; ++j) unit[j] = 1.0 / std::sqrt(G0[static_cast<std::size_t>(j) * ns + j]);
      X->scale(Teuchos::ArrayView<const double>(unit));
    }
    if (W)
      for (int pass = 0; pass < 2; ++pass) {  // X -= W (W^T C X)
        const int m = static_cast<int>(W->getNumVectors());
        MultiVector CX(map, static_cast<std::size_t>(ns));
        full.C->apply(*X, CX);
        X->multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, -1.0, *W, replicated(transposeProduct(*W, CX), m, ns, comm),
                    1.0);
      }
    int p = 0;
    const std::vector<double> T = orthonormalizer(project(*full.C, *X), ns, 1.0, p);
    if (p == 0) continue;
    MultiVector S(map, static_cast<std::size_t>(p));
    S.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, *X, replicated(T, ns, p, comm), 0.0);
    W = std::make_unique<MultiVector>(joined(W.get(), S));
  }
  const int q = static_cast<int>(W->getNumVectors());
  std::vector<double> Kw = project(*full.K, *W), Y;
  for (int c = 0; c < q; ++c)  // symmetric to round-off: make it exactly so for LAPACK
    for (int r = 0; r < c; ++r) {
      const double v = 0.5 * (Kw[static_cast<std::size_t>(c) * q + r] + Kw[static_cast<std::size_t>(r) * q + c]);
      Kw[static_cast<std::size_t>(c) * q + r] = Kw[static_cast<std::size_t>(r) * q + c] = v;
    }
  rates = denseEigenpairs(Kw, identity(q), q, &Y);
  MultiVector B(map, static_cast<std::size_t>(q));
  B.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, *W, replicated(Y, q, q, comm), 0.0);
  return B;
}

ReducedThermalModel reduce(const ThermalFullModel& full, const std::vector<int>& heatedNodes, int modes,
                           const ThermalReductionOptions& opt) {
  const std::string what = "body '" + full.name + "' thermal model";
  bool definite = !full.definition.fixedNodes.empty();
  for (const auto& c : full.definition.convection) definite = definite || c.coefficient > 0;
  EPAPHE_REQUIRE(definite,
                 what << ": the body is insulated (no face held at the reference temperature, no convection), "
                         "so a steady heat input has no steady state; give it a convection or a fixed "
                         "temperature face");
  const auto map = full.K->getRowMap();
  const int nh = static_cast<int>(heatedNodes.size());
  MultiVector E(map, nh > 0 ? nh + 1 : 1);
  {
    auto e = E.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (int k = 0; k < nh; ++k) {
      const int n = heatedNodes[k];
      EPAPHE_REQUIRE(n >= 0 && n < full.numNodes() && !full.weights(n).empty(),
                     what << ": heated node " << (n >= 0 && n < full.numNodes() ? full.mesh.nodeId(n) : n)
                          << " is not a free node of the mesh (held at the reference temperature, in no element "
                             "or outside it)");
      // a mid-side node's input goes half to each corner of its edge (its temperature is their mean, eq. 75)
      for (const auto& [f, w] : full.weights(n))
        if (map->isNodeGlobalElement(f)) e(map->getLocalElement(f), k) += w;
    }
    auto g = full.load->getLocalViewHost(Tpetra::Access::ReadOnly);
    for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) e(l, E.getNumVectors() - 1) = g(l, 0);
  }
  std::vector<double> gNorm(1);
  full.load->norm2(Teuchos::ArrayView<double>(gNorm));
  MultiVector X(map, E.getNumVectors());
  const auto solver = makeSolver(full.K, opt.solver, "K of " + what);
  solver->solve(E, X);
  const int staticColumns = static_cast<int>(E.getNumVectors()) - (gNorm[0] > 0 ? 0 : 1);

  modes = std::min(modes, full.numFree);
  Teuchos::RCP<MultiVector> Phi;
  if (modes > 0) {
    EigenResult eig;
    if (full.numFree <= opt.denseUpTo)
      eig = denseLowestEigenpairs(*full.K, *full.C, modes, what);
    else {
      EigenOptions eo;
      eo.count = modes;
      eo.tolerance = opt.eigenTolerance;
      eig = lowestEigenpairs(full.K, full.C, *solver, eo);
    }
    Phi = eig.vectors;
  }
  // the Krylov vectors of the inputs (eq. 58): X_{j+1} = K^{-1} C X_j from X_1 = K^{-1} E, the
  // static response's first correction for the input's rate of change (the "static + dynamic
  // correction" of the modal truncation: the heat that has not yet spread, which no mode holds)
  std::vector<std::unique_ptr<MultiVector>> blocks;
  if (nh > 0)
    for (int j = 1; j < opt.krylovBlocks; ++j) {
      const MultiVector& previous = j == 1 ? X : *blocks.back();
      MultiVector CX(map, static_cast<std::size_t>(nh));
      full.C->apply(*previous.subView(Teuchos::Range1D(0, nh - 1)), CX);
      blocks.push_back(std::make_unique<MultiVector>(map, static_cast<std::size_t>(nh)));
      solver->solve(CX, *blocks.back());
    }
  std::unique_ptr<MultiVector> X1;  // the static responses (and the convection's steady state)
  if (staticColumns > 0) X1 = std::make_unique<MultiVector>(*X.subCopy(Teuchos::Range1D(0, staticColumns - 1)));
  std::vector<MultiVector*> ordered;
  if (X1) ordered.push_back(X1.get());
  for (const auto& block : blocks) ordered.push_back(block.get());
  ReducedThermalModel red;
  MultiVector B = orthogonalBasis(full, Phi.get(), ordered, red.rate);
  const int p = red.numModes();
  red.ambientLoad = transposeProduct(B, *full.load);
  const std::vector<double> rows = gatherRows(B);
  red.name = full.name;
  red.referenceTemperature = full.definition.referenceTemperature;
  red.numNodes = full.numNodes();
  red.basis.assign(static_cast<std::size_t>(red.numNodes) * p, 0.0);
  for (int n = 0; n < red.numNodes; ++n)
    for (const auto& [f, w] : full.weights(n))
      for (int i = 0; i < p; ++i)
        red.basis[static_cast<std::size_t>(n) * p + i] += w * rows[static_cast<std::size_t>(f) * p + i];
  red.heatedNodes = heatedNodes;
  for (int n : heatedNodes)
    red.heatedRows.insert(red.heatedRows.end(), red.basis.begin() + static_cast<std::ptrdiff_t>(n) * p,
                          red.basis.begin() + static_cast<std::ptrdiff_t>(n + 1) * p);
  return red;
}

}  // namespace

ReducedThermalModel reduceThermal(const ThermalFullModel& full, const std::vector<int>& heatedNodes,
                                  const ThermalReductionOptions& options) {
  EPAPHE_REQUIRE(options.modes >= 0,
                 "body '" << full.name << "' thermal model: " << options.modes << " modes asked; give 0 or more");
  EPAPHE_REQUIRE(options.krylovBlocks >= 1, "body '" << full.name << "' thermal model: " << options.krylovBlocks
                                                     << " Krylov blocks asked; give 1 (static responses) or more");
  return reduce(full, heatedNodes, options.modes, options);
}

ReducedThermalModel fullThermalModel(const ThermalFullModel& full, const std::vector<int>& heatedNodes) {
  ThermalReductionOptions all;
  all.denseUpTo = full.numFree;
  all.krylovBlocks = 1;  // every mode: the Krylov vectors are in their span
  return reduce(full, heatedNodes, full.numFree, all);
}

}  // namespace epaphe
