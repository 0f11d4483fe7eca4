// The plain data of the online loop (no Tpetra): node sets of a mesh, a reduced model's kind,
// frequencies of a dense model against the closed form.
#include "Epaphe_Error.hpp"
#include "Epaphe_Mesh.hpp"
#include "Epaphe_ReducedModel.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace epaphe;

TEST(ModelData, NodeSetsResolveUnionsAndNameTheKnownOnesOtherwise) {
  const Mesh box = makeBoxMesh({0, 0, 0}, {1, 1, 1}, {2, 1, 1});
  EXPECT_EQ(box.numNodes(), 12);
  const auto xm = box.nodeSet("x-", "test"), xp = box.nodeSet("x+", "test");
  EXPECT_EQ(xm.size(), 4u);
  EXPECT_EQ(box.nodeSet("x-, x+", "test").size(), xm.size() + xp.size());  // disjoint faces
  EXPECT_EQ(box.nodeSet("x-, x-", "test"), xm);                            // no repeats
  try {
    box.nodeSet("tip", "body 'Bar'");
    FAIL() << "an unknown node set was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("body 'Bar': unknown node set 'tip'"), std::string::npos) << what;
    EXPECT_NE(what.find("'x+'"), std::string::npos) << what;  // the known ones are listed
  }
}

TEST(ModelData, AReducedModelCarriesItsKindAndItsName) {
  for (ReductionKind k : {ReductionKind::CraigBampton, ReductionKind::Guyan, ReductionKind::None,
                          ReductionKind::FullLumped, ReductionKind::MasslessBoundary}) {
    EXPECT_EQ(reductionKindNamed(reductionName(k)), k);
    ReducedModel r;
    r.kind = k;
    EXPECT_EQ(r.sparse(), k == ReductionKind::FullLumped);
    EXPECT_EQ(r.massless(), k == ReductionKind::MasslessBoundary);
  }
  EXPECT_THROW(reductionKindNamed("Craig Bampton"), Error);
}

TEST(ModelData, DenseFrequenciesOfTwoMassesOnSpringsMatchTheClosedForm) {
  // m1 = m2 = m, springs k (ground - 1) and k (1 - 2): omega^2 = (3 -+ sqrt 5) / 2 k / m.
  const double m = 2.0, k = 800.0;
  const std::vector<double> K = {2 * k, -k, -k, k}, M = {m, 0, 0, m};
  const auto f = denseFrequencies(K, M, 2);
  ASSERT_EQ(f.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const double omega2 = (3.0 + (i == 0 ? -1.0 : 1.0) * std::sqrt(5.0)) / 2.0 * k / m;
    EXPECT_NEAR(f[i], std::sqrt(omega2) / (2 * M_PI), 1e-12 * f[i]);
  }
}
