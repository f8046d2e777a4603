#include "signorini/io/inp_reader.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>

#include <fmt/format.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"

namespace signorini {

namespace {

namespace fs = std::filesystem;

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
std::string trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}
// Fields of a line split at commas, trimmed; a trailing comma adds no empty field.
std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  size_t a = 0;
  while (true) {
    size_t b = s.find(',', a);
    out.push_back(trim(s.substr(a, b == std::string::npos ? std::string::npos : b - a)));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  if (out.size() > 1 && out.back().empty()) out.pop_back();
  return out;
}

struct DataLine {
  const std::string* file;
  int line;
  std::vector<std::string> fields;
  std::string where() const { return *file + ":" + std::to_string(line); }
};

// One keyword line and its data lines.
struct Card {
  const std::string* file = nullptr;
  int line = 0;
  std::string keyword;                                      // upper case, single spaces, no '*'
  std::vector<std::pair<std::string, std::string>> params;  // upper-case name, value as written
  std::vector<DataLine> data;

  std::string where() const { return *file + ":" + std::to_string(line); }
  std::string key() const { return "*" + keyword; }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(where(), key(), what); }
  [[noreturn]] void fail(const DataLine& d, const std::string& what) const { throw InputError(d.where(), key(), what); }
  bool has(const std::string& p) const {
    for (auto& [k, v] : params)
      if (k == p) return true;
    return false;
  }
  std::string raw(const std::string& p) const {
    for (auto& [k, v] : params)
      if (k == p) return v;
    return "";
  }
  // A name parameter (upper case); required unless a default is given.
  std::string name(const std::string& p, std::optional<std::string> fallback = std::nullopt) const {
    if (!has(p) || trim(raw(p)).empty()) {
      if (fallback) return *fallback;
      fail("needs the parameter " + p + "=");
    }
    return upper(trim(raw(p)));
  }
  // Rejects parameters outside `allowed`.
  void allow(std::initializer_list<const char*> allowed) const {
    for (auto& [k, v] : params) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || k == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail("parameter " + k + " is not supported here" + (list.empty() ? "" : " (Signorini reads: " + list + ")"));
      }
    }
  }
};

Real number(const Card& c, const DataLine& d, size_t i, const std::string& what) {
  if (i >= d.fields.size() || d.fields[i].empty()) c.fail(d, "missing " + what);
  std::string s = d.fields[i];
  for (char& ch : s)
    if (ch == 'd' || ch == 'D') ch = 'e';  // Fortran exponents, 1.5d3
  char* end = nullptr;
  errno = 0;
  const Real v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') c.fail(d, "expected a number for " + what + ", got '" + d.fields[i] + "'");
  if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1))
    c.fail(d, "expected a finite number for " + what + ", got '" + d.fields[i] + "'");
  return v;
}
Real number_or(const Card& c, const DataLine& d, size_t i, const std::string& what, Real fallback) {
  return i < d.fields.size() && !d.fields[i].empty() ? number(c, d, i, what) : fallback;
}
bool is_integer(const std::string& s) {
  if (s.empty()) return false;
  for (size_t i = (s[0] == '-' || s[0] == '+'); i < s.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return s.size() > (s[0] == '-' || s[0] == '+');
}
Index integer(const Card& c, const DataLine& d, size_t i, const std::string& what);
// A node or element id: an integer from 1 to 2^31 - 1.
Index id_number(const Card& c, const DataLine& d, size_t i, const std::string& what) {
  const Index v = integer(c, d, i, what);
  if (v < 1 || v > 2147483647) c.fail(d, what + " must be from 1 to 2147483647, got " + d.fields[i]);
  return v;
}
Index integer(const Card& c, const DataLine& d, size_t i, const std::string& what) {
  if (i >= d.fields.size() || !is_integer(d.fields[i]))
    c.fail(d, "expected an integer for " + what + (i < d.fields.size() ? ", got '" + d.fields[i] + "'" : ""));
  errno = 0;
  const long long v = std::strtoll(d.fields[i].c_str(), nullptr, 10);
  if (errno == ERANGE) c.fail(d, what + " '" + d.fields[i] + "' is out of range");
  return static_cast<Index>(v);
}

// ---------------------------------------------------------------- lexing
struct Lexer {
  std::vector<Card> cards;
  std::vector<std::unique_ptr<std::string>> files;  // stable storage for file names

  void read(const std::string& path, const std::string& from_where, int depth) {
    if (depth > 16) throw InputError(from_where, "*INCLUDE", "*INCLUDE nested more than 16 deep (an include cycle?)");
    std::error_code ec;
    std::ifstream in(path, std::ios::binary);
    if (!in || !fs::is_regular_file(path, ec))
      throw InputError(from_where.empty() ? path : from_where, from_where.empty() ? "" : "*INCLUDE",
                       from_where.empty() ? "cannot open the file" : "cannot open '" + path + "'");
    files.push_back(std::make_unique<std::string>(path));
    const std::string* file = files.back().get();
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.find('\0') != std::string::npos)
        throw InputError(*file + ":" + std::to_string(n), "", "binary data in an .inp file");
      const std::string t = trim(line);
      if (t.empty() || t.rfind("**", 0) == 0) continue;
      if (t[0] == '*') {
        Card c;
        c.file = file;
        c.line = n;
        std::vector<std::string> f = split(t.substr(1));
        std::string kw;
        for (char ch : upper(f[0]))
          if (!(ch == ' ' && (kw.empty() || kw.back() == ' '))) kw += ch;
        c.keyword = trim(kw);
        if (c.keyword.empty()) throw InputError(c.where(), "", "a keyword line without a keyword");
        for (size_t i = 1; i < f.size(); ++i) {
          if (f[i].empty()) continue;
          const size_t eq = f[i].find('=');
          std::string k = upper(trim(f[i].substr(0, eq)));
          std::string collapsed;
          for (char ch : k)
            if (!(ch == ' ' && (collapsed.empty() || collapsed.back() == ' '))) collapsed += ch;
          c.params.emplace_back(collapsed, eq == std::string::npos ? "" : trim(f[i].substr(eq + 1)));
        }
        if (c.keyword == "INCLUDE") {
          std::string inc = c.raw("INPUT");
          if (!inc.empty() && inc.front() == '"' && inc.back() == '"' && inc.size() >= 2) inc = inc.substr(1, inc.size() - 2);
          if (inc.empty()) c.fail("needs INPUT=<file>");
          fs::path p(inc);
          std::error_code ec;
          if (p.is_relative()) {
            const fs::path here = fs::path(path).parent_path() / p;
            if (fs::exists(here, ec) || !fs::exists(p, ec)) p = here;
          }
          if (!fs::is_regular_file(p, ec)) c.fail("'" + p.string() + "' is not a readable file");
          read(p.string(), c.where(), depth + 1);
          continue;
        }
        cards.push_back(std::move(c));
      } else {
        if (cards.empty()) throw InputError(*file + ":" + std::to_string(n), "", "a data line before any *KEYWORD line");
        cards.back().data.push_back({file, n, split(t)});
      }
    }
  }
};

// ---------------------------------------------------------------- element types
struct InpElement {
  ElementType type;
  std::string dimension;  // plane_strain, plane_stress, axisymmetric, 3d
  std::vector<int> order; // our local node k is the .inp node order[k]
};

std::optional<InpElement> inp_element(const std::string& name, std::string* note) {
  std::string base = name;
  if (base.size() > 1 && (base.back() == 'R' || base.back() == 'I' || base.back() == 'H')) {
    *note = name + ": integrated as " + base.substr(0, base.size() - 1) +
            " (Signorini's full integration; no reduced integration, incompatible modes or hybrid pressure)";
    base.pop_back();
  }
  std::string dim;
  std::string shape;
  if (base.rfind("CPE", 0) == 0) dim = "plane_strain", shape = base.substr(3);
  else if (base.rfind("CPS", 0) == 0) dim = "plane_stress", shape = base.substr(3);
  else if (base.rfind("CAX", 0) == 0) dim = "axisymmetric", shape = base.substr(3);
  else if (base.rfind("C3D", 0) == 0) dim = "3d", shape = base.substr(3);
  else return std::nullopt;
  const bool two = dim != "3d";
  using T = ElementType;
  if (two && shape == "3") return InpElement{T::tri3, dim, {0, 1, 2}};
  if (two && shape == "6") return InpElement{T::tri6, dim, {0, 1, 2, 3, 4, 5}};
  if (two && shape == "4") return InpElement{T::quad4, dim, {0, 1, 2, 3}};
  if (two && shape == "8") return InpElement{T::quad8, dim, {0, 1, 2, 3, 4, 5, 6, 7}};
  if (!two && shape == "4") return InpElement{T::tet4, dim, {0, 1, 2, 3}};
  // Abaqus C3D10 mid-edge nodes: 12 23 31 14 24 34; ours (Gmsh): 01 12 20 30 32 31.
  if (!two && shape == "10") return InpElement{T::tet10, dim, {0, 1, 2, 3, 4, 5, 6, 7, 9, 8}};
  if (!two && shape == "8") return InpElement{T::hex8, dim, {0, 1, 2, 3, 4, 5, 6, 7}};
  // Abaqus C3D20 mid-edge nodes: 12 23 34 41 56 67 78 85 15 26 37 48;
  // ours (Gmsh): 01 03 04 12 15 23 26 37 45 47 56 67.
  if (!two && shape == "20")
    return InpElement{T::hex20, dim, {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 16, 9, 17, 10, 18, 19, 12, 15, 13, 14}};
  return std::nullopt;
}

// Corner nodes (our local numbering = the .inp's for corners) of face S<k> (1-based).
std::vector<int> face_corners(ElementType t, int k) {
  static const std::vector<std::vector<int>> tri{{0, 1}, {1, 2}, {2, 0}};
  static const std::vector<std::vector<int>> quad{{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  static const std::vector<std::vector<int>> tet{{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  static const std::vector<std::vector<int>> hex{{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                                                 {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
  const std::vector<std::vector<int>>* f = nullptr;
  switch (t) {
    case ElementType::tri3: case ElementType::tri6: f = &tri; break;
    case ElementType::quad4: case ElementType::quad8: f = &quad; break;
    case ElementType::tet4: case ElementType::tet10: f = &tet; break;
    case ElementType::hex8: case ElementType::hex20: f = &hex; break;
    default: return {};
  }
  return k >= 1 && k <= static_cast<int>(f->size()) ? (*f)[k - 1] : std::vector<int>{};
}

// The catalogue facet of `t` with these corners.
const Facet* facet_with_corners(ElementType t, std::vector<int> corners) {
  std::sort(corners.begin(), corners.end());
  for (const Facet& f : element_info(t).facets) {
    const int nc = element_info(f.type).num_corners;
    std::vector<int> c(f.nodes.begin(), f.nodes.begin() + nc);
    std::sort(c.begin(), c.end());
    if (c == corners) return &f;
  }
  return nullptr;
}

// ---------------------------------------------------------------- the model
struct Material {
  std::string where;
  bool elastic = false, hyper = false, plastic = false, kinematic = false, density = false;
  Real E = 0, nu = 0, C10 = 0, D1 = 0, rho = 0;
  std::vector<std::pair<Real, Real>> table;  // (strain, stress) of *PLASTIC
  std::string plastic_where, elastic_where;  // the data's cards, for messages
};
struct Section {
  std::string elset, material, where;
  std::optional<Real> thickness;
};
struct Interaction {
  std::string where, behavior = "HARD", behavior_where;
  Real K = 0;
  Real mu = 0, stick = 0;
  std::string friction_where;
};
struct Pair {
  std::string interaction, type, slave, master, where;
};
struct Surface {
  bool nodes = false;
  std::vector<std::pair<std::string, std::string>> items;  // (element or node set / id, face or "")
  std::string where;
  std::vector<std::pair<const Card*, size_t>> lines;  // the card and data line of each item
};
struct Valued {
  Vec3 v = Vec3::Zero();
  Real s = 0;
  std::string where;
};
struct StepState {
  std::map<std::pair<std::string, int>, Valued> bc;  // (node set, component) -> value
  std::map<std::string, Valued> cload;                // node set -> total force
  std::map<std::string, Valued> dload;                // facet set -> pressure
  std::map<std::string, Valued> body;                 // body (section elset) -> force per volume
};
struct StepOut {
  std::string name, where;
  Real initial = 1, min = 1e-5, max = 1;
  std::optional<Index> max_count;
  StepState state;
};

using OriginLines = std::vector<std::string>;

class Translator {
 public:
  explicit Translator(const std::string& path) : path_(path) {}

  void run(bool deck) {
    Lexer lx;
    lx.read(path_, "", 0);
    cards_ = std::move(lx.cards);
    files_ = std::move(lx.files);
    for (const Card& c : cards_) card(c, deck);
    if (in_step_) throw InputError(step_card_->where(), "*STEP", "the step is not closed by *END STEP");
    build_mesh(deck);
  }

  Mesh mesh;
  std::string yaml;
  std::vector<std::string> origin;

  void translate();

 private:
  std::string path_;
  std::vector<Card> cards_;
  std::vector<std::unique_ptr<std::string>> files_;
  // nodes and elements as read (ids), resolved in build_mesh
  std::vector<Index> node_id_;
  std::vector<Vec3> xyz_;
  std::unordered_map<Index, Index> node_of_;
  std::vector<ElementType> etype_;
  std::vector<Index> eid_, eoff_{0}, econn_ids_;
  std::vector<std::pair<const Card*, int>> eline_;  // card and data line index, for messages
  std::unordered_map<Index, Index> elem_of_;
  std::map<std::string, std::vector<Index>> nset_ids_, elset_ids_;
  std::map<std::string, std::string> nset_where_, elset_where_;
  std::map<std::string, Surface> surfaces_;
  std::string dimension_, dimension_where_;
  std::set<std::string> element_notes_;
  std::map<std::string, Material> materials_;
  Material* mat_ = nullptr;
  std::vector<Section> sections_;
  std::map<std::string, Interaction> interactions_;
  Interaction* inter_ = nullptr;
  std::vector<Pair> pairs_;
  std::vector<StepOut> steps_;
  StepState state_;
  bool in_step_ = false;
  const Card* step_card_ = nullptr;
  bool step_has_procedure_ = false;
  bool nlgeom_any_ = false, nlgeom_all_ = true;
  bool file_output_ = false;
  std::string title_;
  std::set<std::string> noticed_;
  std::vector<std::string> deferred_;  // messages of ignored settings, printed once translated
  // exterior facets (built on first use)
  std::vector<std::pair<Index, const Facet*>> exterior_;
  bool exterior_built_ = false;
  std::vector<std::vector<Index>> elem_nodes_cache_;

  // One line per kind of notice (`kind`), at its first occurrence.
  void notice(const Card& c, const std::string& text, const std::string& kind = "") {
    if (noticed_.insert(kind.empty() ? c.keyword + text : kind).second) log::info("{}: *{}: {}", c.where(), c.keyword, text);
  }
  void card(const Card& c, bool deck);
  void mesh_card(const Card& c);
  void step_card(const Card& c);
  void model_card(const Card& c);
  std::vector<Index> set_members(const Card& c, bool nodes);
  // CalculiX's predefined sets, NALL (every node) and EALL (every element), made when first
  // named (unless the deck defines them).
  void implicit_set(const std::string& name) {
    if (name == "NALL" && !nset_ids_.count(name)) {
      auto& v = nset_ids_[name] = node_id_;
      std::sort(v.begin(), v.end());
    }
    if (name == "EALL" && !elset_ids_.count(name)) {
      auto& v = elset_ids_[name] = eid_;
      std::sort(v.begin(), v.end());
    }
  }
  // Node set name for a data line's first field (a set name or a node id).
  std::string node_target(const Card& c, const DataLine& d);
  std::vector<Index> element_nodes(Index e) const;
  void build_exterior();
  std::vector<Index> elements_of(const std::string& elset_or_id, const Card& c, const DataLine& d);
  void add_facets(const std::string& set, const std::vector<Index>& elems, int face, const Card& c, const DataLine& d);
  void build_mesh(bool deck);
  std::string facet_set_for_dload(const Card& c, const DataLine& d, int face);
  const Section* section_of(const std::string& elset) const {
    for (auto& s : sections_)
      if (s.elset == elset) return &s;
    return nullptr;
  }
};

void Translator::card(const Card& c, bool deck) {
  const std::string& k = c.keyword;
  if (k != "ELASTIC" && k != "PLASTIC" && k != "HYPERELASTIC" && k != "DENSITY" && k != "EXPANSION" &&
      k != "CONDUCTIVITY" && k != "SPECIFIC HEAT")
    mat_ = nullptr;
  if (k != "SURFACE BEHAVIOR" && k != "FRICTION") inter_ = nullptr;
  static const std::set<std::string> mesh_keys{"NODE", "ELEMENT", "NSET", "ELSET", "SURFACE"};
  static const std::set<std::string> output_keys{
      "NODE FILE", "EL FILE", "ELEMENT FILE", "CONTACT FILE", "NODE PRINT", "EL PRINT", "ELEMENT PRINT",
      "CONTACT PRINT", "NODE OUTPUT", "ELEMENT OUTPUT", "CONTACT OUTPUT", "OUTPUT", "SECTION PRINT",
      "RESTART", "FILE FORMAT", "MONITOR", "PREPRINT", "ENERGY PRINT"};
  if (mesh_keys.count(k)) {
    if (in_step_) c.fail("mesh and set definitions belong before the first *STEP");
    mesh_card(c);
    return;
  }
  if (output_keys.count(k)) {
    if (k == "NODE FILE" || k == "EL FILE" || k == "ELEMENT FILE" || k == "CONTACT FILE" || k == "NODE OUTPUT" ||
        k == "ELEMENT OUTPUT" || k == "CONTACT OUTPUT" || k == "OUTPUT")
      file_output_ = true;
    if (deck)
      notice(c, "output requests (this one and the others) are mapped to Signorini's outputs: displacement, stress "
                "and contact fields in ParaView files, reaction totals per boundary node set in reactions.csv, a "
                "contact table per pair and increment",
             "output");
    return;
  }
  if (!deck) return;  // the mesh alone
  if (in_step_ || k == "STEP") step_card(c);
  else model_card(c);
}

std::vector<Index> Translator::set_members(const Card& c, bool nodes) {
  auto& sets = nodes ? nset_ids_ : elset_ids_;
  std::vector<Index> out;
  const bool generate = c.has("GENERATE");
  for (const DataLine& d : c.data) {
    if (generate) {
      const Index a = id_number(c, d, 0, "the first id"), b = id_number(c, d, 1, "the last id");
      const Index inc = d.fields.size() > 2 && !d.fields[2].empty() ? integer(c, d, 2, "the increment") : 1;
      if (inc <= 0 || b < a) c.fail(d, "GENERATE needs first <= last and a positive increment");
      if ((b - a) / inc > 100000000) c.fail(d, "GENERATE range too large");
      for (Index i = a; i <= b; i += inc) out.push_back(i);
      continue;
    }
    for (const std::string& f : d.fields) {
      if (f.empty()) continue;
      if (is_integer(f)) {
        out.push_back(id_number(c, DataLine{d.file, d.line, {f}}, 0, nodes ? "a node id" : "an element id"));
      } else {
        implicit_set(upper(f));
        auto it = sets.find(upper(f));
        if (it == sets.end()) c.fail(d, std::string("no ") + (nodes ? "node" : "element") + " set named '" + upper(f) + "' (defined so far)");
        out.insert(out.end(), it->second.begin(), it->second.end());
      }
    }
  }
  return out;
}

void Translator::mesh_card(const Card& c) {
  const std::string& k = c.keyword;
  if (k == "NODE") {
    c.allow({"NSET", "SYSTEM"});
    if (c.has("SYSTEM") && upper(c.raw("SYSTEM")) != "R") c.fail("only rectangular coordinates (SYSTEM=R) are read");
    const std::string nset = c.has("NSET") ? c.name("NSET") : "";
    for (const DataLine& d : c.data) {
      const Index id = id_number(c, d, 0, "the node id");
      if (d.fields.size() < 3) c.fail(d, "a node line is: id, x, y[, z]");
      if (d.fields.size() > 4) c.fail(d, "a node line is: id, x, y[, z] (got " + std::to_string(d.fields.size()) + " fields)");
      Vec3 x = Vec3::Zero();
      for (size_t i = 1; i < d.fields.size(); ++i) x(i - 1) = number_or(c, d, i, "coordinate " + std::string(1, "xyz"[i - 1]), 0);
      if (!node_of_.emplace(id, static_cast<Index>(node_id_.size())).second) c.fail(d, "node " + std::to_string(id) + " is defined twice");
      node_id_.push_back(id);
      xyz_.push_back(x);
      if (!nset.empty()) nset_ids_[nset].push_back(id);
    }
    if (!nset.empty()) nset_where_.emplace(nset, c.where());
  } else if (k == "ELEMENT") {
    c.allow({"TYPE", "ELSET"});
    const std::string tname = c.name("TYPE");
    std::string note;
    auto et = inp_element(tname, &note);
    if (!et)
      c.fail("element type " + tname + " is not available (Signorini reads CPE3/4/6/8, CPS3/4/6/8, CAX3/4/6/8, "
             "C3D4, C3D8, C3D10, C3D20, with R/I/H suffixes integrated fully)");
    if (!note.empty() && element_notes_.insert(tname).second) log::info("{}: *ELEMENT: {}", c.where(), note);
    if (dimension_.empty()) dimension_ = et->dimension, dimension_where_ = c.where();
    else if (dimension_ != et->dimension)
      c.fail("element type " + tname + " makes a " + et->dimension + " model, but the elements at " + dimension_where_ +
             " make it " + dimension_ + ": Signorini solves one kind of analysis at a time");
    const std::string elset = c.has("ELSET") ? c.name("ELSET") : "";
    const int nn = element_info(et->type).num_nodes;
    std::vector<std::string> fields;
    for (size_t i = 0; i < c.data.size(); ++i) {
      const DataLine& d = c.data[i];
      fields.insert(fields.end(), d.fields.begin(), d.fields.end());
      if (static_cast<int>(fields.size()) < nn + 1) continue;  // continued on the next line
      if (static_cast<int>(fields.size()) > nn + 1)
        c.fail(d, fmt::format("{} has {} nodes, this element line has {}", tname, nn, fields.size() - 1));
      DataLine all{d.file, d.line, fields};
      const Index id = id_number(c, all, 0, "the element id");
      if (!elem_of_.emplace(id, static_cast<Index>(eid_.size())).second) c.fail(d, "element " + std::to_string(id) + " is defined twice");
      std::vector<Index> ids(nn);
      for (int j = 0; j < nn; ++j) ids[j] = id_number(c, all, j + 1, "node " + std::to_string(j + 1));
      for (int j = 0; j < nn; ++j) econn_ids_.push_back(ids[et->order[j]]);
      eoff_.push_back(static_cast<Index>(econn_ids_.size()));
      etype_.push_back(et->type);
      eid_.push_back(id);
      eline_.emplace_back(&c, static_cast<int>(i));
      if (!elset.empty()) elset_ids_[elset].push_back(id);
      fields.clear();
    }
    if (!fields.empty()) c.fail(c.data.back(), fmt::format("the last element line is incomplete ({} has {} nodes)", tname, nn));
    if (!elset.empty()) elset_where_.emplace(elset, c.where());
  } else if (k == "NSET" || k == "ELSET") {
    const bool nodes = k == "NSET";
    c.allow({nodes ? "NSET" : "ELSET", "GENERATE", "INTERNAL"});
    const std::string name = c.name(nodes ? "NSET" : "ELSET");
    std::vector<Index> m = set_members(c, nodes);
    auto& v = (nodes ? nset_ids_ : elset_ids_)[name];
    v.insert(v.end(), m.begin(), m.end());
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    (nodes ? nset_where_ : elset_where_).emplace(name, c.where());
  } else if (k == "SURFACE") {
    c.allow({"NAME", "TYPE", "INTERNAL"});
    const std::string name = c.name("NAME");
    const std::string type = c.name("TYPE", std::string("ELEMENT"));
    if (type != "ELEMENT" && type != "NODE") c.fail("TYPE=" + type + " is not available (ELEMENT or NODE)");
    Surface& s = surfaces_[name];
    if (!s.items.empty() && s.nodes != (type == "NODE")) c.fail("surface " + name + " was defined with another TYPE");
    s.nodes = type == "NODE";
    s.where = c.where();
    for (size_t i = 0; i < c.data.size(); ++i) {
      const DataLine& d = c.data[i];
      if (d.fields.empty() || d.fields[0].empty()) c.fail(d, "expected an element (or node) set or id");
      std::string face = d.fields.size() > 1 ? upper(d.fields[1]) : "";
      if (s.nodes) face.clear();  // a node surface's second field is a weight
      s.items.emplace_back(d.fields[0], face);
      s.lines.emplace_back(&c, i);
    }
  }
}

void Translator::model_card(const Card& c) {
  const std::string& k = c.keyword;
  if (k == "HEADING") {
    if (!c.data.empty()) {
      std::string t;
      for (auto& f : c.data[0].fields) t += (t.empty() ? "" : ", ") + f;
      title_ = t;
    }
  } else if (k == "MATERIAL") {
    c.allow({"NAME"});
    const std::string name = c.name("NAME");
    if (materials_.count(name)) c.fail("material " + name + " is defined twice");
    mat_ = &materials_[name];
    mat_->where = c.where();
  } else if (k == "ELASTIC" || k == "PLASTIC" || k == "HYPERELASTIC" || k == "DENSITY") {
    if (!mat_) c.fail("belongs after a *MATERIAL card");
    if (c.data.empty()) c.fail("needs a data line");
    const DataLine& d = c.data[0];
    if (k == "ELASTIC") {
      c.allow({"TYPE"});
      const std::string type = c.name("TYPE", std::string("ISO"));
      if (type != "ISO" && type != "ISOTROPIC")
        c.fail("TYPE=" + type + " is not available: Signorini's elasticity is isotropic");
      if (c.data.size() > 1) c.fail(c.data[1], "temperature-dependent elasticity is not available (one data line: E, nu)");
      mat_->elastic = true;
      mat_->elastic_where = c.where();
      mat_->E = number(c, d, 0, "Young's modulus");
      mat_->nu = number(c, d, 1, "Poisson's ratio");
      if (d.fields.size() > 2 && !d.fields[2].empty()) c.fail(d, "temperature-dependent elasticity is not available (E, nu)");
    } else if (k == "PLASTIC") {
      c.allow({"HARDENING"});
      const std::string h = c.name("HARDENING", std::string("ISOTROPIC"));
      if (h != "ISOTROPIC" && h != "KINEMATIC") c.fail("HARDENING=" + h + " is not available (ISOTROPIC or KINEMATIC)");
      mat_->plastic = true;
      mat_->kinematic = h == "KINEMATIC";
      mat_->plastic_where = c.where();
      for (const DataLine& l : c.data) {
        if (l.fields.size() > 2 && !l.fields[2].empty()) c.fail(l, "temperature-dependent plasticity is not available");
        mat_->table.emplace_back(number_or(c, l, 1, "the plastic strain", 0), number(c, l, 0, "the yield stress"));
      }
    } else if (k == "HYPERELASTIC") {
      c.allow({"NEO HOOKE"});
      if (!c.has("NEO HOOKE")) c.fail("only the NEO HOOKE model is available (parameters: NEO HOOKE)");
      mat_->hyper = true;
      mat_->elastic_where = c.where();
      mat_->C10 = number(c, d, 0, "C10");
      mat_->D1 = number(c, d, 1, "D1");
    } else {
      mat_->density = true;
      mat_->rho = number(c, d, 0, "the density");
    }
  } else if (k == "EXPANSION" || k == "CONDUCTIVITY" || k == "SPECIFIC HEAT") {
    notice(c, "ignored: Signorini's analyses are isothermal");
  } else if (k == "SOLID SECTION") {
    c.allow({"ELSET", "MATERIAL"});
    Section s{c.name("ELSET"), c.name("MATERIAL"), c.where(), std::nullopt};
    if (!c.data.empty() && !c.data[0].fields.empty() && !c.data[0].fields[0].empty())
      s.thickness = number(c, c.data[0], 0, "the thickness");
    if (s.thickness && !(*s.thickness > 0)) c.fail(c.data[0], "the thickness must be positive");
    if (section_of(s.elset)) c.fail("element set " + s.elset + " has two sections");
    sections_.push_back(s);
  } else if (k == "SURFACE INTERACTION") {
    c.allow({"NAME"});
    const std::string name = c.name("NAME");
    inter_ = &interactions_[name];
    inter_->where = c.where();
  } else if (k == "SURFACE BEHAVIOR") {
    if (!inter_) c.fail("belongs after a *SURFACE INTERACTION card");
    c.allow({"PRESSURE-OVERCLOSURE"});
    const std::string b = c.name("PRESSURE-OVERCLOSURE", std::string("HARD"));
    inter_->behavior_where = c.where();
    if (b == "HARD") {
      inter_->behavior = b;
    } else if (b == "LINEAR") {
      inter_->behavior = b;
      if (c.data.empty()) c.fail("LINEAR needs a data line: the slope K (pressure per unit overclosure)");
      inter_->K = number(c, c.data[0], 0, "the slope K");
      if (!(inter_->K > 0)) c.fail(c.data[0], "the slope K must be positive");
      const DataLine& d = c.data[0];
      if (number_or(c, d, 1, "sigma_inf", 0) != 0 || number_or(c, d, 2, "c0", 0) != 0)
        notice(c, "sigma_inf and c0 are ignored: Signorini's penalty is p = K <-g>, without tension at clearance");
    } else {
      c.fail("PRESSURE-OVERCLOSURE=" + b + " is not available: HARD (exact, Lagrange multipliers) or LINEAR "
             "(penalty with slope K)");
    }
  } else if (k == "FRICTION") {
    if (!inter_) c.fail("belongs after a *SURFACE INTERACTION card");
    c.allow({});
    if (c.data.empty()) c.fail("needs a data line: mu[, stick slope]");
    inter_->mu = number(c, c.data[0], 0, "the friction coefficient");
    if (inter_->mu < 0) c.fail(c.data[0], "the friction coefficient must not be negative");
    inter_->stick = number_or(c, c.data[0], 1, "the stick slope", 0);
    if (inter_->stick < 0) c.fail(c.data[0], "the stick slope must not be negative");
    inter_->friction_where = c.where();
  } else if (k == "CONTACT PAIR") {
    c.allow({"INTERACTION", "TYPE", "SMALL SLIDING", "ADJUST"});
    const std::string type = c.name("TYPE", std::string("NODE TO SURFACE"));
    if (type != "NODE TO SURFACE" && type != "SURFACE TO SURFACE" && type != "MORTAR" && type != "LINMORTAR" &&
        type != "PGMORTAR" && type != "PGLINMORTAR")
      c.fail("TYPE=" + type + " is not available (NODE TO SURFACE, SURFACE TO SURFACE, MORTAR)");
    if (c.has("SMALL SLIDING")) notice(c, "SMALL SLIDING ignored: Signorini searches for contact at every increment");
    if (c.has("ADJUST")) notice(c, "ADJUST ignored: slave nodes are not moved onto the master at the start");
    const std::string inter = c.name("INTERACTION");
    if (c.data.empty()) c.fail("needs a data line: slave surface, master surface");
    for (const DataLine& d : c.data) {
      if (d.fields.size() != 2 || d.fields[0].empty() || d.fields[1].empty())
        c.fail(d, "a contact pair line is: slave surface, master surface");
      pairs_.push_back({inter, type, upper(d.fields[0]), upper(d.fields[1]), d.where()});
    }
  } else if (k == "BOUNDARY") {
    step_card(c);
  } else if (k == "AMPLITUDE" || k == "ORIENTATION") {
    notice(c, "accepted but not used: referring to it (AMPLITUDE=, ORIENTATION=) is not available");
  } else if (k == "CONTROLS") {
    notice(c, "Signorini's own controls apply (increment cutback and Newton settings: solver and increments keys)");
  } else {
    c.fail("keyword *" + k + " is not available in Signorini's .inp reader (see docs/deck.md, \"CalculiX and Abaqus "
           "decks\", for the keywords it reads)");
  }
}

std::string Translator::node_target(const Card& c, const DataLine& d) {
  const std::string f = d.fields.empty() ? "" : d.fields[0];
  if (f.empty()) c.fail(d, "expected a node set or a node id");
  if (is_integer(f)) {
    const Index id = integer(c, d, 0, "the node id");
    if (!node_of_.count(id)) c.fail(d, "node " + f + " is not defined");
    const std::string name = "node:" + f;
    nset_ids_[name] = {id};
    nset_where_.emplace(name, d.where());
    return name;
  }
  const std::string name = upper(f);
  implicit_set(name);
  if (!nset_ids_.count(name)) {
    std::string known;
    for (auto& [n, v] : nset_ids_)
      if (n.rfind("node:", 0) != 0) known += (known.empty() ? "" : ", ") + n;
    c.fail(d, "no node set named '" + name + "' (node sets: " + (known.empty() ? "none" : known) + ")");
  }
  return name;
}

void Translator::step_card(const Card& c) {
  const std::string& k = c.keyword;
  const int dim = dimension_ == "3d" ? 3 : 2;
  if (k == "STEP") {
    if (in_step_) c.fail("a *STEP inside a step (close the previous one with *END STEP)");
    c.allow({"NLGEOM", "INC", "NAME", "AMPLITUDE", "INCF", "THERMAL NETWORK", "SOLVER", "PERTURBATION"});
    if (c.has("PERTURBATION")) c.fail("PERTURBATION steps are not available");
    if (c.has("AMPLITUDE") && upper(c.raw("AMPLITUDE")) != "RAMP")
      c.fail("AMPLITUDE=" + upper(c.raw("AMPLITUDE")) + ": loads ramp linearly over the step in Signorini");
    const bool nl = c.has("NLGEOM") && upper(c.raw("NLGEOM")) != "NO";
    nlgeom_any_ = nlgeom_any_ || nl;
    nlgeom_all_ = nlgeom_all_ && nl;
    in_step_ = true;
    step_card_ = &c;
    step_has_procedure_ = false;
    StepOut s;
    s.where = c.where();
    s.name = c.has("NAME") ? trim(c.raw("NAME")) : "step" + std::to_string(steps_.size() + 1);
    if (c.has("INC")) {
      const Index n = integer(c, DataLine{c.file, c.line, {trim(c.raw("INC"))}}, 0, "INC");
      if (n < 1) c.fail("INC must be positive");
      s.max_count = n;
    }
    steps_.push_back(s);
    if (c.has("SOLVER")) notice(c, "SOLVER ignored: Signorini chooses its linear solver (solver.linear)");
    return;
  }
  if (k == "STATIC") {
    c.allow({"DIRECT", "SOLVER", "TIME RESET", "TOTAL TIME AT START"});
    if (step_has_procedure_) c.fail("a step has one procedure");
    step_has_procedure_ = true;
    StepOut& s = steps_.back();
    if (!c.data.empty()) {
      const DataLine& d = c.data[0];
      const Real dt0 = number_or(c, d, 0, "the initial increment", 1), T = number_or(c, d, 1, "the step time", 1);
      if (!(T > 0)) c.fail(d, "the step time must be positive");
      if (!(dt0 > 0)) c.fail(d, "the initial increment must be positive");
      const Real dtmin = number_or(c, d, 2, "the minimum increment", 0), dtmax = number_or(c, d, 3, "the maximum increment", 0);
      s.max = dtmax > 0 ? std::min(1.0, dtmax / T) : 1.0;
      s.initial = std::min(dt0 / T, s.max);
      s.min = dtmin > 0 ? std::min(dtmin / T, s.initial) : std::min(1e-5, s.initial);
      if (c.has("DIRECT")) s.min = s.max = s.initial;
    }
    return;
  }
  if (k == "BOUNDARY" || k == "CLOAD" || k == "DLOAD") {
    c.allow({"OP", "AMPLITUDE", "FIXED", "TYPE"});
    if (c.has("AMPLITUDE")) c.fail("AMPLITUDE= is not available: values ramp linearly over the step");
    if (c.has("FIXED")) c.fail("FIXED is not available: give the value");
    if (c.has("TYPE") && upper(c.raw("TYPE")) != "DISPLACEMENT") c.fail("TYPE=" + upper(c.raw("TYPE")) + " is not available");
    const std::string op = c.name("OP", std::string("MOD"));
    if (op != "MOD" && op != "NEW") c.fail("OP=" + op + ": expected MOD or NEW");
    if (!in_step_ && k != "BOUNDARY") c.fail("loads belong in a *STEP");
    if (!in_step_ && op == "NEW") c.fail("OP=NEW belongs in a step");
    if (dimension_.empty()) c.fail("comes before any *ELEMENT: the model's dimension is not known yet");
    if (k == "BOUNDARY") {
      if (op == "NEW") state_.bc.clear();
      for (const DataLine& d : c.data) {
        const std::string set = node_target(c, d);
        // Abaqus' named conditions: their translational part (nodes have no rotations).
        const std::string named = d.fields.size() > 1 ? upper(d.fields[1]) : "";
        if (named == "ENCASTRE" || named == "PINNED" || named == "XSYMM" || named == "YSYMM" || named == "ZSYMM") {
          if (d.fields.size() > 2) c.fail(d, named + " takes no further values");
          const int only = named == "XSYMM" ? 0 : named == "YSYMM" ? 1 : named == "ZSYMM" ? 2 : -1;
          if (only >= dim) c.fail(d, named + " has no meaning in a 2D model");
          for (int comp = 0; comp < dim; ++comp)
            if (only < 0 || comp == only) state_.bc[{set, comp}] = Valued{Vec3::Zero(), 0, d.where()};
          continue;
        }
        if (!named.empty() && !is_integer(named))
          c.fail(d, "expected a degree of freedom or ENCASTRE, PINNED, XSYMM, YSYMM, ZSYMM; got '" + d.fields[1] + "'");
        const Index first = integer(c, d, 1, "the first degree of freedom");
        const Index last = d.fields.size() > 2 && !d.fields[2].empty() ? integer(c, d, 2, "the last degree of freedom") : first;
        const Real value = number_or(c, d, 3, "the value", 0);
        if (first < 1 || last < first) c.fail(d, "degrees of freedom are first <= last, from 1");
        for (Index dof = first; dof <= last; ++dof) {
          if (dof > 3) c.fail(d, fmt::format("degree of freedom {} is not available: Signorini's nodes have "
                                             "displacements 1 to {} only (no rotations, temperatures)", dof, dim));
          if (dof > dim) {
            notice(c, "degree of freedom 3 of a 2D model ignored (no out-of-plane displacement)");
            continue;
          }
          state_.bc[{set, static_cast<int>(dof - 1)}] = Valued{Vec3::Zero(), value, d.where()};
        }
      }
    } else if (k == "CLOAD") {
      if (op == "NEW") state_.cload.clear();
      if (dimension_ == "axisymmetric")
        c.fail("concentrated loads on axisymmetric elements are not read (Abaqus gives them for the whole circle, "
               "CalculiX for its segment): use a *DLOAD pressure or a YAML deck (docs/deck.md)");
      for (const DataLine& d : c.data) {
        const std::string set = node_target(c, d);
        const Index dof = integer(c, d, 1, "the degree of freedom");
        const Real v = number(c, d, 2, "the magnitude");
        if (dof < 1 || dof > dim) c.fail(d, fmt::format("degree of freedom {} is not a force component of this {}D model", dof, dim));
        std::set<Index> members(nset_ids_[set].begin(), nset_ids_[set].end());
        Valued& val = state_.cload[set];
        val.v(dof - 1) = v * static_cast<Real>(members.size());  // a *CLOAD acts on every node of the set
        val.where = d.where();
      }
    } else {
      if (op == "NEW") state_.dload.clear(), state_.body.clear();
      for (const DataLine& d : c.data) {
        if (d.fields.size() < 3) c.fail(d, "a distributed load line is: element set or id, load type, magnitude");
        const std::string type = upper(d.fields[1]);
        const Real mag = number(c, d, 2, "the magnitude");
        if (type.size() == 2 && type[0] == 'P' && std::isdigit(static_cast<unsigned char>(type[1]))) {
          const std::string set = facet_set_for_dload(c, d, type[1] - '0');
          state_.dload[set] = Valued{Vec3::Zero(), mag, d.where()};
        } else if (type == "GRAV" || type == "BX" || type == "BY" || type == "BZ") {
          const std::string elset = upper(d.fields[0]);
          std::vector<const Section*> targets;
          for (auto& s : sections_)
            if (elset == "EALL" || s.elset == elset) targets.push_back(&s);
          if (targets.empty()) c.fail(d, "a body load applies to a *SOLID SECTION's element set (or EALL)");
          for (const Section* s : targets) {
            Valued& b = state_.body[s->elset];
            b.where = d.where();
            if (type == "GRAV") {
              Vec3 dir = Vec3::Zero();
              for (int i = 0; i < 3; ++i) dir(i) = number_or(c, d, 3 + i, "the direction", 0);
              if (!(dir.norm() > 0)) c.fail(d, "GRAV needs a direction (g, nx, ny, nz)");
              auto mit = materials_.find(s->material);
              if (mit == materials_.end() || !mit->second.density)
                c.fail(d, "GRAV needs the *DENSITY of material " + s->material);
              b.v = mit->second.rho * mag * dir.normalized();
            } else {
              const int comp = type[1] - 'X';
              if (comp >= dim) c.fail(d, type + " is not a component of this 2D model");
              b.v(comp) = mag;
            }
          }
        } else {
          c.fail(d, "load type " + type + " is not available (P1..P6 pressure on element faces, GRAV, BX, BY, BZ)");
        }
      }
    }
    return;
  }
  if (k == "END STEP") {
    if (!step_has_procedure_) step_card_->fail("the step has no procedure: Signorini solves *STATIC steps");
    steps_.back().state = state_;
    in_step_ = false;
    return;
  }
  if (k == "CONTROLS") {
    notice(c, "Signorini's own controls apply (increment cutback and Newton settings: solver and increments keys)");
    return;
  }
  if (k == "DYNAMIC" || k == "FREQUENCY" || k == "BUCKLE" || k == "HEAT TRANSFER" || k == "VISCO" ||
      k == "COUPLED TEMPERATURE-DISPLACEMENT" || k == "MODAL DYNAMIC" || k == "STEADY STATE DYNAMICS")
    c.fail("the procedure *" + k + " is not available: Signorini solves *STATIC steps");
  c.fail("keyword *" + k + " is not available inside a step in Signorini's .inp reader (see docs/deck.md, "
         "\"CalculiX and Abaqus decks\")");
}

std::vector<Index> Translator::element_nodes(Index e) const {
  std::vector<Index> out;
  for (Index i = eoff_[e]; i < eoff_[e + 1]; ++i) out.push_back(node_of_.at(econn_ids_[i]));
  return out;
}

void Translator::build_exterior() {
  if (exterior_built_) return;
  exterior_built_ = true;
  // Facets keyed by their sorted corner nodes; those of one cell only are exterior.
  struct KeyHash {
    size_t operator()(const std::array<Index, 4>& k) const {
      size_t h = 1469598103934665603ull;
      for (Index v : k) h = (h ^ static_cast<size_t>(v)) * 1099511628211ull;
      return h;
    }
  };
  std::unordered_map<std::array<Index, 4>, std::pair<int, std::pair<Index, const Facet*>>, KeyHash> count;
  for (Index e = 0; e < static_cast<Index>(etype_.size()); ++e) {
    const Index* conn = econn_ids_.data() + eoff_[e];
    for (const Facet& f : element_info(etype_[e]).facets) {
      std::array<Index, 4> key{-1, -1, -1, -1};
      const int nc = element_info(f.type).num_corners;
      for (int i = 0; i < nc && i < 4; ++i) key[i] = conn[f.nodes[i]];
      for (int i = 1; i < nc && i < 4; ++i)  // insertion sort of the corners
        for (int j = i; j > 0 && key[j - 1] > key[j]; --j) std::swap(key[j - 1], key[j]);
      auto& slot = count[key];
      if (slot.first++ == 0) slot.second = {e, &f};
    }
  }
  for (auto& [key, v] : count)
    if (v.first == 1) exterior_.push_back(v.second);
  std::sort(exterior_.begin(), exterior_.end(),
            [](auto& a, auto& b) { return a.first != b.first ? a.first < b.first : a.second < b.second; });
}

std::vector<Index> Translator::elements_of(const std::string& name, const Card& c, const DataLine& d) {
  std::vector<Index> out;
  if (is_integer(name)) {
    const Index id = std::strtoll(name.c_str(), nullptr, 10);
    auto it = elem_of_.find(id);
    if (it == elem_of_.end()) c.fail(d, "element " + name + " is not defined");
    out.push_back(it->second);
    return out;
  }
  implicit_set(upper(name));
  auto it = elset_ids_.find(upper(name));
  if (it == elset_ids_.end()) c.fail(d, "no element set named '" + upper(name) + "'");
  for (Index id : it->second) {
    auto e = elem_of_.find(id);
    if (e == elem_of_.end()) c.fail(d, "element set " + upper(name) + " holds element " + std::to_string(id) + ", which is not defined");
    out.push_back(e->second);
  }
  return out;
}

void Translator::add_facets(const std::string& set, const std::vector<Index>& elems, int face, const Card& c,
                            const DataLine& d) {
  auto& blocks = mesh.facet_sets[set];
  for (Index e : elems) {
    const std::vector<int> corners = face_corners(etype_[e], face);
    const Facet* f = corners.empty() ? nullptr : facet_with_corners(etype_[e], corners);
    if (!f)
      c.fail(d, fmt::format("element {} ({}) has no face S{}", eid_[e], element_info(etype_[e]).name, face));
    const std::vector<Index> nodes = element_nodes(e);
    std::vector<Index> fn;
    for (int i : f->nodes) fn.push_back(nodes[i]);
    auto b = std::find_if(blocks.begin(), blocks.end(), [&](const ElementBlock& x) { return x.type == f->type; });
    if (b == blocks.end()) {
      blocks.push_back(ElementBlock{f->type, {}, {}});
      b = blocks.end() - 1;
    }
    b->add(fn, eid_[e] * 10 + face);
  }
}

std::string Translator::facet_set_for_dload(const Card& c, const DataLine& d, int face) {
  const std::string target = upper(d.fields[0]);
  const std::string set = (is_integer(target) ? "element:" + target : target) + ":S" + std::to_string(face);
  if (!mesh.facet_sets.count(set)) {
    // The elements may be read already (elements come before steps); nodes are resolved
    // lazily, so check them now.
    std::vector<Index> elems = elements_of(target, c, d);
    for (Index e : elems)
      for (Index i = eoff_[e]; i < eoff_[e + 1]; ++i)
        if (!node_of_.count(econn_ids_[i]))
          c.fail(d, fmt::format("element {} uses node {}, which is not defined", eid_[e], econn_ids_[i]));
    add_facets(set, elems, face, c, d);
  }
  return set;
}

void Translator::build_mesh(bool deck) {
  if (etype_.empty()) throw InputError(path_, "*ELEMENT", "no elements: an .inp deck needs *NODE and *ELEMENT cards");
  // Node ids of the elements.
  for (Index e = 0; e < static_cast<Index>(etype_.size()); ++e)
    for (Index i = eoff_[e]; i < eoff_[e + 1]; ++i)
      if (!node_of_.count(econn_ids_[i])) {
        const auto& [c, l] = eline_[e];
        c->fail(c->data[l], fmt::format("element {} uses node {}, which is not defined", eid_[e], econn_ids_[i]));
      }
  mesh.dim = dimension_ == "3d" ? 3 : 2;
  mesh.nodes = xyz_;
  if (mesh.dim == 2)
    for (Vec3& x : mesh.nodes) x(2) = 0;
  mesh.node_ids = node_id_;
  // Node sets.
  for (auto& [name, ids] : nset_ids_) {
    std::vector<Index> v;
    v.reserve(ids.size());
    for (Index id : ids) {
      auto it = node_of_.find(id);
      if (it == node_of_.end())
        throw InputError(nset_where_.count(name) ? nset_where_[name] : path_, "*NSET",
                         "node set " + name + " holds node " + std::to_string(id) + ", which is not defined");
      v.push_back(it->second);
    }
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    mesh.node_sets[name] = std::move(v);
  }
  std::vector<Index> all(node_id_.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<Index>(i);
  if (!mesh.node_sets.count("NALL")) mesh.node_sets["NALL"] = all;
  // Regions: the sections' element sets for a deck, every element set (and EALL) for a mesh.
  auto region = [&](const std::string& name, const std::vector<Index>& elems) {
    auto& blocks = mesh.regions[name];
    for (Index e : elems) {
      auto b = std::find_if(blocks.begin(), blocks.end(), [&](const ElementBlock& x) { return x.type == etype_[e]; });
      if (b == blocks.end()) {
        blocks.push_back(ElementBlock{etype_[e], {}, {}});
        b = blocks.end() - 1;
      }
      b->add(element_nodes(e), eid_[e]);
    }
  };
  auto elems_of_set = [&](const std::string& name, const std::string& where, const std::string& key) {
    std::vector<Index> out;
    auto it = elset_ids_.find(name);
    if (it == elset_ids_.end()) {
      std::string known;
      for (auto& [n, v] : elset_ids_) known += (known.empty() ? "" : ", ") + n;
      throw InputError(where, key, "no element set named '" + name + "' (element sets: " + (known.empty() ? "none" : known) + ")");
    }
    std::set<Index> seen;
    for (Index id : it->second) {
      auto e = elem_of_.find(id);
      if (e == elem_of_.end())
        throw InputError(where, key, "element set " + name + " holds element " + std::to_string(id) + ", which is not defined");
      if (seen.insert(e->second).second) out.push_back(e->second);
    }
    return out;
  };
  if (deck) {
    std::vector<std::string> owner(etype_.size());
    for (const Section& s : sections_) {
      std::vector<Index> elems =
          s.elset == "EALL" && !elset_ids_.count("EALL") ? [&] {
            std::vector<Index> v(etype_.size());
            for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<Index>(i);
            return v;
          }()
                                                        : elems_of_set(s.elset, s.where, "*SOLID SECTION");
      for (Index e : elems) {
        if (!owner[e].empty())
          throw InputError(s.where, "*SOLID SECTION",
                           fmt::format("element {} is in the sections of {} and {}", eid_[e], owner[e], s.elset));
        owner[e] = s.elset;
      }
      region(s.elset, elems);
    }
    for (size_t e = 0; e < owner.size(); ++e)
      if (owner[e].empty()) {
        const auto& [c, l] = eline_[e];
        c->fail(c->data[l], fmt::format("element {} has no *SOLID SECTION", eid_[e]));
      }
  } else {
    for (auto& [name, ids] : elset_ids_) region(name, elems_of_set(name, elset_where_[name], "*ELSET"));
    if (!elset_ids_.count("EALL")) {
      std::vector<Index> v(etype_.size());
      for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<Index>(i);
      region("EALL", v);
    }
  }
  // Surfaces.
  for (auto& [name, s] : surfaces_) {
    if (s.nodes) {
      std::vector<Index> ids;
      for (size_t i = 0; i < s.items.size(); ++i) {
        const Card& c = *s.lines[i].first;
        const DataLine& d = c.data[s.lines[i].second];
        const std::string& item = s.items[i].first;
        if (is_integer(item)) ids.push_back(id_number(c, d, 0, "the node id"));
        else {
          implicit_set(upper(item));
          auto it = nset_ids_.find(upper(item));
          if (it == nset_ids_.end()) c.fail(d, "no node set named '" + upper(item) + "'");
          ids.insert(ids.end(), it->second.begin(), it->second.end());
        }
      }
      std::vector<Index> v;
      for (Index id : ids) {
        auto it = node_of_.find(id);
        if (it == node_of_.end())
          throw InputError(s.where, "*SURFACE", "surface " + name + " holds node " + std::to_string(id) + ", which is not defined");
        v.push_back(it->second);
      }
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
      if (!mesh.node_sets.count(name)) mesh.node_sets[name] = v;
      // Its facets: the exterior facets whose nodes all belong to the surface.
      build_exterior();
      std::vector<char> in(node_id_.size(), 0);
      for (Index n : v) in[n] = 1;
      auto& blocks = mesh.facet_sets[name];
      for (auto& [e, f] : exterior_) {
        const std::vector<Index> nodes = element_nodes(e);
        bool all_in = true;
        std::vector<Index> fn;
        for (int i : f->nodes) all_in = all_in && in[nodes[i]], fn.push_back(nodes[i]);
        if (!all_in) continue;
        const ElementType ft = f->type;
        auto b = std::find_if(blocks.begin(), blocks.end(), [&](const ElementBlock& x) { return x.type == ft; });
        if (b == blocks.end()) {
          blocks.push_back(ElementBlock{ft, {}, {}});
          b = blocks.end() - 1;
        }
        b->add(fn, eid_[e] * 10 + static_cast<Index>(f - element_info(etype_[e]).facets.data()) + 1);
      }
      if (blocks.empty()) mesh.facet_sets.erase(name);
    } else {
      for (size_t i = 0; i < s.items.size(); ++i) {
        const Card& c = *s.lines[i].first;
        const DataLine& d = c.data[s.lines[i].second];
        const std::vector<Index> elems = elements_of(s.items[i].first, c, d);
        const std::string& face = s.items[i].second;
        if (face.empty()) {
          // No face: the exterior faces of these elements.
          build_exterior();
          std::set<Index> mine(elems.begin(), elems.end());
          for (auto& [e, f] : exterior_) {
            if (!mine.count(e)) continue;
            const std::vector<Index> nodes = element_nodes(e);
            int k = 0;
            for (int j = 1; j <= 6 && !k; ++j) {
              const std::vector<int> cs = face_corners(etype_[e], j);
              if (!cs.empty() && facet_with_corners(etype_[e], cs) == f) k = j;
            }
            add_facets(name, {e}, k, c, d);
          }
          continue;
        }
        if (face.size() != 2 || face[0] != 'S' || !std::isdigit(static_cast<unsigned char>(face[1])))
          c.fail(d, "expected a face S1 ... S6, got '" + face + "'");
        add_facets(name, elems, face[1] - '0', c, d);
      }
    }
  }
}

// ---------------------------------------------------------------- YAML
std::string q(const std::string& s) {
  std::string o = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') o += '\\';
    o += ch;
  }
  return o + "\"";
}
std::string num(Real v) { return fmt::format("{:.17g}", v); }

void Translator::translate() {
  auto line = [&](const std::string& text, const std::string& from) {
    yaml += text + "\n";
    origin.push_back(from);
  };
  const std::string file_where = path_;
  if (sections_.empty()) throw InputError(path_, "*SOLID SECTION", "no *SOLID SECTION: every element needs a material");
  if (steps_.empty()) throw InputError(path_, "*STEP", "no *STEP: Signorini needs at least one *STATIC step");
  line("title: " + q(title_.empty() ? fs::path(path_).stem().string() : title_), file_where);
  // analysis
  std::optional<Real> thickness;
  std::string thickness_where;
  for (const Section& s : sections_)
    if (s.thickness && dimension_ != "3d" && dimension_ != "axisymmetric") {
      if (thickness && std::abs(*thickness - *s.thickness) > 1e-12 * *thickness)
        throw InputError(s.where, "*SOLID SECTION",
                         fmt::format("thickness {} differs from {} at {}: Signorini has one thickness per model",
                                     *s.thickness, *thickness, thickness_where));
      thickness = s.thickness, thickness_where = s.where;
    }
  if (nlgeom_any_ && !nlgeom_all_)
    log::info("{}: *STEP: NLGEOM in some steps: the whole analysis is solved at finite strain", path_);
  std::string analysis = "analysis: {dimension: " + dimension_ +
                         ", kinematics: " + (nlgeom_any_ ? "finite_strain" : "small_strain");
  if (thickness) analysis += ", thickness: " + num(*thickness);
  line(analysis + "}", thickness ? thickness_where : dimension_where_);
  line("mesh: {file: " + q(path_) + "}", dimension_where_);
  // materials (those of the sections)
  line("materials:", file_where);
  std::set<std::string> used;
  for (const Section& s : sections_) {
    auto it = materials_.find(s.material);
    if (it == materials_.end()) {
      std::string known;
      for (auto& [n, v] : materials_) known += (known.empty() ? "" : ", ") + n;
      throw InputError(s.where, "*SOLID SECTION",
                       "no *MATERIAL named " + s.material + " (materials: " + (known.empty() ? "none" : known) + ")");
    }
    if (!used.insert(s.material).second) continue;
    const Material& m = it->second;
    std::string text;
    if (m.hyper) {
      if (!(m.D1 > 0) || !(m.C10 > 0))
        throw InputError(m.where, "*HYPERELASTIC", "NEO HOOKE needs C10 > 0 and D1 > 0 (compressible)");
      const Real mu = 2 * m.C10, K = 2 / m.D1;
      text = fmt::format("{{model: neo_hookean, E: {}, nu: {}}}", num(9 * K * mu / (3 * K + mu)),
                         num((3 * K - 2 * mu) / (2 * (3 * K + mu))));
    } else if (!m.elastic) {
      throw InputError(m.where, "*MATERIAL", "material " + s.material + " has no *ELASTIC (or *HYPERELASTIC) data");
    } else if (!m.plastic) {
      text = fmt::format("{{model: linear_elastic, E: {}, nu: {}}}", num(m.E), num(m.nu));
    } else {
      auto t = m.table;
      std::sort(t.begin(), t.end());
      if (t.front().first != 0)
        throw InputError(m.plastic_where, "*PLASTIC", "the first point of the hardening curve is at plastic strain 0");
      Real H = 0;
      if (t.size() >= 2) {
        if (!(t.back().first > t.front().first))
          throw InputError(m.plastic_where, "*PLASTIC", "the hardening curve's points are all at plastic strain 0");
        H = (t.back().second - t.front().second) / (t.back().first - t.front().first);
        for (auto& [eps, sig] : t)
          if (std::abs(t.front().second + H * eps - sig) > 1e-6 * std::abs(sig))
            throw InputError(m.plastic_where, "*PLASTIC",
                             "a piecewise-linear hardening curve is not available: Signorini's j2_plasticity hardens "
                             "linearly (give two points) or by Voce's law (in a YAML deck)");
      }
      text = fmt::format("{{model: j2_plasticity, E: {}, nu: {}, yield_stress: {}", num(m.E), num(m.nu), num(t.front().second));
      if (H != 0)
        text += m.kinematic ? fmt::format(", hardening: {{kinematic: {{H: {}}}}}", num(H))
                            : fmt::format(", hardening: {{isotropic: {{type: linear, H: {}}}}}", num(H));
      text += "}";
    }
    line("  " + q(s.material) + ": " + text, m.plastic ? m.plastic_where : m.elastic_where);
  }
  line("bodies:", file_where);
  for (const Section& s : sections_)
    line("  - {name: " + q(s.elset) + ", region: " + q(s.elset) + ", material: " + q(s.material) + "}", s.where);
  if (!pairs_.empty()) {
    line("contact:", file_where);
    for (const Pair& p : pairs_) {
      auto it = interactions_.find(p.interaction);
      if (it == interactions_.end()) throw InputError(p.where, "*CONTACT PAIR", "no *SURFACE INTERACTION named " + p.interaction);
      const Interaction& in = it->second;
      for (const std::string& s : {p.slave, p.master})
        if (!mesh.facet_sets.count(s)) {
          std::string known;
          for (auto& [n, v] : surfaces_) known += (known.empty() ? "" : ", ") + n;
          throw InputError(p.where, "*CONTACT PAIR",
                           surfaces_.count(s) ? "surface " + s + " has no exterior element faces"
                                              : "no *SURFACE named " + s + " (surfaces: " + (known.empty() ? "none" : known) + ")");
        }
      const std::string disc = p.type == "NODE TO SURFACE"      ? "node_to_segment"
                               : p.type == "SURFACE TO SURFACE" ? "segment_to_segment"
                                                                : "mortar";
      // The same surface on both sides: self-contact.
      std::string text = p.slave == p.master
                             ? "  - {name: " + q(p.slave + "-self") + ", surface: " + q(p.slave) + ", self: true" +
                                   ", discretization: " + disc
                             : "  - {name: " + q(p.slave + "-" + p.master) + ", slave: " + q(p.slave) +
                                   ", master: " + q(p.master) + ", discretization: " + disc;
      text += in.behavior == "HARD" ? ", enforcement: {method: lagrange}"
                                    : ", enforcement: {method: penalty, penalty: " + num(in.K) + "}";
      if (in.mu > 0) {
        text += ", friction: {law: coulomb, mu: " + num(in.mu);
        if (in.behavior != "HARD" && in.stick > 0) text += ", penalty: " + num(in.stick);
        text += "}";
      }
      line(text + "}", p.where);
    }
  }
  line("steps:", file_where);
  for (const StepOut& s : steps_) {
    line("  - name: " + q(s.name), s.where);
    std::string inc = fmt::format("    increments: {{initial: {}, min: {}, max: {}", num(s.initial), num(s.min), num(s.max));
    if (s.max_count) inc += ", max_count: " + std::to_string(*s.max_count);
    line(inc + "}", s.where);
    // Boundary conditions grouped by node set.
    std::map<std::string, std::vector<std::pair<int, Valued>>> by_set;
    for (auto& [key, v] : s.state.bc) by_set[key.first].emplace_back(key.second, v);
    if (!by_set.empty()) {
      line("    boundary:", s.where);
      for (auto& [set, comps] : by_set)
        for (auto& [comp, v] : comps)
          line("      - {set: " + q(set) + ", u" + std::string(1, "xyz"[comp]) + ": " + num(v.s) + "}", v.where);
    }
    const int dim = dimension_ == "3d" ? 3 : 2;
    auto vec = [&](const Vec3& v) {
      std::string t = "[";
      for (int i = 0; i < dim; ++i) t += (i ? ", " : "") + num(v(i));
      return t + "]";
    };
    if (!s.state.cload.empty() || !s.state.dload.empty() || !s.state.body.empty()) {
      line("    loads:", s.where);
      for (auto& [set, v] : s.state.cload) line("      - {set: " + q(set) + ", force: " + vec(v.v) + "}", v.where);
      for (auto& [set, v] : s.state.dload) line("      - {set: " + q(set) + ", pressure: " + num(v.s) + "}", v.where);
      for (auto& [body, v] : s.state.body) line("      - {body: " + q(body) + ", body_force: " + vec(v.v) + "}", v.where);
    }
  }
  line(std::string("output: {vtu: ") + (file_output_ ? "every_increment" : "last") + "}", file_where);
  // The keyword of each origin, for messages: "file:line" of a card or of one of its data lines.
  std::set<std::string> wanted(origin.begin(), origin.end());
  std::map<std::string, std::string> keyword;
  for (const Card& c : cards_) {
    if (wanted.count(c.where())) keyword[c.where()] = c.key();
    for (const DataLine& d : c.data)
      if (wanted.count(d.where())) keyword[d.where()] = c.key();
  }
  for (std::string& o : origin)
    if (keyword.count(o)) o += "\t" + keyword[o];
}

}  // namespace

InpDeck read_inp(const std::string& path) {
  Translator t(path);
  t.run(true);
  t.translate();
  return InpDeck{std::move(t.mesh), std::move(t.yaml), std::move(t.origin)};
}

Mesh read_inp_mesh(const std::string& path) {
  Translator t(path);
  t.run(false);
  return std::move(t.mesh);
}

}  // namespace signorini
