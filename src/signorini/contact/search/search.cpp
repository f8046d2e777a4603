#include "signorini/contact/search/search.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "signorini/core/error.hpp"

namespace signorini {

namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

Real point_segment_distance2(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real len2 = ab.squaredNorm();
  Real t = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (p - (a + t * ab)).squaredNorm();
}

// Squared distance to a triangle, by the Voronoi region of p: a vertex, an edge (one
// segment projection) or the interior (the distance to the plane). The regions are told
// apart by the signs of six dot products (Ericson, Real-Time Collision Detection, 2005,
// sec. 5.1.5); a degenerate (zero-area) triangle falls back to its three edges.
Real point_triangle_distance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Vec3 n = ab.cross(ac);
  const Real n2 = n.squaredNorm();
  if (!(n2 > 0))  // degenerate: coincident or collinear corners (the regions' divisions would be 0/0)
    return std::min({point_segment_distance2(p, a, b), point_segment_distance2(p, b, c), point_segment_distance2(p, c, a)});
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();  // vertex a
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();  // vertex b
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (ap - (d1 / (d1 - d3)) * ab).squaredNorm();  // edge ab
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();  // vertex c
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (ap - (d2 / (d2 - d6)) * ac).squaredNorm();  // edge ac
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return (bp - ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)).squaredNorm();  // edge bc
  if (!(va + vb + vc > 0))
    return std::min({point_segment_distance2(p, a, b), point_segment_distance2(p, b, c), point_segment_distance2(p, c, a)});
  const Real d = n.dot(ap);  // interior: the distance to the plane
  return d * d / n2;
}

// Per-facet record for the accelerated methods: centroid, bounding radius, id, corners.
struct Record {
  Vec3 centroid;
  Real radius;
  Index id;
  std::array<Vec3, 4> corners;
};

Record make_record(const SearchFacets& f, Index i) {
  Record r;
  r.id = i;
  r.centroid.setZero();
  const Vec3* c = f.facet(i);
  for (int k = 0; k < f.corners; ++k) {
    r.corners[k] = c[k];
    r.centroid += c[k];
  }
  r.centroid /= f.corners;
  r.radius = 0;
  for (int k = 0; k < f.corners; ++k) r.radius = std::max(r.radius, (c[k] - r.centroid).norm());
  return r;
}

inline Real record_distance(const Record& r, int n, const Vec3& p) { return point_facet_distance(r.corners.data(), n, p); }

// ---- all-to-all: the reference ----
class AllToAll final : public ContactSearch {
 public:
  std::string name() const override { return "all_to_all"; }
  void build(const SearchFacets& f) override { facets_ = &f; }
  void closest(const std::vector<Vec3>& pts, Real dmax, std::vector<SearchHit>& hits) const override {
    hits.assign(pts.size(), SearchHit{});
#pragma omp parallel for schedule(dynamic, 64)
    for (Index i = 0; i < static_cast<Index>(pts.size()); ++i) {
      SearchHit h;
      for (Index f = 0; f < facets_->size(); ++f) {
        const Real d = point_facet_distance(facets_->facet(f), facets_->corners, pts[i]);
        if (d < h.distance && d <= dmax) h = {f, d};
      }
      hits[i] = h;
    }
  }

 private:
  const SearchFacets* facets_ = nullptr;
};

// ---- uniform bucket grid ----
// A grid of columns: the facets are binned by centroid (counting sort) into square columns
// of about two mean edge lengths across the two axes along which the surface spreads most,
// and sorted by centroid along the third axis inside each column, so that a query visits
// only the columns near it and, in each, the slice of facets at its height (a binary
// search), however much space the surface leaves empty. The records (bounding sphere,
// corners, id) are stored contiguously in that order. A query starts from the facet closest
// to the previous point of the same thread (neighbouring nodes have neighbouring answers),
// then visits only what can still hold a closer facet, pruning by bounding sphere before
// the exact distance.
class BucketGrid final : public ContactSearch {
 public:
  std::string name() const override { return "bucket_grid"; }
  void build(const SearchFacets& f) override {
    corners_ = f.corners;
    const Index n = f.size();
    // Buffers keep their capacity between builds: re-detection in a later increment
    // allocates nothing.
    cell_of_.resize(n);
    Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    Real rmax = 0, edge_sum = 0;
    const int edges = f.corners == 2 ? 1 : f.corners;
    // Bounds, largest radius and edge sum by fixed blocks, combined in block order: the same
    // sum (so the same cells, and the same answers at ties) whatever the number of threads.
    const Index block = 4096, nb = (n + block - 1) / block;
    std::vector<Vec3> blo(nb, Vec3::Constant(kInf)), bhi(nb, Vec3::Constant(-kInf));
    std::vector<Real> br(nb, 0), be(nb, 0);
#pragma omp parallel for schedule(static)
    for (Index k = 0; k < nb; ++k)
      for (Index i = k * block; i < std::min(n, (k + 1) * block); ++i) {
        const Vec3 m = centroid(f, i);
        const Vec3* c = f.facet(i);
        Real r2 = 0;
        for (int q = 0; q < f.corners; ++q) r2 = std::max(r2, (c[q] - m).squaredNorm());
        for (int q = 0; q < edges; ++q) be[k] += (c[(q + 1) % f.corners] - c[q]).norm();
        blo[k] = blo[k].cwiseMin(m);
        bhi[k] = bhi[k].cwiseMax(m);
        br[k] = std::max(br[k], r2);
      }
    for (Index k = 0; k < nb; ++k) {
      lo = lo.cwiseMin(blo[k]);
      hi = hi.cwiseMax(bhi[k]);
      rmax = std::max(rmax, br[k]);
      edge_sum += be[k];
    }
    lo_ = lo;
    spheres_.resize(n);
    corner_data_.resize(n * f.corners);
    ids_.resize(n);
    position_.resize(n);
    if (n == 0) return;
    // The sorted axis: the one along which the centroids spread least.
    const Vec3 ext = hi - lo;
    axis_ = 0;
    for (int d = 1; d < 3; ++d)
      if (ext(d) < ext(axis_)) axis_ = d;
    u_ = (axis_ + 1) % 3, v_ = (axis_ + 2) % 3;
    const Real mean_edge = edge_sum / (static_cast<Real>(n) * edges);
    cell_ = std::max(2 * mean_edge, 1e-12 * std::max(1.0, ext.norm()));
    auto set_dims = [&] {
      dims_[0] = std::max<Index>(1, static_cast<Index>(ext(u_) / cell_) + 1);
      dims_[1] = std::max<Index>(1, static_cast<Index>(ext(v_) / cell_) + 1);
    };
    set_dims();
    // Keep the number of columns in proportion to the facets (thin or sparse surfaces).
    while (dims_[0] * dims_[1] > 2 * n + 8) {
      cell_ *= 1.5;
      set_dims();
    }
    const Index ncol = dims_[0] * dims_[1];
    // Binned by the centre as stored (single precision), which the pruning measures from.
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) cell_of_[i] = column_index(centroid(f, i).cast<float>().cast<Real>());
    // Counting sort of the facets by column (start_ shifted by one during the fill, then back).
    start_.assign(ncol + 1, 0);
    for (Index i = 0; i < n; ++i) ++start_[cell_of_[i] + 1];
    for (Index c = 0; c < ncol; ++c) start_[c + 1] += start_[c];
    for (Index i = 0; i < n; ++i) position_[i] = start_[cell_of_[i]]++;
    for (Index c = ncol; c > 0; --c) start_[c] = start_[c - 1];
    start_[0] = 0;
    // The records, then each column sorted along the axis (its facets are few).
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) write_record(f, i, position_[i]);
#pragma omp parallel
    {
      std::vector<std::pair<float, Index>> key;  // (height, facet id), per thread
      std::vector<Sphere> sp;
      std::vector<Vec3> corners;
      std::vector<Index> id;
#pragma omp for schedule(dynamic, 256)
      for (Index c = 0; c < ncol; ++c) {
        const Index b = start_[c], e = start_[c + 1];
        if (e - b < 2) continue;
        key.clear();
        for (Index r = b; r < e; ++r) key.emplace_back(spheres_[r].c[axis_], r);
        // By height, then by slot: the same order whatever the threads (the fill is serial).
        std::sort(key.begin(), key.end());
        sp.assign(spheres_.begin() + b, spheres_.begin() + e);
        corners.assign(corner_data_.begin() + b * corners_, corner_data_.begin() + e * corners_);
        id.assign(ids_.begin() + b, ids_.begin() + e);
        for (Index k = 0; k < e - b; ++k) {
          const Index from = key[k].second - b;
          spheres_[b + k] = sp[from];
          ids_[b + k] = id[from];
          for (int j = 0; j < corners_; ++j) corner_data_[(b + k) * corners_ + j] = corners[from * corners_ + j];
        }
      }
    }
    float r = 0;
    for (const Sphere& sp : spheres_) r = std::max(r, sp.r);
    rmax_ = r;
#pragma omp parallel for schedule(static)
    for (Index k = 0; k < n; ++k) position_[ids_[k]] = k;
  }

  void closest(const std::vector<Vec3>& pts, Real dmax, std::vector<SearchHit>& hits) const override {
    hits.assign(pts.size(), SearchHit{});
    if (spheres_.empty()) return;
#pragma omp parallel
    {
      Index hint = -1;
#pragma omp for schedule(static)
      for (Index i = 0; i < static_cast<Index>(pts.size()); ++i) {
        hits[i] = query(pts[i], dmax, hint);
        if (hits[i].facet >= 0) hint = position_[hits[i].facet];
      }
    }
  }

 private:
  // Bounding spheres in single precision (half the memory traffic of the hot loop); the
  // radius is measured from the rounded centre and rounded up, so pruning stays exact.
  struct Sphere {
    float c[3];
    float r;
  };

  Vec3 centroid(const SearchFacets& f, Index i) const {
    const Vec3* c = f.facet(i);
    Vec3 m = Vec3::Zero();
    for (int q = 0; q < f.corners; ++q) m += c[q];
    return m / f.corners;
  }
  void write_record(const SearchFacets& f, Index i, Index k) {
    const Vec3* c = f.facet(i);
    const Vec3 m = centroid(f, i);
    Sphere& sp = spheres_[k];
    Vec3 cf;
    for (int d = 0; d < 3; ++d) {
      sp.c[d] = static_cast<float>(m(d));
      cf(d) = sp.c[d];
    }
    Real r2 = 0;
    for (int j = 0; j < f.corners; ++j) {
      corner_data_[k * f.corners + j] = c[j];
      r2 = std::max(r2, (c[j] - cf).squaredNorm());
    }
    sp.r = std::nextafter(static_cast<float>(std::sqrt(r2)), std::numeric_limits<float>::infinity());
    ids_[k] = i;
  }
  Index coord(Real x, int d, Index dim) const {
    return std::clamp<Index>(static_cast<Index>(std::floor((x - lo_(d)) / cell_)), 0, dim - 1);
  }
  Index column_index(const Vec3& x) const { return coord(x(v_), v_, dims_[1]) * dims_[0] + coord(x(u_), u_, dims_[0]); }
  // Best facet among those that can be closer than `limit`.
  void scan(const Vec3& p, SearchHit& best, Real limit) const {
    const Real reach = limit + rmax_;
    const Index ulo = coord(p(u_) - reach, u_, dims_[0]), uhi = coord(p(u_) + reach, u_, dims_[0]);
    const Index vlo = coord(p(v_) - reach, v_, dims_[1]), vhi = coord(p(v_) + reach, v_, dims_[1]);
    const int a = axis_;
    const Real alo = p(a) - reach, ahi = p(a) + reach;
    Real bound = limit;
    for (Index j = vlo; j <= vhi; ++j)
      for (Index c = j * dims_[0] + ulo; c <= j * dims_[0] + uhi; ++c) {
        // The first facet of the column at height alo or above.
        Index r = start_[c], e = start_[c + 1];
        for (Index len = e - r; len > 0;) {
          const Index half = len / 2;
          if (static_cast<Real>(spheres_[r + half].c[a]) < alo) r += half + 1, len -= half + 1;
          else len = half;
        }
        for (; r < e; ++r) {
          const Sphere& sp = spheres_[r];
          if (static_cast<Real>(sp.c[a]) > ahi) break;
          const Real reach_r = bound + sp.r;
          const Real dx = p(0) - sp.c[0], dy = p(1) - sp.c[1], dz = p(2) - sp.c[2];
          if (dx * dx + dy * dy + dz * dz > reach_r * reach_r) continue;
          const Real d = point_facet_distance(corner_data_.data() + r * corners_, corners_, p);
          // At a tie the lower facet id: the answer does not depend on the visiting order.
          if (d < bound || (d == bound && (d < best.distance || ids_[r] < best.facet))) {
            bound = d;
            best = {ids_[r], d};
          }
        }
      }
  }
  SearchHit query(const Vec3& p, Real dmax, Index hint) const {
    SearchHit best;
    if (hint >= 0) {
      const Real d = point_facet_distance(corner_data_.data() + hint * corners_, corners_, p);
      if (d <= dmax) {
        best = {ids_[hint], d};
        scan(p, best, d);
        return best;
      }
    }
    // No usable hint: grow the search radius until a facet is found or dmax is reached.
    for (Real r = cell_;; r *= 2) {
      const Real limit = std::min(r, dmax);
      scan(p, best, std::nextafter(limit, kInf));
      if (best.facet >= 0 || limit >= dmax) return best;
    }
  }

  int corners_ = 3;
  int axis_ = 2, u_ = 0, v_ = 1;    // the sorted axis and the two axes of the columns
  std::vector<Sphere> spheres_;     // bounding spheres in column order (the hot loop)
  std::vector<Vec3> corner_data_;   // corners in the same order
  std::vector<Index> ids_;          // facet id of each slot
  std::vector<Index> start_, position_, cell_of_;
  Vec3 lo_ = Vec3::Zero();
  Real cell_ = 1, rmax_ = 0;
  Index dims_[2] = {1, 1};
};

// ---- AABB tree ----
class AabbTree final : public ContactSearch {
 public:
  std::string name() const override { return "bvh"; }
  void build(const SearchFacets& f) override {
    corners_ = f.corners;
    const Index n = f.size();
    records_.resize(n);
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) records_[i] = make_record(f, i);
    nodes_.clear();
    if (n == 0) return;
    nodes_.reserve(2 * n / kLeaf + 2);
    build_node(0, n);
    position_.resize(n);
    for (Index k = 0; k < n; ++k) position_[records_[k].id] = k;
  }
  void closest(const std::vector<Vec3>& pts, Real dmax, std::vector<SearchHit>& hits) const override {
    hits.assign(pts.size(), SearchHit{});
    if (records_.empty()) return;
#pragma omp parallel
    {
      Index hint = -1;
      std::vector<Index> stack;
#pragma omp for schedule(static)
      for (Index i = 0; i < static_cast<Index>(pts.size()); ++i) {
        const Vec3& p = pts[i];
        SearchHit best;
        Real bound = std::nextafter(dmax, kInf);
        if (hint >= 0) {
          const Real d = record_distance(records_[hint], corners_, p);
          if (d <= dmax) {
            best = {records_[hint].id, d};
            bound = d;
          }
        }
        stack.assign(1, 0);
        while (!stack.empty()) {
          const Node& nd = nodes_[stack.back()];
          stack.pop_back();
          if (box_distance(nd, p) > bound) continue;
          if (nd.left < 0) {
            for (Index r = nd.begin; r < nd.end; ++r) {
              const Record& rec = records_[r];
              const Real d = record_distance(rec, corners_, p);
              if (d < bound || (d == bound && (d < best.distance || rec.id < best.facet))) {
                bound = d;
                best = {rec.id, d};
              }
            }
          } else {
            // Visit the nearer child first.
            const Index a = nd.left, b = nd.right;
            const bool a_first = box_distance(nodes_[a], p) <= box_distance(nodes_[b], p);
            stack.push_back(a_first ? b : a);
            stack.push_back(a_first ? a : b);
          }
        }
        hits[i] = best;
        if (best.facet >= 0) hint = position_[best.facet];
      }
    }
  }

 private:
  static constexpr Index kLeaf = 4;
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    Index begin = 0, end = 0;
    Index left = -1, right = -1;
  };
  static Real box_distance(const Node& n, const Vec3& p) {
    return (p - p.cwiseMax(n.lo).cwiseMin(n.hi)).norm();
  }
  Index build_node(Index begin, Index end) {
    const Index id = static_cast<Index>(nodes_.size());
    nodes_.push_back(Node{});
    Vec3 lo = Vec3::Constant(kInf), hi = -lo, clo = lo, chi = hi;
    for (Index r = begin; r < end; ++r) {
      for (int k = 0; k < corners_; ++k) {
        lo = lo.cwiseMin(records_[r].corners[k]);
        hi = hi.cwiseMax(records_[r].corners[k]);
      }
      clo = clo.cwiseMin(records_[r].centroid);
      chi = chi.cwiseMax(records_[r].centroid);
    }
    nodes_[id].lo = lo;
    nodes_[id].hi = hi;
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    if (end - begin <= kLeaf) return id;
    int axis;
    (chi - clo).maxCoeff(&axis);
    const Index mid = (begin + end) / 2;
    std::nth_element(records_.begin() + begin, records_.begin() + mid, records_.begin() + end,
                     [axis](const Record& a, const Record& b) { return a.centroid(axis) < b.centroid(axis); });
    const Index l = build_node(begin, mid);
    const Index r = build_node(mid, end);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }
  int corners_ = 3;
  std::vector<Record> records_;
  std::vector<Node> nodes_;
  std::vector<Index> position_;
};

}  // namespace

Real SearchFacets::mean_edge_length() const {
  const Index n = size();
  if (n == 0) return 0;
  Real s = 0;
  const int edges = corners == 2 ? 1 : corners;
  for (Index f = 0; f < n; ++f) {
    const Vec3* c = facet(f);
    for (int k = 0; k < edges; ++k) s += (c[(k + 1) % corners] - c[k]).norm();
  }
  return s / (n * edges);
}

Real point_facet_distance(const Vec3* c, int n, const Vec3& p) {
  if (n == 2) return std::sqrt(point_segment_distance2(p, c[0], c[1]));
  if (n == 3) return std::sqrt(point_triangle_distance2(p, c[0], c[1], c[2]));
  return std::sqrt(std::min(point_triangle_distance2(p, c[0], c[1], c[2]), point_triangle_distance2(p, c[0], c[2], c[3])));
}

const std::vector<std::string>& search_method_names() {
  static const std::vector<std::string> n{"bucket_grid", "bvh", "all_to_all"};
  return n;
}

std::unique_ptr<ContactSearch> make_search(const std::string& method) {
  if (method == "bucket_grid") return std::make_unique<BucketGrid>();
  if (method == "bvh") return std::make_unique<AabbTree>();
  if (method == "all_to_all") return std::make_unique<AllToAll>();
  throw Error("unknown search method '" + method + "' (bucket_grid, bvh, all_to_all)");
}

}  // namespace signorini
