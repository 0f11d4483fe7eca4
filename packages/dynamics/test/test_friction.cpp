// Coulomb friction in the contact correction (thesis section 2.5.2, eqs. 2.29-2.35): a point mass
// sliding on a plane, where the central difference with Lagrange contact is solvable by hand,
// and a two-node body with a full (coupled) flexibility, where MC is not symmetric.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestModels.hpp"
#include "TestSurfaces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

using namespace epaphe;
using epaphe::test::floorPlane;
using epaphe::test::pointMass;

namespace {

/// Two nodes on 6 DOFs with a full mass matrix (A A^T + 2 I) and springs of 50 N/m to the ground:
/// every block of the flexibility couples every direction of both nodes.
ReducedModel coupledPair() {
  ReducedModel r;
  r.name = "pair";
  r.size = 6;
  double A[36];
  for (int i = 0; i < 36; ++i) A[i] = 0.1 * ((i * 7) % 11) - 0.4;
  r.M.assign(36, 0.0);
  r.K.assign(36, 0.0);
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      double s = 0;
      for (int k = 0; k < 6; ++k) s += A[i * 6 + k] * A[j * 6 + k];
      r.M[j * 6 + i] = s + (i == j ? 2.0 : 0.0);
    }
    r.K[i * 7] = 50.0;
  }
  r.nodeDof = {0, 1, 2, 3, 4, 5};
  r.recovery.assign(36, 0.0);
  for (int i = 0; i < 6; ++i) r.recovery[i * 7] = 1;
  r.coords = {{0.1, 0.2, 0.0}, {-0.3, 0.1, 0.0}};
  r.nodeSets["all"] = {0, 1};
  r.retainedNodes = {0, 1};
  return r;
}

void set(const DenseVector& v, const std::vector<double>& a) {
  auto h = Kokkos::create_mirror_view(v);
  for (std::size_t i = 0; i < a.size(); ++i) h(i) = a[i];
  Kokkos::deep_copy(v, h);
}
std::vector<double> get(const DenseVector& v) {
  auto h = Kokkos::create_mirror_view(v);
  Kokkos::deep_copy(h, v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

constexpr double kMass = 2.0, kG = 9.81, kMu = 0.3, kH = 1e-3;
constexpr double kVx = 0.6, kVy = -0.8;  // initial sliding velocity, speed 1 m/s

/// The point mass on the floor, sliding at (kVx, kVy) and pressed by its weight.
struct Slider {
  ReducedModel r = pointMass(kMass);
  BSplineSurface s = floorPlane();
  CentralDifference cd{r, kH, {}};
  SurfaceContact c;
  DenseVector qm{"qm", 3}, q{"q", 3}, qp{"qp", 3};
  CostSplit cost;

  explicit Slider(const ContactOptions& o) : c(r, {0}, {&s}, o, cd.flexibility()) {
    cd.setConstantForce({0, 0, -kMass * kG});  // its weight, on the floor z = 0
    set(qm, {-kVx * kH, -kVy * kH, 0.0});      // q_{-1}: sliding at (kVx, kVy), q_0 = 0
  }
  /// One step: predict, correct with friction, advance. Returns the step's contact + external work.
  double step() {
    cd.predict(q, qm, qp);
    c.correct(qp, q, cost);
    const double w = c.workIncrement(qp, qm) + cd.externalWorkIncrement(qp, qm);
    std::swap(qm, q);
    std::swap(q, qp);
    return w;
  }
};

ContactOptions withFriction(double mu, const std::string& method = "Lagrange", double kp = 1e10) {
  ContactOptions o;
  o.set("Friction coefficient", mu);
  o.set("Method", method);
  o.set("Penalty stiffness", kp);
  return o;
}

}  // namespace

TEST(Friction, SlidingNodeDeceleratesAtMuGThenSticks) {
  Slider run(withFriction(kMu));
  const double dv = kMu * kG * kH;  // velocity lost per step while sliding
  const double v0 = std::hypot(kVx, kVy);
  const int expectedStop = static_cast<int>(std::floor(v0 / dv));  // 339: the step that stops it
  double vx = kVx, vy = kVy;
  int stop = -1;
  std::vector<double> xStop;
  for (int n = 0; n < 1000; ++n) {
    run.step();  // now q = q_{n+1}, qm = q_n
    const std::vector<double> a = get(run.qm), b = get(run.q);
    ASSERT_EQ(run.c.numActive(), 1) << "step " << n;
    EXPECT_NEAR(b[2], 0.0, 1e-12) << "step " << n;                                 // held on the floor
    EXPECT_NEAR(run.c.force()(0), kMass * kG, 1e-6 * kMass * kG) << "step " << n;  // lambda = m g
    const double wx = (b[0] - a[0]) / kH, wy = (b[1] - a[1]) / kH;
    const double speed = std::hypot(wx, wy), before = std::hypot(vx, vy);
    if (stop < 0 && before > dv) {  // sliding: Coulomb deceleration mu g, along the sliding
      EXPECT_NEAR(before - speed, dv, 0.01 * dv) << "step " << n;
      EXPECT_NEAR(wx * kVy - wy * kVx, 0.0, 1e-12 * v0) << "step " << n;  // direction kept
      EXPECT_EQ(run.c.appliedFriction()(0), kMu) << "step " << n;
      // t opposes the sliding (to the digits left in x*_{n+1} - x_n once the node is slow)
      EXPECT_NEAR(run.c.tangent()(0, 0), -kVx / v0, 1e-9) << "step " << n;
      EXPECT_NEAR(run.c.tangent()(0, 1), -kVy / v0, 1e-9) << "step " << n;
    } else {  // stopped at the step where mu g h exceeds the speed, and stays stuck
      if (stop < 0) {
        stop = n;
        xStop = b;
        EXPECT_LT(run.c.appliedFriction()(0), kMu);  // sticking: less than the full friction
      }
      EXPECT_LE(speed, 1e-12 * v0) << "step " << n;                      // at rest: no chattering
      EXPECT_GE(wx * kVx + wy * kVy, -1e-12 * v0 * v0) << "step " << n;  // never reversed
    }
    vx = wx;
    vy = wy;
  }
  EXPECT_EQ(stop, expectedStop);
  ASSERT_FALSE(xStop.empty());
  const std::vector<double> end = get(run.q);
  EXPECT_NEAR(end[0], xStop[0], 1e-12);  // no drift once stuck
  EXPECT_NEAR(end[1], xStop[1], 1e-12);
  // distance slid from q_0 = 0: the sum over the sliding steps of h (v0 - (n+1) dv)
  double dist = 0;
  for (int n = 0; n < expectedStop; ++n) dist += kH * (v0 - (n + 1) * dv);
  EXPECT_NEAR(std::hypot(xStop[0], xStop[1]), dist, 1e-9);
}

namespace {

/// x = A^{-1} b for a small dense A (row-major, n x n), Gauss-Jordan with partial pivoting.
std::vector<double> solveByHand(std::vector<double> A, std::vector<double> b) {
  const int n = static_cast<int>(b.size());
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int i = c + 1; i < n; ++i)
      if (std::fabs(A[i * n + c]) > std::fabs(A[p * n + c])) p = i;
    for (int j = 0; j < n; ++j) std::swap(A[c * n + j], A[p * n + j]);
    std::swap(b[c], b[p]);
    for (int i = 0; i < n; ++i) {
      if (i == c) continue;
      const double f = A[i * n + c] / A[c * n + c];
      for (int j = 0; j < n; ++j) A[i * n + j] -= f * A[c * n + j];
      b[i] -= f * b[c];
    }
  }
  for (int i = 0; i < n; ++i) b[i] /= A[i * n + i];
  return b;
}

}  // namespace

TEST(Friction, ZeroFrictionReproducesTheFrictionlessCorrection) {
  // The two-node coupled body (full, non-diagonal M, so that every correction couples every DOF)
  // pressed into the floor z = 0 at t = 0: q_0 = 0, q_{-1} = -h v, so q* = h v (no force acts at
  // q_0 = 0) and both nodes penetrate by -g*_a = -(h v_z), a = 0, 1 (DOFs 2 and 5).
  // The correction by hand (eqs. 2.32-2.35): F = h^2 M^{-1} (undamped), the contact directions are
  // e_z at DOFs 2 and 5, q = q* + F [e_2 e_5] lambda with
  //   Lagrange:        [F22 F25; F52 F55] lambda = -g*   (both gaps close exactly),
  //   lumped Lagrange: the same matrix with its row sums on the diagonal (section 2.5.2),
  //   penalty:         lambda = k_p (-g*)                 (eq. 2.34).
  // Each is computed here; the program's frictionless correction (no q_n: the normal law alone)
  // must match it, and the friction entry points at mu = 0 (with q_n) and at mu > 0 without q_n
  // (no friction direction) must reproduce that frictionless correction. Tolerances: the by-hand
  // and the program's F come from two different factorizations of the same 6 x 6 M (condition
  // number 1.9), so they agree to a few ulps of |q*|; 1e-12 |q*| leaves room for any order of the
  // sums. The mu = 0 paths run the same arithmetic as the frictionless one: 1e-15 |q*|.
  const ReducedModel r = coupledPair();
  const BSplineSurface s = floorPlane();
  const double h = 1e-3, kp = 1e5;
  const std::vector<double> v = {1.0, -0.5, -2.0, -0.7, 0.3, -1.5};
  std::vector<double> qStar(6), F(36);
  double scale = 0.0;
  for (int i = 0; i < 6; ++i) {
    qStar[i] = h * v[i];
    scale = std::max(scale, std::fabs(qStar[i]));
  }
  for (int j = 0; j < 6; ++j) {  // column j of h^2 M^{-1}
    std::vector<double> Mrow(r.M.begin(), r.M.end()), e(6, 0.0);
    e[j] = h * h;
    const std::vector<double> col = solveByHand(Mrow, e);  // M is symmetric: row- or column-major alike
    for (int i = 0; i < 6; ++i) F[i * 6 + j] = col[i];
  }
  const int dofs[2] = {2, 5};
  for (int variant = 0; variant < 3; ++variant) {
    const std::string which = variant == 0 ? "Lagrange" : variant == 1 ? "lumped Lagrange" : "penalty";
    std::vector<double> MC(4), gStar = {qStar[2], qStar[5]}, lambda(2);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) MC[a * 2 + b] = F[dofs[a] * 6 + dofs[b]];
    if (variant == 1)
      for (int a = 0; a < 2; ++a) {
        MC[a * 2 + a] = MC[a * 2] + MC[a * 2 + 1];
        MC[a * 2 + 1 - a] = 0.0;
      }
    if (variant == 2)
      for (int a = 0; a < 2; ++a) lambda[a] = kp * (-gStar[a]);
    else
      lambda = solveByHand(MC, {-gStar[0], -gStar[1]});
    ASSERT_GT(std::min(lambda[0], lambda[1]), 0.0) << which << ": both nodes must be in contact";
    std::vector<double> byHand(qStar);
    for (int i = 0; i < 6; ++i)
      for (int a = 0; a < 2; ++a) byHand[i] += F[i * 6 + dofs[a]] * lambda[a];
    if (variant == 0) {  // the gaps close exactly
      EXPECT_NEAR(byHand[2], 0.0, 1e-12 * scale);
      EXPECT_NEAR(byHand[5], 0.0, 1e-12 * scale);
    }
    std::vector<double> frictionless;
    for (int api = 0; api < 3; ++api) {  // frictionless (no q_n); mu = 0 with q_n; mu = 0.5 without q_n
      CentralDifference cd(r, h, {});
      ContactOptions o;
      if (variant == 1) o.set("Lump contact matrix", true);
      if (variant == 2) {
        o.set("Method", "Penalty");
        o.set("Penalty stiffness", kp);
      }
      if (api == 2) o.set("Friction coefficient", 0.5);  // without q_n there is no friction direction
      SurfaceContact c(r, {0, 1}, {&s}, o, cd.flexibility());
      DenseVector qm("qm", 6), q("q", 6), qp("qp", 6);
      std::vector<double> m(6);
      for (int i = 0; i < 6; ++i) m[i] = -h * v[i];
      set(qm, m);
      cd.predict(q, qm, qp);
      const std::vector<double> predicted = get(qp);
      for (int i = 0; i < 6; ++i) ASSERT_NEAR(predicted[i], qStar[i], 1e-15 * scale) << which << ", q*" << i;
      CostSplit cost;
      if (api == 1)
        c.correct(qp, q, cost);
      else
        c.correct(qp, cost);
      const std::vector<double> got = get(qp);
      EXPECT_EQ(c.numActive(), 2) << which << ", api " << api;
      if (api == 0) {
        frictionless = got;
        for (int i = 0; i < 6; ++i)
          EXPECT_NEAR(got[i], byHand[i], 1e-12 * scale) << which << ": frictionless against by hand, q" << i;
      } else {
        for (int i = 0; i < 6; ++i)
          EXPECT_NEAR(got[i], frictionless[i], 1e-15 * scale)
              << which << (api == 1 ? ": mu = 0 with q_n" : ": mu = 0.5 without q_n") << " against frictionless, q"
              << i;
        for (int a = 0; a < 2; ++a) {  // c_a = n_a: no friction applied
          EXPECT_EQ(c.appliedFriction()(a), 0.0) << which << ", api " << api << ", node " << a;
          for (int i = 0; i < 3; ++i) EXPECT_EQ(c.tangent()(a, i), 0.0) << which << ", api " << api << ", node " << a;
        }
      }
    }
    // Coulomb friction (its own joint solve, 3 unknowns per node) in the limit mu -> 0: the
    // friction forces are at most mu lambda_a, so q departs from the frictionless correction by
    // O(mu) of that correction (|q_frictionless - q*|): the tangential forces move q by F's tangential
    // columns times mu lambda, and the normal multipliers readjust by as much again, with F's largest
    // entry 1.13 times its smallest diagonal one and 2 nodes: about 5 mu, asserted. Lumping is
    // a frictionless option (the friction solve does not lump), so the lumped variant is skipped.
    if (variant == 1) continue;
    const double mu = 1e-6;
    double correction = 0.0;
    for (int i = 0; i < 6; ++i) correction = std::max(correction, std::fabs(frictionless[i] - qStar[i]));
    CentralDifference cd(r, h, {});
    SurfaceContact c(r, {0, 1}, {&s}, withFriction(mu, variant == 0 ? "Lagrange" : "Penalty", kp), cd.flexibility());
    DenseVector qm("qm", 6), q("q", 6), qp("qp", 6);
    std::vector<double> m(6);
    for (int i = 0; i < 6; ++i) m[i] = -h * v[i];
    set(qm, m);
    cd.predict(q, qm, qp);
    CostSplit cost;
    c.correct(qp, q, cost);
    const std::vector<double> got = get(qp);
    double worst = 0.0;
    for (int i = 0; i < 6; ++i) worst = std::max(worst, std::fabs(got[i] - frictionless[i]));
    std::cout << which << ": Coulomb friction at mu = " << mu << " departs from the frictionless correction by "
              << worst / (mu * correction) << " mu |correction| (bound 5)\n";
    EXPECT_LE(worst, 5.0 * mu * correction) << which << ": Coulomb friction at mu = " << mu;
    EXPECT_GT(worst, 0.0) << which << ": friction at mu = " << mu << " changed nothing";
    EXPECT_EQ(c.numActive(), 2) << which;
  }
  // and a real friction coefficient does change it, by much more than round-off
  CentralDifference cd(r, h, {});
  SurfaceContact c(r, {0, 1}, {&s}, withFriction(0.5), cd.flexibility());
  DenseVector qm("qm", 6), q("q", 6), qp("qp", 6), q0("q0", 6), qm0("qm0", 6), qp0("qp0", 6);
  std::vector<double> m(6);
  for (int i = 0; i < 6; ++i) m[i] = -h * v[i];
  set(qm, m);
  cd.predict(q, qm, qp);
  CostSplit cost;
  c.correct(qp, q, cost);
  SurfaceContact c0(r, {0, 1}, {&s}, withFriction(0.0), cd.flexibility());
  set(qm0, m);
  cd.predict(q0, qm0, qp0);
  c0.correct(qp0, q0, cost);
  EXPECT_GT(std::fabs(get(qp)[0] - get(qp0)[0]), 1e-6);
}

TEST(Friction, EnergyBalanceIsExactAndFrictionDissipates) {
  for (const std::string method : {"Lagrange", "Penalty"}) {
    const std::string which = method == "Lagrange" ? "Lagrange" : "penalty";
    Slider run(withFriction(kMu, method, 1e6));
    const double e0 = run.cd.halfStepEnergy(run.qm, run.q);
    double work = 0, contactWork = 0, frictionWork = 0, heat = 0, nodeHeat = 0;
    for (int n = 0; n < 1000; ++n) {
      run.cd.predict(run.q, run.qm, run.qp);
      run.c.correct(run.qp, run.q, run.cost);
      const double wc = run.c.workIncrement(run.qp, run.qm);
      contactWork += wc;
      frictionWork += run.c.workIncrementSplit(run.qp, run.qm)[1];
      run.c.frictionHeatByNode(run.qp, run.qm, kH, &nodeHeat);
      heat += nodeHeat;
      work += wc + run.cd.externalWorkIncrement(run.qp, run.qm);
      std::swap(run.qm, run.q);
      std::swap(run.q, run.qp);
    }
    const double e = run.cd.halfStepEnergy(run.qm, run.q);
    EXPECT_NEAR(e - e0, work, 1e-10 * e0) << which;  // every joule accounted for
    EXPECT_LT(contactWork, -0.9 * e0) << which;      // friction took the kinetic energy
    // the heat friction makes on a still surface is the friction forces' negative work
    EXPECT_NEAR(heat, -frictionWork, 1e-10 * e0) << which;
    if (method == "Lagrange") {
      EXPECT_NEAR(contactWork, -e0, 1e-6 * e0);  // ... all of it: the node is at rest on the floor
      EXPECT_NEAR(e, 0.0, 1e-6 * e0);
      EXPECT_NEAR(heat, e0, 1e-6 * e0);  // and it became heat
    }
  }
  // the coupled pair: non-symmetric MC, springs, nodes sliding, sticking and bouncing
  const ReducedModel r = coupledPair();
  const BSplineSurface s = floorPlane();
  const double h = 1e-3;
  CentralDifference cd(r, h, {});
  cd.setConstantForce({0, 0, -20.0, 0, 0, -20.0});
  SurfaceContact c(r, {0, 1}, {&s}, withFriction(0.4), cd.flexibility());
  DenseVector qm("qm", 6), q("q", 6), qp("qp", 6);
  set(qm, {-h * 1.0, h * 0.5, 0.0, h * 0.7, -h * 0.3, 0.0});
  const double e0 = cd.halfStepEnergy(qm, q);
  double work = 0, contactWork = 0, frictionWork = 0, heat = 0, nodeHeat[2];
  CostSplit cost;
  for (int n = 0; n < 3000; ++n) {
    cd.predict(q, qm, qp);
    c.correct(qp, q, cost);
    const double wc = c.workIncrement(qp, qm);
    contactWork += wc;
    frictionWork += c.workIncrementSplit(qp, qm)[1];
    c.frictionHeatByNode(qp, qm, h, nodeHeat);
    heat += nodeHeat[0] + nodeHeat[1];
    work += wc + cd.externalWorkIncrement(qp, qm);
    std::swap(qm, q);
    std::swap(q, qp);
  }
  EXPECT_NEAR(cd.halfStepEnergy(qm, q) - e0, work, 1e-10 * e0);
  EXPECT_LT(contactWork, 0.0);
  EXPECT_GT(heat, 0.0);
  EXPECT_NEAR(heat, -frictionWork, 1e-10 * e0);
}

TEST(Friction, PenaltyDecelerationIsMuKpPenetrationOverM) {
  // First contact step: q* = (vx h, 0, -vz h), penetration vz h, lambda = kp vz h (eq. 2.34),
  // correction F VCT lambda = h^2/m kp pen (n + mu t) (eq. 2.35): the tangential velocity drops by
  // mu kp pen h / m, a deceleration mu kp pen / m.
  const double m = 3.0, h = 1e-3, kp = 1e5, mu = 0.4, vz = 2.0;
  const ReducedModel r = pointMass(m);
  const BSplineSurface s = floorPlane();
  for (const double vx : {1.0, 0.01}) {  // sliding on; stopped (stuck)
    CentralDifference cd(r, h, {});
    SurfaceContact c(r, {0}, {&s}, withFriction(mu, "Penalty", kp), cd.flexibility());
    DenseVector qm("qm", 3), q("q", 3), qp("qp", 3);
    set(qm, {-vx * h, 0.0, vz * h});
    cd.predict(q, qm, qp);
    CostSplit cost;
    c.correct(qp, q, cost);
    const std::vector<double> got = get(qp);
    const double pen = vz * h;
    EXPECT_NEAR(c.force()(0), kp * pen, 1e-9 * kp * pen);
    EXPECT_NEAR(got[2], -vz * h + h * h / m * kp * pen, 1e-12);  // normal part as without friction
    EXPECT_EQ(got[1], 0.0);
    const double decel = (vx - got[0] / h) / h;
    if (vx * h > mu * kp * pen * h * h / m) {
      EXPECT_NEAR(decel, mu * kp * pen / m, 1e-9 * mu * kp * pen / m);
      EXPECT_EQ(c.appliedFriction()(0), mu);
    } else {  // the full friction would reverse the sliding: it stops instead
      EXPECT_NEAR(got[0], 0.0, 1e-15);
      EXPECT_LT(c.appliedFriction()(0), mu);
    }
  }
}

TEST(Friction, NormalTangentCouplingSlidesSticksOrSlidesBack) {
  // One node whose mass couples x and z (M_xz = 0.5): its normal force alone moves it along t by
  // lambda t^T F n, here against the sliding. Hitting the floor at vz = 2 while sliding along +x at
  // vx, it slides on with mu (fast), stops exactly (stick: friction impulse (s - lambda t^T F n) /
  // t^T F t, within the cone), or, with little friction, is pushed back by the normal force and
  // slides back, friction mu along t = +x opposing that (appliedFriction() >= 0 and t is the
  // direction of the friction force).
  const double h = 1e-3, vz = 2.0;
  ReducedModel r = pointMass(1.0);
  r.M[2] = r.M[6] = 0.5;
  const BSplineSurface s = floorPlane();
  enum Expect { Slide, Stick, Back };
  const struct {
    double vx, mu;
    Expect expect;
  } cases[] = {{3.0, 0.5, Slide}, {1.5, 0.5, Stick}, {0.5, 0.5, Stick}, {0.5, 0.1, Back}};
  for (const auto& k : cases) {
    std::vector<double> frictionless;
    for (const double mu : {0.0, k.mu}) {
      CentralDifference cd(r, h, {});
      SurfaceContact c(r, {0}, {&s}, withFriction(mu), cd.flexibility());
      DenseVector qm("qm", 3), q("q", 3), qp("qp", 3);
      set(qm, {-k.vx * h, 0.0, vz * h});
      cd.predict(q, qm, qp);
      CostSplit cost;
      c.correct(qp, q, cost);
      ASSERT_EQ(c.numActive(), 1);
      const std::vector<double> got = get(qp);
      const std::string what = "vx " + std::to_string(k.vx) + ", mu " + std::to_string(mu);
      EXPECT_NEAR(got[2], 0.0, 1e-15) << what;  // on the floor
      if (mu == 0.0) {
        frictionless = got;
        continue;
      }
      const double applied = c.appliedFriction()(0);
      if (k.expect == Slide) {  // slowed down by friction, still moving along +x
        EXPECT_EQ(applied, mu) << what;
        EXPECT_GT(got[0], 0.0) << what;
        EXPECT_LT(got[0], frictionless[0] - 1e-6) << what;
      } else if (k.expect == Stick) {  // no tangential motion over the step
        EXPECT_LE(std::fabs(applied), mu) << what;
        EXPECT_NEAR(got[0], 0.0, 1e-15) << what;
      } else {  // the normal force pushes it back; friction (now along +x) slows that down
        EXPECT_EQ(applied, mu) << what;
        EXPECT_NEAR(c.tangent()(0, 0), 1.0, 1e-12) << what;
        EXPECT_LT(frictionless[0], got[0] - 1e-6) << what;
        EXPECT_LT(got[0], 0.0) << what;
      }
    }
    if (k.vx == 0.5 && k.expect == Stick) EXPECT_LT(frictionless[0], 0.0);  // held against a push back
  }
}

TEST(Friction, CoupledStuckNodesDoNotCreep) {
  // The coupled pair resting on the floor, pressed by 20 N per node and pushed sideways by a few N
  // (well inside the cone for mu = 1): the joint solve holds both nodes although each one's
  // correction moves the other, and a node with no predicted tangential motion still gets
  // friction. Without friction the same loads make them slide.
  const ReducedModel r = coupledPair();
  const BSplineSurface s = floorPlane();
  const double h = 1e-3;
  const std::vector<double> load = {3.0, -2.0, -20.0, -1.0, 2.5, -20.0};
  for (const double mu : {1.0, 0.0}) {
    CentralDifference cd(r, h, {});
    cd.setConstantForce(load);
    SurfaceContact c(r, {0, 1}, {&s}, withFriction(mu), cd.flexibility());
    DenseVector qm("qm", 6), q("q", 6), qp("qp", 6);
    CostSplit cost;
    double maxTangential = 0.0;
    for (int n = 0; n < 2000; ++n) {
      cd.predict(q, qm, qp);
      c.correct(qp, q, cost);
      ASSERT_EQ(c.numActive(), 2) << "mu " << mu << ", step " << n;
      const std::vector<double> got = get(qp);
      for (const int i : {0, 1, 3, 4}) maxTangential = std::max(maxTangential, std::fabs(got[i]));
      EXPECT_NEAR(got[2], 0.0, 1e-15);
      EXPECT_NEAR(got[5], 0.0, 1e-15);
      if (mu > 0) {
        EXPECT_LE(c.appliedFriction()(0), mu * (1 + 1e-12)) << "step " << n;
        EXPECT_LE(c.appliedFriction()(1), mu * (1 + 1e-12)) << "step " << n;
      }
      std::swap(qm, q);
      std::swap(q, qp);
    }
    if (mu > 0)
      EXPECT_LE(maxTangential, 1e-12);  // stuck: no creep at all
    else
      EXPECT_GT(maxTangential, 1e-3);  // frictionless: the sideways loads move them
  }
}

TEST(Friction, NonSymmetricContactMatrixStillClosesTheGaps) {
  const ReducedModel r = coupledPair();
  const BSplineSurface s = floorPlane();
  const double h = 1e-3;
  for (const double mu : {0.0, 0.2, 1.0}) {
    CentralDifference cd(r, h, {});
    SurfaceContact c(r, {0, 1}, {&s}, withFriction(mu), cd.flexibility());
    DenseVector qm("qm", 6), q("q", 6), qp("qp", 6);
    set(qm, {-h * 1.0, h * 0.5, h * 2.0, h * 0.7, -h * 0.3, h * 1.5});
    cd.predict(q, qm, qp);
    CostSplit cost;
    c.correct(qp, q, cost);
    ASSERT_EQ(c.numActive(), 2) << "mu " << mu;
    EXPECT_LT(c.gap()(0), -1e-4);
    c.measureGaps(qp, cost);
    EXPECT_NEAR(c.gap()(0), 0.0, 1e-15) << "mu " << mu;
    EXPECT_NEAR(c.gap()(1), 0.0, 1e-15) << "mu " << mu;
  }
}

TEST(Friction, NegativeOrNonFiniteCoefficientIsRejected) {
  const ReducedModel r = pointMass(1.0);
  const BSplineSurface s = floorPlane();
  CentralDifference cd(r, 1e-3, {});
  for (const double mu : {-0.1, std::nan("")}) {
    try {
      SurfaceContact c(r, {0}, {&s}, withFriction(mu), cd.flexibility());
      ADD_FAILURE() << "mu = " << mu << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("friction"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(SurfaceContact(r, {0}, {&s}, withFriction(0.0), cd.flexibility()));
}
