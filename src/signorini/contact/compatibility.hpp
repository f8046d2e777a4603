// One table of what a contact pair may combine: analysis (plane strain, plane stress,
// axisymmetric, 3D) x slave and master facet types x discretization (node-to-segment with one
// or two passes, node-to-node, or a rigid plane, cylinder or sphere) x enforcement x friction
// x smoothing. Each unsupported combination has a rule with its own message; what no rule
// excludes is supported. The deck reader checks a pair once at set-up (the message then names
// the deck's file, line and key), so does ContactInterface for pairs built in code;
// `signorini describe contact` prints the table and docs/contact.md quotes it; the
// finite-difference tangent grid (tests/unit/test_contact_tangent_grid.cpp) runs every
// combination the table allows.
#pragma once
#include <string>
#include <vector>

#include "signorini/contact/contact_settings.hpp"
#include "signorini/fem/analysis_settings.hpp"
#include "signorini/mesh/mesh.hpp"
#include "signorini/mesh/element_type.hpp"

namespace signorini {

struct ContactCombination {
  Dimension dimension = Dimension::plane_strain;
  ElementType slave_facet = ElementType::line2;
  ElementType master_facet = ElementType::line2;  // ignored for a rigid obstacle
  // node_to_segment, node_to_node, mortar, rigid_plane, rigid_cylinder, rigid_sphere
  std::string discretization = "node_to_segment";
  int passes = 1;
  std::string method = "lagrange";  // lagrange, augmented_lagrangian, penalty
  std::string friction = "none";    // none, coulomb, tresca
  std::string smoothing = "none";   // none, hermite
  bool self = false;                // self-contact (one surface, slave and master)
  std::string slave_set, master_set;  // the facet sets, for messages (may be empty)
  bool rigid() const { return discretization.rfind("rigid_", 0) == 0; }
  std::string text() const;  // e.g. "3D, tri3 slave on quad4 master, node_to_segment, lagrange, coulomb"
};

struct CompatibilityIssue {
  std::string key;      // the deck key the rule is about (slave, master.rigid, passes, smoothing, friction, discretization)
  std::string message;  // why the combination is not available, and what to use instead
};

// The first rule the combination breaks, or an empty message when it is supported.
CompatibilityIssue check_contact_combination(const ContactCombination& c);

// The combinations a pair uses: one per slave facet type x master facet type of its surfaces.
std::vector<ContactCombination> contact_combinations(const ContactPairSettings& s, const Mesh& mesh,
                                                     Dimension dimension);
// The first of the pair's combinations the table excludes (empty message: all supported);
// `combination` gets its text. The deck reader reports it with the place, check_contact_pair
// throws it.
CompatibilityIssue first_unsupported(const ContactPairSettings& s, const Mesh& mesh, Dimension dimension,
                                     std::string* combination = nullptr);
// Throws Error naming the pair when one of its combinations is not supported.
void check_contact_pair(const ContactPairSettings& s, const Mesh& mesh, Dimension dimension);

// Every supported combination over the table's values: each slave facet type on each master
// facet type of its dimension (a rigid obstacle once per slave type).
std::vector<ContactCombination> supported_contact_combinations();

// The table as text: the values of each column, then the rules (what is not available, why).
std::string contact_compatibility_text();

}  // namespace signorini
