// Minimal logging: one sink (stderr by default), levels, and a wall clock. Progress lines
// and the Newton residual history go through here so that tests can silence them.
#pragma once
#include <fmt/format.h>
#include <chrono>
#include <string>

namespace signorini::log {

enum class Level { debug = 0, info = 1, warning = 2, error = 3, quiet = 4 };

void set_level(Level level);
Level level();
void write(Level level, const std::string& text);

template <typename... Args>
void info(fmt::format_string<Args...> f, Args&&... args) {
  if (level() <= Level::info) write(Level::info, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) {
  if (level() <= Level::debug) write(Level::debug, fmt::format(f, std::forward<Args>(args)...));
}
template <typename... Args>
void warning(fmt::format_string<Args...> f, Args&&... args) {
  if (level() <= Level::warning)
    write(Level::warning, fmt::format(f, std::forward<Args>(args)...));
}

// Seconds since the first call in this process.
double elapsed();
// Peak resident memory of this process in MiB (from /proc/self/status), 0 if unknown.
double peak_memory_mib();
// The resident memory now (VmRSS), in MiB.
double memory_mib();

class Timer {
 public:
  Timer() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace signorini::log
