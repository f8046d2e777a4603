// libFuzzer target: the Gmsh .msh reader (read_gmsh: Gmsh's parser, then our conversion and
// checks). Seeds: .msh files of the tests and examples (fuzz/corpus/msh).
#include "fuzz_common.hpp"
#include "signorini/mesh/gmsh_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace signorini;
  const std::string path = fuzz::write_input(data, size, "input.msh");
  return fuzz::guarded([&] { read_gmsh(path); });
}
