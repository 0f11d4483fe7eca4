// The massless-boundary reduction (Epaphe_CraigBampton.hpp, masslessBoundary).
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

/// The six rigid-body motions of a free body (translations along x, y, z, rotations about them
/// through the nodes' centroid) over its free DOFs, M-orthonormalised: Phi_r^T M Phi_r = I.
Teuchos::RCP<MultiVector> rigidBodyModes(const FullModel& full) {
  const auto map = full.M->getRowMap();
  std::array<double, 3> c = {0, 0, 0};
  for (const auto& x : full.mesh.coords)
    for (int d = 0; d < 3; ++d) c[d] += x[d] / full.numNodes();
  auto R = Teuchos::rcp(new MultiVector(map, 6));
  {
    auto r = R->getLocalViewHost(Tpetra::Access::ReadWrite);
    for (int node = 0; node < full.numNodes(); ++node)
      for (int d = 0; d < 3; ++d) {
        const int g = full.eq[3 * node + d];
        if (g < 0 || !map->isNodeGlobalElement(g)) continue;
        const LO l = map->getLocalElement(g);
        r(l, d) = 1.0;
        // rotation about axis a: u = e_a x (x - c); component d of it
        for (int a = 0; a < 3; ++a) {
          const int b = (a + 1) % 3, e = (a + 2) % 3;  // e_a x y = y_b e_e - y_e e_b
          if (d == e) r(l, 3 + a) = full.mesh.coords[node][b] - c[b];
          if (d == b) r(l, 3 + a) = -(full.mesh.coords[node][e] - c[e]);
        }
      }
  }
  MultiVector MR(map, 6);
  full.M->apply(*R, MR);
  std::vector<double> L = transposeProduct(*R, MR);  // Gram matrix R^T M R, then its Cholesky factor
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.POTRF('L', 6, L.data(), 6, &info);
  EPAPHE_REQUIRE(info == 0, "body '" << full.name
                                     << "': its six rigid-body motions are not independent in the mass "
                                        "inner product (column "
                                     << info << "): are its nodes on one line?");
  lapack.TRTRI('L', 'N', 6, L.data(), 6, &info);  // L^{-1}; Phi_r = R L^{-T}
  std::vector<double> LinvT(36, 0.0);
  for (int j = 0; j < 6; ++j)
    for (int i = j; i < 6; ++i) LinvT[static_cast<std::size_t>(i) * 6 + j] = L[static_cast<std::size_t>(j) * 6 + i];
  auto Phi = Teuchos::rcp(new MultiVector(map, 6));
  Phi->multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, *R, replicated(LinvT, 6, 6, map->getComm()), 0.0);
  return Phi;
}

/// A solver of the shifted K + sigma M of a free body whose answers are made M-orthogonal to its
/// rigid-body modes: X = Q (K + sigma M)^{-1} B, Q = I - Phi_r Phi_r^T M, the M-orthogonal projector
/// onto the elastic motions (the inertia-relief iteration below; deflate() alone cleans vectors).
class RigidDeflatedSolver final : public SparseSolver {
public:
  RigidDeflatedSolver(const SparseSolver& shifted, const MultiVector& rigid, const CrsMatrix& M)
      : shifted_(shifted), rigid_(rigid), Mrigid_(rigid.getMap(), rigid.getNumVectors()) {
    M.apply(rigid, Mrigid_);
  }
  void solve(const MultiVector& B, MultiVector& X) const override {
    shifted_.solve(B, X);
    deflate(X);
  }
  /// X = Q X: the rigid-body parts removed.
  void deflate(MultiVector& X) const {
    const int r = static_cast<int>(rigid_.getNumVectors()), k = static_cast<int>(X.getNumVectors());
    const auto c = transposeProduct(Mrigid_, X);  // Phi_r^T M X
    X.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, -1.0, rigid_, replicated(c, r, k, X.getMap()->getComm()), 1.0);
  }
  /// F = P F, P = I - M Phi_r Phi_r^T: forces balanced by the rigid-body inertia they set off.
  void balance(MultiVector& F) const {
    const int r = static_cast<int>(rigid_.getNumVectors()), k = static_cast<int>(F.getNumVectors());
    const auto c = transposeProduct(rigid_, F);  // Phi_r^T F
    F.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, -1.0, Mrigid_, replicated(c, r, k, F.getMap()->getComm()), 1.0);
  }
  std::string name() const override { return shifted_.name() + ", rigid-body modes deflated"; }
  long iterations() const override { return shifted_.iterations(); }

private:
  const SparseSolver& shifted_;
  const MultiVector& rigid_;
  MultiVector Mrigid_;
};

/// Inertia relief (the free-free attachment modes of Craig & Chang, AIAA J. 15 (1977); MacNeal 1971):
/// the elastic response U of a free body to unit forces E on its retained DOFs, each force balanced
/// by the rigid-body inertia it sets off, P = I - M Phi_r Phi_r^T, and its rigid part removed:
///   K U = P E,  Phi_r^T M U = 0,  i.e.  U = sum over elastic modes of phi phi^T E / omega^2.
/// With the deflated shifted solver S = Q (K + sigma M)^{-1}, U is the fixed point of
///   U = S (P E + sigma M U)
/// (from (K + sigma M) U = P E + sigma M U), reached at the rate sigma / (omega_1^2 + sigma) per pass.
MultiVector inertiaReliefResponses(const FullModel& full, const RigidDeflatedSolver& S, const MultiVector& E,
                                   double sigma, double rate) {
  MultiVector PE(E, Teuchos::Copy), U(E.getMap(), E.getNumVectors()), B(E.getMap(), E.getNumVectors()),
      MU(E.getMap(), E.getNumVectors());
  S.balance(PE);
  // sigma M U's contribution shrinks by `rate` a pass: stop when it can no longer change U's digits.
  const int passes = rate <= 0 ? 1 : std::max(1, static_cast<int>(std::ceil(std::log(1e-16) / std::log(rate))) + 1);
  EPAPHE_REQUIRE(rate < 0.5,
                 "body '" << full.name << "': the inertia-relief iteration would converge at " << rate
                          << " per pass; the shift is too close to the lowest elastic mode (a bug: report it)");
  for (int it = 0; it < passes; ++it) {
    full.M->apply(U, MU);
    B.update(1.0, PE, sigma, MU, 0.0);
    S.solve(B, U);
  }
  return U;
}

/// [Phi_r, Phi_e]: the rigid-body modes (none when `rigid` is null) then the elastic ones, each
/// M-normalised exactly (Anasazi's are M-orthonormal to its tolerance).
MultiVector joinedModes(const MultiVector* rigid, const MultiVector& elastic, const CrsMatrix& M) {
  const int nr = rigid ? static_cast<int>(rigid->getNumVectors()) : 0, ne = static_cast<int>(elastic.getNumVectors());
  MultiVector Phi(elastic.getMap(), static_cast<std::size_t>(nr + ne));
  {
    auto phi = Phi.getLocalViewHost(Tpetra::Access::OverwriteAll);
    auto e = elastic.getLocalViewHost(Tpetra::Access::ReadOnly);
    decltype(e) r;
    if (rigid) r = rigid->getLocalViewHost(Tpetra::Access::ReadOnly);
    for (std::size_t l = 0; l < phi.extent(0); ++l) {
      for (int j = 0; j < nr; ++j) phi(l, j) = r(l, j);
      for (int j = 0; j < ne; ++j) phi(l, nr + j) = e(l, j);
    }
  }
  MultiVector MPhi(Phi.getMap(), Phi.getNumVectors());
  M.apply(Phi, MPhi);
  const auto g = transposeProduct(Phi, MPhi);
  std::vector<double> scale(Phi.getNumVectors());
  for (std::size_t j = 0; j < scale.size(); ++j) scale[j] = 1.0 / std::sqrt(g[j * scale.size() + j]);
  Phi.scale(Teuchos::ArrayView<const double>(scale));
  return Phi;
}

/// A rigid translation's modal coordinates Phi^T M e_d and mass e_d^T M e_d (the momentum, the
/// initial velocity), into `red`.
void keepTranslations(const FullModel& full, const MultiVector& Phi, ReducedModel& red) {
  const MultiVector T = rigidTranslations(full);
  MultiVector MT(T.getMap(), 3);
  full.M->apply(T, MT);
  red.modalTranslation = transposeProduct(Phi, MT);
  for (int d = 0; d < 3; ++d) red.translationMass[d] = rigidMass(full, d);
}

/// Mode selection by participation: of the candidate modes, columns [first, first + count) of V
/// (M-orthonormal, ascending frequency), the `keep` with the largest generalized force under a unit
/// load along `dir` on every retained node, r_k = sum over the retained nodes of phi_k(node) . dir:
/// the mode's participation in that load pattern (its effective mass for it is r_k^2, Kammer &
/// Triller's ranking of modes by effective mass, for the load the contact applies). On a bar hitting
/// a wall end-on, the bending and twisting modes have r_k = 0 (their face moves antisymmetrically)
/// and give way to the axial ones. Returns the chosen columns in ascending frequency (ties in r_k^2
/// within 1e-12 of the largest: the lower mode).
std::vector<std::size_t> selectByParticipation(const MultiVector& V, const ReducedModel& red,
                                               const std::vector<int>& rIndex, int first, int count, int keep,
                                               const std::array<double, 3>& dir) {
  std::vector<int> axisOf;  // per retained DOF r: its direction (0, 1, 2)
  for (std::size_t nd = 0; nd < red.nodeDof.size(); ++nd)
    if (const int r = red.nodeDof[nd]; r >= 0) {
      if (axisOf.size() <= static_cast<std::size_t>(r)) axisOf.resize(static_cast<std::size_t>(r) + 1, 0);
      axisOf[r] = static_cast<int>(nd % 3);
    }
  std::vector<double> weight(rIndex.size(), 0.0);  // the load on free DOF g: dir's component if retained
  for (std::size_t g = 0; g < rIndex.size(); ++g)
    if (rIndex[g] >= 0) weight[g] = dir[axisOf[rIndex[g]]];
  const auto map = V.getMap();
  const auto v = V.getLocalViewHost(Tpetra::Access::ReadOnly);
  std::vector<double> local(static_cast<std::size_t>(count), 0.0), r(local.size(), 0.0);
  for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l) {
    const double w = weight[map->getGlobalElement(l)];
    if (w != 0.0)
      for (int k = 0; k < count; ++k) local[k] += w * v(l, first + k);
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, count, local.data(), r.data());
  double top = 0.0;
  for (double x : r) top = std::max(top, x * x);
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return r[a] * r[a] > r[b] * r[b] + 1e-12 * top; });
  order.resize(static_cast<std::size_t>(keep));
  std::sort(order.begin(), order.end());
  std::vector<std::size_t> cols;
  for (int k : order) cols.push_back(static_cast<std::size_t>(first + k));
  return cols;
}

/// The massless-boundary model from the kept modes Phi = [Phi_r, Phi_e] (nRigid rigid, m elastic) and
/// the static responses X to unit forces on the nR retained DOFs: G, K, M, the rigid translations and
/// the recovery rows, into `red` (Epaphe_ReducedModel.hpp).
void assembleMassless(const FullModel& full, const MultiVector& Phi, const MultiVector& X,
                      const std::vector<int>& rIndex, int nR, int nRigid, int m, ReducedModel& red) {
  const auto comm = full.K->getComm();
  const auto rowMap = full.K->getRowMap();
  const std::string body = "body '" + full.name + "'";
  // G = X_bb - Phi_b Omega^{-2} Phi_b^T over the elastic modes (Omega_j > 0): the rigid modes have no
  // static part, the inertia-relief X none of theirs.
  red.numModes = nRigid + m;
  red.size = nR + red.numModes;
  const std::vector<double> w2 = red.modalStiffness();
  const int mAll = red.numModes;
  red.boundaryModes = gatherRows(Phi, rIndex, nR);  // Phi_b, nR x (nRigid + m)
  std::vector<double> G = gatherRows(X, rIndex, nR);
  auto phib = [&](int i, int j) { return red.boundaryModes[static_cast<std::size_t>(j) * nR + i]; };
  for (int j = 0; j < nR; ++j)
    for (int i = 0; i < nR; ++i) {
      double s = 0;
      for (int k = nRigid; k < mAll; ++k) s += phib(i, k) * phib(j, k) / w2[k];
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
  for (int k = 0; k < mAll; ++k) {
    red.K[static_cast<std::size_t>(nR + k) * n + nR + k] += w2[k];
    red.M[static_cast<std::size_t>(nR + k) * n + nR + k] = 1.0;
  }
  keepTranslations(full, Phi, red);

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
        for (int k = nRigid; k < mAll; ++k) s -= phi(l, k) / w2[k] * phib(c, k);
        res[c] = s;
      }
      for (int c = 0; c < nR; ++c) {
        double s = 0;
        for (int r = 0; r < nR; ++r) s += res[r] * Ginv[static_cast<std::size_t>(c) * nR + r];
        a[c] = s;
        local[i * n + c] = s;
      }
      for (int k = 0; k < mAll; ++k) {
        double s = phi(l, k);
        for (int c = 0; c < nR; ++c) s -= a[c] * phib(c, k);
        local[i * n + nR + k] = s;
      }
    }
  }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), red.recovery.data());
}

}  // namespace

ReducedModel masslessBoundary(const FullModel& full, const std::vector<int>& retained, const CraigBamptonOptions& opt,
                              ReductionReport* report) {
  Stopwatch total;
  ReductionReport rep;
  const auto comm = full.K->getComm();
  const int nFree = full.numFree, m = opt.modes;
  const std::string body = "body '" + full.name + "'";
  EPAPHE_REQUIRE(m > 0, body << ": the massless-boundary reduction keeps the body's mass in its modes only, but " << m
                             << " modes are asked; set 'Fixed-interface modes' > 0");
  // A body with no boundary condition is free: its six rigid-body modes join the kept modes (with
  // Omega = 0) and the static part is the inertia-relief flexibility.
  const bool free = std::none_of(full.eq.begin(), full.eq.end(), [](int g) { return g < 0; });
  const int nRigid = free ? 6 : 0;

  std::vector<int> rIndex;
  int nR = 0;
  ReducedModel red = retainedShell(full, retained, ReductionKind::MasslessBoundary, rIndex, nR);
  EPAPHE_REQUIRE(nR + m + nRigid <= nFree, body << ": " << nR << " retained DOFs, " << m << " modes"
                                                << (free ? " and 6 rigid-body modes" : "") << " exceed the model's "
                                                << nFree << " free DOFs; keep fewer modes");
  rep.retainedDofs = nR;
  rep.condensedDofs = nFree - nR;

  // One factor serves the static responses and Anasazi's shift-invert: K itself for a held body;
  // K + sigma M for a free one, sigma = 1e-9 max_i K_ii / M_ii, far below its lowest elastic
  // eigenvalue (the inertia-relief iteration then converges in a few passes) while K + sigma M
  // stays well inside double precision (condition about 1e9, and its ill-conditioned directions are
  // the rigid modes, which the deflation removes).
  Stopwatch sw;
  double sigma = 0;
  Teuchos::RCP<const CrsMatrix> shifted = full.K;
  if (free) {
    sigma = 1e-9 * largestDiagonalRatio(*full.K, *full.M);
    shifted = Tpetra::MatrixMatrix::add(1.0, false, *full.K, sigma, false, *full.M);
  }
  auto factor = makeSolver(shifted, opt.solver, (free ? "K + sigma M of " : "K of ") + body, opt.iterativeTolerance);
  Teuchos::RCP<MultiVector> rigid = free ? rigidBodyModes(full) : Teuchos::null;
  std::unique_ptr<RigidDeflatedSolver> deflated;
  if (free) deflated = std::make_unique<RigidDeflatedSolver>(*factor, *rigid, *full.M);
  rep.factorSeconds = sw.seconds();

  sw.restart();
  EigenOptions eo;
  // A free body's six rigid-body modes come first (lambda = 0, theta = 1/sigma: the block of 6 Krylov
  // vectors resolves the six-fold eigenvalue); they give way to the exact ones, and the elastic
  // vectors are made M-orthogonal to those (Anasazi's are, to its tolerance).
  const int candidates = std::max(m, opt.candidates);
  EPAPHE_REQUIRE(nR + candidates + nRigid <= nFree, body << ": " << candidates << " candidate modes and " << nR
                                                         << " retained DOFs exceed the model's " << nFree
                                                         << " free DOFs; ask fewer 'Candidate modes'");
  eo.count = candidates + nRigid;
  eo.shift = -sigma;
  eo.tolerance = opt.eigenTolerance;
  EigenResult er = opt.denseEigen ? denseLowestEigenpairs(*full.K, *full.M, eo.count, body)
                                  : lowestEigenpairs(full.K, full.M, *factor, eo);
  if (candidates > m) {  // keep the m the contact's load excites most (selectByParticipation)
    std::vector<std::size_t> cols(static_cast<std::size_t>(nRigid));
    std::iota(cols.begin(), cols.end(), std::size_t{0});
    for (std::size_t c : selectByParticipation(*er.vectors, red, rIndex, nRigid, candidates, m, opt.loadDirection))
      cols.push_back(c);
    std::vector<double> lambda;
    for (std::size_t c : cols) lambda.push_back(er.lambda[c]);
    er.vectors = er.vectors->subCopy(Teuchos::ArrayView<const std::size_t>(cols));
    er.lambda = lambda;
  }
  const double top = er.lambda.back();
  for (int k = 0; k < nRigid + m; ++k)
    EPAPHE_REQUIRE(
        (k < nRigid) == (std::abs(er.lambda[k]) <= 1e-8 * top),
        body << ": eigenvalue " << k + 1 << " is " << er.lambda[k] << " (the largest kept " << top << "); "
             << (free ? "a free body has exactly 6 rigid-body modes, this one has "
                      : "a body held by its boundary conditions has none, this one has ")
             << std::count_if(er.lambda.begin(), er.lambda.end(), [&](double l) { return std::abs(l) <= 1e-8 * top; })
             << ": the model has a mechanism; clamp it fully, or remove every clamp");
  er.lambda.erase(er.lambda.begin(), er.lambda.begin() + nRigid);
  Teuchos::RCP<MultiVector> elastic = er.vectors->subCopy(Teuchos::Range1D(nRigid, nRigid + m - 1));
  if (free) deflated->deflate(*elastic);
  const auto rowMap = full.K->getRowMap();
  MultiVector Phi = joinedModes(rigid.get(), *elastic, *full.M);  // [Phi_r, Phi_e]
  rep.eigenIterations = er.restarts;
  rep.eigenSolves = er.operatorVectors;
  rep.eigenSolveSeconds = er.operatorSeconds;
  red.modeFrequencies.assign(static_cast<std::size_t>(nRigid), 0.0);
  for (double l : er.lambda) red.modeFrequencies.push_back(std::sqrt(l) / (2 * M_PI));
  rep.eigenSeconds = sw.seconds();

  // The static response to a unit force on each retained DOF: X = K^{-1} E_b (held), or its
  // inertia-relief form (free).
  sw.restart();
  MultiVector E(rowMap, static_cast<std::size_t>(nR));
  {
    auto e = E.getLocalViewHost(Tpetra::Access::ReadWrite);
    for (LO l = 0; l < static_cast<LO>(rowMap->getNodeNumElements()); ++l)
      if (const int r = rIndex[rowMap->getGlobalElement(l)]; r >= 0) e(l, r) = 1.0;
  }
  MultiVector X(rowMap, static_cast<std::size_t>(nR));
  if (free)
    Tpetra::deep_copy(X, inertiaReliefResponses(full, *deflated, E, sigma, sigma / (er.lambda.front() + sigma)));
  else
    factor->solve(E, X);
  rep.constraintSeconds = sw.seconds();
  rep.solverIterations = factor->iterations();

  sw.restart();
  assembleMassless(full, Phi, X, rIndex, nR, nRigid, m, red);
  rep.projectSeconds = sw.seconds();
  rep.seconds = total.seconds();
  if (report) *report = rep;
  return red;
}

}  // namespace epaphe
