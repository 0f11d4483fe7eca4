// Massless-boundary reduction (MacNeal's residual flexibility; Epaphe_ReducedModel.hpp) and its
// central difference (Epaphe_CentralDifference.cpp): the static response and the recovery of every
// node are exact, the frequencies are the full model's, the boundary follows the modes in free
// flight, a correction q += F f moves the modes by P_e Phi_b^T f / 2 and leaves the static residual
// G f on the boundary, and the discrete energy balance closes under arbitrary boundary forces.
// Each of these fails if A, B, F, K_res or the recovery rows are wrong.
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_FullModel.hpp"

#include "TestBar.hpp"
#include "TestModels.hpp"

#include <Teuchos_LAPACK.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace epaphe;

namespace {

using test::noise;

/// The steel bar (TestBar.hpp), clamped at x = 0 unless told otherwise.
FullModel bar(int nx, bool clamped = true) {
  return test::bar(nx, clamped);
}

/// x = A^{-1} b for a dense symmetric positive definite A (column-major).
std::vector<double> solve(std::vector<double> A, std::vector<double> b) {
  const int n = static_cast<int>(b.size());
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.POSV('U', n, 1, A.data(), n, b.data(), n, &info);
  EXPECT_EQ(info, 0);
  return b;
}

void set(const DenseVector& v, const std::vector<double>& a) {
  for (std::size_t i = 0; i < a.size(); ++i) v(i) = a[i];
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

ReducedModel massless(const FullModel& full, int modes) {
  CraigBamptonOptions o;
  o.modes = modes;
  return masslessBoundary(full, full.mesh.nodeSet("x+", "test"), o);
}

}  // namespace

TEST(MasslessBoundary, StaticResponseRecoveryAndFrequenciesAreTheFullModels) {
  const FullModel full = bar(12);
  const ReducedModel red = massless(full, 8);
  const ReducedModel ref = unreducedModel(full);
  const int nb = red.boundarySize(), n = red.size;
  ASSERT_EQ(nb, 27);  // 9 tip nodes
  ASSERT_EQ(n, nb + 8);
  ASSERT_TRUE(red.massless());
  EXPECT_EQ(red.method(), "Massless boundary");

  // M = diag(0, I): the boundary carries no mass, the modes are M-orthonormal.
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) EXPECT_EQ(red.m(i, j), (i == j && i >= nb) ? 1.0 : 0.0) << i << ", " << j;

  // Recovery rows of the retained DOFs are unit rows: u_b is a coordinate.
  for (int node : full.mesh.nodeSet("x+", "test"))
    for (int d = 0; d < 3; ++d) {
      const int i = red.nodeDof[3 * node + d];
      ASSERT_GE(i, 0);
      for (int j = 0; j < n; ++j) EXPECT_EQ(red.recoveryRow(node, d)[j], j == i ? 1.0 : 0.0);
    }

  // Static: a force f on the tip. The reduced K q = [f, 0] and u = R q give every node's
  // displacement of the full K u = f, to round-off (stated: 1e-9 of the largest).
  const std::vector<double> fb = noise(nb, 7);
  std::vector<double> fq(static_cast<std::size_t>(n), 0.0), ff(static_cast<std::size_t>(ref.size), 0.0);
  for (int node : full.mesh.nodeSet("x+", "test"))
    for (int d = 0; d < 3; ++d) {
      fq[red.nodeDof[3 * node + d]] = 1e4 * fb[red.nodeDof[3 * node + d]];
      ff[full.eq[3 * node + d]] = 1e4 * fb[red.nodeDof[3 * node + d]];
    }
  const std::vector<double> q = solve(red.K, fq), u = solve(ref.K, ff);
  double worst = 0;
  for (int node = 0; node < full.numNodes(); ++node)
    for (int d = 0; d < 3; ++d) {
      const int g = full.eq[3 * node + d];
      const double exact = g >= 0 ? u[g] : 0.0;
      double rec = 0;
      for (int j = 0; j < n; ++j) rec += red.recoveryRow(node, d)[j] * q[j];
      worst = std::max(worst, std::abs(rec - exact));
    }
  EXPECT_LT(worst, 1e-9 * maxAbs(u)) << "largest |u| " << maxAbs(u);

  // Frequencies: the kept modes are the full model's lowest (retained nodes free), to Anasazi's tolerance.
  const std::vector<double> fr = reducedFrequencies(red), fullF = fullModelFrequencies(full, 8);
  ASSERT_EQ(fr.size(), 8u);
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(fr[k], fullF[k], 1e-8 * fullF[k]) << "mode " << k;

  // Stable step: the last kept mode's, 2 / omega_8, far above the Craig-Bampton model's (its massive
  // tip nodes set the highest frequency).
  const StableStep s = criticalTimeStep(red, {}, 0.0, DampingOptions{});
  EXPECT_NEAR(s.critical, 2.0 / (2 * M_PI * fullF[7]), 1e-8 * s.critical);
  CraigBamptonOptions cbo;
  cbo.modes = 8;
  const ReducedModel cb = craigBampton(full, full.mesh.nodeSet("x+", "test"), cbo);
  EXPECT_GT(s.critical, 3 * criticalTimeStep(cb, {}, 0.0, DampingOptions{}).critical);
}

TEST(MasslessBoundary, RefusesWhatItCannotModel) {
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const FullModel clamped = bar(6);
  const FullModel free = bar(6, false);
  EXPECT_NE(message([&] { massless(free, free.numFree - 27 - 5); }).find("and 6 rigid-body modes exceed"),
            std::string::npos);
  EXPECT_NE(message([&] { massless(clamped, 0); }).find("'Fixed-interface modes' > 0"), std::string::npos);
  // With every mode kept the modes carry all the flexibility: G = 0 is refused.
  EXPECT_NE(message([&] { massless(clamped, clamped.numFree - 27); }).find("keep fewer modes"), std::string::npos);
}

// A free body (no boundary condition): its six rigid-body modes join the kept modes with Omega = 0,
// and the static part is the inertia-relief flexibility. Checked against the dense full model's
// complete eigendecomposition: the residual flexibility G and the recovery of a static residual are
// the sums over the discarded elastic modes, sum phi phi_b^T / omega^2 (exact for a free body:
// the inertia-relief flexibility is the sum over all elastic modes); the kept frequencies are the
// full model's; a rigid translation is exact (the boundary translates, K t = 0, every node moves
// by one, t^T M t is the body's mass).
TEST(MasslessBoundary, FreeBodyKeepsRigidModesAndTheInertiaReliefFlexibility) {
  const FullModel full = bar(12, false);
  const int kept = 8;
  const ReducedModel red = massless(full, kept);
  const ReducedModel ref = unreducedModel(full);
  const int nb = red.boundarySize(), n = red.size, N = ref.size;
  ASSERT_EQ(nb, 27);
  ASSERT_EQ(red.numModes, 6 + kept);
  ASSERT_EQ(n, nb + 6 + kept);

  std::vector<double> V;  // every mode of the full model, M-orthonormal, ascending
  const std::vector<double> w2 = denseEigenpairs(ref.K, ref.M, N, &V);
  const double top = w2.back();
  for (int k = 0; k < 6; ++k) ASSERT_LT(std::abs(w2[k]), 1e-9 * top) << "rigid mode " << k;
  ASSERT_GT(w2[6], 1e-6 * top);
  // the split between kept and discarded modes is not inside a repeated eigenvalue
  ASSERT_GT(w2[6 + kept] - w2[5 + kept], 1e-3 * w2[6 + kept]);

  const std::vector<double> fr = reducedFrequencies(red);
  ASSERT_EQ(fr.size(), static_cast<std::size_t>(6 + kept));
  for (int k = 0; k < 6; ++k) EXPECT_EQ(fr[k], 0.0);
  for (int k = 6; k < 6 + kept; ++k) EXPECT_NEAR(fr[k], std::sqrt(w2[k]) / (2 * M_PI), 1e-8 * fr[k]) << "mode " << k;

  // G = sum over the discarded elastic modes of phi_b phi_b^T / omega^2 (stated: 1e-8 of its largest entry)
  std::vector<int> bRow(static_cast<std::size_t>(nb));  // retained DOF c -> full model row
  for (int node : full.mesh.nodeSet("x+", "test"))
    for (int d = 0; d < 3; ++d) bRow[red.nodeDof[3 * node + d]] = full.eq[3 * node + d];
  auto v = [&](int row, int k) { return V[static_cast<std::size_t>(k) * N + row]; };
  double worstG = 0, largestG = 0;
  for (int c = 0; c < nb; ++c)
    for (int c2 = 0; c2 < nb; ++c2) {
      double exact = 0;
      for (int k = 6 + kept; k < N; ++k) exact += v(bRow[c], k) * v(bRow[c2], k) / w2[k];
      const double g = red.residualFlexibility[static_cast<std::size_t>(c2) * nb + c];
      worstG = std::max(worstG, std::abs(g - exact));
      largestG = std::max(largestG, std::abs(exact));
    }
  EXPECT_LT(worstG, 1e-8 * largestG) << "largest G entry " << largestG;

  // A static residual r = u_b - Phi_b eta = G f (eta = 0) recovers every node's u = sum_discarded phi phi_b^T f /
  // omega^2.
  const std::vector<double> f = noise(nb, 11);
  std::vector<double> q(static_cast<std::size_t>(n), 0.0);
  for (int c = 0; c < nb; ++c)
    for (int c2 = 0; c2 < nb; ++c2) q[c] += red.residualFlexibility[static_cast<std::size_t>(c2) * nb + c] * f[c2];
  double worstU = 0, largestU = 0;
  for (int node = 0; node < full.numNodes(); ++node)
    for (int d = 0; d < 3; ++d) {
      const int row = full.eq[3 * node + d];
      double exact = 0, rec = 0;
      for (int k = 6 + kept; k < N; ++k) {
        double pf = 0;
        for (int c = 0; c < nb; ++c) pf += v(bRow[c], k) * f[c];
        exact += v(row, k) * pf / w2[k];
      }
      for (int j = 0; j < n; ++j) rec += red.recoveryRow(node, d)[j] * q[j];
      worstU = std::max(worstU, std::abs(rec - exact));
      largestU = std::max(largestU, std::abs(exact));
    }
  EXPECT_LT(worstU, 1e-8 * largestU) << "largest |u| " << largestU;

  // A rigid translation: exact in the modes, the boundary following them. Recovered to 1e-9: the rows
  // R = [Res G^{-1}, Phi - Res G^{-1} Phi_b] cancel Res G^{-1} Phi_b eta between their two parts, terms
  // about cond(G) larger than the result (measured: 5e-11).
  for (int d = 0; d < 3; ++d) {
    const std::vector<double> t = red.rigidTranslation(d);
    for (int node = 0; node < full.numNodes(); ++node)
      for (int e = 0; e < 3; ++e) {
        double u = 0;
        for (int j = 0; j < n; ++j) u += red.recoveryRow(node, e)[j] * t[j];
        EXPECT_NEAR(u, e == d ? 1.0 : 0.0, 1e-9) << "node " << node << ", direction " << e;
      }
    double tMt = 0, kt = 0, kScale = 0;
    for (int i = 0; i < n; ++i) {
      double s = 0;
      for (int j = 0; j < n; ++j) {
        tMt += t[i] * red.m(i, j) * t[j];
        s += red.k(i, j) * t[j];
        kScale = std::max(kScale, std::abs(red.k(i, j)));
      }
      kt = std::max(kt, std::abs(s));
    }
    EXPECT_NEAR(tMt, rigidMass(full, d), 1e-12 * rigidMass(full, d));
    EXPECT_NEAR(red.translationMass[d], rigidMass(full, d), 1e-12 * rigidMass(full, d));
    EXPECT_LT(kt, 1e-10 * kScale);
  }
}

TEST(MasslessCentralDifference, BoundaryFollowsModesCorrectionLeavesResidualAndEnergyBalances) {
  const FullModel full = bar(10);
  const ReducedModel red = massless(full, 6);
  const int nb = red.boundarySize(), n = red.size, m = red.numModes;
  const double fmax = reducedFrequencies(red).back();
  const double h = 0.5 / (2 * M_PI * fmax);  // a quarter of the critical step
  for (int dampingType = 0; dampingType < 3; ++dampingType) {
    DampingOptions damping;
    damping.type = static_cast<DampingType>(dampingType);
    damping.alpha = 50.0;
    damping.beta = 2e-7;
    damping.ratio = 0.02;
    SCOPED_TRACE("damping type " + std::to_string(dampingType));
    CentralDifference cd(red, h, damping);
    const Flexibility F = cd.flexibility();
    ASSERT_EQ(F.numBlocks(), 1);
    auto phi = [&](int c, int k) { return red.boundaryModes[static_cast<std::size_t>(k) * nb + c]; };
    auto G = [&](int c, int c2) { return red.residualFlexibility[static_cast<std::size_t>(c2) * nb + c]; };

    DenseVector q0("q0", n), q1("q1", n), q2("q2", n);
    std::vector<double> start(static_cast<std::size_t>(n), 0.0);
    const std::vector<double> eta0 = noise(m, 3);
    for (int k = 0; k < m; ++k) start[nb + k] = 1e-6 * eta0[k];
    for (int c = 0; c < nb; ++c)
      for (int k = 0; k < m; ++k) start[c] += phi(c, k) * start[nb + k];
    set(q0, start);
    set(q1, start);  // at rest
    const double e0 = cd.halfStepEnergy(q0, q1);
    double work = 0, diss = 0, worstBalance = 0, worstFollow = 0, worstResidual = 0, worstFree = 0;
    std::vector<double> f(static_cast<std::size_t>(nb), 0.0);
    for (int step = 0; step < 400; ++step) {
      cd.predict(q1, q0, q2);
      // free flight: u_b* = Phi_b eta*
      for (int c = 0; c < nb; ++c) {
        double s = 0;
        for (int k = 0; k < m; ++k) s += phi(c, k) * q2(nb + k);
        worstFollow = std::max(worstFollow, std::abs(q2(c) - s));
      }
      // an arbitrary boundary force on half the steps, corrected through F (eqs. 2.35-2.36)
      std::fill(f.begin(), f.end(), 0.0);
      if ((step / 25) % 2 == 1) f = noise(nb, 100u + static_cast<unsigned>(step));
      for (double& x : f) x *= 1e3;
      const auto& P = F.pack();
      auto dense = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dense);
      for (int i = 0; i < n; ++i) {
        double s = 0;
        for (int c = 0; c < nb; ++c) s += dense(static_cast<std::size_t>(c) * n + i) * f[c];
        q2(i) += s;
      }
      // after the correction the boundary is the modes plus the static residual: u_b - Phi_b eta = G f
      // (relative to the largest G f; on steps without force, relative to the boundary's motion)
      std::vector<double> r(static_cast<std::size_t>(nb)), g(r.size(), 0.0), ub(r.size());
      for (int c = 0; c < nb; ++c) {
        r[c] = ub[c] = q2(c);
        for (int k = 0; k < m; ++k) r[c] -= phi(c, k) * q2(nb + k);
        for (int c2 = 0; c2 < nb; ++c2) g[c] += G(c, c2) * f[c2];
      }
      for (int c = 0; c < nb; ++c) {
        if (maxAbs(f) > 0)
          worstResidual = std::max(worstResidual, std::abs(r[c] - g[c]) / maxAbs(g));
        else
          worstFree = std::max(worstFree, std::abs(r[c]) / maxAbs(ub));
      }
      for (int c = 0; c < nb; ++c) work += f[c] * (q2(c) - q0(c)) / 2;  // the contact work's formula
      diss += cd.dampingIncrement(q2, q0);
      const double balance = cd.halfStepEnergy(q1, q2) - e0 + diss - work;
      worstBalance = std::max(worstBalance, std::abs(balance) / std::max({std::abs(e0), std::abs(work), 1e-30}));
      Kokkos::deep_copy(q0, q1);
      Kokkos::deep_copy(q1, q2);
    }
    // (round-off of the f_{n-2} term, carried as C q_n - C (q_n - q_{n-1}) by A and B: measured 1.2e-12)
    EXPECT_LT(worstFollow, 1e-11 * maxAbs(start));
    EXPECT_LT(worstResidual, 1e-10);
    EXPECT_LT(worstFree, 1e-13);
    EXPECT_LT(worstBalance, 1e-11);
  }
}

// The residual's force z = G^{-1} (u_b - Phi_b eta) is made once per q and kept for the predictor, the
// damping exchange and the energy (CentralDifference::residual, three entries found by q's values).
// Whatever the order of the calls, each result must be the one a fresh integrator, which keeps
// nothing, gives for the same arguments: bit for bit. The calls reuse five states: first an order in
// which the state found among the kept ones is the oldest and the next one is new (a replacement
// that evicted the entry just returned would give the new state's z to both), then a random order.
TEST(MasslessCentralDifference, KeptResidualsGiveWhatAFreshIntegratorGives) {
  const FullModel full = bar(10);
  const ReducedModel red = massless(full, 6);
  const int n = red.size;
  const double h = 0.25 / (2 * M_PI * reducedFrequencies(red).back());
  DampingOptions damping;
  damping.type = DampingType::Modal;
  damping.ratio = 0.02;
  CentralDifference cd(red, h, damping);
  std::vector<DenseVector> q;
  for (int s = 0; s < 5; ++s) {
    q.emplace_back("q", n);
    std::vector<double> v = noise(n, 700u + static_cast<unsigned>(s));
    for (double& x : v) x *= 1e-6;
    set(q.back(), v);
  }
  DenseVector out("out", n), ref("ref", n);
  auto check = [&](int what, int a, int b, int c, const std::string& where) {
    const CentralDifference fresh(red, h, damping);
    if (what == 0) {
      EXPECT_EQ(cd.dampingIncrement(q[a], q[b]), fresh.dampingIncrement(q[a], q[b])) << where;
    } else if (what == 1) {
      const auto e = cd.energies(q[a], q[b], q[c]), f = fresh.energies(q[a], q[b], q[c]);
      EXPECT_EQ(e.total, f.total) << where;
      EXPECT_EQ(e.strain, f.strain) << where;
      EXPECT_EQ(e.kinetic, f.kinetic) << where;
    } else {
      cd.predict(q[a], q[b], out);
      fresh.predict(q[a], q[b], ref);
      for (int i = 0; i < n; ++i) EXPECT_EQ(out(i), ref(i)) << where << ", entry " << i;
    }
  };
  check(0, 0, 1, 0, "q0, q1 kept");
  check(0, 2, 1, 0, "q2 kept");
  check(1, 0, 3, 4, "q0 found (the oldest), then q3 new");
  unsigned seed = 12345u;
  auto next = [&seed](int k) {
    seed = seed * 1103515245u + 12345u;
    return static_cast<int>((seed >> 16) % static_cast<unsigned>(k));
  };
  for (int call = 0; call < 300; ++call) {
    const int what = next(3), a = next(5), b = next(5), c = next(5);
    check(what, a, b, c, "random call " + std::to_string(call));
  }
}

// The contact's own force stands for the residual's: after a correction by F [f; 0] the residual is
// G f (eqs. 2.35-2.36), so z = G^{-1} r is f, which setContactForce() keeps for q_{n+1} instead of
// G^{-1}'s product. Two integrators run the same forces, one told the force and one not: their
// motions agree to the round-off of G^{-1} r (bound 1e-10 of the motion's scale; measured 1.8e-14), and
// the told one's energy balance holds as tightly (1e-11, the bound above; measured 1.0e-14).
TEST(MasslessCentralDifference, TheContactForceStandsForTheResidualsForce) {
  const FullModel full = bar(10);
  const ReducedModel red = massless(full, 6);
  const int nb = red.boundarySize(), n = red.size, m = red.numModes;
  const double h = 0.5 / (2 * M_PI * reducedFrequencies(red).back());
  DampingOptions damping;
  damping.type = DampingType::Modal;
  damping.ratio = 0.02;
  const CentralDifference made(red, h, damping), told(red, h, damping);
  const auto& P = made.flexibility().pack();
  auto dense = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), P.dense);
  std::vector<double> start(static_cast<std::size_t>(n), 0.0);
  const std::vector<double> eta0 = noise(m, 3);
  for (int k = 0; k < m; ++k) start[nb + k] = 1e-6 * eta0[k];
  for (int c = 0; c < nb; ++c)
    for (int k = 0; k < m; ++k) start[c] += red.boundaryModes[static_cast<std::size_t>(k) * nb + c] * start[nb + k];
  DenseVector a[3] = {DenseVector("a0", n), DenseVector("a1", n), DenseVector("a2", n)};
  DenseVector b[3] = {DenseVector("b0", n), DenseVector("b1", n), DenseVector("b2", n)};
  DenseVector g("g", n);
  for (int i = 0; i < 2; ++i) {
    set(a[i], start);
    set(b[i], start);
  }
  const double e0 = told.halfStepEnergy(b[0], b[1]);
  double work = 0, diss = 0, worstBalance = 0, worstApart = 0, scale = maxAbs(start);
  for (int step = 0; step < 400; ++step) {
    made.predict(a[1], a[0], a[2]);
    told.predict(b[1], b[0], b[2]);
    std::vector<double> f(static_cast<std::size_t>(nb), 0.0);
    if ((step / 25) % 2 == 1) f = noise(nb, 100u + static_cast<unsigned>(step));
    for (int i = 0; i < n; ++i) {
      g(i) = i < nb ? 1e3 * f[i] : 0.0;
      double s = 0;
      for (int c = 0; c < nb; ++c) s += dense(static_cast<std::size_t>(c) * n + i) * 1e3 * f[c];
      a[2](i) += s;
      b[2](i) += s;
    }
    told.setContactForce(b[2], g);
    for (int c = 0; c < nb; ++c) work += g(c) * (b[2](c) - b[0](c)) / 2;
    diss += told.dampingIncrement(b[2], b[0]);
    made.dampingIncrement(a[2], a[0]);
    const double balance = told.halfStepEnergy(b[1], b[2]) - e0 + diss - work;
    worstBalance = std::max(worstBalance, std::abs(balance) / std::max({std::abs(e0), std::abs(work), 1e-30}));
    for (int i = 0; i < n; ++i) {
      scale = std::max(scale, std::abs(a[2](i)));
      worstApart = std::max(worstApart, std::abs(a[2](i) - b[2](i)));
    }
    for (DenseVector* q : {a, b}) {
      Kokkos::deep_copy(q[0], q[1]);
      Kokkos::deep_copy(q[1], q[2]);
    }
  }
  EXPECT_GT(worstApart, 0.0);  // two ways to z, not one
  EXPECT_LT(worstApart, 1e-10 * scale);
  EXPECT_LT(worstBalance, 1e-11);
}
