// Fuzzing the deck reader: XML parsing (readDeckFromString) and validation against the schema
// (unknown keys, types, ranges, enums). Every input must be accepted or refused with epaphe::Error.
#include "Epaphe_DeckSchema.hpp"
#include "fuzz_driver.hpp"

namespace {
void target(const std::string& input, const std::string&) {
  epaphe::Deck deck = epaphe::readDeckFromString(input, "fuzz.xml");
  (void)deck;
}
}  // namespace

#ifdef EPAPHE_LIBFUZZER
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    target(std::string(reinterpret_cast<const char*>(data), size), "");
  } catch (const epaphe::Error&) {
  }
  return 0;
}
#else
int main(int argc, char** argv) {
  return epaphe::fuzz::runDriver("deck", argc, argv, target);
}
#endif
