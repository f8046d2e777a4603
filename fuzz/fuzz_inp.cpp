// libFuzzer target: the CalculiX/Abaqus .inp reader, through read_deck (the translation and
// the translated deck). Seeds: the CalculiX harness decks and small decks (fuzz/corpus/inp).
#include "fuzz_common.hpp"
#include "signorini/io/deck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace signorini;
  static const Registry registry = default_registry();
  const std::string path = fuzz::write_input(data, size, "job.inp");
  return fuzz::guarded([&] { read_deck(path, registry); });
}
