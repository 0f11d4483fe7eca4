// A surface carried by a flexible body that turns relative to the contact node's body (thesis
// section 3.3 with a flexible casing): each body vibrates in its own frame, only the contact sees
// the rotation R. The carrier is 16 grid nodes of a plane, x = 1 in its own frame with its normal
// towards -x; turned by 90 degrees about z it is the plane y = 1 of the node's frame, normal -y.
// The node's correction must act along the turned normal (-y), the carrier's along its own frame's
// normal (+x on the plane, pushed away): D_a q = u_a - R sum w_pq u_pq.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_CentralDifference.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestModels.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

using namespace epaphe;

namespace {

constexpr int kGrid = 16, kN = 3 + 3 * kGrid;  // system: the node's 3 DOFs, then the grid's 48

/// `n` nodes of mass m on springs k to the ground, every DOF retained (diagonal K and M).
ReducedModel freeNodes(int n, double m, double k) {
  ReducedModel r;
  r.name = "carrier";
  r.size = 3 * n;
  r.K.assign(std::size_t(r.size) * r.size, 0.0);
  r.M = r.K;
  for (int i = 0; i < r.size; ++i) {
    r.K[std::size_t(i) * r.size + i] = k;
    r.M[std::size_t(i) * r.size + i] = m;
  }
  return r;
}

/// The carrier's grid in its own frame: x = 1, u along z and v along y (S_u x S_v = -e_x), over
/// [-2, 2]^2.
std::vector<double> planeGrid() {
  std::vector<double> g;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) g.insert(g.end(), {1.0, -2.0 + 4.0 * j / 3.0, -2.0 + 4.0 * i / 3.0});
  return g;
}

struct Scene {
  double h;
  ReducedModel node, carrier;
  CentralDifference cdNode, cdCarrier;
  std::vector<double> grid = planeGrid();
  BSplineSurface plane{"plane", 4, 4, grid, [] {
                         SurfaceOptions o;
                         o.closureU = o.closureV = Closure::Open;
                         return o;
                       }()};
  Flexibility F;
  std::unique_ptr<SurfaceContact> contact;

  /// The node at X (its body's frame), the plane turned by phase + omega t about z.
  Scene(const std::array<double, 3>& X, double mNode, double mGrid, double kSpring, double step, double omega,
        double phase, const ContactOptions& options)
      : h(step),
        node(test::pointMass(mNode)),
        carrier(freeNodes(kGrid, mGrid, kSpring)),
        cdNode(node, h, {}),
        cdCarrier(carrier, h, {}) {
    F = cdNode.flexibility();  // block diagonal: the node's 3 DOFs, then the carrier's
    F.append(cdCarrier.flexibility());
    ContactNodes cn;
    const int dof[3] = {0, 1, 2};
    cn.add(0, 0, dof, X.data());
    ContactSurface cs;
    cs.surface = cs.moving = &plane;
    cs.block = 1;
    for (int g = 0; g < 3 * kGrid; ++g) cs.gridDofs.push_back(3 + g);
    cs.gridX = grid;
    cs.omega = omega;
    cs.phase = phase;
    ContactOptions o = options;
    o.timeStep = h;
    contact = std::make_unique<SurfaceContact>(std::move(cn), std::vector<ContactSurface>{cs},
                                               std::vector<ContactBlock>{{0, 3}, {3, 3 * kGrid}}, o, F);
  }
};

std::vector<double> get(const DenseVector& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return std::vector<double>(h.data(), h.data() + h.extent(0));
}

}  // namespace

TEST(TurningCarriedSurface, NodeIsPushedAlongTheTurnedNormalTheCarrierAlongItsOwn) {
  // Node at (0.3, 1 + p, 0.2): in the carrier's frame (turned back by 90 degrees) at (1 + p, -0.3,
  // 0.2), p beyond the plane x = 1.
  const double p = 1e-4, h = 1e-3, mNode = 2.0, mGrid = 0.5;
  Scene s({0.3, 1.0 + p, 0.2}, mNode, mGrid, 0.0, h, 0.0, M_PI / 2, {});
  DenseVector q("q", kN);
  CostSplit cost;
  s.contact->correct(q, cost);
  ASSERT_EQ(s.contact->numActive(), 1);
  EXPECT_NEAR(s.contact->gap()(0), -p, 1e-12);
  const double lambda = s.contact->force()(0);
  ASSERT_GT(lambda, 0.0);
  const auto dq = get(q);
  // The node: F G lambda = h^2/m lambda n_a, n_a = R n_s = -e_y.
  const double a = h * h / mNode * lambda;
  EXPECT_NEAR(dq[0], 0.0, 1e-12 * a);
  EXPECT_NEAR(dq[1], -a, 1e-12 * a);
  EXPECT_NEAR(dq[2], 0.0, 1e-12 * a);
  // The carrier, in its own frame: h^2/m lambda w_pq (-n_s) = along +x only, summing to lambda.
  double fx = 0, fy = 0, fz = 0, fmax = 0;
  for (int g = 0; g < kGrid; ++g) {
    const double f[3] = {dq[3 + 3 * g] * mGrid / (h * h), dq[4 + 3 * g] * mGrid / (h * h),
                         dq[5 + 3 * g] * mGrid / (h * h)};
    fx += f[0];
    fy += f[1];
    fz += f[2];
    fmax = std::max(fmax, std::fabs(f[0]));
    EXPECT_NEAR(f[1], 0.0, 1e-12 * lambda) << "grid node " << g << ": pushed along y (the node's frame normal)";
    EXPECT_NEAR(f[2], 0.0, 1e-12 * lambda) << "grid node " << g;
  }
  EXPECT_NEAR(fx, lambda, 1e-10 * lambda);  // the interpolating weights sum to 1
  EXPECT_GT(fmax, 0.1 * lambda);
  // Momentum: the node's impulse and the carrier's turned into the node's frame cancel,
  // m_a dq_a + R sum_g m_c dq_g = 0, with R e_x = e_y and R e_y = -e_x.
  EXPECT_NEAR(mNode * dq[0] - h * h * fy, 0.0, 1e-10 * mNode * a);
  EXPECT_NEAR(mNode * dq[1] + h * h * fx, 0.0, 1e-10 * mNode * a);
  EXPECT_NEAR(mNode * dq[2] + h * h * fz, 0.0, 1e-10 * mNode * a);
  // The gap is closed on the moved, re-projected surface (to second order in the bending of the
  // carrier: it would stay about -p/2 with the carrier pushed along the wrong normal).
  s.contact->measureGaps(q, cost);
  EXPECT_NEAR(s.contact->gap()(0), 0.0, 1e-3 * p);
  // Work of the step from rest (qPrev = 0), 1/2 lambda n_a . D_a dq, equals the work of each body's
  // forces on its own motion in its own frame (node: lambda n_a; carrier: m dq / h^2 per DOF).
  DenseVector zero("zero", kN);
  double byBody = lambda * -dq[1];
  for (int i = 3; i < kN; ++i) byBody += mGrid / (h * h) * dq[i] * dq[i];
  const double w = s.contact->workIncrement(q, zero);
  EXPECT_NEAR(w, 0.5 * byBody, 1e-10 * w);
  EXPECT_GT(w, 0.0);  // pushed apart from rest: the bodies gain energy
}

TEST(TurningCarriedSurface, EnergyBalanceIsExactWhileTheSurfaceTurns) {
  // The node pressed (200 N along +y) against the plane, which turns at -1 rad/s from 90 degrees
  // (towards the node); the carrier's nodes on springs. Over 300 steps (0.3 rad) the bodies'
  // energies change by exactly the contact work (which the turning surface makes non-zero) and the
  // external work, with and without friction.
  for (const double mu : {0.0, 0.3}) {
    ContactOptions o;
    o.set("Friction coefficient", mu);
    const double h = 1e-3;
    Scene s({0.2, 0.9999, 0.1}, 2.0, 0.5, 1e4, h, -1.0, M_PI / 2, o);
    s.cdNode.setConstantForce({0.0, 200.0, 0.0});
    DenseVector Q[3] = {DenseVector("q0", kN), DenseVector("q1", kN), DenseVector("q2", kN)};
    auto qmH = Kokkos::create_mirror_view(Q[0]);
    qmH(1) = -h * 0.1;  // the node moving at 0.1 m/s towards the plane
    Kokkos::deep_copy(Q[0], qmH);
    auto nodePart = [](const DenseVector& v) { return DenseVector(v.data(), 3); };
    auto gridPart = [](const DenseVector& v) { return DenseVector(v.data() + 3, 3 * kGrid); };
    auto energy = [&](const DenseVector& a, const DenseVector& b) {
      return s.cdNode.halfStepEnergy(nodePart(a), nodePart(b)) + s.cdCarrier.halfStepEnergy(gridPart(a), gridPart(b));
    };
    int prev = 0, cur = 1, next = 2, contacts = 0;
    const double e0 = energy(Q[prev], Q[cur]);
    double work = 0, contactWork = 0, gridMotion = 0, scale = e0;
    CostSplit cost;
    for (int n = 0; n < 300; ++n) {
      s.cdNode.predict(nodePart(Q[cur]), nodePart(Q[prev]), nodePart(Q[next]));
      s.cdCarrier.predict(gridPart(Q[cur]), gridPart(Q[prev]), gridPart(Q[next]));
      s.contact->setTime((n + 1) * h);
      s.contact->correct(Q[next], Q[cur], cost);
      contacts += s.contact->numActive();
      const double wc = s.contact->workIncrement(Q[next], Q[prev]);
      contactWork += wc;
      work += wc + s.cdNode.externalWorkIncrement(nodePart(Q[next]), nodePart(Q[prev]));
      const double e = energy(Q[cur], Q[next]);
      scale = std::max(scale, std::fabs(e));
      ASSERT_NEAR(e - e0, work, 1e-10 * scale) << "mu = " << mu << ", step " << n;
      for (double x : get(gridPart(Q[next]))) gridMotion = std::max(gridMotion, std::fabs(x));
      std::swap(prev, cur);
      std::swap(cur, next);
    }
    EXPECT_GT(contacts, 250) << "mu = " << mu;  // pressed on the plane almost all along
    std::printf("mu = %g: %d steps in contact, carrier moved by %.3g m, contact work %.3g J, energy %.3g J\n", mu,
                contacts, gridMotion, contactWork, scale);
    EXPECT_GT(gridMotion, 1e-4) << "mu = " << mu;  // the carrier gave way
    EXPECT_GT(std::fabs(contactWork), 1e-3 * scale) << "mu = " << mu;
  }
}

namespace {

/// A closed cylinder of radius r about z (64 x 5 grid nodes, interpolated), normal inwards.
BSplineSurface drum(double r) {
  const int nu = 64, nv = 5;
  std::vector<double> g;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double th = 2 * M_PI * i / nu;
      g.insert(g.end(), {r * std::cos(th), r * std::sin(th), -1.0 + 2.0 * j / (nv - 1)});
    }
  SurfaceOptions o;
  o.closureU = Closure::Periodic;
  o.closureV = Closure::Open;
  o.orientation = -1;
  return BSplineSurface("drum", nu, nv, g, o);
}

}  // namespace

// The sign of friction on a turning surface (docs/theory/divergence.md, equations (42), (43)): a free
// point mass m inside a rigid drum of radius R turning at omega, launched along the drum's surface
// at v0, is pressed on it by its own velocity (lambda = m v^2 / R) and dragged towards the surface
// speed V = omega R: m dv/dt = mu m v^2 / R sign(V - v), so v(t) = v0 / (1 - s mu v0 t / R), s = sign(V - v0),
// until v = V, where it sticks. The surface's work on it is W = m V (v1 - v0), its kinetic energy
// changes by m (v1^2 - v0^2) / 2 and friction dissipates D = W - dK = m (V - v0)^2 / 2 at v1 = V,
// whatever mu. Tolerances: O(h) of the central difference (h mu v0 / R = 5e-5 per step) and the
// interpolated drum's radius (64 grid nodes, about 1e-6 R).
TEST(TurningRigidDrum, FrictionDragsAFreeBodyTowardsTheSurfaceSpeed) {
  const double m = 2.0, R = 1.0, omega = 2.0, V = omega * R, mu = 0.5, h = 1e-4;
  for (const double v0 : {1.0, 3.0}) {
    const double s = V > v0 ? 1.0 : -1.0;
    const double tStick = R / (s * mu) * (1.0 / v0 - 1.0 / V);  // 1 s and 1/3 s
    ReducedModel body = test::pointMass(m);
    CentralDifference cd(body, h, {});
    BSplineSurface surface = drum(R);
    ContactNodes cn;
    const int dof[3] = {0, 1, 2};
    const double X[3] = {R, 0.0, 0.0};
    cn.add(0, 0, dof, X);
    ContactSurface cs;
    cs.surface = &surface;
    cs.omega = omega;
    ContactOptions o;
    o.set("Friction coefficient", mu);
    o.timeStep = h;
    SurfaceContact contact(std::move(cn), {cs}, {{0, 3}}, o, cd.flexibility());
    DenseVector Q[3] = {DenseVector("q0", 3), DenseVector("q1", 3), DenseVector("q2", 3)};
    auto qmH = Kokkos::create_mirror_view(Q[0]);
    qmH(1) = -h * v0;  // q_{-1}: moving along +y (the drum's surface motion at the node) at v0
    Kokkos::deep_copy(Q[0], qmH);
    int prev = 0, cur = 1, next = 2;
    const double e0 = cd.halfStepEnergy(Q[prev], Q[cur]);
    double work = 0, surfaceWork = 0, worst = 0, vLast = v0, heat = 0, nodeHeat = 0;
    CostSplit cost;
    const int steps = static_cast<int>(1.5 * tStick / h);
    for (int n = 0; n < steps; ++n) {
      cd.predict(Q[cur], Q[prev], Q[next]);
      contact.setTime((n + 1) * h);
      contact.correct(Q[next], Q[cur], cost);
      ASSERT_EQ(contact.numActive(), 1) << "v0 = " << v0 << ", step " << n;
      work += contact.workIncrement(Q[next], Q[prev]);
      contact.frictionHeatByNode(Q[next], Q[prev], h, &nodeHeat);
      heat += nodeHeat;
      const auto a = get(Q[prev]), b = get(Q[next]);
      // the surface's work: the force on the node, lambda (n + mu_a t), on the drum's motion at it,
      // h omega e_z x (X + q_{n+1})
      const auto& views = contact.detection().views();
      double f[3];
      for (int d = 0; d < 3; ++d)
        f[d] = contact.force()(0) * (views.normal(0, d) + contact.appliedFriction()(0) * contact.tangent()(0, d));
      surfaceWork += h * omega * (-f[0] * (X[1] + b[1]) + f[1] * (X[0] + b[0]));
      const double v = std::hypot(b[0] - a[0], b[1] - a[1]) / (2 * h), t = n * h;  // v_n at t_n
      if (t < tStick - 0.01) {
        const double exact = v0 / (1.0 - s * mu * v0 * t / R);
        worst = std::max(worst, std::fabs(v - exact) / exact);
        EXPECT_GT(s * (v - vLast), 0.0) << "v0 = " << v0 << ", step " << n << ": not dragged towards V";
      } else if (t > tStick + 0.01) {
        EXPECT_NEAR(v, V, 1e-3 * V) << "v0 = " << v0 << ", step " << n << ": not carried with the drum";
      }
      vLast = v;
      std::swap(prev, cur);
      std::swap(cur, next);
    }
    EXPECT_LT(worst, 2e-3) << "v0 = " << v0;
    const double e1 = cd.halfStepEnergy(Q[prev], Q[cur]);
    // the contact work of the balance is the work of the contact forces on the body: dK exactly
    EXPECT_NEAR(e1 - e0, work, 1e-10 * std::max(e0, e1)) << "v0 = " << v0;
    const double W = m * V * (V - v0), dK = 0.5 * m * (V * V - v0 * v0), D = 0.5 * m * (V - v0) * (V - v0);
    EXPECT_NEAR(e1 - e0, dK, 2e-3 * std::fabs(dK)) << "v0 = " << v0;
    EXPECT_NEAR(surfaceWork, W, 2e-3 * std::fabs(W)) << "v0 = " << v0;  // the surface's work
    EXPECT_NEAR(surfaceWork - work, D, 5e-3 * D) << "v0 = " << v0;      // dissipated by friction
    EXPECT_NEAR(W, dK + D, 1e-12 * std::fabs(W));
    EXPECT_NEAR(heat, D, 5e-3 * D) << "v0 = " << v0;  // the heat friction made at the node (eq. 42)
    std::printf("drum: v0 = %g m/s: frictional heat %.6g J, closed form %g J\n", v0, heat, D);
    std::printf(
        "drum: v0 = %g m/s, V = %g m/s: velocity within %.2g of v0/(1 - s mu v0 t/R); surface work %.6g J "
        "(closed form %g), kinetic energy change %.6g J (%g), dissipated %.6g J (%g)\n",
        v0, V, worst, surfaceWork, W, e1 - e0, dK, surfaceWork - work, D);
  }
}
