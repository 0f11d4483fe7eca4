// The scene check (Epaphe_SceneCheck.hpp) on decks written inline: a valid scene passes; each fault
// that needs no reduced model is refused with a message naming the key and the value; a fault that
// needs the reduced model (the critical step) passes it, for the setup to catch. The run gives the
// same messages: setup() calls checkScene first (tests/badinput checks that on the whole catalogue).
#include "Epaphe_DeckSchema.hpp"
#include "Epaphe_Error.hpp"
#include "Epaphe_SceneCheck.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace epaphe;

namespace {

/// The bar on a wall with `body` and `extra` inserted into the bar's list and the deck.
std::string deck(const std::string& body = "", const std::string& extra = "") {
  return R"xml(<ParameterList name="Epaphe">
  <ParameterList name="Bodies"><ParameterList name="Bar">
    <ParameterList name="Mesh">
      <Parameter name="Type" type="string" value="Box"/>
      <Parameter name="Lengths" type="Array(double)" value="{0.2, 0.02, 0.02}"/>
      <Parameter name="Elements" type="Array(int)" value="{10, 1, 1}"/>
    </ParameterList>
    <Parameter name="Contact node set" type="string" value="x+"/>
    )xml" +
         body + R"xml(
  </ParameterList></ParameterList>
  <ParameterList name="Surfaces"><ParameterList name="Wall">
    <Parameter name="Origin" type="Array(double)" value="{0.2001, -0.1, -0.1}"/>
    <Parameter name="U" type="Array(double)" value="{0, 0.2, 0}"/>
    <Parameter name="V" type="Array(double)" value="{0, 0, 0.2}"/>
  </ParameterList></ParameterList>
  )xml" + extra +
         R"xml(
</ParameterList>)xml";
}

/// The message checkScene raises for `xml`, or "" when it passes.
std::string refusal(const std::string& xml, const std::string& output = "out.h5") {
  try {
    checkScene(readDeckFromString(xml, "inline.xml"), output, false);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SceneCheck, AValidSceneAndAFaultOnlyTheReductionSeesPass) {
  EXPECT_EQ(refusal(deck()), "");
  // h = 1e-3 s is far above the bar's critical step: only the reduced model's frequencies show it
  EXPECT_EQ(
      refusal(deck(
          "",
          R"(<ParameterList name="Time"><Parameter name="Time step" type="double" value="1e-3"/></ParameterList>)")),
      "");
}

TEST(SceneCheck, FaultsWithoutAModelAreRefusedNamingKeyAndValue) {
  const std::string unknownSet = refusal(deck(R"(<Parameter name="Clamped node set" type="string" value="root"/>)"));
  EXPECT_NE(unknownSet.find("'Clamped node set': unknown node set 'root'"), std::string::npos) << unknownSet;
  EXPECT_NE(unknownSet.find("'x-'"), std::string::npos) << unknownSet;  // the known sets are listed

  const std::string notRetained = refusal(deck(R"(<ParameterList name="Reduction">
      <Parameter name="Retained node set" type="string" value="x-"/></ParameterList>)"));
  EXPECT_NE(notRetained.find("is not a retained DOF"), std::string::npos) << notRetained;

  const std::string modes = refusal(deck(R"(<ParameterList name="Reduction">
      <Parameter name="Fixed-interface modes" type="int" value="5000"/></ParameterList>)"));
  EXPECT_NE(modes.find("5000 fixed-interface modes asked but only"), std::string::npos) << modes;

  const std::string massless = refusal(deck(R"(<ParameterList name="Reduction">
      <Parameter name="Method" type="string" value="Massless boundary"/>
      <Parameter name="Fixed-interface modes" type="int" value="5000"/></ParameterList>)"));
  EXPECT_NE(massless.find("(and the free body's 6 rigid-body modes) exceed the model's"), std::string::npos)
      << massless;

  const std::string output = refusal(deck(), "/nonexistent-epaphe-dir/out.h5");
  EXPECT_NE(output.find("directory '/nonexistent-epaphe-dir' does not exist"), std::string::npos) << output;
}
