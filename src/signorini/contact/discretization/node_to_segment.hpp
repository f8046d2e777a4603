// Discretizations that turn contact geometry into constraints, one per slave node.
// Node-to-segment: the slave node against the closest projection on the master facets
// around its search candidate; where no projection falls inside a facet (convex corners,
// blind spots), against the closest point of an edge (node-to-edge, 3D) or the nearest
// master vertex (node-to-vertex). Node-to-node: against
// a master node, along the master's averaged normal frozen at detection (matching meshes).
#pragma once
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/surface.hpp"

namespace signorini {

// candidate[j]: master facet found by the search for slave node j (-1: none). excluded
// (self-contact): per slave node, the sorted master facets it must not be constrained against
// (its own and their neighbours); null: none.
// held: per slave node, a master facet to keep while the node projects onto it up to
// kHeldFacetTolerance beyond its edges (-1: the closest facet; null: none held).
void node_to_segment(const MasterSurface& master, const SlaveSurface& slave, const std::vector<Vec3>& x, int dim,
                     const std::vector<Index>& candidate, ConstraintSet& out,
                     const std::vector<std::vector<Index>>* excluded = nullptr,
                     const std::vector<Index>* held = nullptr);
// How far beyond its edges (in facet parameters) a held facet keeps its node (`held`).
constexpr Real kHeldFacetTolerance = 0.1;

// master_node[j]: the master node paired with slave node j (-1: none); normal[j]: its normal.
void node_to_node(const SlaveSurface& slave, const std::vector<Index>& master_node, const std::vector<Vec3>& normal,
                  const std::vector<Vec3>& x, int dim, ConstraintSet& out);

}  // namespace signorini
