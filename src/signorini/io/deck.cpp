#include "signorini/io/deck.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "signorini/contact/compatibility.hpp"
#include "signorini/contact/surface.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/inp_reader.hpp"
#include "signorini/mesh/gmsh_reader.hpp"

namespace signorini {

namespace {

namespace fs = std::filesystem;

// A YAML node with its place in the deck, for messages.
struct Node {
  YAML::Node node;
  std::string file;
  std::string path;  // dotted key path
  // A deck translated from an .inp: origin[line] is "file:line\t*KEYWORD" of the .inp card
  // that wrote that YAML line, so that messages name the user's file, line and keyword.
  const std::vector<std::string>* origin = nullptr;

  const std::string* origin_of() const {
    const auto m = node.Mark();
    return origin && m.line >= 0 && static_cast<size_t>(m.line) < origin->size() ? &(*origin)[m.line] : nullptr;
  }
  std::string where() const {
    if (const std::string* o = origin_of()) return o->substr(0, o->find('\t'));
    const auto m = node.Mark();
    return m.line >= 0 ? file + ":" + std::to_string(m.line + 1) : file;
  }
  [[noreturn]] void fail(const std::string& what) const {
    if (const std::string* o = origin_of(); o && o->find('\t') != std::string::npos)
      throw InputError(where(), o->substr(o->find('\t') + 1), what + " (in the deck translated from it, at '" + path + "')");
    throw InputError(where(), path, what);
  }
  Node child(const std::string& key) const {
    return {node[key], file, path.empty() ? key : path + "." + key, origin};
  }
  Node at(size_t i) const { return {node[i], file, path + "[" + std::to_string(i) + "]", origin}; }
  bool has(const std::string& key) const { return node.IsMap() && node[key].IsDefined() && !node[key].IsNull(); }

  void expect_map() const {
    if (!node.IsMap()) fail("expected a mapping of keys (key: value)");
  }
  void expect_list() const {
    if (!node.IsSequence()) fail("expected a list");
  }
  // Rejects keys the spec does not declare, and checks required ones are present.
  void check_keys(const TypeSpec& spec) const {
    expect_map();
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string k = it->first.as<std::string>();
      if (!spec.param(k)) {
        std::string allowed;
        for (auto& p : spec.params) allowed += (allowed.empty() ? "" : ", ") + p.name;
        Node bad{it->first, file, path.empty() ? k : path + "." + k, origin};
        bad.fail("unknown key '" + k + "' in " + spec.name + " (allowed: " + allowed + ")");
      }
    }
    for (auto& p : spec.params)
      if (p.required() && !has(p.name)) fail("missing required key '" + p.name + "' (" + p.doc + ")");
  }
  Real as_number() const {
    if (!node.IsScalar()) fail("expected a number");
    Real v = 0;
    try {
      v = node.as<Real>();
    } catch (const YAML::Exception&) {
      fail("expected a number, got '" + node.as<std::string>() + "'");
    }
    // .inf, .nan and numbers beyond the double range (read as infinite) are no input.
    if (!std::isfinite(v)) fail("expected a finite number, got '" + node.as<std::string>() + "'");
    return v;
  }
  std::string as_string() const {
    if (!node.IsScalar()) fail("expected a text value");
    return node.as<std::string>();
  }
  bool as_bool() const {
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
      fail("expected true or false");
    }
  }
  // Validated number with the spec's default.
  Real number(const TypeSpec& spec, const std::string& key) const {
    const ParamSpec* p = spec.param(key);
    if (!has(key)) return std::stod(*p->default_text);
    Node c = child(key);
    Real v = c.as_number();
    std::string bad = p->check_number(v);
    if (!bad.empty()) c.fail("got " + fmt::format("{}", v) + ", expected " + bad);
    return v;
  }
  std::string text(const TypeSpec& spec, const std::string& key) const {
    const ParamSpec* p = spec.param(key);
    if (!has(key)) {
      std::string d = p->default_text.value_or("");
      return d == "\"\"" ? "" : d;
    }
    Node c = child(key);
    std::string v = c.as_string();
    if (!p->choices.empty() && std::find(p->choices.begin(), p->choices.end(), v) == p->choices.end())
      c.fail("got '" + v + "', expected " + p->range_text());
    return v;
  }
  Vec3 vector(int dim) const {
    expect_list();
    if (static_cast<int>(node.size()) != dim && !(dim == 2 && node.size() == 3))
      fail("expected a list of " + std::to_string(dim) + " numbers");
    Vec3 v = Vec3::Zero();
    for (size_t i = 0; i < node.size(); ++i) v(i) = at(i).as_number();
    return v;
  }
};

// Duplicate keys in any mapping of the deck: YAML forbids them, and yaml-cpp would keep the
// first silently. The message names both lines.
void reject_duplicate_keys(const YAML::Node& node, const std::string& file, const std::string& path) {
  if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) reject_duplicate_keys(node[i], file, path + "[" + std::to_string(i) + "]");
    return;
  }
  if (!node.IsMap()) return;
  std::map<std::string, int> seen;  // key -> line (1-based)
  for (auto it = node.begin(); it != node.end(); ++it) {
    const int line = it->first.Mark().line + 1;
    if (!it->first.IsScalar())
      throw InputError(file + ":" + std::to_string(line), path,
                       "a key must be a plain name, not a list or a mapping (a '?' key or a '[...]: ' key?)");
    const std::string k = it->first.as<std::string>();
    const std::string kp = path.empty() ? k : path + "." + k;
    if (auto [at, fresh] = seen.emplace(k, line); !fresh)
      throw InputError(file + ":" + std::to_string(line), kp,
                       fmt::format("duplicate key '{}' (first at line {}): YAML does not allow a key twice in one mapping",
                                   k, at->second));
    reject_duplicate_keys(it->second, file, kp);
  }
}

const TypeSpec& deck_spec(const Registry& r, const std::string& name) {
  const TypeSpec* s = r.find("deck", name);
  if (!s) throw Error("internal: deck section '" + name + "' is not registered");
  return *s;
}

void read_analysis(const Node& n, const Registry& r, Model& m) {
  const TypeSpec& spec = deck_spec(r, "analysis");
  n.check_keys(spec);
  const std::string d = n.text(spec, "dimension");
  m.settings.dimension = d == "plane_strain"   ? Dimension::plane_strain
                         : d == "plane_stress" ? Dimension::plane_stress
                         : d == "axisymmetric" ? Dimension::axisymmetric
                                               : Dimension::three_d;
  m.settings.finite_strain = n.text(spec, "kinematics") == "finite_strain";
  m.settings.thickness = n.number(spec, "thickness");
  if (n.has("thickness") && (m.settings.dimension == Dimension::axisymmetric || m.settings.dimension == Dimension::three_d))
    n.child("thickness").fail("thickness applies to plane_strain and plane_stress only");
}

void read_mesh(const Node& n, const Registry& r, Model& m, DeckReport& rep, Mesh* preread, const RankExchange* ranks) {
  const TypeSpec& spec = deck_spec(r, "mesh");
  n.check_keys(spec);
  GmshOptions opt;
  opt.ranks = ranks;
  opt.where = n.child("file").where();
  if (n.has("parameters")) {
    Node p = n.child("parameters");
    p.expect_map();
    for (auto it = p.node.begin(); it != p.node.end(); ++it) {
      const std::string k = it->first.as<std::string>();
      opt.parameters[k] = p.child(k).as_number();
    }
  }
  opt.order = static_cast<int>(n.number(spec, "order"));
  opt.trusted = n.has("trusted") && n.child("trusted").as_bool();
  opt.max_elements = n.number(spec, "max_elements");
  fs::path file = n.child("file").as_string();
  if (file.is_relative()) file = fs::path(m.deck_path).parent_path() / file;
  std::string ext = file.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == ".inp" && n.has("parameters")) n.child("parameters").fail("parameters apply to .geo files only");
  if (ext == ".inp" && opt.order > 0)
    n.child("order").fail("an .inp mesh keeps its element order (write the quadratic elements in the .inp)");
  if (preread) m.mesh = std::move(*preread);
  else if (ext == ".inp") m.mesh = read_inp_mesh(file.string());
  else m.mesh = read_gmsh(file.string(), opt);
  if (const Real scale = n.number(spec, "scale"); scale != 1)
    for (Vec3& x : m.mesh.nodes) x *= scale;
  const int dim = m.settings.spatial_dim();
  if (m.mesh.dim != dim)
    n.child("file").fail(fmt::format("the mesh has {}D cells but the analysis is {} ({}D)", m.mesh.dim,
                                     to_string(m.settings.dimension), dim));
  MeshCheck chk = check_and_orient(m.mesh);
  auto ids = [](const std::vector<Index>& v) {
    std::string s;
    for (size_t i = 0; i < v.size() && i < 20; ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    if (v.size() > 20) s += fmt::format(", ... ({} in all)", v.size());
    return s;
  };
  if (!chk.inverted.empty())
    n.child("file").fail("inverted or badly distorted elements (Jacobian changes sign), ids: " + ids(chk.inverted));
  if (!chk.degenerate.empty())
    n.child("file").fail("degenerate elements (zero area or volume), ids: " + ids(chk.degenerate));
  rep.reoriented_cells = chk.reoriented;
  rep.orphan_facets = orient_facets(m.mesh);
  m.mesh.complete_node_sets();
}

// j2_plasticity's 'hardening' map into the factory's values ("hardening.isotropic.H", ...).
void read_hardening(const Node& h, const Registry& r, ParamValues& pv) {
  h.check_keys(deck_spec(r, "hardening"));
  if (h.has("isotropic")) {
    const Node iso = h.child("isotropic");
    const TypeSpec& spec = deck_spec(r, "isotropic_hardening");
    iso.check_keys(spec);
    const bool voce = iso.text(spec, "type") == "voce";
    pv["hardening.isotropic.H"] = iso.number(spec, "H");
    pv["hardening.isotropic.voce"] = voce;
    for (const char* k : {"saturation", "rate"}) {
      if (voce && !iso.has(k)) iso.fail(std::string("voce hardening needs '") + k + "'");
      if (!voce && iso.has(k)) iso.child(k).fail(std::string("'") + k + "' is for type: voce");
      if (voce) pv[std::string("hardening.isotropic.") + k] = iso.number(spec, k);
    }
    if (voce && pv.count("yield_stress") && pv["hardening.isotropic.saturation"] < pv["yield_stress"])
      iso.child("saturation").fail("the saturation stress is below the yield stress (softening is not supported)");
  }
  if (h.has("kinematic")) {
    const Node kin = h.child("kinematic");
    const TypeSpec& spec = deck_spec(r, "kinematic_hardening");
    kin.check_keys(spec);
    pv["hardening.kinematic.H"] = kin.number(spec, "H");
  }
}

void read_materials_and_bodies(const Node& mats, const Node& bodies, const Registry& r, Model& m) {
  mats.expect_map();
  std::map<std::string, std::shared_ptr<Material>> materials;
  for (auto it = mats.node.begin(); it != mats.node.end(); ++it) {
    const std::string name = it->first.as<std::string>();
    Node mn = mats.child(name);
    mn.expect_map();
    if (!mn.has("model")) mn.fail("missing key 'model' (one of: " + fmt::format("{}", fmt::join(r.names("material"), ", ")) + ")");
    const std::string model = mn.child("model").as_string();
    const TypeSpec* spec = r.find("material", model);
    if (!spec)
      mn.child("model").fail("unknown material model '" + model +
                             "' (known: " + fmt::format("{}", fmt::join(r.names("material"), ", ")) + ")");
    mn.check_keys(*spec);
    ParamValues pv;
    for (auto& p : spec->params)
      if ((p.kind == ParamKind::number || p.kind == ParamKind::integer) && (!p.optional || mn.has(p.name)))
        pv[p.name] = mn.number(*spec, p.name);
    if (model == "j2_plasticity") {
      if (mn.has("hardening")) read_hardening(mn.child("hardening"), r, pv);
      if (mn.has("rate_exponent") && !(pv["viscosity"] > 0))
        mn.child("rate_exponent").fail("a rate exponent needs a viscosity > 0 (viscoplasticity)");
      // The finite-strain model (multiplicative, F = F_e F_p) has isotropic hardening only.
      pv["finite_strain"] = m.settings.finite_strain;
      if (m.settings.finite_strain && mn.has("hardening") && mn.child("hardening").has("kinematic"))
        mn.child("hardening").child("kinematic").fail(
            "kinematic hardening is for small strain only (the finite-strain j2_plasticity has isotropic hardening; "
            "use analysis.kinematics: small_strain, or remove 'kinematic')");
    }
    materials[name] = r.make_material(model, pv);
  }
  bodies.expect_list();
  if (bodies.node.size() == 0) bodies.fail("at least one body is needed");
  const TypeSpec& bspec = deck_spec(r, "body");
  std::set<std::string> used_regions, names;
  for (size_t i = 0; i < bodies.node.size(); ++i) {
    Node b = bodies.at(i);
    b.check_keys(bspec);
    const std::string name = b.text(bspec, "name"), region = b.text(bspec, "region");
    const bool rigid = b.has("rigid") && b.child("rigid").as_bool();
    if (b.has("reference") && !rigid) b.child("reference").fail("a reference node set is for a rigid body (add rigid: true)");
    if (!rigid && !b.has("material")) b.fail("missing key 'material' (a deformable body needs one; or rigid: true)");
    if (rigid && b.has("material"))
      b.child("material").fail("a rigid body has no material (remove 'material', or 'rigid: true' for a deformable body)");
    const std::string mat = rigid ? std::string() : b.text(bspec, "material");
    if (!names.insert(name).second) b.child("name").fail("two bodies are named '" + name + "'");
    auto rit = m.mesh.regions.find(region);
    if (rit == m.mesh.regions.end())
      b.child("region").fail("no region (physical group of " + std::to_string(m.mesh.dim) + "D cells) named '" +
                             region + "' in the mesh (regions: " + m.mesh.region_names() + ")");
    if (!used_regions.insert(region).second) b.child("region").fail("region '" + region + "' is used by two bodies");
    auto mit = materials.find(mat);
    if (!rigid && mit == materials.end()) {
      std::string known;
      for (auto& [k, v] : materials) known += (known.empty() ? "" : ", ") + k;
      b.child("material").fail("no material named '" + mat + "' (materials: " + known + ")");
    }
    if (m.settings.dimension == Dimension::axisymmetric)
      for (auto& blk : rit->second)
        for (Index node : blk.conn)
          if (m.mesh.nodes[node](0) < -1e-12)
            b.child("region").fail("axisymmetric analysis needs x = r >= 0, but region '" + region +
                                   "' has nodes at negative x");
    m.bodies.push_back(
        std::make_unique<Body>(name, m.mesh.take_region(region), rigid ? nullptr : mit->second, m.settings));
    if (rigid && b.has("reference")) {
      const std::string ref = b.child("reference").as_string();
      auto nit = m.mesh.node_sets.find(ref);
      if (nit == m.mesh.node_sets.end())
        b.child("reference").fail("no node set (physical group) named '" + ref + "' in the mesh");
      m.bodies.back()->set_reference_nodes(nit->second);
    }
  }
  // A node of a rigid body may not belong to another body (it would be dragged along).
  std::map<Index, std::string> owner;
  for (size_t i = 0; i < m.bodies.size(); ++i)
    for (auto& blk : m.bodies[i]->blocks())
      for (Index n : blk.conn) {
        const auto placed = owner.emplace(n, m.bodies[i]->name());
        const auto it = placed.first;
        if (!placed.second && it->second != m.bodies[i]->name() && (m.bodies[i]->rigid() || [&] {
              for (auto& o : m.bodies)
                if (o->name() == it->second) return o->rigid();
              return false;
            }()))
          bodies.at(i).child("region").fail("body '" + m.bodies[i]->name() + "' shares node " +
                                            std::to_string(m.mesh.node_ids[n]) + " with body '" + it->second +
                                            "', and one of them is rigid: a rigid body must be meshed apart");
      }
}

std::string component_name(int c) { return std::string(1, "xyz"[c]); }

// The rigid body whose reference node set is `set` (null: none).
Body* rigid_body_of_reference(const std::string& set, Model& m) {
  auto it = m.mesh.node_sets.find(set);
  if (it == m.mesh.node_sets.end()) return nullptr;
  for (auto& b : m.bodies)
    if (b->rigid() && !b->reference_nodes().empty() && b->reference_nodes() == it->second) return b.get();
  return nullptr;
}

// A rotation or a moment of a rigid body or obstacle: one number about z in plane strain and
// plane stress, a vector [x, y, z] in 3D (a rotation: the rotation vector, axis times angle in
// radians), as a Vec3 (plane problems: the z component).
Vec3 read_turn(const Node& n, const Model& m, const std::string& subject) {
  const std::string what = n.path.substr(n.path.rfind('.') + 1);
  if (m.settings.dimension == Dimension::axisymmetric)
    n.fail(subject + " does not turn in an axisymmetric analysis (it moves along the axis only)");
  if (m.settings.dimension == Dimension::three_d) {
    if (!n.node.IsSequence() || n.node.size() != 3)
      n.fail("in 3D, '" + what + "' is a vector [x, y, z]" +
             (what == "rotation" ? " (the rotation vector: axis times angle, radians)" : ""));
    return n.vector(3);
  }
  if (n.node.IsSequence())
    n.fail("in plane strain and plane stress, '" + what + "' is one number (about z" +
           (what == "rotation" ? ", radians, counter-clockwise)" : ")"));
  return Vec3(0, 0, n.as_number());
}

// A rigid obstacle whose angle some step prescribes or loads: it turns (one more unknown).
void mark_turning(const std::string& pair, Model& m) {
  for (auto& cp : m.contacts)
    if (cp.name == pair) cp.turns = true;
}

// The contact pair with a rigid obstacle named by the node's value.
std::string rigid_pair_named(const Node& n, const Model& m) {
  const std::string name = n.as_string();
  for (auto& cp : m.contacts)
    if (cp.name == name && cp.rigid) return name;
  n.fail("no contact pair with a rigid obstacle named '" + name + "'");
}

// The facet set named by the node's value; an error lists the facet sets there are.
std::string facet_set_named(const Node& n, const Mesh& mesh) {
  const std::string set = n.as_string();
  if (!mesh.facet_sets.count(set))
    n.fail("no facet set (physical group of " + std::to_string(mesh.dim - 1) + "D facets) named '" + set +
           "' (facet sets: " + mesh.facet_set_names() + ")");
  return set;
}

void read_value(const Node& v, DirichletCondition& d) {
  if (v.node.IsMap()) {
    v.expect_map();
    for (auto it = v.node.begin(); it != v.node.end(); ++it)
      if (it->first.as<std::string>() != "ramp") v.fail("a prescribed value is a number, {ramp: [start, end]} or hold");
    Node r = v.child("ramp");
    r.expect_list();
    if (r.node.size() != 2) r.fail("expected [start, end]");
    d.start = r.at(0).as_number();
    d.end = r.at(1).as_number();
  } else if (v.node.IsScalar() && v.node.Scalar() == "hold") {
    d.hold = true;  // where the step finds it
  } else {
    Real x = 0;
    if (v.node.IsScalar() && !YAML::convert<Real>::decode(v.node, x))
      v.fail("a prescribed value is a number, {ramp: [start, end]} or hold; got '" + v.node.Scalar() + "'");
    d.end = v.as_number();
  }
}

void read_step(const Node& s, size_t index, const Registry& r, Model& m) {
  const TypeSpec& spec = deck_spec(r, "step");
  s.check_keys(spec);
  Step step;
  step.name = s.has("name") ? s.child("name").as_string() : "step" + std::to_string(index + 1);
  const int dim = m.settings.spatial_dim();
  step.duration = s.number(spec, "time");
  if (s.has("increments")) {
    const TypeSpec& is = deck_spec(r, "increments");
    Node inc = s.child("increments");
    inc.check_keys(is);
    step.initial_increment = inc.number(is, "initial");
    step.min_increment = inc.number(is, "min");
    step.max_increment = inc.number(is, "max");
    step.max_increments = static_cast<int>(inc.number(is, "max_count"));
    if (step.min_increment > step.initial_increment) inc.child("min").fail("min is larger than initial");
    if (step.initial_increment > step.max_increment) inc.child("initial").fail("initial is larger than max");
  }
  if (s.has("boundary")) {
    Node bl = s.child("boundary");
    bl.expect_list();
    const TypeSpec& bs = deck_spec(r, "boundary");
    for (size_t i = 0; i < bl.node.size(); ++i) {
      Node b = bl.at(i);
      b.check_keys(bs);
      if (b.has("contact")) {
        if (b.has("set")) b.fail("a boundary entry has either 'set' or 'contact'");
        ObstacleMotion om;
        om.pair = rigid_pair_named(b.child("contact"), m);
        if (!b.has("u") && !b.has("rotation"))
          b.fail("a rigid obstacle moves by 'u: [...]' (a ~ leaves a component free) and turns by 'rotation'");
        if (b.has("u")) {
          Node u = b.child("u");
          u.expect_list();
          if (static_cast<int>(u.node.size()) != dim) u.fail("expected " + std::to_string(dim) + " components");
          for (int c = 0; c < dim; ++c)
            if (!u.at(c).node.IsNull()) om.u[c] = u.at(c).as_number();
        }
        if (b.has("rotation")) {
          om.rotation = read_turn(b.child("rotation"), m, "a rigid obstacle");
          mark_turning(om.pair, m);
        }
        for (const char* k : {"ux", "uy", "uz"})
          if (b.has(k)) b.child(k).fail("a rigid obstacle moves by 'u: [...]' (a ~ leaves a component free)");
        step.obstacles.push_back(om);
        continue;
      }
      if (!b.has("set")) b.fail("a boundary entry needs 'set' (or 'contact' for a rigid obstacle)");
      const std::string set = b.text(bs, "set");
      if (!m.mesh.node_sets.count(set))
        b.child("set").fail("no node set named '" + set + "' in the mesh (sets: " + m.mesh.node_set_names() + ")");
      bool any = false;
      if (b.has("rotation")) {
        // A meshed rigid body turned about its reference node.
        Body* body = rigid_body_of_reference(set, m);
        if (!body)
          b.child("rotation").fail("'rotation' turns a rigid body (set: its reference node set) or a rigid obstacle "
                                   "(contact: <pair>); '" + set + "' is no rigid body's reference set");
        const Vec3 rotation = read_turn(b.child("rotation"), m, "a rigid body");
        body->set_turns(true);
        step.body_turns.push_back({body->name(), rotation});
        any = true;
      }
      if (b.has("u")) {
        Node u = b.child("u");
        u.expect_list();
        if (static_cast<int>(u.node.size()) != dim) u.fail("expected " + std::to_string(dim) + " components");
        for (int c = 0; c < dim; ++c) {
          DirichletCondition d{set, c, std::nullopt, 0, u.at(c).where()};
          if (u.at(c).node.IsNull()) continue;  // ~ leaves that component free
          read_value(u.at(c), d);
          step.dirichlet.push_back(d);
          any = true;
        }
      }
      for (int c = 0; c < 3; ++c) {
        const std::string key = "u" + component_name(c);
        if (!b.has(key)) continue;
        if (c >= dim) b.child(key).fail("there is no " + key + " in a 2D analysis");
        DirichletCondition d{set, c, std::nullopt, 0, b.child(key).where()};
        read_value(b.child(key), d);
        step.dirichlet.push_back(d);
        any = true;
      }
      if (!any) b.fail("a boundary condition needs u: [...], ux/uy/uz or (a rigid body's reference set) rotation");
    }
  }
  if (s.has("loads")) {
    Node ll = s.child("loads");
    ll.expect_list();
    const TypeSpec& ls = deck_spec(r, "load");
    for (size_t i = 0; i < ll.node.size(); ++i) {
      Node l = ll.at(i);
      l.check_keys(ls);
      Load load;
      load.where = l.where();
      int kinds = 0;
      for (auto k : {"force", "traction", "pressure", "body_force", "centrifugal"}) kinds += l.has(k);
      const bool moment_only = (l.has("contact") || l.has("set")) && l.has("moment") && kinds == 0;
      if (kinds != 1 && !moment_only)
        l.fail("a load has exactly one of force, traction, pressure, body_force, centrifugal");
      if (l.has("moment") && !l.has("contact") && !(l.has("set") && kinds == 0))
        l.child("moment").fail("a moment loads a rigid obstacle ('contact') or a rigid body ('set': its reference node "
                               "set, the moment alone)");
      if (moment_only && l.has("set")) {
        // A moment on a meshed rigid body, about its reference node.
        const std::string set = l.child("set").as_string();
        Body* body = rigid_body_of_reference(set, m);
        if (!body) l.child("set").fail("a moment loads a rigid body through its reference node set; '" + set + "' is none");
        load.moment = read_turn(l.child("moment"), m, "a rigid body");
        body->set_turns(true);
        load.kind = LoadKind::body_moment;
        load.set = body->name();
        step.loads.push_back(load);
        continue;
      }
      if (l.has("contact")) {
        if ((!l.has("force") && !l.has("moment")) || kinds > 1 || l.has("set") || l.has("body"))
          l.fail("a rigid obstacle is loaded by 'force: [...]' and/or 'moment' alone");
        load.kind = LoadKind::obstacle_force;
        load.set = rigid_pair_named(l.child("contact"), m);
        load.obstacle_translations = l.has("force");
        if (l.has("force")) load.vector = l.child("force").vector(dim);
        if (l.has("moment")) {
          load.moment = read_turn(l.child("moment"), m, "a rigid obstacle");
          mark_turning(load.set, m);
        }
      } else if (l.has("body_force") || l.has("centrifugal")) {
        const char* key = l.has("body_force") ? "body_force" : "centrifugal";
        if (!l.has("body")) l.fail(std::string(key) + " needs 'body: <body name>'");
        if (l.has("set")) l.child("set").fail(std::string("a ") + key + " load takes 'body', not 'set'");
        load.set = l.child("body").as_string();
        bool found = false;
        for (auto& b : m.bodies) found = found || b->name() == load.set;
        if (!found) l.child("body").fail("no body named '" + load.set + "'");
        if (l.has("body_force")) {
          load.kind = LoadKind::body_force;
          load.vector = l.child("body_force").vector(dim);
        } else {
          load.kind = LoadKind::centrifugal;
          const Node c = l.child("centrifugal");
          const TypeSpec& cs = deck_spec(r, "centrifugal");
          c.check_keys(cs);
          Centrifugal& cf = load.centrifugal;
          cf.density = c.number(cs, "density");
          cf.omega = c.number(cs, "omega");
          const bool axi = m.settings.dimension == Dimension::axisymmetric;
          if (axi) {
            for (const char* k : {"axis", "origin"})
              if (c.has(k)) c.child(k).fail(std::string("in axisymmetry the axis is the symmetry axis (no '") + k + "')");
            cf.axis = Vec3::UnitY();
          } else if (dim == 2) {
            if (c.has("axis")) c.child("axis").fail("in 2D the axis is out of the plane (no 'axis'; 'origin' places it)");
            cf.axis = Vec3::UnitZ();
          } else {
            if (!c.has("axis")) c.fail("a centrifugal load in 3D needs 'axis: [ax, ay, az]'");
            const Vec3 a = c.child("axis").vector(3);
            if (!(a.norm() > 0)) c.child("axis").fail("the axis has zero length");
            cf.axis = a.normalized();
          }
          if (c.has("origin")) cf.origin = c.child("origin").vector(dim);
        }
      } else {
        if (!l.has("set")) l.fail("this load needs 'set'");
        load.set = l.child("set").as_string();
        if (l.has("force")) {
          load.kind = LoadKind::nodal_force;
          if (!m.mesh.node_sets.count(load.set))
            l.child("set").fail("no node set named '" + load.set + "' (sets: " + m.mesh.node_set_names() + ")");
          load.vector = l.child("force").vector(dim);
        } else {
          facet_set_named(l.child("set"), m.mesh);
          if (l.has("traction")) {
            load.kind = LoadKind::traction;
            load.vector = l.child("traction").vector(dim);
          } else {
            load.kind = LoadKind::pressure;
            load.pressure = l.child("pressure").as_number();
          }
        }
      }
      step.loads.push_back(load);
    }
  }
  m.steps.push_back(std::move(step));
}

// Mean facet edge length of a facet set and the stiffness of the body that owns it.
struct SurfaceInfo {
  Real median_edge = 0;
  Real stiffness = 0;
  std::string body;
};
SurfaceInfo surface_info(const Model& m, const std::string& set) {
  // The median edge length: on graded meshes the mean is dominated by the coarse far field.
  SurfaceInfo info;
  const auto& facets = m.mesh.facet_sets.at(set);
  std::vector<Real> edges = facet_edge_lengths(facets, m.mesh.nodes);
  Index any = -1;
  for (const ElementBlock& b : facets)
    if (b.size()) any = b.element(b.size() - 1)[0];
  if (!edges.empty()) {
    std::nth_element(edges.begin(), edges.begin() + edges.size() / 2, edges.end());
    info.median_edge = edges[edges.size() / 2];
  }
  for (auto& body : m.bodies)
    for (auto& blk : body->blocks())
      if (std::find(blk.conn.begin(), blk.conn.end(), any) != blk.conn.end()) {
        info.stiffness = body->rigid() ? std::numeric_limits<Real>::infinity() : body->material().stiffness_scale();
        info.body = body->name();
      }
  return info;
}

// "auto" (returns 0) or a positive number.
Real auto_or_positive(const Node& n) {
  if (n.node.IsScalar() && n.node.as<std::string>() == "auto") return 0;
  const Real v = n.as_number();
  if (!(v > 0)) n.fail("expected auto or a positive number");
  return v;
}

// The reference bounding box of a facet set.
std::pair<Vec3, Vec3> facet_set_box(const Mesh& mesh, const std::string& set) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const ElementBlock& b : mesh.facet_sets.at(set))
    for (Index n : b.conn) lo = lo.cwiseMin(mesh.nodes[n]), hi = hi.cwiseMax(mesh.nodes[n]);
  return {lo, hi};
}

// Multi-body contact (master: auto with more than two surfaces, or contact: {auto: {...}}):
// the pairs of surfaces of different bodies whose reference bounding boxes come within
// `reach` of each other (the pair's search.max_distance, or else twice the larger of the two
// median facet sizes), in the order given.
std::vector<std::pair<std::string, std::string>> automatic_pairs(const Model& m, const std::vector<std::string>& sets,
                                                                 Real max_distance) {
  std::vector<std::pair<std::string, std::string>> out;
  for (size_t i = 0; i < sets.size(); ++i)
    for (size_t j = i + 1; j < sets.size(); ++j) {
      const SurfaceInfo a = surface_info(m, sets[i]), b = surface_info(m, sets[j]);
      if (!a.body.empty() && a.body == b.body) continue;  // self-contact is an entry of its own (self: true)
      const Real reach = max_distance > 0 ? max_distance : 2 * std::max(a.median_edge, b.median_edge);
      const auto [alo, ahi] = facet_set_box(m.mesh, sets[i]);
      const auto [blo, bhi] = facet_set_box(m.mesh, sets[j]);
      const Vec3 gap = (blo - ahi).cwiseMax(alo - bhi).cwiseMax(Vec3::Zero());
      if (gap.norm() <= reach) out.emplace_back(sets[i], sets[j]);
    }
  return out;
}

void choose_slave(const Model& m, const std::string& a, const std::string& b, ContactPairSettings& cs);
void check_and_add_pair(const Node& c, ContactPairSettings cs, Model& m);

void read_contacts(const Node& list_or_auto, const Registry& r, Model& m) {
  const TypeSpec& spec = deck_spec(r, "contact");
  const TypeSpec& es = deck_spec(r, "enforcement");
  const TypeSpec& ss = deck_spec(r, "search");
  // contact: {auto: {surfaces: [...], ...}}: one multi-body entry, master: auto implied.
  const bool auto_map = list_or_auto.node.IsMap();
  if (auto_map) {
    if (!list_or_auto.has("auto") || list_or_auto.node.size() != 1)
      list_or_auto.fail("expected a list of contact pairs, or {auto: {surfaces: [...], ...}}");
    if (list_or_auto.child("auto").has("master"))
      list_or_auto.child("auto").child("master").fail("contact: {auto: ...} chooses masters itself (no 'master')");
  } else {
    list_or_auto.expect_list();
  }
  const size_t entries = auto_map ? 1 : list_or_auto.node.size();
  for (size_t i = 0; i < entries; ++i) {
    Node c = auto_map ? list_or_auto.child("auto") : list_or_auto.at(i);
    c.check_keys(spec);
    ContactPairSettings cs;
    cs.where = c.where();
    cs.name = c.has("name") ? c.child("name").as_string() : "contact" + std::to_string(i + 1);
    for (auto& other : m.contacts)
      if (other.name == cs.name) c.child("name").fail("two contact pairs are named '" + cs.name + "'");
    auto facet_set = [&](const Node& n) { return facet_set_named(n, m.mesh); };
    const bool rigid = c.has("master") && c.child("master").node.IsMap();
    const bool automatic = auto_map || (!rigid && c.has("master") && c.child("master").as_string() == "auto");
    std::vector<std::string> auto_sets;  // more than two surfaces: multi-body
    if (c.has("self") && c.child("self").as_bool() && (rigid || automatic))
      c.child("self").fail("self-contact has one surface, named by 'surface' (no master)");
    if (rigid) {
      Node rm = c.child("master");
      const TypeSpec& rs = deck_spec(r, "rigid");
      rm.check_keys(rs);
      const int dim = m.settings.spatial_dim();
      RigidObstacle& ob = cs.obstacle;
      ob.shape = rm.text(rs, "rigid");
      ob.inside = rm.has("inside") && rm.child("inside").as_bool();
      if (ob.shape == "plane") {
        if (!rm.has("point") || !rm.has("normal")) rm.fail("a rigid plane needs 'point' and 'normal'");
        ob.point = rm.child("point").vector(dim);
        ob.normal = rm.child("normal").vector(dim);
        if (!(ob.normal.norm() > 0)) rm.child("normal").fail("the normal must not be zero");
        ob.normal.normalize();
        if (ob.inside) rm.child("inside").fail("inside applies to a cylinder or a sphere");
      } else {
        if (!rm.has("center") || !rm.has("radius")) rm.fail("a rigid " + ob.shape + " needs 'center' and 'radius'");
        ob.point = rm.child("center").vector(dim);
        ob.radius = rm.number(rs, "radius");
        if (ob.shape == "cylinder" && dim == 3) {
          if (!rm.has("axis")) rm.fail("a rigid cylinder in 3D needs 'axis'");
          ob.axis = rm.child("axis").vector(3);
          if (!(ob.axis.norm() > 0)) rm.child("axis").fail("the axis must not be zero");
          ob.axis.normalize();
        }
      }
      cs.rigid = true;
      if (!c.has("slave")) c.fail("a contact pair needs a 'slave' facet set");
      cs.slave = facet_set(c.child("slave"));
      if (c.has("discretization")) c.child("discretization").fail("a rigid obstacle is node-to-surface by nature");
    } else if (automatic) {
      if (!c.has("surfaces") || c.has("slave"))
        c.fail("with master: auto, name the surfaces with 'surfaces: [A, B, ...]' (and no 'slave')");
      Node sf = c.child("surfaces");
      sf.expect_list();
      if (sf.node.size() < 2) sf.fail("expected two facet sets or more");
      for (size_t k = 0; k < sf.node.size(); ++k) {
        auto_sets.push_back(facet_set(sf.at(k)));
        for (size_t l = 0; l < k; ++l)
          if (auto_sets[l] == auto_sets[k]) sf.at(k).fail("facet set '" + auto_sets[k] + "' is listed twice");
      }
      // Two surfaces in a list entry: the single pair of master: auto (named by the entry). The
      // map form always follows the multi-body rules (pair names, reach, different bodies).
      if (auto_sets.size() == 2 && !auto_map) auto_sets.clear();
    }
    if (automatic && auto_sets.empty()) {
      Node sf = c.child("surfaces");
      const std::string a = facet_set(sf.at(0)), b = facet_set(sf.at(1));
      choose_slave(m, a, b, cs);
      log::info("contact '{}': master: auto chose slave '{}' and master '{}'", cs.name, cs.slave, cs.master);
    } else if (!automatic && !rigid && c.has("self") && c.child("self").as_bool()) {
      // Self-contact: one surface, slave and master at once.
      if (!c.has("surface")) c.fail("self: true needs 'surface' (the facet set in contact with itself)");
      for (const char* k : {"master", "slave", "surfaces"})
        if (c.has(k)) c.child(k).fail(std::string("self-contact names its one facet set with 'surface', not '") + k + "'");
      cs.self = true;
      cs.slave = cs.master = facet_set(c.child("surface"));
    } else if (!automatic && !rigid) {
      if (c.has("surface")) c.child("surface").fail("'surface' goes with self: true (self-contact)");
      if (!c.has("master") || !c.has("slave")) c.fail("a contact pair needs 'master' and 'slave' facet sets");
      if (c.has("surfaces")) c.child("surfaces").fail("'surfaces' goes with master: auto");
      cs.master = facet_set(c.child("master"));
      cs.slave = facet_set(c.child("slave"));
      if (cs.master == cs.slave)
        c.child("slave").fail("master and slave are the same facet set: for self-contact write surface: " + cs.slave +
                              ", self: true");
      const SurfaceInfo im = surface_info(m, cs.master), is = surface_info(m, cs.slave);
      if (is.median_edge > 1.2 * im.median_edge)
        log::warning("{}: contact '{}': the slave surface '{}' (median facet size {:.3g}) is coarser than the master "
                     "'{}' ({:.3g}); master nodes may then penetrate the slave. Make the finer surface slave, use "
                     "master: auto, or passes: 2.",
                     cs.where, cs.name, cs.slave, is.median_edge, cs.master, im.median_edge);
      else if (is.median_edge >= 0.83 * im.median_edge && is.stiffness > 1.5 * im.stiffness)
        log::warning("{}: contact '{}': at about equal mesh density the less deformable body should be master, but the "
                     "slave '{}' (E = {:g}) is stiffer than the master '{}' (E = {:g}).",
                     cs.where, cs.name, cs.slave, is.stiffness, cs.master, im.stiffness);
    }
    if (!cs.rigid) cs.discretization = c.text(spec, "discretization");
    cs.passes = static_cast<int>(c.number(spec, "passes"));
    cs.smoothing = c.text(spec, "smoothing");
    if (c.has("enforcement")) {
      Node e = c.child("enforcement");
      e.check_keys(es);
      cs.method = e.text(es, "method");
      if (e.has("penalty")) cs.penalty = auto_or_positive(e.child("penalty"));
      cs.penalty_factor = e.number(es, "penalty_factor");
      cs.max_flips = static_cast<int>(e.number(es, "max_flips"));
      if (e.has("gap_tolerance")) cs.gap_tolerance = auto_or_positive(e.child("gap_tolerance"));
      cs.max_uzawa = static_cast<int>(e.number(es, "max_uzawa"));
      if (e.has("gamma")) cs.nitsche_gamma = auto_or_positive(e.child("gamma"));
      // theta: 1 by default; at finite strain 0, the only variant there (docs/contact.md, Nitsche
      // at finite strain: the others' Newton matrix needs the stress's second derivative).
      const Real theta = m.settings.finite_strain && !e.has("theta") ? 0 : e.number(es, "theta");
      if (theta != 1 && theta != 0 && theta != -1) e.child("theta").fail("theta is 1 (symmetric), 0 or -1");
      if (m.settings.finite_strain && theta != 0 && cs.method == "nitsche")
        e.child("theta").fail("at finite strain nitsche takes theta: 0 (the default there): the Newton matrix of "
                              "theta 1 and -1 needs the second derivative of the bodies' stress");
      cs.nitsche_theta = static_cast<int>(theta);
      if (cs.method != "nitsche")
        for (const char* k : {"gamma", "theta"})
          if (e.has(k)) e.child(k).fail(std::string("'") + k + "' goes with method: nitsche");
    }
    if (c.has("friction")) {
      Node fn = c.child("friction");
      const TypeSpec& fs = deck_spec(r, "friction");
      fn.check_keys(fs);
      cs.friction = fn.text(fs, "law");
      if (cs.friction == "coulomb") {
        if (!fn.has("mu")) fn.fail("coulomb friction needs 'mu' (the friction coefficient)");
        cs.friction_parameter = fn.number(fs, "mu");
      } else if (cs.friction == "tresca") {
        if (!fn.has("bound")) fn.fail("tresca friction needs 'bound' (the largest tangential traction)");
        cs.friction_parameter = fn.number(fs, "bound");
      }
      if (cs.friction != "coulomb" && fn.has("mu")) fn.child("mu").fail("'mu' goes with law: coulomb");
      if (cs.friction != "tresca" && fn.has("bound")) fn.child("bound").fail("'bound' goes with law: tresca");
      if (fn.has("penalty") && cs.method == "nitsche")
        fn.child("penalty").fail("'penalty' does not go with method: nitsche (its tangential parameter is its normal "
                                 "one, gamma0 E / h: set enforcement.gamma)");
      if (fn.has("penalty")) cs.tangential_penalty = auto_or_positive(fn.child("penalty"));
      if (fn.has("stick_predictor")) cs.stick_predictor = fn.child("stick_predictor").as_bool();
    }
    if (c.has("search")) {
      Node s = c.child("search");
      s.check_keys(ss);
      cs.search = s.text(ss, "method");
      if (s.has("max_distance")) cs.max_distance = auto_or_positive(s.child("max_distance"));
      cs.update = s.text(ss, "update");
    }
    if (!auto_sets.empty()) {
      // Multi-body: one pair per two surfaces within reach, named <name>_<A>_<B>.
      const auto pairs = automatic_pairs(m, auto_sets, cs.max_distance);
      if (pairs.empty())
        c.child("surfaces").fail("no two of these surfaces (of different bodies) come within reach of each other "
                                 "(set search.max_distance to widen it)");
      std::string made;
      for (const auto& [a, b] : pairs) {
        ContactPairSettings p = cs;
        p.name = cs.name + "_" + a + "_" + b;
        for (auto& other : m.contacts)
          if (other.name == p.name) c.fail("two contact pairs are named '" + p.name + "'");
        choose_slave(m, a, b, p);
        check_and_add_pair(c, p, m);
        made += (made.empty() ? "" : ", ") + p.name + " (slave " + p.slave + ")";
      }
      log::info("contact '{}': {} pairs: {}", cs.name, pairs.size(), made);
      continue;
    }
    check_and_add_pair(c, cs, m);
  }
}

// The finer surface is slave; at about equal density the stiffer body is master.
void choose_slave(const Model& m, const std::string& a, const std::string& b, ContactPairSettings& cs) {
  const SurfaceInfo ia = surface_info(m, a), ib = surface_info(m, b);
  const bool a_slave = ia.median_edge < 0.83 * ib.median_edge ||
                       (ia.median_edge <= 1.2 * ib.median_edge && ib.median_edge <= 1.2 * ia.median_edge &&
                        ia.stiffness <= ib.stiffness);
  cs.slave = a_slave ? a : b;
  cs.master = a_slave ? b : a;
}

// A pair's last checks (the compatibility table, the slave surface's weights), then it joins
// the model.
void check_and_add_pair(const Node& c, ContactPairSettings cs, Model& m) {
  {
    // The combination against the compatibility table (each facet type of either surface).
    if (const CompatibilityIssue issue = first_unsupported(cs, m.mesh, m.settings.dimension); !issue.message.empty()) {
      // The deepest node of the rule's key (e.g. master.rigid) the deck has (Nodes are copied,
      // never assigned: assigning a YAML::Node writes into the deck).
      std::vector<Node> at{c};
      for (size_t a = 0, b; a <= issue.key.size(); a = b + 1) {
        b = std::min(issue.key.find('.', a), issue.key.size());
        const std::string part = issue.key.substr(a, b - a);
        if (!at.back().node.IsMap() || !at.back().has(part)) break;
        at.push_back(at.back().child(part));
      }
      at.back().fail(issue.message);
    }
    // Slave facets must give every node a positive contact area (checked here, with the place).
    try {
      make_slave_surface(m.mesh, cs.slave, m.settings,
                         slave_basis(cs.discretization, cs.rigid, m.settings.spatial_dim() == 3, cs.method));
      if (cs.passes == 2) make_slave_surface(m.mesh, cs.master, m.settings);
    } catch (const Error& e) {
      c.fail(e.what());
    }
    // Nitsche's method reads the bodies' stress at the contact surface: elastic bodies.
    if (cs.method == "nitsche") {
      const Node at = c.child("enforcement").child("method");
      for (auto& b : m.bodies)
        if (!b->rigid() && b->material().history_size() > 0)
          at.fail("nitsche needs bodies without history (elastic): body '" + b->name() + "' is " +
                  b->material().model());
    }
    m.contacts.push_back(cs);
  }
}

void read_solver(const Node& n, const Registry& r, Model& m) {
  const TypeSpec& spec = deck_spec(r, "solver");
  n.check_keys(spec);
  if (n.has("linear") && n.child("linear").node.IsMap()) {
    const TypeSpec& ls = deck_spec(r, "linear");
    const Node l = n.child("linear");
    l.check_keys(ls);
    m.linear_solver.type = l.text(ls, "type");
    m.linear_solver.rtol = l.number(ls, "rtol");
    m.linear_solver.forcing = l.text(ls, "forcing");
    m.linear_solver.options = l.text(ls, "options");
    m.linear_solver.partition = l.text(ls, "partition");
    m.linear_solver.iterative_above = static_cast<Index>(l.number(ls, "iterative_above"));
    m.linear_solver.direct_factor_limit = l.number(ls, "direct_factor_limit");
  } else if (n.has("linear")) {
    const Node c = n.child("linear");
    const ParamSpec* p = deck_spec(r, "linear").param("type");
    m.linear_solver.type = c.as_string();
    if (std::find(p->choices.begin(), p->choices.end(), m.linear_solver.type) == p->choices.end())
      c.fail("got '" + m.linear_solver.type + "', expected " + p->range_text());
  }
  if (n.has("linear")) m.linear_solver_where = n.child("linear").where();
  if (is_petsc_solver(m.linear_solver.type) && !petsc_available())
    n.child("linear").fail("linear solver '" + m.linear_solver.type +
                           "' needs PETSc, and this build has none (install petsc-dev, e.g. with "
                           "scripts/install-deps.sh, and reconfigure)");
  auto& ns = m.newton;
  ns.max_iterations = static_cast<int>(n.number(spec, "max_iterations"));
  ns.residual_tolerance = n.number(spec, "residual_tolerance");
  ns.absolute_tolerance = n.number(spec, "absolute_tolerance");
  ns.energy_tolerance = n.number(spec, "energy_tolerance");
  ns.line_search = n.has("line_search") ? n.child("line_search").as_bool() : true;
  ns.penetration_step = n.number(spec, "penetration_step");
  ns.residual_growth = n.number(spec, "residual_growth");
  ns.predictor = n.has("predictor") ? n.child("predictor").as_bool() : true;
  ns.condense_contact = n.has("condense_contact") ? n.child("condense_contact").as_bool() : true;
  ns.cutback_factor = n.number(spec, "cutback_factor");
  ns.growth_factor = n.number(spec, "growth_factor");
  ns.easy_iterations = static_cast<int>(n.number(spec, "easy_iterations"));
  ns.stabilization = n.number(spec, "stabilization");
  ns.pseudo_transient = n.has("pseudo_transient") ? n.child("pseudo_transient").as_bool() : true;
}

void read_checks(const Node& n, const Registry& r, Model& m) {
  n.expect_list();
  const TypeSpec& spec = deck_spec(r, "check");
  for (size_t i = 0; i < n.node.size(); ++i) {
    Node c = n.at(i);
    c.check_keys(spec);
    Check ch;
    ch.where = c.where();
    ch.name = c.text(spec, "name");
    ch.kind = c.text(spec, "quantity");
    if (c.has("component")) {
      const std::string comp = c.text(spec, "component");
      ch.component = comp == "x" ? 0 : comp == "y" ? 1 : comp == "z" ? 2 : Check::radial;
      if (ch.component == Check::radial) {
        if (ch.kind != "contact_half_width" && ch.kind != "contact_stick_half_width")
          c.child("component").fail("'r' (a radius) is for contact_half_width and contact_stick_half_width only");
        if (m.settings.spatial_dim() != 3)
          c.child("component").fail("'r' (a radius in the contact plane) is for 3D; in 2D use x or y");
      } else if (ch.component >= m.settings.spatial_dim()) {
        c.child("component").fail("no such component in 2D");
      }
    } else if (ch.kind != "contact_pressure_max" && ch.kind != "contact_pressure") {
      c.fail("a " + ch.kind + " check needs 'component' (x, y or z)");
    }
    ch.expected = c.number(spec, "expected");
    ch.tolerance = c.number(spec, "tolerance");
    ch.reference = c.text(spec, "reference");
    if (ch.kind == "displacement" || ch.kind == "contact_pressure" || ch.kind == "contact_half_width" ||
        ch.kind == "contact_stick_half_width") {
      if (!c.has("at")) c.fail("a " + ch.kind + " check needs 'at: [x, y(, z)]'");
      ch.point = c.child("at").vector(m.settings.spatial_dim());
    }
    if (ch.kind == "reaction") {
      if (!c.has("set")) c.fail("a reaction check needs 'set'");
      ch.set = c.child("set").as_string();
      if (!m.mesh.node_sets.count(ch.set))
        c.child("set").fail("no node set named '" + ch.set + "' (sets: " + m.mesh.node_set_names() + ")");
    }
    if (ch.kind.rfind("contact_", 0) == 0) {
      if (!c.has("pair")) c.fail("a " + ch.kind + " check needs 'pair: <contact pair name>'");
      ch.pair = c.child("pair").as_string();
      bool found = false;
      for (auto& cp : m.contacts) found = found || cp.name == ch.pair;
      if (!found) c.child("pair").fail("no contact pair named '" + ch.pair + "'");
    }
    if (ch.kind == "contact_stick_half_width") {
      bool frictional = false;
      for (auto& cp : m.contacts) frictional = frictional || (cp.name == ch.pair && cp.friction != "none");
      if (!frictional) c.child("quantity").fail("contact_stick_half_width needs a contact pair with friction");
    }
    m.checks.push_back(ch);
  }
}

// What is still open where the YAML parser gave up: the innermost unclosed flow bracket
// ({ or [) or quoted scalar before (line, col) (0-based), as " (the '{' opened at line N is
// not closed)"; empty when nothing is open. The parser reports where it noticed the error,
// often lines after the bracket or quote that caused it. A quote opens a scalar only at the
// start of a token (a plain scalar may hold an apostrophe: Klang's pin); # starts a comment
// only after a blank; block scalars (| or >) are skipped.
std::string yaml_open_context(const std::string& text, int err_line, int err_col) {
  struct Open {
    char c;
    int line, col;
  };
  std::vector<Open> stack;
  std::optional<Open> quote;
  int line = 0, col = 0;
  int block_indent = -1;  // inside a block scalar: lines indented more than this belong to it
  bool line_start = true;
  int indent = 0;
  char prev = '\n';  // the last character that is not a blank
  bool prev_blank = true;
  for (size_t i = 0; i < text.size(); ++i) {
    if (line > err_line || (line == err_line && col >= err_col)) break;
    const char ch = text[i];
    if (ch == '\n') {
      // A line ending in | or > (after a key or a dash) starts a block scalar.
      if (!quote && (prev == '|' || prev == '>')) block_indent = indent;
      ++line, col = 0, line_start = true, indent = 0, prev_blank = true;
      if (!quote) prev = '\n';
      continue;
    }
    if (line_start && ch == ' ') {
      ++indent, ++col;
      continue;
    }
    if (line_start) {
      line_start = false;
      if (block_indent >= 0 && indent > block_indent) {  // skip the block scalar's line
        while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        continue;
      }
      block_indent = -1;
    }
    if (quote) {
      if (quote->c == '"' && ch == '\\') {
        ++i, col += 2;
        continue;
      }
      if (ch == quote->c) {
        if (quote->c == '\'' && i + 1 < text.size() && text[i + 1] == '\'') {  // '' inside '...'
          ++i, col += 2;
          continue;
        }
        quote.reset();
        prev = ch, prev_blank = false;
      }
      ++col;
      continue;
    }
    if (ch == '#' && prev_blank) {  // a comment: to the end of the line
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if ((ch == '"' || ch == '\'') && (prev == '\n' || (prev_blank && std::string(":,[{-").find(prev) != std::string::npos) ||
                                      prev == '[' || prev == '{' || prev == ',')) {
      quote = Open{ch, line, col};
    } else if (ch == '{' || ch == '[') {
      stack.push_back({ch, line, col});
    } else if ((ch == '}' || ch == ']') && !stack.empty()) {
      if ((ch == '}') != (stack.back().c == '{'))
        return fmt::format(" (the '{}' opened at line {}, column {} is closed by '{}' at line {}, column {})",
                           stack.back().c, stack.back().line + 1, stack.back().col + 1, ch, line + 1, col + 1);
      stack.pop_back();
    }
    if (ch != ' ' && ch != '\t') prev = ch;
    prev_blank = ch == ' ' || ch == '\t';
    ++col;
  }
  auto where = [](const Open& o) { return fmt::format("line {}, column {}", o.line + 1, o.col + 1); };
  if (quote)
    return fmt::format(" (the quoted text opened by {} at {} is not closed)", quote->c, where(*quote));
  if (!stack.empty()) return fmt::format(" (the '{}' opened at {} is not closed)", stack.back().c, where(stack.back()));
  return "";
}

}  // namespace

namespace {
Model read_deck_unguarded(const std::string& path, const Registry& registry, DeckReport* report,
                          const RankExchange* ranks) {
  if (!fs::exists(path)) throw InputError(path, "", "deck file does not exist");
  if (fs::is_directory(path)) throw InputError(path, "", "is a directory, not a deck file");
  YAML::Node root;
  std::string ext = fs::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  std::optional<InpDeck> inp;
  if (ext == ".inp") {
    inp = read_inp(path);
    try {
      root = YAML::Load(inp->yaml);
    } catch (const YAML::Exception& e) {
      throw Error(std::string("internal: the deck translated from ") + path + " is not valid YAML: " + e.what());
    }
    log::debug("deck translated from {}:\n{}", path, inp->yaml);
  } else try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    throw InputError(path + ":" + std::to_string(e.mark.line + 1), "",
                     "malformed YAML: " + e.msg + yaml_open_context(text.str(), e.mark.line, e.mark.column));
  } catch (const YAML::Exception& e) {
    throw InputError(path, "", std::string("cannot read the deck: ") + e.what());
  }
  reject_duplicate_keys(root, path, "");
  Node top{root, path, "", inp ? &inp->origin : nullptr};
  if (!root.IsMap()) throw InputError(path, "", "a deck is a mapping of sections (title, analysis, mesh, ...)");
  top.check_keys(deck_spec(registry, "deck"));
  Model m;
  m.deck_path = path;
  m.title = top.has("title") ? top.child("title").as_string() : fs::path(path).stem().string();
  DeckReport rep;
  read_analysis(top.child("analysis"), registry, m);
  read_mesh(top.child("mesh"), registry, m, rep, inp ? &inp->mesh : nullptr, ranks);
  read_materials_and_bodies(top.child("materials"), top.child("bodies"), registry, m);
  Node steps = top.child("steps");
  steps.expect_list();
  if (steps.node.size() == 0) steps.fail("at least one step is needed");
  if (top.has("contact")) read_contacts(top.child("contact"), registry, m);
  for (size_t i = 0; i < steps.node.size(); ++i) read_step(steps.at(i), i, registry, m);
  if (top.has("solver")) {
    read_solver(top.child("solver"), registry, m);
    // Algebraic multigrid, Cholesky and CG cannot take the multipliers' saddle point: they
    // must be condensed.
    const std::string& t = m.linear_solver.type;
    const bool amg = is_amg_solver(t);
    const bool multipliers = std::any_of(m.contacts.begin(), m.contacts.end(),
                                         [](const ContactPairSettings& c) { return c.method == "lagrange"; });
    if ((amg || is_symmetric_only_solver(t)) && multipliers && !m.newton.condense_contact)
      top.child("solver").child("condense_contact").fail(
          "linear solver " + t + " needs the contact multipliers condensed (condense_contact: true, the default): " +
          (amg ? "algebraic multigrid" : "a symmetric solver without pivoting") +
          " cannot take their saddle point; or use enforcement: penalty, or linear: umfpack or mumps");
    const std::string refusal = symmetric_solver_refusal(m);
    if (!refusal.empty()) top.child("solver").child("linear").fail(refusal);
  }
  if (top.has("output")) {
    const TypeSpec& os = deck_spec(registry, "output");
    Node o = top.child("output");
    o.check_keys(os);
    m.output.directory = o.text(os, "directory");
    m.output.vtu = o.text(os, "vtu");
    m.output.restart = o.text(os, "restart");
  }
  if (top.has("checks")) read_checks(top.child("checks"), registry, m);
  if (report) *report = rep;
  return m;
}
}  // namespace

Model read_deck(const std::string& path, const Registry& registry, DeckReport* report, const RankExchange* ranks) {
  // Whatever the deck holds, a yaml-cpp or filesystem exception becomes an error that names
  // the file (the fuzzer's rule: bad input gets an InputError).
  try {
    return read_deck_unguarded(path, registry, report, ranks);
  } catch (const YAML::Exception& e) {
    throw InputError(e.mark.line >= 0 ? path + ":" + std::to_string(e.mark.line + 1) : path, "", e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    throw InputError(path, "", e.what());
  }
}

}  // namespace signorini
