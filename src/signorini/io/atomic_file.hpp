// Writes a file atomically: to a temporary file beside it, then renamed over the target, so
// a reader (or a crash) never sees half a file.
#pragma once
#include <string>

namespace signorini {

void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace signorini
