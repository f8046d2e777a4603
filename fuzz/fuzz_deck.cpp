// libFuzzer target: the YAML deck reader (read_deck). Seeds: the shipped example decks and
// decks on square.msh (fuzz/corpus/deck).
#include "fuzz_common.hpp"
#include "signorini/io/deck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace signorini;
  static const Registry registry = default_registry();
  const std::string path = fuzz::write_input(data, size, "deck.yaml");
  return fuzz::guarded([&] { read_deck(path, registry); });
}
