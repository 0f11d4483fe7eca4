#include "Epaphe_Deck.hpp"
#include "Epaphe_Error.hpp"

#include <gtest/gtest.h>

using namespace epaphe;

namespace {

enum class Color { Red = 0, Blue = 1 };

Teuchos::ParameterList valid() {
  Teuchos::ParameterList pl("Top");
  deck::addDouble(pl, "Time step", 1e-7, "h", 1e-300);
  deck::addInt(pl, "Modes", 10, "modes", 0, 100);
  deck::addEnum(pl, "Color", "Red", {"Red", "Blue"}, {0, 1}, "a color");
  deck::addDoubleArray(pl, "Origin", {0, 0, 0}, "origin");
  auto& any = pl.sublist("Bodies").sublist("*");
  deck::addDouble(any, "Density", 7800, "rho", 1e-300);
  return pl;
}

std::string errorOf(const std::string& xml) {
  auto user = deck::readXmlString(xml, "deck.xml");
  try {
    deck::validateAndSetDefaults(*user, valid(), "deck.xml", xml);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Deck, DefaultsAndEnums) {
  const std::string xml =
      "<ParameterList name=\"Top\"><Parameter name=\"Color\" type=\"string\" value=\"Blue\"/>"
      "<ParameterList name=\"Bodies\"><ParameterList name=\"Cube\"/></ParameterList></ParameterList>";
  auto user = deck::readXmlString(xml, "deck.xml");
  deck::validateAndSetDefaults(*user, valid(), "deck.xml", xml);
  EXPECT_EQ(user->get<double>("Time step"), 1e-7);
  EXPECT_EQ(user->get<int>("Modes"), 10);
  EXPECT_EQ(deck::getEnum<Color>(*user, "Color"), Color::Blue);
  EXPECT_EQ(user->sublist("Bodies").sublist("Cube").get<double>("Density"), 7800);
}

TEST(Deck, IntegerAcceptedForDouble) {
  const std::string xml =
      "<ParameterList name=\"Top\"><Parameter name=\"Time step\" type=\"int\" value=\"1\"/></ParameterList>";
  auto user = deck::readXmlString(xml, "deck.xml");
  deck::validateAndSetDefaults(*user, valid(), "deck.xml", xml);
  EXPECT_EQ(user->get<double>("Time step"), 1.0);
}

TEST(Deck, UnknownKeyNamesNearestAndLine) {
  const std::string e = errorOf(
      "<ParameterList name=\"Top\">\n<Parameter name=\"Time stpe\" type=\"double\" value=\"1\"/>\n</ParameterList>");
  EXPECT_NE(e.find("deck.xml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown parameter 'Time stpe'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'Time step'"), std::string::npos) << e;
}

TEST(Deck, UnknownKeyInTemplateList) {
  const std::string e = errorOf(
      "<ParameterList name=\"Top\"><ParameterList name=\"Bodies\"><ParameterList name=\"Cube\">"
      "<Parameter name=\"Densty\" type=\"double\" value=\"1\"/></ParameterList></ParameterList></ParameterList>");
  EXPECT_NE(e.find("did you mean 'Density'"), std::string::npos) << e;
}

TEST(Deck, WrongTypeNamesValueAndExpected) {
  const std::string e =
      errorOf("<ParameterList name=\"Top\"><Parameter name=\"Modes\" type=\"string\" value=\"ten\"/></ParameterList>");
  EXPECT_NE(e.find("'Top->Modes' has type string (value ten), expected int"), std::string::npos) << e;
}

TEST(Deck, OutOfRangeNamesRange) {
  const std::string e =
      errorOf("<ParameterList name=\"Top\"><Parameter name=\"Modes\" type=\"int\" value=\"101\"/></ParameterList>");
  EXPECT_NE(e.find("= 101 is out of range: allowed values are in [0, 100]"), std::string::npos) << e;
  const std::string f = errorOf(
      "<ParameterList name=\"Top\"><Parameter name=\"Time step\" type=\"double\" value=\"0\"/></ParameterList>");
  EXPECT_NE(f.find("'Top->Time step' = 0 is out of range"), std::string::npos) << f;
}

TEST(Deck, EnumTypoSuggests) {
  const std::string e =
      errorOf("<ParameterList name=\"Top\"><Parameter name=\"Color\" type=\"string\" value=\"Blu\"/></ParameterList>");
  EXPECT_NE(e.find("is not one of 'Red', 'Blue'; did you mean 'Blue'?"), std::string::npos) << e;
}

TEST(Deck, MalformedXml) {
  try {
    deck::readXmlString("<ParameterList name=\"Top\"><Parameter name=\"x\"", "bad.xml");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.xml: not a valid XML parameter list"), std::string::npos) << e.what();
  }
}

TEST(Deck, Nearest) {
  EXPECT_EQ(deck::nearest("Densty", {"Density", "Modes"}), "Density");
  EXPECT_EQ(deck::nearest("zzzzzz", {"Density", "Modes"}), "");
}
