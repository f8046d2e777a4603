// Writes a file atomically: to a temporary file beside it, then renamed over the target, so
// a reader (or a crash) never sees half a file.
#pragma once
#include <functional>
#include <ostream>
#include <string>

namespace signorini {

void write_file_atomically(const std::string& path, const std::string& content);
// The same with the content streamed by `write` (large files: nothing held in memory).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace signorini
