#include "Epaphe_CraigBampton.hpp"

#include "Epaphe_EigenSolver.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ReductionShared.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_SparseSolver.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <numeric>
#include <array>
#include <memory>
#include <cmath>

namespace epaphe {
namespace {

/// The blocks of one matrix X (K or M) split by retained (R) and condensed (C) DOFs.
struct Blocks {
  Teuchos::RCP<CrsMatrix> CC;
  Teuchos::RCP<MultiVector> CR;  // nC x nR, dense columns
  std::vector<double> RR;        // nR x nR, column-major, replicated
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
      if (rIndex[gc] >= 0)
        cr(lc, rIndex[gc]) += val(k);
      else {
        cols.push_back(cIndex[gc]);
        vals.push_back(val(k));
      }
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
  const auto a = transposeProduct(Psi, *X.CR);  // Psi^T X_CR
  const auto b = transposeProduct(Psi, XPsi);   // Psi^T X_CC Psi
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

/// The full model's vectors split into retained rows (x_R: dense nR x k, replicated) and condensed
/// rows (x_C: on the condensation's map), and joined back. The condensed map holds, on each rank,
/// the rank's own condensed rows in the full row map's order, so both directions are local copies
/// (plus one sum over ranks for x_R).
class RetainedCondensed {
public:
  RetainedCondensed(const Teuchos::RCP<const Map>& rowMap, const Teuchos::RCP<const Map>& cMap,
                    const std::vector<int>& rIndex, int nR)
      : rowMap_(rowMap), cMap_(cMap), nR_(nR), row_(rowMap->getNodeNumElements()) {
    LO c = 0;
    for (LO l = 0; l < static_cast<LO>(row_.size()); ++l) {
      const int r = rIndex[rowMap->getGlobalElement(l)];
      row_[l] = r >= 0 ? r : -1 - c++;  // r >= 0: retained index; else -1 - (local condensed row)
    }
  }
  int retained() const { return nR_; }
  const Teuchos::RCP<const Map>& condensedMap() const { return cMap_; }

  void split(const MultiVector& X, std::vector<double>& xR, MultiVector& xC) const {
    const int k = static_cast<int>(X.getNumVectors());
    std::vector<double> local(static_cast<std::size_t>(nR_) * k, 0.0);
    xR.assign(local.size(), 0.0);
    auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto c = xC.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (std::size_t l = 0; l < row_.size(); ++l)
      for (int j = 0; j < k; ++j) {
        if (row_[l] >= 0)
          local[static_cast<std::size_t>(j) * nR_ + row_[l]] = x(l, j);
        else
          c(-1 - row_[l], j) = x(l, j);
      }
    Teuchos::reduceAll(*rowMap_->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(),
                       xR.data());
  }

  void join(const std::vector<double>& xR, const MultiVector& xC, MultiVector& X) const {
    const int k = static_cast<int>(X.getNumVectors());
    auto x = X.getLocalViewHost(Tpetra::Access::OverwriteAll);
    auto c = xC.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (std::size_t l = 0; l < row_.size(); ++l)
      for (int j = 0; j < k; ++j)
        x(l, j) = row_[l] >= 0 ? xR[static_cast<std::size_t>(j) * nR_ + row_[l]] : c(-1 - row_[l], j);
  }

private:
  Teuchos::RCP<const Map> rowMap_, cMap_;
  int nR_;
  std::vector<LO> row_;
};

/// Solves the full model's K x = b with the reduction's K_CC factor, no second factorization. By
/// block elimination with Psi = -K_CC^{-1} K_CR (eq. 2.10) and K symmetric:
///   S x_R = b_R + Psi^T b_C,   S = K_RR + K_RC Psi  (the Guyan stiffness, eq. 2.11),
///   x_C = K_CC^{-1} b_C + Psi x_R,
/// one K_CC solve per vector and an nR x nR Cholesky of S factored once.
class SchurComplementSolver final : public SparseSolver {
public:
  /// `S`: nR x nR column-major. Throws if S is not positive definite (the body has a free rigid
  /// motion: K is singular); the caller then uses a shifted factor instead.
  SchurComplementSolver(const SparseSolver& kcc, const MultiVector& Psi, const RetainedCondensed& split,
                        std::vector<double> S)
      : kcc_(kcc), Psi_(Psi), split_(split), L_(std::move(S)) {
    Teuchos::LAPACK<int, double> lapack;
    int info = 0;
    lapack.POTRF('L', split.retained(), L_.data(), split.retained(), &info);
    EPAPHE_REQUIRE(info == 0,
                   "the Guyan stiffness is not positive definite (Cholesky failed at column " << info << ")");
  }
  void solve(const MultiVector& B, MultiVector& X) const override {
    const int nR = split_.retained(), k = static_cast<int>(B.getNumVectors());
    std::vector<double> r;
    MultiVector bC(split_.condensedMap(), static_cast<std::size_t>(k)), xC(bC.getMap(), static_cast<std::size_t>(k));
    split_.split(B, r, bC);
    const std::vector<double> ptb = transposeProduct(Psi_, bC);  // Psi^T b_C
    for (std::size_t i = 0; i < r.size(); ++i) r[i] += ptb[i];
    Teuchos::LAPACK<int, double> lapack;
    int info = 0;
    lapack.POTRS('L', nR, k, L_.data(), nR, r.data(), nR, &info);  // x_R
    kcc_.solve(bC, xC);
    xC.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, Psi_, replicated(r, nR, k, B.getMap()->getComm()), 1.0);
    split_.join(r, xC, X);
  }
  std::string name() const override { return "Schur complement over " + kcc_.name(); }
  long iterations() const override { return kcc_.iterations(); }

private:
  const SparseSolver& kcc_;
  const MultiVector& Psi_;
  const RetainedCondensed& split_;
  std::vector<double> L_;
};

/// The full model's lowest `count` frequencies (Hz) by Anasazi's shift-invert at sigma = 0 through
/// the reduction's own K_CC factor (SchurComplementSolver): no second factorization. Empty when K
/// is singular (a free rigid motion), which is exactly when the reduced model has a zero
/// frequency: a null vector u of K has u_C = Psi u_R, so R u_R is one of the reduced model's.
std::vector<double> frequenciesThroughCondensation(const FullModel& full, const ReducedModel& red,
                                                   const SparseSolver& kcc, const MultiVector& Psi,
                                                   const RetainedCondensed& split, int count, double tolerance) {
  const int nR = split.retained(), n = red.size;
  const std::vector<double> w2 = denseEigenpairs(red.K, red.M, n);
  if (w2.front() <= 1e-8 * w2.back()) return {};
  std::vector<double> S(static_cast<std::size_t>(nR) * nR);
  for (int j = 0; j < nR; ++j)
    for (int i = 0; i < nR; ++i) S[static_cast<std::size_t>(j) * nR + i] = red.K[static_cast<std::size_t>(j) * n + i];
  std::unique_ptr<SchurComplementSolver> schur;
  try {
    schur = std::make_unique<SchurComplementSolver>(kcc, Psi, split, std::move(S));
  } catch (const Error&) {
    return {};
  }
  EigenOptions eo;
  eo.count = count;
  eo.shift = 0.0;
  eo.tolerance = tolerance;
  const EigenResult er = lowestEigenpairs(full.K, full.M, *schur, eo);
  std::vector<double> f;
  for (double l : er.lambda) f.push_back(std::sqrt(std::max(l, 0.0)) / (2 * M_PI));
  return f;
}

}  // namespace

ReducedModel craigBampton(const FullModel& full, const std::vector<int>& retained, const CraigBamptonOptions& opt,
                          ReductionReport* report) {
  Stopwatch total;
  ReductionReport rep;
  const auto comm = full.K->getComm();
  const int nFree = full.numFree;
  EPAPHE_REQUIRE(opt.modes >= 0,
                 "body '" << full.name << "': " << opt.modes << " fixed-interface modes asked; use 0 or more");

  // Retained DOFs in the order (retained node, direction): q = [x_R, eta].
  std::vector<int> rIndex, cIndex(static_cast<std::size_t>(nFree), -1);
  int nR = 0;
  ReducedModel red =
      retainedShell(full, retained, opt.modes > 0 ? ReductionKind::CraigBampton : ReductionKind::Guyan, rIndex, nR);
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
    if (opt.startModes && opt.startModes->numModes >= 1 && opt.startModes->size - opt.startModes->numModes == nR &&
        opt.startModes->recovery.size() == full.eq.size() * static_cast<std::size_t>(opt.startModes->size)) {
      const ReducedModel& p = *opt.startModes;
      auto x0 = Teuchos::rcp(new MultiVector(cMap, static_cast<std::size_t>(std::min(p.numModes, opt.modes))));
      auto v = x0->getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (std::size_t i = 0; i < full.eq.size(); ++i) {
        const int g = full.eq[i];
        if (g < 0 || rIndex[g] >= 0) continue;
        const LO lc = cMap->getLocalElement(cIndex[g]);
        if (lc == Teuchos::OrdinalTraits<LO>::invalid()) continue;
        for (std::size_t j = 0; j < x0->getNumVectors(); ++j)
          v(lc, j) = p.recovery[i * static_cast<std::size_t>(p.size) + nR + j];
      }
      eo.start = x0;
    }
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
  if (!opt.basisOnly) {
    red.K = project(Kb, Psi, Phi.get(), nR, opt.modes);
    red.M = project(Mb, Psi, Phi.get(), nR, opt.modes);
  }
  rep.projectSeconds = sw.seconds();

  if (opt.checkFrequencies > 0 && !opt.basisOnly) {  // the frequency check, through the same factor
    sw.restart();
    const RetainedCondensed rc(full.K->getRowMap(), cMap, rIndex, nR);
    red.fullFrequencies = frequenciesThroughCondensation(full, red, *factor, Psi, rc,
                                                         std::min(opt.checkFrequencies, nFree - 1), opt.checkTolerance);
    rep.checkSeconds = sw.seconds();
  }
  sw.restart();

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
  rep.projectSeconds += sw.seconds();
  rep.seconds = total.seconds() - rep.checkSeconds;
  if (report) *report = rep;
  return red;
}

}  // namespace epaphe
