// Full models kept sparse with a lumped mass ("Full, lumped mass"): the HRZ lumping, its
// frequencies against the consistent mass as the mesh is refined, the sparse central difference
// (energy conserved, the same steps as the dense code on the same matrices), the stable-step
// estimate by Lanczos against LAPACK, and the contact correction with a diagonal flexibility.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestBar.hpp"
#include "TestModels.hpp"

#include <Teuchos_DefaultComm.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

using namespace epaphe;

namespace {

using test::bar;
using test::noise;
using test::steel;

FullModel cantilever(int nx) {
  return bar(nx, true);
}

/// The lumped model as a dense ReducedModel (the reference the sparse code must reproduce).
ReducedModel denseCopy(const ReducedModel& sparse) {
  ReducedModel d = sparse;
  const int n = sparse.size;
  d.kind = ReductionKind::None;
  d.K.assign(static_cast<std::size_t>(n) * n, 0.0);
  d.M.assign(d.K.size(), 0.0);
  for (int i = 0; i < n; ++i) {
    d.M[static_cast<std::size_t>(i) * n + i] = sparse.lumpedMass[i];
    for (std::size_t k = sparse.sparseK.rowStart[i]; k < sparse.sparseK.rowStart[i + 1]; ++k)
      d.K[static_cast<std::size_t>(sparse.sparseK.cols[k]) * n + i] = sparse.sparseK.values[k];
  }
  d.sparseK = {};
  d.lumpedMass.clear();
  d.recovery.assign(3 * static_cast<std::size_t>(d.numNodes()) * n, 0.0);
  for (std::size_t i = 0; i < d.nodeDof.size(); ++i)
    if (d.nodeDof[i] >= 0) d.recovery[i * n + d.nodeDof[i]] = 1.0;
  return d;
}

void set(const DenseVector& v, const std::vector<double>& a) {
  auto h = Kokkos::create_mirror_view(v);
  for (std::size_t i = 0; i < a.size(); ++i) h(i) = a[i];
  Kokkos::deep_copy(v, h);
}
std::vector<double> get(const DenseVector& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

}  // namespace

TEST(LumpedMass, HrzIsPositiveKeepsTheRigidMassAndEqualsTheRowSumOnABox) {
  for (bool clamped : {false, true}) {
    const FullModel full = bar(8, clamped);
    const ReducedModel consistent = unreducedModel(full);
    const ReducedModel lumped = sparseModel(withLumpedMass(full));
    const int n = full.numFree;
    ASSERT_EQ(lumped.size, n);
    ASSERT_TRUE(lumped.sparse());
    EXPECT_TRUE(lumped.K.empty() && lumped.M.empty() && lumped.recovery.empty());  // no dense storage
    for (int d = 0; d < 3; ++d) {
      const auto t = lumped.rigidTranslation(d);
      const auto Mt = lumped.massTimes(t);
      double m = 0;
      for (int i = 0; i < n; ++i) m += t[i] * Mt[i];
      EXPECT_NEAR(m, rigidMass(full, d), 1e-12 * m) << "direction " << d;
    }
    // Affine 8-node hexahedra, free-free: HRZ = element-wise HRZ = the row sum of the consistent
    // mass (m_e / 8 per corner). Clamped: every mass is scaled by the same factor, t^T M t over the
    // free DOFs / element-wise HRZ's total, here (N - 2C/3) / (N - C/2) with N = 32 elements, C = 4
    // at the clamp (see withLumpedMass).
    const double factor = clamped ? (32.0 - 2.0 * 4 / 3) / (32.0 - 4.0 / 2) : 1.0;
    for (int node = 0; node < full.numNodes(); ++node) {
      if (clamped && full.mesh.coords[node][0] < 0.05) continue;  // rows next to the clamp miss its columns
      for (int d = 0; d < 3; ++d) {
        const int i = full.eq[3 * node + d];
        double row = 0;
        for (int j = 0; j < n; ++j) row += consistent.m(i, j);
        EXPECT_GT(lumped.lumpedMass[i], 0.0);
        EXPECT_NEAR(lumped.lumpedMass[i], factor * row, 1e-12 * row) << "node " << node << " direction " << d;
      }
    }
  }
}

TEST(LumpedMass, FrequenciesApproachTheConsistentOnesAsTheMeshIsRefined) {
  // The free 5 cm steel cube of chapter 4 on n x n x n hexahedra: its lowest 6 elastic frequencies
  // (after the 6 rigid-body modes, by Anasazi as the run's frequency check computes them) with the
  // lumped mass against the consistent mass on the same mesh. The lumped ones are lower, and the gap
  // falls about 4-fold per halving of the elements (both masses converge to the continuum's, at
  // second order). Stated tolerance: within 3 % on the 12 x 12 x 12 mesh.
  double previous = 1e300;
  for (int n : {3, 6, 12}) {
    const Mesh mesh = makeBoxMesh({-0.025, 0.045, -0.025}, {0.05, 0.05, 0.05}, {n, n, n});
    const FullModel full = assembleHexModel("cube", mesh, steel, {}, Teuchos::DefaultComm<int>::getComm());
    const auto fc = fullModelFrequencies(full, 12), fl = fullModelFrequencies(withLumpedMass(full), 12);
    double worst = 0;
    for (int k = 6; k < 12; ++k) {
      EXPECT_LT(fl[k], fc[k]) << n << " elements, mode " << k;
      worst = std::max(worst, (fc[k] - fl[k]) / fc[k]);
    }
    std::printf(
        "cube %2d x %2d x %2d: lumped vs consistent mass, 6 lowest elastic frequencies, largest difference "
        "%.3e (first: %.1f / %.1f Hz)\n",
        n, n, n, worst, fl[6], fc[6]);
    EXPECT_LT(worst, 0.4 * previous) << n << " elements";
    previous = worst;
  }
  EXPECT_LT(previous, 0.03);
}

TEST(LumpedCentralDifference, FreeVibrationConservesEnergyAndMatchesTheDenseSteps) {
  const ReducedModel sparse = sparseModel(withLumpedMass(cantilever(16)));
  const ReducedModel dense = denseCopy(sparse);
  const int n = sparse.size;
  const double h = 0.5 * criticalTimeStep(dense, {}, 0.0, {}).critical;
  CentralDifference cs(sparse, h, {}), cdn(dense, h, {});
  DenseVector a[3] = {DenseVector("a0", n), DenseVector("a1", n), DenseVector("a2", n)};
  DenseVector b[3] = {DenseVector("b0", n), DenseVector("b1", n), DenseVector("b2", n)};
  auto u0 = noise(n, 7), u1 = noise(n, 8);  // every mode excited, the highest ones too
  for (int i = 0; i < n; ++i) u1[i] = 1e-6 * u0[i] + 1e-9 * u1[i];
  for (int i = 0; i < n; ++i) u0[i] *= 1e-6;
  set(a[0], u0), set(a[1], u1), set(b[0], u0), set(b[1], u1);
  const double e0 = cs.halfStepEnergy(a[0], a[1]);
  EXPECT_NEAR(e0, cdn.halfStepEnergy(b[0], b[1]), 1e-12 * e0);
  double drift = 0, diff = 0, scale = 0;
  int prev = 0, cur = 1, next = 2;
  for (int step = 0; step < 4000; ++step) {
    cs.predict(a[cur], a[prev], a[next]);
    cdn.predict(b[cur], b[prev], b[next]);
    drift = std::max(drift, std::abs(cs.halfStepEnergy(a[cur], a[next]) - e0) / e0);
    const int old = prev;
    prev = cur, cur = next, next = old;
  }
  const auto qa = get(a[cur]), qb = get(b[cur]);
  for (int i = 0; i < n; ++i) {
    diff = std::max(diff, std::abs(qa[i] - qb[i]));
    scale = std::max(scale, std::abs(qb[i]));
  }
  std::printf(
      "sparse lumped step: energy drift %.2e over 4000 steps, largest difference to the dense steps %.2e "
      "of %.2e\n",
      drift, diff, scale);
  EXPECT_LT(drift, 1e-11);
  EXPECT_LT(diff, 1e-9 * scale);
  EXPECT_NEAR(cs.strain(a[cur]), cdn.strain(b[cur]), 1e-9 * cdn.strain(b[cur]));
}

TEST(LumpedCentralDifference, RayleighAlphaBalanceIsExactAndModalOrBetaAreRefused) {
  const ReducedModel sparse = sparseModel(withLumpedMass(cantilever(8)));
  const int n = sparse.size;
  DampingOptions d;
  d.type = DampingType::Rayleigh;
  d.alpha = 2000.0;
  const double h = 0.5 * criticalTimeStep(sparse, {}, 0.0, d).critical;
  CentralDifference cd(sparse, h, d);
  DenseVector qm("qm", n), q("q", n);
  auto u = noise(n, 3);
  for (double& x : u) x *= 1e-6;
  set(q, u);
  const auto b = test::freeSteps(cd, qm, q, 3000);
  EXPECT_LT(b.end, 0.9 * b.start);
  EXPECT_NEAR(b.end + b.damping, b.start, 1e-11 * b.start);
  d.beta = 1e-7;
  EXPECT_THROW(CentralDifference(sparse, h, d), Error);
  d = DampingOptions{};
  d.type = DampingType::Modal;
  d.ratio = 0.01;
  EXPECT_THROW(CentralDifference(sparse, h, d), Error);
}

TEST(LumpedCentralDifference, LanczosCriticalStepMatchesLapackAndIsSafe) {
  const ReducedModel sparse = sparseModel(withLumpedMass(cantilever(16)));
  const ReducedModel dense = denseCopy(sparse);
  std::vector<int> springs;
  for (int node : sparse.nodeSet("x+", "test"))
    for (int d = 0; d < 3; ++d) springs.push_back(sparse.nodeDof[3 * node + d]);
  for (double kp : {0.0, 1e10, 1e12}) {
    const HighestEigenvalue l = highestEigenvalue(sparse, springs, kp);
    const StableStep exact = criticalTimeStep(dense, springs, kp, {});
    const StableStep estimate = criticalTimeStep(sparse, springs, kp, {});
    std::printf(
        "kp %.0e: Lanczos %d iterations, critical step %.6e s (LAPACK %.6e s), Gershgorin bound %.3f x "
        "lambda_max\n",
        kp, l.iterations, estimate.critical, exact.critical, l.gershgorin / (exact.omegaMax * exact.omegaMax));
    EXPECT_TRUE(l.converged);
    EXPECT_LE(estimate.critical, exact.critical * (1 + 1e-12));  // never above the true critical step
    EXPECT_NEAR(estimate.critical, exact.critical, 1e-8 * exact.critical);
    EXPECT_GE(l.gershgorin, l.value);
  }
  // Past the estimate the scheme blows up, below it stays bounded.
  const double hc = criticalTimeStep(sparse, {}, 0.0, {}).critical;
  const int n = sparse.size;
  for (double f : {0.98, 1.02}) {
    CentralDifference cd(sparse, f * hc, {});
    DenseVector qm("qm", n), q("q", n), qp("qp", n);
    auto u = noise(n, 11);
    for (double& x : u) x *= 1e-9;
    set(q, u);
    for (int step = 0; step < 300; ++step) {
      cd.predict(q, qm, qp);
      std::swap(qm, q);
      std::swap(q, qp);
    }
    double big = 0;
    for (double x : get(q)) big = std::max(big, std::abs(x));
    if (f < 1)
      EXPECT_LT(big, 1e-6) << "h = " << f << " h_crit";
    else
      EXPECT_GT(big, 1.0) << "h = " << f << " h_crit";
  }
}

namespace {
/// A 4 x 4 node plate z = 0 over [0, 3]^2 with its own diagonal flexibility (48 DOFs, block 1) and
/// one node (block 0, 3 DOFs) under it: the node pushed into the plate is corrected with a
/// diagonal flexibility block, or with the same values as a dense block. Both must agree.
struct NodeOnPlate {
  std::vector<double> grid;
  std::unique_ptr<BSplineSurface> plate;
  std::vector<double> q;
  NodeOnPlate() {
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) grid.insert(grid.end(), {1.0 * i, 1.0 * j, 0.0});
    SurfaceOptions o;
    o.closureU = o.closureV = Closure::Open;
    plate = std::make_unique<BSplineSurface>("plate", 4, 4, grid, o);
    q.assign(51, 0.0);
    q[2] = -0.0015;             // the node (at z = 0.001 - 0.0015) has crossed the plate
    q[3 + 3 * 5 + 2] = 0.0002;  // which bends a little towards it
  }
  std::vector<double> correct(bool diagonal, const std::string& method, std::vector<double>* force) {
    ContactNodes nodes;
    const int dof[3] = {0, 1, 2};
    const double x[3] = {1.3, 1.6, 0.001};
    nodes.add(0, 0, dof, x);
    ContactSurface cs;
    cs.surface = cs.moving = plate.get();
    cs.block = 1;
    for (int g = 0; g < 16; ++g)
      for (int d = 0; d < 3; ++d) {
        cs.gridDofs.push_back(3 + 3 * g + d);
        cs.gridX.push_back(grid[3 * g + d]);
      }
    DenseMatrix F0("F0", 3, 3);
    auto F0h = Kokkos::create_mirror_view(F0);
    const double f0[9] = {2e-3, 1e-4, 0, 1e-4, 3e-3, 2e-4, 0, 2e-4, 4e-3};
    for (int k = 0; k < 9; ++k) F0h(k % 3, k / 3) = f0[k];
    Kokkos::deep_copy(F0, F0h);
    std::vector<double> d1(48);
    for (int i = 0; i < 48; ++i) d1[i] = 1e-3 * (1.0 + 0.1 * (i % 7));
    Flexibility F(F0);
    if (diagonal) {
      DenseVector D1("D1", 48);
      set(D1, d1);
      F.append(Flexibility::diagonal(D1));
    } else {
      DenseMatrix F1("F1", 48, 48);
      auto h = Kokkos::create_mirror_view(F1);
      for (int i = 0; i < 48; ++i) h(i, i) = d1[i];
      Kokkos::deep_copy(F1, h);
      F.append(Flexibility(F1));
    }
    ContactOptions o;
    o.set("Method", method);
    o.set("Penalty stiffness", 1e3);
    SurfaceContact c(nodes, {cs}, {ContactBlock{0, 3}, ContactBlock{3, 48}}, o, F);
    DenseVector v("q", 51);
    set(v, q);
    CostSplit cost;
    c.correct(v, cost);
    EXPECT_EQ(c.numActive(), 1);
    if (force) force->push_back(c.force()(0));
    // the corrected gap, measured again at the corrected q: closed up to the change of the plate's
    // shape over the correction (second order)
    const double predicted = c.gap()(0);
    EXPECT_LT(predicted, 0.0);
    c.measureGaps(v, cost);
    if (method == "Lagrange") EXPECT_LT(std::abs(c.gap()(0)), 1e-5 * std::abs(predicted));
    return get(v);
  }
};
}  // namespace

TEST(LumpedContact, DiagonalFlexibilityBlockEqualsTheSameDenseBlock) {
  for (const std::string& method : {"Lagrange", "Penalty"}) {
    NodeOnPlate s;
    std::vector<double> fd, fs;
    const auto qd = s.correct(true, method, &fd);
    const auto qs = s.correct(false, method, &fs);
    ASSERT_EQ(qd.size(), qs.size());
    EXPECT_GT(fd[0], 0.0);
    EXPECT_NEAR(fd[0], fs[0], 1e-12 * fs[0]);
    for (std::size_t i = 0; i < qd.size(); ++i) EXPECT_NEAR(qd[i], qs[i], 1e-15) << "DOF " << i;
    // the node pushed up (along n), the plate's node nearest the foot point down
    EXPECT_GT(qd[2], s.q[2]);
    EXPECT_LT(qd[3 + 3 * 5 + 2], s.q[3 + 3 * 5 + 2]);
  }
}
