// Contact enforcement strategies (Epaphe_ContactEnforcement.hpp), each checked by hand on point
// masses against the plane z = 0, where F = h^2 / m per DOF and every law has a closed form.
#include "Epaphe_BSplineSurface.hpp"
#include "Epaphe_ContactEnforcement.hpp"
#include "Epaphe_CoulombFriction.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_ForwardIncrementLagrange.hpp"
#include "Epaphe_SmallDense.hpp"
#include "Epaphe_SurfaceContact.hpp"

#include "TestSurfaces.hpp"

#include <Teuchos_StandardParameterEntryValidators.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace epaphe;

using test::floorPlane;

namespace {

constexpr double kF = 2e-4;  // F = h^2 / m per DOF (m = 5 kg, h = 1e-3 s... any positive value)

/// n free point masses at z = 0 (x spread along x), F = kF I.
struct Masses {
  BSplineSurface floor = floorPlane();
  int n;
  explicit Masses(int count) : n(count) {}
  SurfaceContact make(const ContactOptions& o) {
    DenseVector d("F", 3 * n);
    Kokkos::deep_copy(d, kF);
    return make(o, Flexibility::diagonal(d));
  }
  /// ...with the flexibility F of the nodes' 3 n DOFs
  SurfaceContact make(const ContactOptions& o, const Flexibility& F) {
    ContactNodes nodes;
    for (int k = 0; k < n; ++k) {
      const int dof[3] = {3 * k, 3 * k + 1, 3 * k + 2};
      const double x[3] = {-1.0 + 0.5 * k, 0.1, 0.0};
      nodes.add(k, 0, dof, x);
    }
    return SurfaceContact(nodes, {ContactSurface{&floor, nullptr, -1, {}, {}}}, {ContactBlock{0, 3 * n}}, o, F);
  }
};

ContactOptions options(const std::string& m, double mu = 0.0) {
  ContactOptions o;
  o.set("Method", m);
  o.set("Friction coefficient", mu);
  o.set("Penalty stiffness", 1e6);
  o.timeStep = 1e-3;
  return o;
}

}  // namespace

TEST(ContactEnforcement, TheFactoryMakesTheLawTheOptionsAskFor) {
  EXPECT_STREQ(makeContactEnforcement(options("Lagrange"), 4)->name(), "Lagrange");
  EXPECT_STREQ(makeContactEnforcement(options("Penalty"), 4)->name(), "Penalty");
  auto f = makeContactEnforcement(options("Penalty", 0.3), 4);
  EXPECT_STREQ(f->name(), "Coulomb friction");
  EXPECT_DOUBLE_EQ(f->addedStiffness(), 1e6);  // the normal law's
  EXPECT_FALSE(f->closesGaps());
  EXPECT_TRUE(makeContactEnforcement(options("Lagrange", 0.3), 4)->closesGaps());
  EXPECT_THROW(makeContactEnforcement(options("Lagrange", -0.1), 4), Error);
  ContactOptions bad = options("Penalty");
  bad.set("Penalty stiffness", 0.0);
  EXPECT_THROW(makeContactEnforcement(bad, 4), Error);
}

TEST(ContactEnforcement, EachStrategyOwnsItsKeysAndTheContactListHasThemAll) {
  const auto all = contactValidParameters();
  for (const auto& part : {ForwardIncrementLagrange::getValidParameters(), PenaltyContact::getValidParameters(),
                           CoulombFriction::getValidParameters(), ContactDetection::getValidParameters()})
    for (auto it = part->begin(); it != part->end(); ++it)
      EXPECT_TRUE(all->isParameter(part->name(it))) << part->name(it);
  EXPECT_TRUE(all->isParameter("Method"));
  Teuchos::ParameterList deck("Contact");
  deck.setParameters(*all);
  deck.set("Friction coefficient", 0.25);
  const ContactOptions o = contactOptions(deck, 2e-6);
  EXPECT_EQ(o.method(), "Lagrange");
  const Teuchos::ParameterList complete = o.complete();
  EXPECT_DOUBLE_EQ(complete.get<double>("Friction coefficient"), 0.25);
  EXPECT_DOUBLE_EQ(o.timeStep, 2e-6);
  EXPECT_TRUE(detectionOptions(complete).skipDistant);
  // a key not set takes its default
  EXPECT_DOUBLE_EQ(ContactOptions{}.complete().get<double>("Penalty stiffness"), 1e10);
}

TEST(ContactLaw, TheRegistryAnswersForEachLaw) {
  const std::vector<std::string> names = contactLawNames();
  ASSERT_GE(names.size(), 2u);
  EXPECT_EQ(names[0], "Lagrange");
  EXPECT_EQ(names[1], "Penalty");
  const Teuchos::ParameterList cp = options("Penalty").complete();
  const ContactLaw& penalty = contactLaw("Penalty");
  EXPECT_FALSE(penalty.closesGaps());
  EXPECT_DOUBLE_EQ(penalty.stableStepStiffness(cp), 3e6);  // each penalty spring counts three times
  EXPECT_DOUBLE_EQ(penalty.springStiffness(cp), 1e6);
  EXPECT_EQ(penalty.stiffnessKey(), "Penalty stiffness");
  const ContactLaw& lagrange = contactLaw("Lagrange");
  EXPECT_TRUE(lagrange.closesGaps());
  EXPECT_DOUBLE_EQ(lagrange.stableStepStiffness(cp), 0.0);
  EXPECT_DOUBLE_EQ(lagrange.springStiffness(cp), 0.0);
  EXPECT_THROW(contactLaw("Lagrang"), Error);
  // the Method enum of the schema lists the registered laws
  const auto valid = contactValidParameters();
  const auto method = Teuchos::rcp_dynamic_cast<const Teuchos::StringToIntegralParameterEntryValidator<int>>(
      valid->getEntry("Method").validator());
  ASSERT_FALSE(method.is_null());
  EXPECT_EQ(static_cast<std::size_t>(method->validStringValues()->size()), names.size());
  // a second law of the same name, or a key another law holds, is refused
  struct Copy final : public ContactLaw {
    std::string n;
    Teuchos::RCP<const Teuchos::ParameterList> keys;
    Copy(std::string name, Teuchos::RCP<const Teuchos::ParameterList> k) : n(std::move(name)), keys(std::move(k)) {}
    std::string name() const override { return n; }
    std::string description() const override { return "a copy"; }
    Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override { return keys; }
    std::unique_ptr<ContactEnforcement> make(const Teuchos::ParameterList&, const ContactLawSetup&) const override {
      return nullptr;
    }
    bool closesGaps() const override { return false; }
  };
  const auto refusal = [](const std::shared_ptr<const ContactLaw>& law) {
    try {
      registerContactLaw(law);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("registered");
  };
  EXPECT_NE(refusal(std::make_shared<Copy>("Penalty", Teuchos::rcp(new Teuchos::ParameterList)))
                .find("a contact law named 'Penalty' is registered already"),
            std::string::npos);
  EXPECT_NE(refusal(std::make_shared<Copy>("Other", PenaltyContact::getValidParameters()))
                .find("which the Contact list holds already; rename it"),
            std::string::npos);
  EXPECT_EQ(contactLawNames().size(), names.size());
}

TEST(ContactEnforcement, LagrangeClosesEveryGapAndReleasesNothingOnAFloor) {
  // Node k predicted at z = -1e-3 (k odd) or above the floor: lambda = -g / F, the node lands on it.
  Masses m(4);
  SurfaceContact c = m.make(options("Lagrange"));
  DenseVector q("q", 12);
  for (int k = 0; k < 4; ++k) q(3 * k + 2) = k % 2 ? -1e-3 : 2e-3;
  CostSplit cost;
  c.correct(q, cost);
  EXPECT_EQ(c.numActive(), 2);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(c.force()(k), k % 2 ? 1e-3 / kF : 0.0, 1e-9) << k;
    EXPECT_NEAR(q(3 * k + 2), k % 2 ? 0.0 : 2e-3, 1e-15) << k;
  }
}

TEST(ContactEnforcement, LagrangeReleasesANodeTheOthersLiftAndSolvesTheRestAlone) {
  // Four nodes on the floor, coupled in z (F_zz(a, b) = kF / (1 + |a - b|), a != b): nodes 0, 1 and 3
  // predicted 1e-3 below it, node 2 1e-5. The first solve pulls node 2 (lambda < 0: its neighbours'
  // forces lift it); the second, on MC's rows and columns of nodes 0, 1 and 3, must equal the solve of
  // those three alone, and close their gaps while node 2 ends above the floor.
  constexpr int n = 4;
  const auto coupling = [](int a, int b) { return a == b ? kF * 2.0 : kF / (1.0 + std::abs(a - b)); };
  DenseMatrix Fm("F", 3 * n, 3 * n);
  for (int i = 0; i < 3 * n; ++i) Fm(i, i) = kF;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) Fm(3 * a + 2, 3 * b + 2) = coupling(a, b);
  Masses m(n);
  SurfaceContact c = m.make(options("Lagrange"), Flexibility(Fm));
  const double depth[n] = {1e-3, 1e-3, 1e-5, 1e-3};
  DenseVector q("q", 3 * n);
  for (int k = 0; k < n; ++k) q(3 * k + 2) = -depth[k];
  CostSplit cost;
  c.correct(q, cost);
  // the three alone: F_zz on nodes 0, 1, 3 times lambda = their depths
  const int kept[3] = {0, 1, 3};
  std::vector<double> A(9), lambda(3);
  for (int i = 0; i < 3; ++i) {
    lambda[i] = depth[kept[i]];
    for (int j = 0; j < 3; ++j) A[3 * j + i] = coupling(kept[i], kept[j]);
  }
  std::vector<int> ipiv;
  ASSERT_EQ(solveDense(3, A.data(), 3, lambda.data(), ipiv), 0);
  EXPECT_EQ(c.numActive(), 3);
  EXPECT_EQ(c.force()(2), 0.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(c.force()(kept[i]), lambda[i], 1e-12 * lambda[i]) << "node " << kept[i];
    EXPECT_NEAR(q(3 * kept[i] + 2), 0.0, 1e-15) << "node " << kept[i];
  }
  EXPECT_GT(q(3 * 2 + 2), 0.0);
}

TEST(ContactEnforcement, PenaltyPushesByItsStiffnessAndLeavesTheRest) {
  Masses m(2);
  SurfaceContact c = m.make(options("Penalty"));
  DenseVector q("q", 6);
  q(2) = -1e-3;
  q(5) = 1e-3;
  CostSplit cost;
  c.correct(q, cost);
  EXPECT_NEAR(c.force()(0), 1e6 * 1e-3, 1e-6);
  EXPECT_EQ(c.force()(1), 0.0);
  EXPECT_NEAR(q(2), -1e-3 + kF * 1e3, 1e-15);  // dq = F lambda n
  EXPECT_DOUBLE_EQ(c.addedStiffness(), 1e6);
}

TEST(ContactEnforcement, CoulombFrictionSticksInsideTheConeAndSlidesOnItsEdge) {
  // One node pressed 1e-3 into the floor while moving dx sideways over the step. Sticking needs the
  // tangential force dx / F, the normal one is 1e-3 / F: it sticks when dx < mu 1e-3, else it slides
  // with s = mu lambda against the motion.
  for (const double dx : {2e-4, 8e-4}) {
    Masses m(1);
    const double mu = 0.5;
    SurfaceContact c = m.make(options("Lagrange", mu));
    DenseVector q("q", 3), qn("qn", 3);
    q(0) = dx;
    q(2) = -1e-3;
    CostSplit cost;
    c.correct(q, qn, cost);
    const double lambda = 1e-3 / kF;
    EXPECT_NEAR(c.force()(0), lambda, 1e-9 * lambda);
    EXPECT_NEAR(q(2), 0.0, 1e-15);
    if (dx < mu * 1e-3) {  // stuck: no tangential motion over the step, mu_a = |s| / lambda
      EXPECT_NEAR(q(0), 0.0, 1e-15) << dx;
      EXPECT_NEAR(c.appliedFriction()(0), dx / 1e-3, 1e-9);
    } else {  // sliding on the cone: s = mu lambda, the node moves dx - F mu lambda
      EXPECT_NEAR(c.appliedFriction()(0), mu, 1e-12) << dx;
      EXPECT_NEAR(c.tangent()(0, 0), -1.0, 1e-12);
      EXPECT_NEAR(q(0), dx - kF * mu * lambda, 1e-15);
    }
  }
}

TEST(ContactEnforcement, CoulombFrictionOpposesTheSlipWhereTheFlexibilityIsNotIsotropic) {
  // One node pressed into the floor, ten times as supple along y as along x (F = diag(kF, 10 kF, kF)),
  // moving obliquely over the step: it slides, and Coulomb's force opposes its slip w (the corrected
  // motion), s = -mu lambda w / |w| (eq. (74)). The radial return, s along K^{-1} w_0, would leave
  // it 23.7 degrees off the slip here.
  Masses m(1);
  const double mu = 0.3;
  ContactNodes nodes;
  const int dof[3] = {0, 1, 2};
  const double x[3] = {-1.0, 0.1, 0.0};
  nodes.add(0, 0, dof, x);
  DenseVector d("F", 3);
  d(0) = kF;
  d(1) = 10 * kF;
  d(2) = kF;
  SurfaceContact c(nodes, {ContactSurface{&m.floor, nullptr, -1, {}, {}}}, {ContactBlock{0, 3}},
                   options("Lagrange", mu), Flexibility::diagonal(d));
  DenseVector q("q", 3), qn("qn", 3);
  q(0) = 2e-3;
  q(1) = 1e-3;
  q(2) = -1e-3;
  CostSplit cost;
  c.correct(q, qn, cost);
  const double lambda = 1e-3 / kF;
  ASSERT_NEAR(c.force()(0), lambda, 1e-9 * lambda);
  EXPECT_NEAR(c.appliedFriction()(0), mu, 1e-12);  // sliding
  const double w[2] = {q(0), q(1)}, t[2] = {c.tangent()(0, 0), c.tangent()(0, 1)};
  const double nw = std::hypot(w[0], w[1]);
  ASSERT_GT(nw, 1e-6);
  EXPECT_NEAR(std::hypot(t[0], t[1]), 1.0, 1e-12);
  EXPECT_NEAR((w[0] * t[0] + w[1] * t[1]) / nw, -1.0, 1e-12);  // against the slip: full dissipation
  // the slip is the predicted motion less F s: w = (2e-3, 1e-3) + mu lambda diag(kF, 10 kF) t
  EXPECT_NEAR(w[0], 2e-3 + mu * lambda * kF * t[0], 1e-15);
  EXPECT_NEAR(w[1], 1e-3 + mu * lambda * 10 * kF * t[1], 1e-15);
}

TEST(SmallDense, EliminationWithPivotingSolvesAsLapackDoes) {
  for (const int n : {1, 3, 12, 48, 100}) {  // 100: the LAPACK path
    std::vector<double> A(static_cast<std::size_t>(n) * n), x(n), b(n, 0.0);
    unsigned seed = 12345u + n;
    auto rnd = [&] {
      seed = seed * 1103515245u + 12345u;
      return static_cast<double>((seed >> 8) & 0xffff) / 32768.0 - 1.0;
    };
    for (double& a : A) a = rnd();
    for (int i = 0; i < n; ++i) A[static_cast<std::size_t>(i) * n + (i + 3) % n] += 0.5;  // not diagonally dominant
    for (double& v : x) v = rnd();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) b[i] += A[static_cast<std::size_t>(j) * n + i] * x[j];
    std::vector<int> ipiv;
    ASSERT_EQ(solveDense(n, A.data(), n, b.data(), ipiv), 0);
    for (int i = 0; i < n; ++i) EXPECT_NEAR(b[i], x[i], 1e-9) << "n = " << n << ", unknown " << i;
  }
  std::vector<double> S = {1, 2, 2, 4};  // singular
  std::vector<double> r = {1, 1};
  std::vector<int> ipiv;
  EXPECT_EQ(solveDense(2, S.data(), 2, r.data(), ipiv), 2);
}

namespace {

/// Five nodes pressed into a plane carried by a second body (a 6 x 5 grid in z = 0, turned by
/// 0.3 rad about z), the carrier's flexibility diagonal d_i: as a dense block (C_ab through the
/// flexibility between the patches' control points, H = (B_u x B_v) F (B_u x B_v)^T, eq. 2.26) or as
/// a diagonal block (C_ab by walking D_a's grid entries). Both must give the same forces and correction.
/// Nodes 0 and 3 are on one patch, 1 and 4 on another, 2 alone: the dense block reads H once for the
/// nodes of a patch (RelativeFlexibility's groups), in groups whose nodes are not neighbours in the list.
struct CarriedPlane {
  static constexpr int kNu = 6, kNv = 5, kNodes = 5, kGridDofs = 3 * kNu * kNv, kN = 3 * kNodes + kGridDofs;
  std::vector<double> grid;
  BSplineSurface plane;
  CarriedPlane() : grid(makeGrid()), plane("carried", kNu, kNv, grid, openOptions()) {}
  static std::vector<double> makeGrid() {
    std::vector<double> g;
    for (int i = 0; i < kNu; ++i)
      for (int j = 0; j < kNv; ++j) g.insert(g.end(), {-1.0 + 2.0 * i / (kNu - 1), -1.0 + 2.0 * j / (kNv - 1), 0.0});
    return g;
  }
  static SurfaceOptions openOptions() {
    SurfaceOptions o;
    o.closureU = o.closureV = Closure::Open;
    return o;
  }
  SurfaceContact make(bool denseCarrier, double mu) {
    ContactNodes nodes;
    // inside the patches' spans of the grid (0.4 by 0.5), in the plane's turned frame
    const double local[kNodes][2] = {{-0.45, 0.3}, {-0.05, -0.2}, {0.35, -0.3}, {-0.33, 0.18}, {0.08, -0.33}};
    for (int k = 0; k < kNodes; ++k) {
      const int dof[3] = {3 * k, 3 * k + 1, 3 * k + 2};
      const double c = std::cos(0.3), s = std::sin(0.3);
      const double x[3] = {c * local[k][0] - s * local[k][1], s * local[k][0] + c * local[k][1], 0.0};
      nodes.add(k, 0, dof, x);
    }
    DenseMatrix Fn("Fn", 3 * kNodes, 3 * kNodes);  // the nodes' body: coupled
    for (int i = 0; i < 3 * kNodes; ++i)
      for (int j = 0; j < 3 * kNodes; ++j) Fn(i, j) = i == j ? 1e-3 : 1e-4 / (1.0 + (i - j) * (i - j));
    Flexibility F(Fn);
    DenseVector d("d", kGridDofs);
    for (int i = 0; i < kGridDofs; ++i) d(i) = 4e-4 * (1.0 + 0.3 * std::sin(1.7 * i));
    if (denseCarrier) {
      DenseMatrix Fc("Fc", kGridDofs, kGridDofs);
      for (int i = 0; i < kGridDofs; ++i) Fc(i, i) = d(i);
      F.append(Flexibility(Fc));
    } else {
      F.append(Flexibility::diagonal(d));
    }
    ContactSurface cs;
    cs.surface = cs.moving = &plane;
    cs.block = 1;
    for (int g = 0; g < kGridDofs; ++g) cs.gridDofs.push_back(3 * kNodes + g);
    cs.gridX = grid;
    cs.phase = 0.3;
    ContactOptions o = options("Lagrange", mu);
    return SurfaceContact(nodes, {cs}, {ContactBlock{0, 3 * kNodes}, ContactBlock{3 * kNodes, kGridDofs}}, o, F);
  }
};

}  // namespace

TEST(ContactEnforcement, CarriedSurfaceOnADenseBlockCorrectsAsItsEntriesDo) {
  for (double mu : {0.0, 0.3}) {
    std::vector<double> forces[2], dq[2];
    for (int dense = 0; dense < 2; ++dense) {
      CarriedPlane scene;
      SurfaceContact c = scene.make(dense == 1, mu);
      DenseVector q("q", CarriedPlane::kN), qn("qn", CarriedPlane::kN);
      for (int k = 0; k < CarriedPlane::kNodes; ++k) {
        q(3 * k + 2) = -1e-3 * (1 + k);  // pressed in
        q(3 * k) = 2e-4 * k;             // and sliding or not
        qn(3 * k) = 1e-4 * k;
      }
      for (int g = 0; g < CarriedPlane::kGridDofs; g += 3) q(3 * CarriedPlane::kNodes + g + 2) = 2e-5 * std::cos(g);
      CostSplit cost;
      const DenseVector qStar("qStar", CarriedPlane::kN);
      Kokkos::deep_copy(qStar, q);
      c.correct(q, qn, cost);
      ASSERT_EQ(c.numActive(), CarriedPlane::kNodes) << "mu = " << mu;
      for (int k = 0; k < CarriedPlane::kNodes; ++k) forces[dense].push_back(c.force()(k));
      for (int i = 0; i < CarriedPlane::kN; ++i) dq[dense].push_back(q(i) - qStar(i));
    }
    double fmax = 0.0, dmax = 0.0;
    for (double f : forces[0]) fmax = std::max(fmax, std::fabs(f));
    for (double x : dq[0]) dmax = std::max(dmax, std::fabs(x));
    ASSERT_GT(fmax, 0.0);
    for (std::size_t k = 0; k < forces[0].size(); ++k)
      EXPECT_NEAR(forces[1][k], forces[0][k], 1e-9 * fmax) << "mu = " << mu << ", node " << k;
    for (std::size_t i = 0; i < dq[0].size(); ++i)
      EXPECT_NEAR(dq[1][i], dq[0][i], 1e-9 * dmax) << "mu = " << mu << ", DOF " << i;
  }
}

TEST(ContactEnforcement, SelfLockingMarginsAreOneLessMuOverTheirCriticalCoefficient) {
  // One node on the floor (n = +z) with a dense flexibility coupling x and z, F_xz = b: sliding along
  // +x (friction t = -x), c = n + mu t, so n^T F c = F_zz - mu b and the correction's margin (48) is
  // 1 - mu b / F_zz; the static compliance S given apart gives (50), 1 - mu S_zx / S_zz (Lagrange)
  // and (S_zz - mu S_zx + 1/k_p) / (S_zz + 1/k_p) (penalty).
  const double a = 2e-4, b = 1e-4, czz = 3e-4, mu = 0.5;
  const double S[9] = {4e-6, 0.0, 3e-6, 0.0, 4e-6, 0.0, 3e-6, 0.0, 2e-6};  // row-major, x y z
  for (const std::string method : {"Lagrange", "Penalty"}) {
    BSplineSurface floor = floorPlane();
    ContactNodes nodes;
    const int dof[3] = {0, 1, 2};
    const double x[3] = {0.0, 0.1, 0.0};
    nodes.add(0, 0, dof, x);
    DenseMatrix F("F", 3, 3);
    F(0, 0) = a;
    F(1, 1) = a;
    F(2, 2) = czz;
    F(0, 2) = F(2, 0) = b;
    const double kp = 1e5;
    ContactOptions o = options(method, mu);
    o.set("Penalty stiffness", kp);
    SurfaceContact c(nodes, {ContactSurface{&floor, nullptr, -1, {}, {}}}, {ContactBlock{0, 3}}, o, Flexibility(F));
    c.setStaticCompliance(std::vector<double>(S, S + 9));
    DenseVector q("q", 3), qn("qn", 3);
    q(0) = 1e-2;  // far outside the cone: it slides
    q(2) = -1e-4;
    CostSplit cost;
    c.correct(q, qn, cost);
    const SelfLocking* lock = c.enforcement().selfLocking();
    ASSERT_NE(lock, nullptr);
    ASSERT_EQ(lock->sliding, 1);
    EXPECT_NEAR(c.tangent()(0, 0), -1.0, 1e-12);
    EXPECT_NEAR(lock->stepMargin, 1.0 - mu * b / czz, 1e-12);
    const double kappa = method == "Penalty" ? 1.0 / kp : 0.0;
    EXPECT_NEAR(lock->margin, (S[8] - mu * S[6] + kappa) / (S[8] + kappa), 1e-12);
    EXPECT_EQ(lock->node, 0);
  }
}
