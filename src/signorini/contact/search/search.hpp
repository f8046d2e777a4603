// Global contact search: for each slave point, the closest master facet (exact point-facet
// distance on the facet's corners: segments in 2D, triangles in 3D, quadrilaterals as two
// triangles) within a maximal detection distance. Methods: all-to-all (the O(N M)
// reference), a bucket grid (columns across the surface, facets sorted along them) and a
// bounding volume (AABB) tree; all give the same
// answer, so the fastest is the default.
#pragma once
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"

namespace signorini {

struct SearchFacets {
  int corners = 3;           // 2 (segments), 3 (triangles) or 4 (quadrilaterals)
  std::vector<Vec3> points;  // corners, facet after facet
  Index size() const { return corners ? static_cast<Index>(points.size()) / corners : 0; }
  const Vec3* facet(Index f) const { return points.data() + f * corners; }
  Real mean_edge_length() const;
};

struct SearchHit {
  Index facet = -1;
  Real distance = std::numeric_limits<Real>::infinity();
};

// Exact distance from p to the facet (segment, triangle, or quadrilateral as two triangles).
Real point_facet_distance(const Vec3* corners, int n, const Vec3& p);

class ContactSearch {
 public:
  virtual ~ContactSearch() = default;
  virtual std::string name() const = 0;
  // May keep a reference to `facets` (all_to_all and bucket_grid read the corners from it):
  // they must stay alive and unchanged until the next build. Throws SolverError on a
  // non-finite corner (bucket_grid).
  virtual void build(const SearchFacets& facets) = 0;
  // The closest facet to every point, among those closer than max_distance (else facet -1).
  virtual void closest(const std::vector<Vec3>& points, Real max_distance, std::vector<SearchHit>& hits) const = 0;
};

std::unique_ptr<ContactSearch> make_search(const std::string& method);
const std::vector<std::string>& search_method_names();

}  // namespace signorini
