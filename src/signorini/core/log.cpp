#include "signorini/core/log.hpp"

#include <atomic>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>

namespace signorini::log {

namespace {
std::atomic<Level> g_level{Level::info};
std::mutex g_mutex;
const auto g_start = std::chrono::steady_clock::now();
}  // namespace

void set_level(Level l) { g_level = l; }
Level level() { return g_level; }

void write(Level l, const std::string& text) {
  std::lock_guard<std::mutex> lock(g_mutex);
  const char* prefix = l == Level::warning ? "warning: " : (l == Level::error ? "error: " : "");
  // Progress goes to stdout with the rest of the report; warnings and errors to stderr.
  std::FILE* out = l >= Level::warning ? stderr : stdout;
  std::fflush(stdout);
  std::fprintf(out, "%s%s\n", prefix, text.c_str());
  std::fflush(out);
}

double elapsed() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
}

namespace {
double status_mib(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string k = key;
  while (std::getline(in, line)) {
    if (line.rfind(k, 0) == 0) {
      std::istringstream s(line.substr(k.size()));
      double kb = 0;
      s >> kb;
      return kb / 1024.0;
    }
  }
  return 0.0;
}
}  // namespace

double peak_memory_mib() { return status_mib("VmHWM:"); }
double memory_mib() { return status_mib("VmRSS:"); }

}  // namespace signorini::log
