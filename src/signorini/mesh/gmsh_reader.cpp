#include "signorini/mesh/gmsh_reader.hpp"

#include <fmt/format.h>
#include <gmsh.h>
#include <omp.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <functional>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <unordered_map>

#include "signorini/core/error.hpp"
#include "signorini/core/interrupt.hpp"
#include "signorini/core/log.hpp"
#include "signorini/core/rank_exchange.hpp"

namespace signorini {

namespace {

// The ":line" of an ASCII .msh's node line that holds `tag` and a non-finite number (inf,
// nan, or beyond the double range), for the message; empty when not found (binary files).
std::string nonfinite_line(const std::string& path, std::size_t tag) {
  std::ifstream in(path);
  std::string line;
  bool nodes = false;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.rfind("$Nodes", 0) == 0) nodes = true;
    else if (line.rfind("$EndNodes", 0) == 0) nodes = false;
    if (!nodes) continue;
    std::istringstream ss(line);
    std::string first, word;
    if (!(ss >> first) || first != std::to_string(tag)) continue;
    while (ss >> word)
      if (!std::isfinite(std::strtod(word.c_str(), nullptr))) return ":" + std::to_string(n);
  }
  return "";
}

std::mutex g_gmsh_mutex;  // the Gmsh library holds one global model

// The names declared inside DefineConstant[...] blocks of a .geo file, with their default
// when it is a plain number (`name = 0.5` or `name = {0.5, ...}`; NaN otherwise).
std::vector<std::string> declared_constants(const std::string& text, std::map<std::string, Real>* defaults = nullptr) {
  std::vector<std::string> names;
  size_t pos = 0;
  while ((pos = text.find("DefineConstant", pos)) != std::string::npos) {
    size_t open = text.find('[', pos), close = text.find("];", pos);
    if (open == std::string::npos || close == std::string::npos) break;
    std::string body = text.substr(open + 1, close - open - 1);
    // Entries are "name = value" or "name = {value, options}" separated by commas at depth 0.
    std::regex entry(R"((?:^|[,\s\[])([A-Za-z_][A-Za-z0-9_]*)\s*=)");
    int depth = 0;
    std::string flat;
    for (char c : body) {
      if (c == '{') ++depth;
      if (c == '}') --depth;
      flat += depth > 0 && c != '{' ? ' ' : c;
    }
    for (std::sregex_iterator it(flat.begin(), flat.end(), entry), end; it != end; ++it)
      names.push_back((*it)[1]);
    if (defaults) {
      std::regex value(R"((?:^|[,\s\[])([A-Za-z_][A-Za-z0-9_]*)\s*=\s*\{?\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*[,}\]]?)");
      for (std::sregex_iterator it(body.begin(), body.end(), value), end; it != end; ++it) {
        char* stop = nullptr;
        const std::string v = (*it)[2];
        const double d = std::strtod(v.c_str(), &stop);
        (*defaults)[(*it)[1]] = stop && *stop == 0 ? d : std::numeric_limits<Real>::quiet_NaN();
      }
    }
    pos = close;
  }
  return names;
}

struct GmshSession {
  // Gmsh sets OpenMP's thread count to its own option on initialize: restore ours after.
  int threads_ = omp_get_max_threads();
  explicit GmshSession(const std::vector<std::string>& args) {
    std::vector<std::string> a{"signorini"};
    a.insert(a.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& s : a) argv.push_back(s.data());
    gmsh::initialize(static_cast<int>(argv.size()), argv.data(), false);
    gmsh::option::setNumber("General.Terminal", log::level() <= log::Level::debug ? 1 : 0);
    // Gmsh 4.8's parallel surface meshing crashes with some algorithms and size fields.
    gmsh::option::setNumber("General.NumThreads", 1);
  }
  ~GmshSession() {
    gmsh::finalize();
    omp_set_num_threads(threads_);
  }
};

// Every node of the open Gmsh model: coordinates, tags and the index of each tag. Returns the
// index of the first node with a non-finite coordinate, -1 if none.
Index model_nodes(std::vector<Vec3>& xyz, std::vector<std::size_t>& tags, std::unordered_map<std::size_t, Index>& index) {
  std::vector<double> coords, param;
  gmsh::model::mesh::getNodes(tags, coords, param, -1, -1, false, false);
  index.reserve(tags.size());
  xyz.resize(tags.size());
  Index bad = -1;
  for (size_t i = 0; i < tags.size(); ++i) {
    index[tags[i]] = static_cast<Index>(i);
    xyz[i] = Vec3(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]);
    if (bad < 0 && !xyz[i].allFinite()) bad = static_cast<Index>(i);
  }
  return bad;
}

std::string last_gmsh_error() {
  std::string e;
  try {
    gmsh::logger::getLastError(e);
  } catch (...) {
  }
  return e;
}

extern "C" char** environ;

// Path of the gmsh executable on PATH, or "".
std::string find_gmsh_executable() {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/gmsh";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

// A gmsh process meshing `geo` into `msh` (format 4.1), its output in `logf`, in a process
// group of its own (Ctrl-C reaches Signorini, which stops it). `mesh_it` false: only read the
// file and write it again (a .msh checked in a process of its own).
pid_t spawn_gmsh(const std::string& exe, const std::string& geo, const std::vector<std::string>& args, int order,
                 const std::string& msh, const std::string& logf, const std::string& where, bool mesh_it = true) {
  std::vector<std::string> a{exe, geo, mesh_it ? "-3" : "-save", "-format", "msh41", "-o", msh, "-v", "3", "-nt", "1"};
  a.insert(a.end(), args.begin(), args.end());
  if (order > 0) a.insert(a.end(), {"-order", std::to_string(order)});
  std::vector<char*> argv;
  for (auto& x : a) argv.push_back(x.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, logf.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  pid_t pid;
  const int rc = posix_spawn(&pid, exe.c_str(), &fa, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) throw InputError(where, "mesh.file", "cannot run " + exe + ": " + std::strerror(rc));
  return pid;
}

std::string temp_stem() {
  static std::atomic<int> counter{0};
  return (std::filesystem::temp_directory_path() / ("signorini_" + std::to_string(::getpid()) + "_" +
                                                    std::to_string(counter++))).string();
}

// A gmsh child and its files: whatever happens (an exception included), the process is
// stopped and reaped and the files removed, except the output handed over by keep().
struct Child {
  pid_t pid = -1;
  std::vector<std::string> files;
  ~Child() {
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      int st = 0;
      ::waitpid(pid, &st, 0);
    }
    for (auto& f : files) {
      std::error_code ec;
      std::filesystem::remove(f, ec);
    }
  }
  std::string keep(const std::string& file) {
    files.erase(std::remove(files.begin(), files.end(), file), files.end());
    return file;
  }
  // Waits at most `timeout` seconds (< 0: no limit), calling `tick` with the elapsed seconds
  // about 10 times a second; `tick` returning false stops the child. True when the child
  // ended by itself (its status in `status`; a child reaped elsewhere counts as a normal exit).
  bool wait(double timeout, int& status, const std::function<bool(double)>& tick) {
    log::Timer t;
    while (true) {
      const pid_t r = ::waitpid(pid, &status, WNOHANG);
      if (r == pid || (r < 0 && errno == ECHILD)) {
        if (r < 0) status = 0;
        pid = -1;
        return true;
      }
      if ((timeout >= 0 && t.seconds() > timeout) || (tick && !tick(t.seconds()))) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        pid = -1;
        return false;
      }
      ::usleep(100000);
    }
  }
};

// Gmsh's error lines ("Error   : ...") in its log.
std::string log_errors(const std::string& logf) {
  std::ifstream lg(logf);
  std::string line, errors;
  while (std::getline(lg, line))
    if (line.rfind("Error", 0) == 0) errors += (errors.empty() ? "" : "; ") + line;
  return errors;
}

// Element count and dimension of a .msh 4.1 file (from its $Elements blocks' headers).
double msh_elements(const std::string& msh, int* dim) {
  std::ifstream in(msh);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("$Elements", 0) == 0) break;
  std::size_t blocks = 0, total = 0, lo = 0, hi = 0;
  if (!(in >> blocks >> total >> lo >> hi)) return -1;
  int d = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    int edim = 0, tag = 0, type = 0;
    std::size_t n = 0;
    if (!(in >> edim >> tag >> type >> n)) return -1;
    d = std::max(d, edim);
    std::getline(in, line);
    for (std::size_t i = 0; i < n; ++i) std::getline(in, line);
  }
  if (dim) *dim = d;
  return static_cast<double>(total);
}

// Meshes a .geo file in a separate gmsh process, so that a crash of Gmsh's mesher (Gmsh 4.8
// has some) is reported as an error instead of ending this program. Returns the .msh path.
// A meshing that takes more than 5 s has its size estimated (estimate_elements) and stops
// above `max_elements`; otherwise it reports its progress every 10 s.
std::string mesh_in_child(const std::string& exe, const std::string& geo, const std::vector<std::string>& args,
                          int order, const std::string& where, double max_elements) {
  const std::string stem = temp_stem();
  const std::string msh = stem + ".msh", logf = stem + ".log";
  Child child{-1, {msh, logf}};
  child.pid = spawn_gmsh(exe, geo, args, order, msh, logf, where);
  double estimate = -1, last_report = 0;
  bool estimated = false;
  std::string refused;
  int status = 0;
  const bool ended = child.wait(-1, status, [&](double t) {
    if (interrupt_signal()) return false;
    if (t > 5 && !estimated) {
      estimated = true;
      log::info("meshing '{}' takes a while: estimating its size from coarser meshes", geo);
      estimate = estimate_elements(exe, geo, args);
      if (interrupt_signal()) return false;
      if (estimate > max_elements) {
        refused = fmt::format(
            "meshing '{}' would make about {:.3g} elements (estimated from coarser meshes of it), more than "
            "mesh.max_elements = {:.3g}: make the mesh coarser (its size parameters) or raise max_elements",
            geo, estimate, max_elements);
        return false;
      }
      if (estimate >= 0) log::info("meshing '{}': about {:.3g} elements expected", geo, estimate);
      else log::info("meshing '{}': its size could not be estimated from coarser meshes", geo);
      last_report = t;
    }
    if (estimated && t - last_report >= 10) {
      log::info("meshing '{}': {:.0f} s", geo, t);
      last_report = t;
    }
    return true;
  });
  if (interrupt_signal()) throw InputError(where, "mesh.file", "meshing '" + geo + "' interrupted");
  if (!ended) throw InputError(where, "mesh.max_elements", refused);
  const std::string errors = log_errors(logf);
  if (WIFSIGNALED(status))
    throw InputError(where, "mesh.file",
                     "Gmsh crashed (signal " + std::to_string(WTERMSIG(status)) + ") while meshing '" + geo +
                         "'. This is a Gmsh bug (or the mesh is too large for memory); another Mesh.Algorithm in "
                         "the .geo usually avoids it" +
                         (errors.empty() ? "" : " (" + errors + ")"));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !errors.empty() || !std::filesystem::exists(msh))
    throw InputError(where, "mesh.file", "Gmsh could not mesh '" + geo + "': " + (errors.empty() ? "no mesh written" : errors));
  if (estimated) log::info("meshed '{}': {:.0f} elements", geo, msh_elements(msh, nullptr));
  return child.keep(msh);
}

// Under mpirun: `work` (reading the mesh) on rank 0 alone, its verdict on every rank: nothing, or
// the InputError it threw, which every rank then throws alike (so that they stop together,
// rank 0 saying why).
void on_rank0(const RankExchange& ranks, const std::function<void()>& work) {
  std::string verdict;
  auto keep = [&](const std::string& where, const std::string& key, const std::string& message) {
    verdict = where + '\0' + key + '\0' + message;
  };
  if (ranks.rank() == 0) try {
      work();
    } catch (const InputError& e) {
      keep(e.where(), e.key(), e.message());
    } catch (const std::exception& e) {
      keep("", "mesh.file", e.what());
    }
  ranks.broadcast(verdict, 0);
  if (verdict.empty()) return;
  const size_t a = verdict.find('\0'), b = verdict.find('\0', a + 1);
  throw InputError(verdict.substr(0, a), verdict.substr(a + 1, b - a - 1), verdict.substr(b + 1));
}

}  // namespace

void check_msh_in_child(const std::string& exe, const std::string& msh, const std::string& where) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto size = fs::file_size(msh, ec);
  if (ec || !fs::is_regular_file(msh, ec)) throw InputError(where, "mesh.file", "'" + msh + "' is not a readable file");
  const std::string logf = temp_stem() + ".log";
  Child child{-1, {logf}};
  child.pid = spawn_gmsh(exe, msh, {}, 0, "/dev/null", logf, where, false);
  // Reading takes about a second per 10 MB; a malformed count must not hang the run.
  const double limit = 20 + static_cast<double>(size) / 5e6;
  int status = 0;
  const bool ended = child.wait(limit, status, [](double) { return interrupt_signal() == 0; });
  if (interrupt_signal()) throw InputError(where, "mesh.file", "reading '" + msh + "' interrupted");
  if (!ended)
    throw InputError(where, "mesh.file", fmt::format("Gmsh did not finish reading '{}' in {:.0f} s (a malformed count?)",
                                                     msh, limit));
  const std::string errors = log_errors(logf);
  if (WIFSIGNALED(status))
    throw InputError(where, "mesh.file", fmt::format("Gmsh crashed (signal {}) reading '{}': the file is malformed{}",
                                                     WTERMSIG(status), msh, errors.empty() ? "" : " (" + errors + ")"));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !errors.empty())
    throw InputError(where, "mesh.file", "Gmsh cannot read '" + msh + "': " + (errors.empty() ? "it stopped with an error" : errors));
}

double count_elements(const std::string& exe, const std::string& geo, const std::vector<std::string>& args,
                      double size_factor, double timeout, int* dim) {
  const std::string stem = temp_stem();
  const std::string msh = stem + ".msh", logf = stem + ".log";
  Child child{-1, {msh, logf}};
  std::vector<std::string> a = args;
  std::ostringstream f;
  f.precision(17);
  f << size_factor;
  a.insert(a.end(), {"-clscale", f.str()});
  child.pid = spawn_gmsh(exe, geo, a, 0, msh, logf, geo);
  int status = 0;
  if (!child.wait(timeout, status, [](double) { return interrupt_signal() == 0; })) return -2;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return msh_elements(msh, dim);
  return -1;
}

double estimate_elements(const std::string& exe, const std::string& geo, const std::vector<std::string>& args) {
  // Counts N(s) with every size multiplied by s, from s = 4^20 down. Where the sizes are
  // below the geometry's features N grows like s^-e (e = the dimension when the size field
  // scales, less when parts of the mesh are fixed: transfinite lines, layers); the estimate
  // N(1) = N(s) s^e uses the exponent measured between the last two counts (once both are
  // large enough to be past the geometry's own minimum).
  double prev_n = -1, prev_s = 0, s = std::pow(4.0, 20);
  int dim = 3;
  while (true) {
    const double n = count_elements(exe, geo, args, s, 20, &dim);
    if (interrupt_signal()) return -1;
    if (n == -2)  // the coarse mesh itself took more than 20 s: far beyond a limit of 1e7
      return prev_n > 0 ? prev_n * std::pow(prev_s, dim) : -1;
    if (n < 0) return -1;  // Gmsh failed on the coarse mesh: no estimate
    if (s <= 1) return n;
    if (prev_n >= 500 && n >= 2000) {  // both counts past the geometry's own
      const Real e = std::clamp(std::log(n / prev_n) / std::log(prev_s / s), 0.0, static_cast<Real>(dim));
      return n * std::pow(s, e);
    }
    // Saturated (every size beyond the geometry's: the count does not move): larger strides.
    const bool saturated = n == prev_n;
    prev_n = n, prev_s = s;
    s = std::max(1.0, s / (saturated ? 16 : 4));
  }
}

std::string geo_side_effect(const std::string& t) {
  static const std::set<std::string> refused = {"SystemCall", "Exit", "Save", "Print", "OnelabRun"};
  int line = 1;
  size_t i = 0;
  const size_t n = t.size();
  // The next string literal after position i (its contents), for Include and Merge.
  auto next_string = [&](size_t from) {
    size_t q = t.find('"', from);
    if (q == std::string::npos) return std::string();
    size_t e = t.find('"', q + 1);
    return t.substr(q + 1, e == std::string::npos ? std::string::npos : e - q - 1);
  };
  while (i < n) {
    const char c = t[i];
    if (c == '\n') {
      ++line, ++i;
    } else if (c == '/' && i + 1 < n && t[i + 1] == '/') {
      while (i < n && t[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < n && t[i + 1] == '*') {
      i += 2;
      while (i + 1 < n && !(t[i] == '*' && t[i + 1] == '/')) line += t[i++] == '\n';
      i += 2;
    } else if (c == '"') {
      ++i;
      while (i < n && t[i] != '"') line += t[i] == '\n', i += t[i] == '\\' ? 2 : 1;
      ++i;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      size_t e = i;
      while (e < n && (std::isalnum(static_cast<unsigned char>(t[e])) || t[e] == '_')) ++e;
      const std::string word = t.substr(i, e - i);
      if (refused.count(word)) return "line " + std::to_string(line) + ": " + word;
      if (word == "Include" || word == "Merge") {
        const std::string file = next_string(e);
        if (file.empty() || file[0] == '/' || file.find("..") != std::string::npos)
          return "line " + std::to_string(line) + ": " + word + " \"" + file + "\" (outside the script's folder)";
      }
      i = e;
    } else {
      ++i;
    }
  }
  return "";
}

namespace {
Mesh read_gmsh_here(const std::string& path, const GmshOptions& options) {
  namespace fs = std::filesystem;
  const std::string where = options.where.empty() ? path : options.where;
  if (!fs::exists(path)) throw InputError(where, "mesh.file", "mesh file '" + path + "' does not exist");
  const std::string ext = fs::path(path).extension().string();
  if (ext != ".msh" && ext != ".geo")
    throw InputError(where, "mesh.file", "mesh file '" + path + "' must end in .msh or .geo");
  // A .geo's text, read once for the side-effect scan and the parameters' declarations.
  std::string geo_text;
  if (ext == ".geo") {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    geo_text = ss.str();
  }
  if (ext == ".geo" && !options.trusted) {
    if (const std::string bad = geo_side_effect(geo_text); !bad.empty())
      throw InputError(where, "mesh.file",
                       "'" + path + "' " + bad +
                           ": a .geo is a program, and Signorini does not run its side effects (SystemCall, Exit, "
                           "Save, Print, OnelabRun, Include or Merge outside its folder) unless the deck says "
                           "mesh: {trusted: true}");
  }
  std::vector<std::string> args;
  if (!options.parameters.empty()) {
    if (ext != ".geo")
      throw InputError(where, "mesh.parameters", "parameters apply to .geo files only, not '" + path + "'");
    std::map<std::string, Real> defaults;
    auto declared = declared_constants(geo_text, &defaults);
    for (auto& [name, value] : options.parameters) {
      if (std::find(declared.begin(), declared.end(), name) == declared.end())
        throw InputError(where, "mesh.parameters." + name,
                         "'" + path + "' does not declare '" + name +
                             "' with DefineConstant[...], so it cannot be set from the deck");
      // A parameter whose default is positive is a size, a length or a count: zero or a
      // negative value would make Gmsh mesh for a long time or fail late.
      if (auto d = defaults.find(name); d != defaults.end() && d->second > 0 && !(value > 0))
        throw InputError(where, "mesh.parameters." + name,
                         fmt::format("got {}: '{}' declares '{}' with the positive default {} (a size, length or "
                                     "count), so it must stay positive",
                                     value, path, name, d->second));
      std::ostringstream v;
      v.precision(17);
      v << value;
      args.insert(args.end(), {"-setnumber", name, v.str()});
    }
  }

  // A .geo is meshed by the gmsh program when it is installed (a crash of its mesher then
  // cannot take this process down), else in this process through the API.
  std::string to_read = path, generated;
  const std::string exe = find_gmsh_executable();
  if (!exe.empty() && ext == ".msh") check_msh_in_child(exe, path, where);
  if (!exe.empty() && ext == ".geo") {
    generated = mesh_in_child(exe, path, args, options.order, where, options.max_elements);
    to_read = generated;
    args.clear();
  }
  struct Cleanup {
    std::string file;
    ~Cleanup() {
      if (!file.empty()) std::filesystem::remove(file);
    }
  } cleanup{generated};
  // A .msh was read by a gmsh process first (check_msh_in_child): a malformed file that
  // crashes or hangs Gmsh's parser, or leaks in it, does so there.
  std::lock_guard<std::mutex> lock(g_gmsh_mutex);
  GmshSession session(args);
  Mesh mesh;
  try {
    gmsh::open(to_read);
    if (ext == ".geo" && generated.empty()) gmsh::model::mesh::generate(gmsh::model::getDimension());
    if (options.order > 0 && generated.empty()) gmsh::model::mesh::setOrder(options.order);
    std::vector<std::size_t> tags;
    std::unordered_map<std::size_t, Index> index;
    if (const Index bad = model_nodes(mesh.nodes, tags, index); bad >= 0) {
      const Vec3& x = mesh.nodes[bad];
      throw InputError(ext == ".msh" ? path + nonfinite_line(path, tags[bad]) : where, "mesh.file",
                       fmt::format("node {} of '{}' has a non-finite coordinate ({}, {}, {})", tags[bad], path, x(0),
                                   x(1), x(2)));
    }
    mesh.node_ids.assign(tags.begin(), tags.end());
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, -1);
    if (groups.empty())
      throw InputError(where, "mesh.file",
                       "mesh '" + path + "' has no physical groups: name its regions and "
                       "boundaries with Physical Surface/Volume/Curve in the .geo");
    int dim = 0;
    for (auto& [d, t] : groups) dim = std::max(dim, d);
    if (dim < 2)
      throw InputError(where, "mesh.file", "mesh '" + path + "' has no 2D or 3D physical group");
    mesh.dim = dim;
    for (auto& [d, t] : groups) {
      std::string name;
      gmsh::model::getPhysicalName(d, t, name);
      if (name.empty()) name = std::to_string(t);
      std::vector<int> entities;
      gmsh::model::getEntitiesForPhysicalGroup(d, t, entities);
      std::map<ElementType, ElementBlock> blocks;
      for (int ent : entities) {
        std::vector<int> types;
        std::vector<std::vector<std::size_t>> etags, enodes;
        gmsh::model::mesh::getElements(types, etags, enodes, d, ent);
        for (size_t k = 0; k < types.size(); ++k) {
          ElementType et = element_type_from_gmsh(types[k]);
          auto& b = blocks.try_emplace(et, ElementBlock{et, {}, {}}).first->second;
          const int nn = element_info(et).num_nodes;
          // Grown once per entity (a group's cells are mostly in one entity): no doubling and its
          // slack, which stayed in the body the cells are moved into.
          if (const size_t need = b.conn.size() + etags[k].size() * nn; need > b.conn.capacity()) {
            b.conn.reserve(std::max(need, b.conn.capacity() + b.conn.capacity() / 2));
            b.ids.reserve(std::max(b.ids.size() + etags[k].size(), b.ids.capacity() + b.ids.capacity() / 2));
          }
          for (size_t e = 0; e < etags[k].size(); ++e) {
            for (int a = 0; a < nn; ++a) b.conn.push_back(index.at(enodes[k][e * nn + a]));
            b.ids.push_back(static_cast<Index>(etags[k][e]));
          }
        }
      }
      if (d == dim || d == dim - 1) {
        auto& target = d == dim ? mesh.regions[name] : mesh.facet_sets[name];
        for (auto& [et, b] : blocks) {
          b.conn.shrink_to_fit();
          b.ids.shrink_to_fit();
          target.push_back(std::move(b));
        }
      }
      std::vector<std::size_t> ntags;
      std::vector<double> ncoords;
      gmsh::model::mesh::getNodesForPhysicalGroup(d, t, ntags, ncoords);
      auto& ns = mesh.node_sets[name];
      for (auto nt : ntags) ns.push_back(index.at(nt));
      std::sort(ns.begin(), ns.end());
      ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    std::string g = last_gmsh_error();
    throw InputError(where, "mesh.file", "Gmsh could not read '" + path + "': " + (g.empty() ? e.what() : g));
  } catch (...) {
    std::string g = last_gmsh_error();
    throw InputError(where, "mesh.file", "Gmsh could not read '" + path + "'" + (g.empty() ? "" : ": " + g));
  }
  if (mesh.regions.empty())
    throw InputError(where, "mesh.file", "mesh '" + path + "' has no cells in a physical group of dimension " +
                                              std::to_string(mesh.dim));
  // Drop nodes that no cell uses? They stay (a physical point may name one); they get no
  // degrees of freedom unless a cell uses them.
  return mesh;
}

// A mesh as bytes (rank 0 to the other ranks, one machine's layout: the ranks of a run share
// one build): counts, then the arrays' bytes.
class MeshBytes {
 public:
  static std::string pack(const Mesh& m) {
    // Two passes: the size, then the bytes into a string of that size (appending alone grows it
    // by doubling, up to about three times the mesh's bytes at once while it is copied).
    std::string b;
    size_t size = 0;
    bool sizing = true;
    auto raw = [&](const void* p, size_t n) {
      if (sizing) size += n;
      else b.append(static_cast<const char*>(p), n);
    };
    auto count = [&](size_t n) {
      const std::uint64_t c = n;
      raw(&c, sizeof c);
    };
    auto array = [&](const auto& v) {
      count(v.size());
      raw(v.data(), v.size() * sizeof(v[0]));
    };
    auto blocks = [&](const std::map<std::string, std::vector<ElementBlock>>& sets) {
      count(sets.size());
      for (const auto& [name, list] : sets) {
        array(name);
        count(list.size());
        for (const ElementBlock& blk : list) {
          const std::int32_t type = static_cast<std::int32_t>(blk.type);
          raw(&type, sizeof type);
          array(blk.conn);
          array(blk.ids);
        }
      }
    };
    auto all = [&] {
      const std::int32_t dim = m.dim;
      raw(&dim, sizeof dim);
      array(m.nodes);
      array(m.node_ids);
      blocks(m.regions);
      blocks(m.facet_sets);
      count(m.node_sets.size());
      for (const auto& [name, nodes] : m.node_sets) {
        array(name);
        array(nodes);
      }
    };
    all();
    b.reserve(size);
    sizing = false;
    all();
    return b;
  }
  static Mesh unpack(const std::string& b) {
    size_t at = 0;
    auto raw = [&](void* p, size_t n) {
      if (n > b.size() - at) throw Error("the mesh sent by rank 0 ends early");
      std::memcpy(p, b.data() + at, n);
      at += n;
    };
    auto count = [&]() {
      std::uint64_t c = 0;
      raw(&c, sizeof c);
      return static_cast<size_t>(c);
    };
    auto array = [&](auto& v) {
      v.resize(count());
      raw(v.data(), v.size() * sizeof(v[0]));
    };
    auto blocks = [&](std::map<std::string, std::vector<ElementBlock>>& sets) {
      for (size_t k = count(); k > 0; --k) {
        std::string name;
        array(name);
        auto& list = sets[name];
        list.resize(count());
        for (ElementBlock& blk : list) {
          std::int32_t type = 0;
          raw(&type, sizeof type);
          blk.type = static_cast<ElementType>(type);
          array(blk.conn);
          array(blk.ids);
        }
      }
    };
    Mesh m;
    std::int32_t dim = 0;
    raw(&dim, sizeof dim);
    m.dim = dim;
    array(m.nodes);
    array(m.node_ids);
    blocks(m.regions);
    blocks(m.facet_sets);
    for (size_t k = count(); k > 0; --k) {
      std::string name;
      array(name);
      array(m.node_sets[name]);
    }
    if (at != b.size()) throw Error("the mesh sent by rank 0 has bytes left over");
    return m;
  }
};
static_assert(sizeof(Vec3) == 3 * sizeof(Real), "a node's coordinates are sent as their bytes");

}  // namespace

Mesh read_gmsh(const std::string& path, const GmshOptions& options) {
  if (!options.ranks || options.ranks->size() <= 1) return read_gmsh_here(path, options);
  // Under mpirun: rank 0 reads (runs gmsh, parses), its verdict and then its mesh go to the others.
  const RankExchange& ranks = *options.ranks;
  Mesh mesh;
  std::string bytes;
  on_rank0(ranks, [&] {
    mesh = read_gmsh_here(path, options);
    bytes = MeshBytes::pack(mesh);
  });
  ranks.broadcast(bytes, 0);
  if (ranks.rank() != 0) mesh = MeshBytes::unpack(bytes);
  log::debug("mesh '{}' read by rank 0 and sent to the {} other ranks ({:.1f} MB)", path, ranks.size() - 1,
             static_cast<double>(bytes.size()) / 1e6);
  return mesh;
}

SurfaceFile read_surface_file(const std::string& path) {
  namespace fs = std::filesystem;
  if (!fs::is_regular_file(path)) throw InputError(path, "", "no such file");
  if (fs::path(path).extension() != ".msh") throw InputError(path, "", "a surface file is a Gmsh .msh");
  std::lock_guard<std::mutex> lock(g_gmsh_mutex);
  GmshSession session({});
  SurfaceFile out;
  try {
    gmsh::open(path);
    std::vector<std::size_t> tags;
    std::unordered_map<std::size_t, Index> index;
    if (const Index bad = model_nodes(out.nodes, tags, index); bad >= 0)
      throw InputError(path, "", fmt::format("node {} has a non-finite coordinate", tags[bad]));
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> etags, enodes;
    gmsh::model::mesh::getElements(types, etags, enodes, 2, -1);
    for (size_t b = 0; b < types.size(); ++b) {
      const ElementType t = element_type_from_gmsh(types[b]);
      const ElementInfo& info = element_info(t);
      std::vector<Vec3>& dst = info.num_corners == 3 ? out.triangles : out.quads;
      for (size_t e = 0; e < etags[b].size(); ++e)
        for (int k = 0; k < info.num_corners; ++k) dst.push_back(out.nodes[index.at(enodes[b][e * info.num_nodes + k])]);
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path, "", std::string("Gmsh cannot read it: ") + e.what() + " " + last_gmsh_error());
  }
  return out;
}

}  // namespace signorini
