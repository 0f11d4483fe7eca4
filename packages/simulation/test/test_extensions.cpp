// Extension points used from outside Epaphe's packages: a reduction method and an importer, written and
// registered by this test alone (ReductionRegistry::add, ImporterRegistry::add), each with a deck key of
// its own, named by a deck that then runs. The custom pair rebuilds what a Box mesh and a Craig-Bampton
// reduction of the same bar give, so the run must match that deck's to the last bit: the custom code was
// called (counted), its keys read, and its model went through the whole run.
#include "Epaphe_CraigBampton.hpp"
#include "Epaphe_Deck.hpp"
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_Hdf5File.hpp"
#include "Epaphe_ModelImporter.hpp"
#include "Epaphe_ReductionMethod.hpp"
#include "Epaphe_Runtime.hpp"
#include "Epaphe_Simulation.hpp"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace epaphe;

namespace {

Runtime* runtime = nullptr;
int reductions = 0, imports = 0;

/// Craig-Bampton under a name of its own, its mode count from its own key 'Test modes'.
class TestReduction : public ModalReduction {
public:
  std::string name() const override { return "Test reduction"; }
  std::string documentation() const override { return "Craig-Bampton with 'Test modes' modes (a test)"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Reduction"));
    deck::addInt(*pl, "Test modes", 2, "Test reduction: fixed-interface modes kept", 0, 1000);
    return pl;
  }
  void setParameters(const Teuchos::ParameterList& rp) override {
    options_ = craigBamptonOptions(rp, false);  // the solver keys and their defaults, as Craig-Bampton's
    options_.modes = rp.get<int>("Test modes");
  }
  std::string cacheKeyText() const override { return "\ntest modes=" + std::to_string(options_.modes); }
  bool cacheable() const override { return false; }
  ReducedModel reduce(const FullModel& full, const std::vector<int>& retained, ReductionReport* report) const override {
    ++reductions;
    return craigBampton(full, retained, options_, report);
  }
  std::string modelName(const ReducedModel&) const override { return name(); }
};

/// A bar along x of Epaphe's hexahedra, from its own keys 'Test length' and 'Test elements'.
class TestBar : public ModelImporter {
public:
  std::string name() const override { return "Test bar"; }
  std::string documentation() const override { return "a bar along x (a test)"; }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Mesh"));
    deck::addDouble(*pl, "Test length", 0.1, "Test bar: length along x (m)", 1e-300);
    deck::addInt(*pl, "Test elements", 4, "Test bar: hexahedra along x", 1, 1000);
    return pl;
  }
  bool builtInMesh() const override { return true; }
  Mesh mesh(const ImportRequest& r) const override {
    return makeBoxMesh({0, 0, 0}, {r.mesh().get<double>("Test length"), 0.02, 0.02},
                       {r.mesh().get<int>("Test elements"), 1, 1});
  }
  FullModel build(const ImportRequest& r, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const override {
    ++imports;
    const Teuchos::ParameterList& mp = r.bodyParams->sublist("Material");
    Material mat;
    mat.density = mp.get<double>("Density");
    mat.young = mp.get<double>("Young's modulus");
    mat.poisson = mp.get<double>("Poisson's ratio");
    return assembleHexModel(r.body, mesh(r), mat, {}, comm);
  }
};

/// A bar flying into a wall, its Mesh and Reduction lists given.
std::string deckWith(const std::string& mesh, const std::string& reduction) {
  return R"xml(<ParameterList name="Epaphe">
  <ParameterList name="Bodies"><ParameterList name="Bar">
    <ParameterList name="Mesh">)xml" +
         mesh + R"xml(</ParameterList>
    <ParameterList name="Reduction">)xml" +
         reduction + R"xml(<Parameter name="Frequency check" type="int" value="3"/>
      <Parameter name="Cache" type="bool" value="false"/></ParameterList>
    <Parameter name="Contact node set" type="string" value="x+"/>
    <Parameter name="Initial velocity" type="Array(double)" value="{5, 0, 0}"/>
  </ParameterList></ParameterList>
  <ParameterList name="Surfaces"><ParameterList name="Wall">
    <Parameter name="Origin" type="Array(double)" value="{0.2001, -0.1, -0.1}"/>
    <Parameter name="U" type="Array(double)" value="{0, 0, 0.2}"/>
    <Parameter name="V" type="Array(double)" value="{0, 0.2, 0}"/>
  </ParameterList></ParameterList>
  <ParameterList name="Time">
    <Parameter name="Time step" type="double" value="2e-7"/>
    <Parameter name="End time" type="double" value="1e-4"/>
  </ParameterList>
  <ParameterList name="Run"><Parameter name="Progress interval" type="double" value="0"/></ParameterList>
</ParameterList>)xml";
}

const std::string customMesh = R"xml(<Parameter name="Type" type="string" value="Test bar"/>
      <Parameter name="Test length" type="double" value="0.2"/><Parameter name="Test elements" type="int" value="10"/>)xml";
const std::string boxMesh = R"xml(<Parameter name="Type" type="string" value="Box"/>
      <Parameter name="Lengths" type="Array(double)" value="{0.2, 0.02, 0.02}"/>
      <Parameter name="Elements" type="Array(int)" value="{10, 1, 1}"/>)xml";

RunSummary run(const std::string& xml, const std::string& output) {
  std::remove(output.c_str());
  Simulation sim(readDeckFromString(xml, "inline.xml"), *runtime, output);
  sim.setup();
  return sim.run();
}

std::string refusal(const std::string& xml) {
  try {
    readDeckFromString(xml, "inline.xml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Extensions, ACustomReductionAndImporterRunADeckAsTheBuiltInOnesTheyCopy) {
  ReductionRegistry::add("Test reduction", [] { return std::make_unique<TestReduction>(); });
  ImporterRegistry::add("Test bar", [] { return std::make_unique<TestBar>(); });
  // The schema knows their names and keys; a misspelt key of theirs is refused with the right one.
  const std::string custom = deckWith(customMesh, R"xml(<Parameter name="Method" type="string" value="Test reduction"/>
      <Parameter name="Test modes" type="int" value="3"/>)xml");
  EXPECT_EQ(refusal(custom), "");
  const std::string misspelt =
      refusal(deckWith(customMesh, R"xml(<Parameter name="Test mdoes" type="int" value="3"/>)xml"));
  EXPECT_NE(misspelt.find("Test modes"), std::string::npos) << misspelt;

  const RunSummary mine = run(custom, "extensions-custom.h5");
  EXPECT_EQ(reductions, 1);
  EXPECT_EQ(imports, 1);
  const RunSummary box = run(deckWith(boxMesh, R"xml(<Parameter name="Method" type="string" value="Craig-Bampton"/>
      <Parameter name="Fixed-interface modes" type="int" value="3"/>)xml"),
                             "extensions-box.h5");
  EXPECT_EQ(reductions, 1);  // the built-in deck does not go through the custom code
  ASSERT_EQ(mine.status, box.status);
  EXPECT_EQ(mine.steps, box.steps);
  EXPECT_GT(box.totals.impulse, 0.0);  // the bar hits the wall
  // Anasazi starts each eigen-solve from a random block: the two reductions agree to round-off, not bits
  const double tol = 1e-9;
  EXPECT_NEAR(mine.totals.impulse, box.totals.impulse, tol * box.totals.impulse);
  EXPECT_NEAR(mine.totals.maxForce, box.totals.maxForce, tol * box.totals.maxForce);
  EXPECT_NEAR(mine.totals.contactWork, box.totals.contactWork, tol * std::abs(box.totals.contactWork));

  const io::Hdf5File a("extensions-custom.h5", io::Hdf5File::Mode::ReadOnly);
  const io::Hdf5File b("extensions-box.h5", io::Hdf5File::Mode::ReadOnly);
  EXPECT_EQ(a.stringAttribute("/bodies/Bar", "reduction"), "Test reduction");
  EXPECT_EQ(b.stringAttribute("/bodies/Bar", "reduction"), "Craig-Bampton");
  auto expectClose = [tol](const std::vector<double>& x, const std::vector<double>& y, const char* what) {
    ASSERT_EQ(x.size(), y.size()) << what;
    ASSERT_FALSE(x.empty()) << what;
    const double scale =
        std::abs(*std::max_element(y.begin(), y.end(), [](double p, double q) { return std::abs(p) < std::abs(q); }));
    for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], y[i], tol * scale) << what << " [" << i << "]";
  };
  expectClose(a.readDoubles("/energy/total"), b.readDoubles("/energy/total"), "/energy/total");
  // the free bar's lowest 3 are rigid-body modes: zero, to the shift-invert solve's noise (about 1e-3 Hz)
  const auto fa = a.readDoubles("/bodies/Bar/frequencies/full"), fb = b.readDoubles("/bodies/Bar/frequencies/full");
  ASSERT_EQ(fa.size(), 3u);
  ASSERT_EQ(fb.size(), 3u);
  for (std::size_t i = 0; i < fa.size(); ++i) EXPECT_NEAR(fa[i], fb[i], 1e-2) << "full frequency " << i << " (Hz)";
}

int main(int argc, char** argv) {
  Runtime rt(&argc, &argv);
  rt.initializeKokkos(1);
  runtime = &rt;
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
