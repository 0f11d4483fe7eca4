#include "Epaphe_CraigBampton.hpp"

#include "Epaphe_EigenSolver.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>

namespace epaphe {
namespace {

/// A^T B as a dense column-major (colsA x colsB) array on every rank.
std::vector<double> transposeProduct(const MultiVector& A, const MultiVector& B) {
  const int m = static_cast<int>(A.getNumVectors()), n = static_cast<int>(B.getNumVectors());
  std::vector<double> out(static_cast<std::size_t>(m) * n, 0.0);
  if (m == 0 || n == 0) return out;
  auto local = Tpetra::createLocalMap<LO, GO>(m, A.getMap()->getComm());
  MultiVector C(local, n);
  C.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, A, B, 0.0);
  auto h = C.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) out[static_cast<std::size_t>(j) * m + i] = h(i, j);
  return out;
}

/// The blocks of one matrix X (K or M) split by retained (R) and condensed (C) DOFs.
struct Blocks {
  Teuchos::RCP<CrsMatrix> CC;
  Teuchos::RCP<MultiVector> CR;   // nC x nR, dense columns
  std::vector<double> RR;         // nR x nR, column-major, replicated
};

Blocks split(const CrsMatrix& X, const std::vector<int>& rIndex, const std::vector<int>& cIndex,
             const Teuchos::RCP<const Map>& cMap, int nR) {
  Blocks b;
  b.CC = Teuchos::rcp(new CrsMatrix(cMap, static_cast<std::size_t>(X.getNodeMaxNumRowEntries())));
  b.CR = Teuchos::rcp(new MultiVector(cMap, static_cast<std::size_t>(nR)));
  std::vector<double> rrLocal(static_cast<std::size_t>(nR) * nR, 0.0);
  b.RR.assign(rrLocal.size(), 0.0);
  const auto rowMap = X.getRowMap();
  const auto colMap = X.getColMap();
  typename CrsMatrix::local_inds_host_view_type idx;
  typename CrsMatrix::values_host_view_type val;
  std::vector<GO> cols;
  std::vector<double> vals;
  auto cr = b.CR->getLocalViewHost(Tpetra::Access::ReadWrite);
  for (LO lr = 0; lr < static_cast<LO>(X.getNodeNumRows()); ++lr) {
    const GO g = rowMap->getGlobalElement(lr);
    X.getLocalRowView(lr, idx, val);
    if (rIndex[g] >= 0) {
      for (std::size_t k = 0; k < idx.extent(0); ++k) {
        const GO gc = colMap->getGlobalElement(idx(k));
        if (rIndex[gc] >= 0) rrLocal[static_cast<std::size_t>(rIndex[gc]) * nR + rIndex[g]] += val(k);
      }
      continue;
    }
    const LO lc = cMap->getLocalElement(cIndex[g]);
    cols.clear();
    vals.clear();
    for (std::size_t k = 0; k < idx.extent(0); ++k) {
      const GO gc = colMap->getGlobalElement(idx(k));
      if (rIndex[gc] >= 0) cr(lc, rIndex[gc]) += val(k);
      else { cols.push_back(cIndex[gc]); vals.push_back(val(k)); }
    }
    b.CC->insertGlobalValues(cIndex[g], Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
  }
  b.CC->fillComplete();
  Teuchos::reduceAll(*X.getComm(), Teuchos::REDUCE_SUM, static_cast<int>(rrLocal.size()), rrLocal.data(), b.RR.data());
  return b;
}

/// X_red = R^T X R in the ordering [retained DOFs, modes] (eqs. 2.6-2.7 with R of eq. 2.12).
std::vector<double> project(const Blocks& X, const MultiVector& Psi, const MultiVector* Phi, int nR, int nM) {
  const int n = nR + nM;
  std::vector<double> red(static_cast<std::size_t>(n) * n, 0.0);
  auto at = [&](int i, int j) -> double& { return red[static_cast<std::size_t>(j) * n + i]; };
  MultiVector XPsi(Psi.getMap(), Psi.getNumVectors());
  X.CC->apply(Psi, XPsi);
  const auto a = transposeProduct(Psi, *X.CR);   // Psi^T X_CR
  const auto b = transposeProduct(Psi, XPsi);    // Psi^T X_CC Psi
  for (int j = 0; j < nR; ++j)
    for (int i = 0; i < nR; ++i)
      at(i, j) = X.RR[static_cast<std::size_t>(j) * nR + i] + a[static_cast<std::size_t>(j) * nR + i] +
                 a[static_cast<std::size_t>(i) * nR + j] + b[static_cast<std::size_t>(j) * nR + i];
  if (Phi && nM > 0) {
    MultiVector XPhi(Phi->getMap(), Phi->getNumVectors());
    X.CC->apply(*Phi, XPhi);
    const auto c = transposeProduct(*X.CR, *Phi);  // X_RC Phi
    const auto d = transposeProduct(Psi, XPhi);    // Psi^T X_CC Phi
    const auto e = transposeProduct(*Phi, XPhi);   // Phi^T X_CC Phi
    for (int j = 0; j < nM; ++j) {
      for (int i = 0; i < nR; ++i) {
        const double v = c[static_cast<std::size_t>(j) * nR + i] + d[static_cast<std::size_t>(j) * nR + i];
        at(i, nR + j) = v;
        at(nR + j, i) = v;
      }
      for (int i = 0; i < nM; ++i) at(nR + i, nR + j) = e[static_cast<std::size_t>(j) * nM + i];
    }
  }
  for (int j = 0; j < n; ++j)  // exact symmetry (round-off)
    for (int i = j + 1; i < n; ++i) at(i, j) = at(j, i) = 0.5 * (at(i, j) + at(j, i));
  return red;
}

/// The rows of a distributed multivector X (rows numbered by the global free DOF g) that
/// `rowIndex[g] >= 0` selects, as a dense (numRows x cols, column-major) array on every rank.
std::vector<double> gatherRows(const MultiVector& X, const std::vector<int>& rowIndex, int numRows) {
  const int cols = static_cast<int>(X.getNumVectors());
  std::vector<double> local(static_cast<std::size_t>(numRows) * cols, 0.0), out(local.size(), 0.0);
  const auto map = X.getMap();
  auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
    const int r = rowIndex[map->getGlobalElement(l)];
    if (r < 0) continue;
    for (int j = 0; j < cols; ++j) local[static_cast<std::size_t>(j) * numRows + r] = x(l, j);
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), out.data());
  return out;
}

/// The reduced model's mesh data and its retained DOFs, numbered in the order (retained node,
/// direction) as q's first entries: `rIndex[g]` is free DOF g's index among them (-1: not retained),
/// `nR` their count.
ReducedModel retainedShell(const FullModel& full, const std::vector<int>& retained, ReductionKind kind,
                           std::vector<int>& rIndex, int& nR) {
  ReducedModel red;
  red.name = full.name;
  red.kind = kind;
  red.coords = full.mesh.coords;
  red.nodeSets = full.mesh.nodeSets;
  red.nodeGrids = full.mesh.nodeGrids;
  red.hexes = full.mesh.hexes;
  red.retainedNodes = retained;
  red.nodeDof.assign(full.eq.size(), -1);
  rIndex.assign(static_cast<std::size_t>(full.numFree), -1);
  nR = 0;
  for (int node : retained) {
    EPAPHE_REQUIRE(node >= 0 && node < full.numNodes(),
                   "body '" << full.name << "': retained node " << node << " is not in the model (0.." << full.numNodes() - 1 << ")");
    for (int d = 0; d < 3; ++d) {
      const int g = full.eq[3 * node + d];
      if (g < 0) continue;
      EPAPHE_REQUIRE(rIndex[g] < 0, "body '" << full.name << "': node " << node << " is retained twice");
      rIndex[g] = nR;
      red.nodeDof[3 * node + d] = nR;
      ++nR;
    }
  }
  EPAPHE_REQUIRE(nR > 0, "body '" << full.name << "': no free DOF is retained; name a retained node set with free nodes");
  return red;
}

}  // namespace

ReducedModel craigBampton(const FullModel& full, const std::vector<int>& retained, const CraigBamptonOptions& opt,
                          ReductionReport* report) {
  Stopwatch total;
  ReductionReport rep;
  const auto comm = full.K->getComm();
  const int nFree = full.numFree;
  EPAPHE_REQUIRE(opt.modes >= 0, "body '" << full.name << "': " << opt.modes << " fixed-interface modes asked; use 0 or more");

  // Retained DOFs in the order (retained node, direction): q = [x_R, eta].
  std::vector<int> rIndex, cIndex(static_cast<std::size_t>(nFree), -1);
  int nR = 0;
  ReducedModel red = retainedShell(full, retained, opt.modes > 0 ? ReductionKind::CraigBampton : ReductionKind::Guyan, rIndex, nR);
  int nC = 0;
  for (int g = 0; g < nFree; ++g)
    if (rIndex[g] < 0) cIndex[g] = nC++;
  EPAPHE_REQUIRE(nC > opt.modes, "body '" << full.name << "': " << opt.modes << " fixed-interface modes asked but only "
                                          << nC << " condensed DOFs exist");
  rep.retainedDofs = nR;
  rep.condensedDofs = nC;

  std::vector<GO> myC;
  const auto rowMap = full.K->getRowMap();
  for (LO l = 0; l < static_cast<LO>(rowMap->getNodeNumElements()); ++l) {
    const GO g = rowMap->getGlobalElement(l);
    if (rIndex[g] < 0) myC.push_back(cIndex[g]);
  }
  auto cMap = Teuchos::rcp(new Map(nC, Teuchos::ArrayView<const GO>(myC), 0, comm));
  const Blocks Kb = split(*full.K, rIndex, cIndex, cMap, nR);
  const Blocks Mb = split(*full.M, rIndex, cIndex, cMap, nR);

  // Constraint modes: K_CC Psi = -K_CR, one factorization, nR right-hand sides (eq. 2.10).
  Stopwatch sw;
  auto factor = makeSolver(Kb.CC, opt.solver, "K_CC of body '" + full.name + "'", opt.iterativeTolerance);
  rep.factorSeconds = sw.seconds();
  sw.restart();
  MultiVector Psi(cMap, static_cast<std::size_t>(nR));
  factor->solve(*Kb.CR, Psi);
  Psi.scale(-1.0);
  rep.constraintSeconds = sw.seconds();

  // Fixed-interface modes: K_CC phi = w^2 M_CC phi, shift-invert through the same factor (eq. 2.13).
  sw.restart();
  Teuchos::RCP<MultiVector> Phi;
  if (opt.modes > 0) {
    EigenOptions eo;
    eo.count = opt.modes;
    eo.shift = 0.0;
    eo.tolerance = opt.eigenTolerance;
    EigenResult er = lowestEigenpairs(Kb.CC, Mb.CC, *factor, eo);
    Phi = er.vectors;
    rep.eigenIterations = er.restarts;
    rep.eigenSolves = er.operatorVectors;
    rep.eigenSolveSeconds = er.operatorSeconds;
    for (double l : er.lambda) red.modeFrequencies.push_back(std::sqrt(std::max(l, 0.0)) / (2 * M_PI));
  }
  rep.eigenSeconds = sw.seconds();
  rep.solverIterations = factor->iterations();

  sw.restart();
  red.numModes = opt.modes;
  red.size = nR + opt.modes;
  red.K = project(Kb, Psi, Phi.get(), nR, opt.modes);
  red.M = project(Mb, Psi, Phi.get(), nR, opt.modes);

  // Recovery rows u = R q for every node: unit rows for retained DOFs, [Psi, Phi] rows otherwise.
  const std::size_t n = static_cast<std::size_t>(red.size);
  std::vector<double> local(full.eq.size() * n, 0.0);
  red.recovery.assign(local.size(), 0.0);
  {
    auto psi = Psi.getLocalViewHost(Tpetra::Access::ReadOnly);
    decltype(psi) phi;
    if (Phi) phi = Phi->getLocalViewHost(Tpetra::Access::ReadOnly);
    for (std::size_t i = 0; i < full.eq.size(); ++i) {
      const int g = full.eq[i];
      if (g < 0) continue;
      if (rIndex[g] >= 0) {
        if (comm->getRank() == 0) local[i * n + rIndex[g]] = 1.0;
        continue;
      }
      const LO lc = cMap->getLocalElement(cIndex[g]);
      if (lc == Teuchos::OrdinalTraits<LO>::invalid()) continue;
      for (int j = 0; j < nR; ++j) local[i * n + j] = psi(lc, j);
      for (int j = 0; j < opt.modes; ++j) local[i * n + nR + j] = phi(lc, j);
    }
  }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), red.recovery.data());
  rep.projectSeconds = sw.seconds();
  rep.seconds = total.seconds();
  if (report) *report = rep;
  return red;
}

ReducedModel masslessBoundary(const FullModel& full, const std::vector<int>& retained, const CraigBamptonOptions& opt,
                              ReductionReport* report) {
  Stopwatch total;
  ReductionReport rep;
  const auto comm = full.K->getComm();
  const int nFree = full.numFree, m = opt.modes;
  const std::string body = "body '" + full.name + "'";
  EPAPHE_REQUIRE(m > 0, body << ": the massless-boundary reduction keeps the body's mass in its modes only, but "
                             << m << " modes are asked; set 'Fixed-interface modes' > 0");
  EPAPHE_REQUIRE(std::any_of(full.eq.begin(), full.eq.end(), [](int g) { return g < 0; }),
                 body << ": the massless-boundary reduction needs the static response K^{-1} of a body held by its "
                         "boundary conditions, and this body has none; give it a 'Clamped node set', or use "
                         "'Craig-Bampton'");

  std::vector<int> rIndex;
  int nR = 0;
  ReducedModel red = retainedShell(full, retained, ReductionKind::MasslessBoundary, rIndex, nR);
  EPAPHE_REQUIRE(nR + m <= nFree, body << ": " << nR << " retained DOFs and " << m << " modes exceed the model's "
                                       << nFree << " free DOFs; keep fewer modes");
  rep.retainedDofs = nR;
  rep.condensedDofs = nFree - nR;

  // One factor of K serves the static responses and Anasazi's shift-invert (shift 0: K is regular).
  Stopwatch sw;
  auto factor = makeSolver(full.K, opt.solver, "K of " + body, opt.iterativeTolerance);
  rep.factorSeconds = sw.seconds();
  sw.restart();
  const auto rowMap = full.K->getRowMap();
  MultiVector E(rowMap, static_cast<std::size_t>(nR)), X(rowMap, static_cast<std::size_t>(nR));
  {
    auto e = E.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (LO l = 0; l < static_cast<LO>(rowMap->getNodeNumElements()); ++l)
      if (const int r = rIndex[rowMap->getGlobalElement(l)]; r >= 0) e(l, r) = 1.0;
  }
  factor->solve(E, X);   // X = K^{-1} E_b: the static response to a unit force on each retained DOF
  rep.constraintSeconds = sw.seconds();

  sw.restart();
  EigenOptions eo;
  eo.count = m;
  eo.shift = 0.0;
  eo.tolerance = opt.eigenTolerance;
  EigenResult er = lowestEigenpairs(full.K, full.M, *factor, eo);
  MultiVector& Phi = *er.vectors;
  {  // M-normalise exactly (Anasazi's are M-orthonormal to its tolerance)
    MultiVector MPhi(rowMap, static_cast<std::size_t>(m));
    full.M->apply(Phi, MPhi);
    const auto g = transposeProduct(Phi, MPhi);
    std::vector<double> scale(static_cast<std::size_t>(m));
    for (int j = 0; j < m; ++j) scale[j] = 1.0 / std::sqrt(g[static_cast<std::size_t>(j) * m + j]);
    Phi.scale(Teuchos::ArrayView<const double>(scale));
  }
  rep.eigenIterations = er.restarts;
  rep.eigenSolves = er.operatorVectors;
  rep.eigenSolveSeconds = er.operatorSeconds;
  for (double l : er.lambda) {
    EPAPHE_REQUIRE(l > 0, body << ": eigenvalue " << l << " of a body held by its boundary conditions; the model "
                               "has a mechanism (a free rigid motion): clamp it fully");
    red.modeFrequencies.push_back(std::sqrt(l) / (2 * M_PI));
  }
  rep.eigenSeconds = sw.seconds();
  rep.solverIterations = factor->iterations();

  sw.restart();
  red.numModes = m;
  red.size = nR + m;
  const std::vector<double> w2 = red.modalStiffness();
  red.boundaryModes = gatherRows(Phi, rIndex, nR);           // Phi_b, nR x m
  std::vector<double> G = gatherRows(X, rIndex, nR);         // (K^{-1})_bb, then minus the modes' part
  auto phib = [&](int i, int j) { return red.boundaryModes[static_cast<std::size_t>(j) * nR + i]; };
  for (int j = 0; j < nR; ++j)
    for (int i = 0; i < nR; ++i) {
      double s = 0;
      for (int k = 0; k < m; ++k) s += phib(i, k) * phib(j, k) / w2[k];
      G[static_cast<std::size_t>(j) * nR + i] -= s;
    }
  for (int j = 0; j < nR; ++j)  // exact symmetry (round-off)
    for (int i = j + 1; i < nR; ++i)
      G[static_cast<std::size_t>(j) * nR + i] = G[static_cast<std::size_t>(i) * nR + j] =
          0.5 * (G[static_cast<std::size_t>(j) * nR + i] + G[static_cast<std::size_t>(i) * nR + j]);
  red.residualFlexibility = G;
  const std::vector<double> Ginv =
      spdInverse(G, nR, "the residual flexibility of " + body,
                 "the kept modes already carry (almost) all the flexibility of the retained DOFs; keep fewer modes "
                 "or use 'Craig-Bampton'");
  // K = K_res + diag(0, Omega^2), M = diag(0, I)
  const int n = red.size;
  red.K = red.residualStiffness();
  red.M.assign(static_cast<std::size_t>(n) * n, 0.0);
  for (int k = 0; k < m; ++k) {
    red.K[static_cast<std::size_t>(nR + k) * n + nR + k] += w2[k];
    red.M[static_cast<std::size_t>(nR + k) * n + nR + k] = 1.0;
  }

  // Recovery rows: u = Phi eta + Res f_b with f_b = G^{-1} (u_b - Phi_b eta), Res = X - Phi Omega^{-2} Phi_b^T.
  std::vector<double> local(full.eq.size() * n, 0.0), res(nR), a(nR);
  red.recovery.assign(local.size(), 0.0);
  {
    auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto phi = Phi.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (std::size_t i = 0; i < full.eq.size(); ++i) {
      const int g = full.eq[i];
      if (g < 0) continue;
      if (rIndex[g] >= 0) {
        if (comm->getRank() == 0) local[i * n + rIndex[g]] = 1.0;
        continue;
      }
      const LO l = rowMap->getLocalElement(g);
      if (l == Teuchos::OrdinalTraits<LO>::invalid()) continue;
      for (int c = 0; c < nR; ++c) {
        double s = x(l, c);
        for (int k = 0; k < m; ++k) s -= phi(l, k) / w2[k] * phib(c, k);
        res[c] = s;
      }
      for (int c = 0; c < nR; ++c) {
        double s = 0;
        for (int r = 0; r < nR; ++r) s += res[r] * Ginv[static_cast<std::size_t>(c) * nR + r];
        a[c] = s;
        local[i * n + c] = s;
      }
      for (int k = 0; k < m; ++k) {
        double s = phi(l, k);
        for (int c = 0; c < nR; ++c) s -= a[c] * phib(c, k);
        local[i * n + nR + k] = s;
      }
    }
  }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), red.recovery.data());
  rep.projectSeconds = sw.seconds();
  rep.seconds = total.seconds();
  if (report) *report = rep;
  return red;
}

std::vector<double> fullModelFrequencies(const FullModel& full, int count, LinearSolver solver,
                                         double iterativeTolerance, const std::vector<double>& upperBoundsHz) {
  double sigma = 0;
  // The lowest elastic bound: above 1e-6 of the highest (rigid-body modes of a reduced model are
  // round-off, many orders below); the shift halfway from it to minus itself.
  const double top = upperBoundsHz.empty() ? 0.0 : *std::max_element(upperBoundsHz.begin(), upperBoundsHz.end());
  double elastic = 0;
  for (double f : upperBoundsHz)
    if (f > 1e-6 * top && (elastic == 0 || f < elastic)) elastic = f;
  if (elastic > 0) {
    const double omega = 2 * M_PI * elastic;
    sigma = -0.5 * omega * omega;
  } else {
    double ratio = 0;
    Tpetra::Vector<double, LO, GO> dk(full.K->getRowMap()), dm(full.M->getRowMap());
    full.K->getLocalDiagCopy(dk);
    full.M->getLocalDiagCopy(dm);
    auto k = dk.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto m = dm.getLocalViewHost(Tpetra::Access::ReadOnly);
    double local = 0;
    for (std::size_t i = 0; i < k.extent(0); ++i) local = std::max(local, k(i, 0) / m(i, 0));
    Teuchos::reduceAll(*full.K->getComm(), Teuchos::REDUCE_MAX, local, Teuchos::outArg(ratio));
    sigma = -1e-4 * ratio;
  }
  auto shifted = Tpetra::MatrixMatrix::add(1.0, false, *full.K, -sigma, false, *full.M);
  auto factor = makeSolver(shifted, solver, "K - sigma M of body '" + full.name + "'", iterativeTolerance);
  EigenOptions eo;
  eo.count = count;
  eo.shift = sigma;
  EigenResult er = lowestEigenpairs(full.K, full.M, *factor, eo);
  std::vector<double> f;
  for (double l : er.lambda) f.push_back(std::sqrt(std::max(l, 0.0)) / (2 * M_PI));
  return f;
}

}  // namespace epaphe
