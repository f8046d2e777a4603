// Shared by the libFuzzer targets (issue 17, item 6): each input is written to a file in a
// private temporary folder (beside a small valid mesh, square.msh, that decks may name) and
// read by the reader under test. An InputError is the expected answer to bad input; any
// other exception, a crash, a sanitizer report, a leak or a hang is a finding.
#pragma once
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"

namespace signorini::fuzz {

inline const std::filesystem::path& folder() {
  static const std::filesystem::path dir = [] {
    namespace fs = std::filesystem;
    const fs::path d = fs::temp_directory_path() / ("signorini_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    fs::copy_file(SIGNORINI_FUZZ_DIR "/square.msh", d / "square.msh", fs::copy_options::overwrite_existing);
    log::set_level(log::Level::quiet);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(std::filesystem::temp_directory_path() / ("signorini_fuzz_" + std::to_string(::getpid())), ec);
    });
    return d;
  }();
  return dir;
}

inline std::string write_input(const uint8_t* data, size_t size, const std::string& name) {
  const std::filesystem::path p = folder() / name;
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return p.string();
}

// Runs `read`; InputError is fine, anything else aborts (a finding).
template <typename F>
int guarded(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "finding: an exception that is not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}

}  // namespace signorini::fuzz
