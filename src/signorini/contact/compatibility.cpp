#include "signorini/contact/compatibility.hpp"

#include <algorithm>
#include <functional>

#include <fmt/format.h>

#include "signorini/core/error.hpp"

namespace signorini {

namespace {

bool is_2d(Dimension d) { return d != Dimension::three_d; }
bool linear(ElementType t) { return element_info(t).order == 1; }
std::string dimension_name(Dimension d) {
  switch (d) {
    case Dimension::plane_strain: return "plane strain";
    case Dimension::plane_stress: return "plane stress";
    case Dimension::axisymmetric: return "axisymmetric";
    case Dimension::three_d: return "3D";
  }
  return "?";
}

struct Rule {
  const char* when;  // the combinations the rule excludes, in words (the table)
  std::function<bool(const ContactCombination&)> excludes;
  const char* key;
  std::function<std::string(const ContactCombination&)> message;
};

// The rules, in the order they are checked (the first one broken is reported).
const std::vector<Rule>& rules() {
  static const std::vector<Rule> r = {
      {"facets of the wrong dimension",
       [](const ContactCombination& c) {
         const int fd = is_2d(c.dimension) ? 1 : 2;
         return element_info(c.slave_facet).dim != fd || (!c.rigid() && element_info(c.master_facet).dim != fd);
       },
       "slave",
       [](const ContactCombination& c) {
         return fmt::format("a {} analysis needs {} facets on its contact surfaces", dimension_name(c.dimension),
                            is_2d(c.dimension) ? "line" : "triangle or quadrilateral");
       }},
      {"nitsche other than segment_to_segment or mortar, or with self-contact",
       [](const ContactCombination& c) {
         return c.method == "nitsche" &&
                ((c.discretization != "segment_to_segment" && c.discretization != "mortar") || c.self);
       },
       "enforcement.method",
       [](const ContactCombination& c) {
         if (c.self) return std::string("nitsche with self-contact is not available (use lagrange or penalty)");
         return "nitsche works on integration points: it needs discretization: segment_to_segment or mortar (not " +
                c.discretization + ")";
       }},
      {"tri6 or quad8 slave facets other than segment_to_segment or 3D mortar (two passes: on either surface)",
       [](const ContactCombination& c) {
         auto bad = [](ElementType t) { return t == ElementType::tri6 || t == ElementType::quad8; };
         const bool transformed = c.discretization == "segment_to_segment" ||
                                  (c.discretization == "mortar" && !is_2d(c.dimension));
         return !transformed && (bad(c.slave_facet) || (c.passes == 2 && bad(c.master_facet)));
       },
       "slave",
       [](const ContactCombination&) {
         return std::string(
             "tri6 and quad8 slave facets give their corner nodes a zero or negative share of the contact area (the "
             "integrals of their shape functions), which a node-based discretization cannot use: use "
             "discretization: mortar or segment_to_segment (their transformed bases have positive weights), make the "
             "quadratic side master, or use tri3, quad4 or quad9 (3D), line2 or line3 (2D) slave facets");
       }},
      {"node_to_node with quadratic facets",
       [](const ContactCombination& c) {
         return c.discretization == "node_to_node" && !(linear(c.slave_facet) && linear(c.master_facet));
       },
       "discretization",
       [](const ContactCombination&) {
         return std::string("node_to_node pairs slave nodes with master corner nodes and cannot use the mid-side nodes "
                            "of quadratic facets: use node_to_segment");
       }},
      {"self-contact with mortar in 3D on quadratic facets",
       [](const ContactCombination& c) {
         return c.self && c.discretization == "mortar" && !is_2d(c.dimension) && !linear(c.slave_facet);
       },
       "self",
       [](const ContactCombination& c) {
         return "self-contact with mortar in 3D takes linear facets (tri3, quad4) so far, not " +
                std::string(element_info(c.slave_facet).name) + ": use node_to_segment";
       }},
      {"a rigid sphere in plane strain or plane stress",
       [](const ContactCombination& c) {
         return c.discretization == "rigid_sphere" &&
                (c.dimension == Dimension::plane_strain || c.dimension == Dimension::plane_stress);
       },
       "master.rigid",
       [](const ContactCombination&) {
         return std::string("a sphere needs an axisymmetric or 3D analysis (use a cylinder in plane problems)");
       }},
      {"self-contact other than node_to_segment or mortar, one pass, without smoothing",
       [](const ContactCombination& c) {
         return c.self && ((c.discretization != "node_to_segment" && c.discretization != "mortar") || c.passes != 1 ||
                           c.smoothing != "none");
       },
       "self",
       [](const ContactCombination& c) {
         if (c.discretization != "node_to_segment" && c.discretization != "mortar")
           return std::string("self-contact is node_to_segment or mortar so far (segment_to_segment: not yet)");
         if (c.passes != 1)
           return std::string("self-contact has one pass: every node of the surface is slave already");
         return std::string("self-contact has no smoothing so far (the surface stays faceted)");
       }},
      {"two passes other than node_to_segment",
       [](const ContactCombination& c) { return c.passes == 2 && c.discretization != "node_to_segment"; }, "passes",
       [](const ContactCombination& c) {
         return c.rigid() ? std::string("a rigid obstacle has one pass")
                          : std::string("two passes apply to node_to_segment only");
       }},
      {"two passes with friction",
       [](const ContactCombination& c) { return c.passes == 2 && c.friction != "none"; }, "friction",
       [](const ContactCombination&) {
         return std::string("friction with passes: 2 is not available (use one pass, with the finer surface slave)");
       }},
      {"smoothing other than node_to_segment",
       [](const ContactCombination& c) { return c.smoothing != "none" && c.discretization != "node_to_segment"; },
       "smoothing",
       [](const ContactCombination& c) {
         return c.rigid() ? std::string("a rigid obstacle is smooth already")
                          : std::string("smoothing applies to node_to_segment only");
       }},
      {"hermite smoothing of other than line2 (2D) or quad4 (3D) facets (two passes: both surfaces)",
       [](const ContactCombination& c) {
         if (c.smoothing != "hermite") return false;
         const ElementType need = is_2d(c.dimension) ? ElementType::line2 : ElementType::quad4;
         return c.master_facet != need || (c.passes == 2 && c.slave_facet != need);
       },
       "smoothing",
       [](const ContactCombination& c) {
         const bool three = !is_2d(c.dimension);
         const bool master_bad = c.master_facet != (three ? ElementType::quad4 : ElementType::line2);
         const std::string& set = master_bad ? c.master_set : c.slave_set;
         return std::string("smoothing: hermite needs ") +
                (three ? "quad4 master facets in 3D (bicubic patches)" : "line2 master facets") + "; " +
                (set.empty() ? std::string("the surface") : "'" + set + "'") + " has " +
                element_info(master_bad ? c.master_facet : c.slave_facet).name;
       }},
  };
  return r;
}

const std::vector<Dimension> kDimensions = {Dimension::plane_strain, Dimension::plane_stress, Dimension::axisymmetric,
                                            Dimension::three_d};
const std::vector<ElementType> kFacets2D = {ElementType::line2, ElementType::line3};
const std::vector<ElementType> kFacets3D = {ElementType::tri3, ElementType::tri6, ElementType::quad4, ElementType::quad8,
                                            ElementType::quad9};
const std::vector<std::string> kDiscretizations = {"node_to_segment", "node_to_node", "mortar", "segment_to_segment",
                                                   "rigid_plane", "rigid_cylinder", "rigid_sphere"};
const std::vector<std::string> kMethods = {"lagrange", "augmented_lagrangian", "penalty", "nitsche"};
const std::vector<std::string> kFrictions = {"none", "coulomb", "tresca"};
const std::vector<std::string> kSmoothings = {"none", "hermite"};

}  // namespace

std::string ContactCombination::text() const {
  std::string s = dimension_name(dimension) + ", " + element_info(slave_facet).name + " slave";
  if (!rigid()) s += " on " + element_info(master_facet).name + " master";
  s += ", " + discretization;
  if (passes == 2) s += " (two passes)";
  if (self) s += " (self-contact)";
  s += ", " + method + ", " + (friction == "none" ? std::string("frictionless") : friction);
  if (smoothing != "none") s += ", " + smoothing + " smoothing";
  return s;
}

CompatibilityIssue check_contact_combination(const ContactCombination& c) {
  for (const Rule& r : rules())
    if (r.excludes(c)) return {r.key, r.message(c)};
  return {};
}

std::vector<ContactCombination> contact_combinations(const ContactPairSettings& s, const Mesh& mesh,
                                                     Dimension dimension) {
  auto types = [&](const std::string& set) {
    std::vector<ElementType> t;
    auto it = mesh.facet_sets.find(set);
    if (it != mesh.facet_sets.end())
      for (const ElementBlock& b : it->second)
        if (std::find(t.begin(), t.end(), b.type) == t.end()) t.push_back(b.type);
    return t;
  };
  ContactCombination base;
  base.dimension = dimension;
  base.discretization = s.rigid ? "rigid_" + s.obstacle.shape : s.discretization;
  base.passes = s.passes;
  base.method = s.method;
  base.friction = s.friction;
  base.smoothing = s.smoothing;
  base.self = s.self;
  base.slave_set = s.slave;
  base.master_set = s.rigid ? "" : s.master;
  std::vector<ContactCombination> out;
  const std::vector<ElementType> masters = s.rigid ? std::vector<ElementType>{ElementType::line2} : types(s.master);
  for (ElementType st : types(s.slave))
    for (ElementType mt : masters) {
      ContactCombination c = base;
      c.slave_facet = st;
      c.master_facet = mt;
      out.push_back(c);
    }
  return out;
}

CompatibilityIssue first_unsupported(const ContactPairSettings& s, const Mesh& mesh, Dimension dimension,
                                     std::string* combination) {
  for (const ContactCombination& c : contact_combinations(s, mesh, dimension)) {
    CompatibilityIssue issue = check_contact_combination(c);
    if (issue.message.empty()) continue;
    if (combination) *combination = c.text();
    return issue;
  }
  return {};
}

void check_contact_pair(const ContactPairSettings& s, const Mesh& mesh, Dimension dimension) {
  std::string combination;
  const CompatibilityIssue issue = first_unsupported(s, mesh, dimension, &combination);
  if (!issue.message.empty()) throw Error("contact '" + s.name + "' (" + combination + "): " + issue.message);
}

std::vector<ContactCombination> supported_contact_combinations() {
  // Every slave facet type against every master facet type of the same dimension (a rigid
  // obstacle has no master facets: once per slave type).
  std::vector<ContactCombination> out;
  for (Dimension d : kDimensions) {
    const std::vector<ElementType>& facets = is_2d(d) ? kFacets2D : kFacets3D;
    for (ElementType f : facets)
      for (const std::string& disc : kDiscretizations)
        for (ElementType mf : disc.rfind("rigid_", 0) == 0 ? std::vector<ElementType>{f} : facets)
          for (int passes : {1, 2})
            for (const std::string& m : kMethods)
              for (const std::string& fr : kFrictions)
                for (const std::string& sm : kSmoothings)
                  for (bool self : {false, true}) {
                  if (self && (disc.rfind("rigid_", 0) == 0 || mf != f)) continue;  // one surface
                  ContactCombination c;
                  c.self = self;
                  c.dimension = d;
                  c.slave_facet = f;
                  c.master_facet = mf;
                  c.discretization = disc;
                  c.passes = passes;
                  c.method = m;
                  c.friction = fr;
                  c.smoothing = sm;
                  if (check_contact_combination(c).message.empty()) out.push_back(c);
                  }
  }
  return out;
}

std::string contact_compatibility_text() {
  std::string s = "compatibility (one table; checked when a deck is read):\n";
  s += "  analysis:        plane strain, plane stress, axisymmetric, 3D\n";
  s += "  facets:          line2, line3 (2D); tri3, tri6, quad4, quad8, quad9 (3D)\n";
  s += "  discretization:  node_to_segment (passes 1 or 2), node_to_node, mortar, segment_to_segment, rigid plane / cylinder / sphere\n";
  s += "  enforcement:     lagrange, augmented_lagrangian, penalty, nitsche\n";
  s += "  friction:        none, coulomb, tresca\n";
  s += "  smoothing:       none, hermite\n";
  s += "  self-contact:    no, yes (one surface: master and slave facets the same)\n";
  s += "  every combination is available except:\n";
  for (const Rule& r : rules()) s += fmt::format("    - {} [key '{}']\n", r.when, r.key);
  s += fmt::format("  {} combinations are supported; each is checked against central differences by the "
                   "tangent grid test.\n",
                   supported_contact_combinations().size());
  return s;
}

}  // namespace signorini
