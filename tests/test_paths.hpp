// Where the tests find the source tree, its test data, the signorini program and the build
// folder. The paths are compiled into one small generated object (test_paths.cpp in the build
// folder, tests/CMakeLists.txt) instead of definitions on every test source, so that the test
// objects carry no absolute path of the tree and a clone in another folder reuses them from
// ccache (CMakeLists.txt, the compiler launcher). Included in every test source (-include).
#pragma once

namespace signorini::test_paths {
const char* test_data();   // tests/data
const char* binary();      // the signorini program
const char* source_dir();  // the source tree
const char* binary_dir();  // the build folder
}  // namespace signorini::test_paths

#define SIGNORINI_TEST_DATA (::signorini::test_paths::test_data())
#define SIGNORINI_BINARY (::signorini::test_paths::binary())
#define SIGNORINI_SOURCE_DIR (::signorini::test_paths::source_dir())
#define SIGNORINI_BINARY_DIR (::signorini::test_paths::binary_dir())
