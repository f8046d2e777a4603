// Two curved, non-matching 3D surfaces for search tests and benchmarks: slave nodes on a
// wavy sheet, and a triangulated master sheet of the same shape, rotated and offset so that
// no node coincides with a master vertex.
#pragma once
#include <vector>

#include "signorini/contact/search/search.hpp"

namespace signorini {

struct SampleSurfaces {
  std::vector<Vec3> slave_nodes;
  SearchFacets master;
};

// About `slave_nodes` nodes and `master_facets` triangles (or quadrilaterals) on the unit
// square, the slave sheet `gap` above the master.
SampleSurfaces sample_surfaces(Index slave_nodes, Index master_facets, Real gap = 1e-3, bool quads = false);

}  // namespace signorini
