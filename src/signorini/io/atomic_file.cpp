#include "signorini/io/atomic_file.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "signorini/core/error.hpp"

namespace signorini {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = path + ".tmp";
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write '" + tmp + "' (does the directory exist and is it writable?)");
    write(out);
    out.flush();
    // Closed here, checked: a file system may report a failed write only when the file closes.
    out.close();
    if (!out) throw Error("writing '" + tmp + "' failed (disk full?): removed, '" + path + "' not replaced");
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw Error("cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
  } catch (...) {
    // The partial file goes: on a full disk it holds the space the next write needs (until
    // session 71 a run stopped by a full disk left its last file's .tmp behind).
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

void write_file_atomically(const std::string& path, const std::string& content) {
  write_file_atomically(path, [&](std::ostream& out) { out.write(content.data(), static_cast<std::streamsize>(content.size())); });
}

}  // namespace signorini
