// The mesh: node coordinates, blocks of cells (one type and one region each), named node
// sets and named facet sets. Physical groups of a Gmsh file become these named sets.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/mesh/element_type.hpp"

namespace signorini {

// Elements of one type: connectivity (num_nodes per element, node indices into
// Mesh::nodes) and the ids the user knows them by (Gmsh tags).
struct ElementBlock {
  ElementType type;
  std::vector<Index> conn;
  std::vector<Index> ids;
  Index size() const { return static_cast<Index>(ids.size()); }
  int nodes_per_element() const { return element_info(type).num_nodes; }
  const Index* element(Index e) const { return conn.data() + e * nodes_per_element(); }
  void add(const std::vector<Index>& nodes, Index id);
};

struct Mesh {
  int dim = 0;                          // dimension of the cells (2 or 3)
  std::vector<Vec3> nodes;              // coordinates (z = 0 in 2D)
  std::vector<Index> node_ids;          // Gmsh node tags, for messages
  std::map<std::string, std::vector<ElementBlock>> regions;     // cells by region name
  std::map<std::string, std::vector<ElementBlock>> facet_sets;  // facets by set name
  std::map<std::string, std::vector<Index>> node_sets;          // sorted node indices

  Index num_nodes() const { return static_cast<Index>(nodes.size()); }
  // Every cell read, those handed over to bodies (take_region) included.
  Index num_cells() const;
  // Moves a region's cells out (to the body made of them), so that they are held once: the
  // region stays, by name, with no cells, and num_cells() still counts them. Throws Error for
  // a region taken twice or not in the mesh.
  std::vector<ElementBlock> take_region(const std::string& name);
  // Names of every set of the given kind, comma separated, for error messages.
  std::string region_names() const;
  std::string facet_set_names() const;
  std::string node_set_names() const;
  // Builds node sets for every region and facet set that has none of the same name.
  void complete_node_sets();

 private:
  Index taken_cells_ = 0;  // cells moved out by take_region
  std::map<std::string, bool> taken_;
};

// Lengths of the corner edges of every facet of a facet set (a line facet has one edge).
std::vector<Real> facet_edge_lengths(const std::vector<ElementBlock>& facets, const std::vector<Vec3>& nodes);

// Reports of the mesh check.
struct MeshCheck {
  std::vector<Index> inverted;    // element ids with a non-positive Jacobian somewhere
  std::vector<Index> degenerate;  // element ids with a nearly zero Jacobian
  int reoriented = 0;             // elements whose node order was mirrored (all negative)
};

// Checks every cell at its quadrature points and corners. Cells whose Jacobian is negative
// everywhere (a clockwise 2D element, a mirrored 3D one) are re-ordered and counted;
// cells with mixed signs or a Jacobian that is nearly zero are reported.
MeshCheck check_and_orient(Mesh& mesh);

// Outward orientation of facet sets: each facet is matched to the cell that owns it and
// re-ordered so that its normal points out of that cell. Facets owned by no cell of the
// mesh are left as they are. Returns the number of facets that had no owner.
Index orient_facets(Mesh& mesh);

}  // namespace signorini
