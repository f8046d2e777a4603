#include "signorini/contact/search/search.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#ifdef __SSE2__
#include <xmmintrin.h>
#endif

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
// Squared distance to a facet of N corners (2: segment, 3: triangle, 4: two triangles),
// inlined into the grid's hot loop.
template <int N>
[[gnu::always_inline]] inline Real facet_distance2(const Vec3* c, const Vec3& p) {
  if constexpr (N == 2) return point_segment_distance2(p, c[0], c[1]);
  else if constexpr (N == 3) return point_triangle_distance2(p, c[0], c[1], c[2]);
  else return std::min(point_triangle_distance2(p, c[0], c[1], c[2]), point_triangle_distance2(p, c[0], c[2], c[3]));
}

// A grid of columns: the facets are binned by centroid (counting sort) into square columns
// of about two edge lengths across the two axes along which the surface spreads most, and
// sorted by centroid along the third axis inside each column, so that a query visits only
// the columns near it and, in each, the slice of facets at its height (a binary search),
// however much space the surface leaves empty. The grid stores, in that order, each
// facet's bounding sphere and unit normal (single precision, 32 bytes) and its id. The
// corners are read from the facets given to build(), which must stay unchanged until the
// next build (the contact discretization owns them; a copy would double the memory). A
// query starts from the facet closest to the previous point of the same thread
// (neighbouring nodes have neighbouring answers), then visits only what can still hold a
// closer facet, pruning four facets at a time by a lower bound of their distance (sphere
// and plane, see test_run) before the exact distance.
// Simd = false tests every facet alone in double precision (the path taken without SSE2;
// make_search("bucket_grid_scalar") lets the tests run it everywhere).
template <bool Simd>
class BucketGrid final : public ContactSearch {
 public:
  std::string name() const override { return Simd ? "bucket_grid" : "bucket_grid_scalar"; }
  void build(const SearchFacets& f) override {
    try {
      build_grid(f);
    } catch (...) {
      ids_.clear();  // an empty grid (closest() finds nothing) rather than a half-built one
      throw;
    }
  }
  void closest(const std::vector<Vec3>& pts, Real dmax, std::vector<SearchHit>& hits) const override {
    switch (corners_) {
      case 2: return closest_n<2>(pts, dmax, hits);
      case 3: return closest_n<3>(pts, dmax, hits);
      default: return closest_n<4>(pts, dmax, hits);
    }
  }

 private:
  void build_grid(const SearchFacets& f) {
    facets_ = &f;
    corners_ = f.corners;
    const Index n = f.size();
    if (n >= std::numeric_limits<std::int32_t>::max())
      throw Error("bucket_grid search: more than 2^31 - 1 master facets (use search method bvh)");
    // The grid's buffers keep their capacity between builds: re-detection in a later
    // increment allocates only a few small arrays (per block of 4096 facets, per thread).
    ids_.resize(n);
    position_.resize(n);
    Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    Real edge2_sum = 0;
    const int edges = f.corners == 2 ? 1 : f.corners;
    // Bounds of the centroids and sum of squared edge lengths by fixed blocks, combined in
    // block order: the same sum (so the same cells, and the same answers at ties) whatever
    // the number of threads.
    const Index block = 4096, nb = (n + block - 1) / block;
    std::vector<Vec3> blo(nb, Vec3::Constant(kInf)), bhi(nb, Vec3::Constant(-kInf));
    std::vector<Real> be(nb, 0);
#pragma omp parallel for schedule(static)
    for (Index k = 0; k < nb; ++k)
      for (Index i = k * block; i < std::min(n, (k + 1) * block); ++i) {
        const Vec3* c = f.facet(i);
        for (int q = 0; q < edges; ++q) be[k] += (c[q + 1 < f.corners ? q + 1 : 0] - c[q]).squaredNorm();
        const Vec3 m = centroid(c, f.corners);
        blo[k] = blo[k].cwiseMin(m);
        bhi[k] = bhi[k].cwiseMax(m);
      }
    for (Index k = 0; k < nb; ++k) {
      lo = lo.cwiseMin(blo[k]);
      hi = hi.cwiseMax(bhi[k]);
      edge2_sum += be[k];
    }
    lo_ = lo;
    if (n == 0) return;
    // Overflow and NaN alike (a NaN or infinite corner, or one beyond 1e154) make the sum
    // non-finite: say which facet. A SolverError: in an analysis it comes from a diverging
    // iterate, and the increment is cut back.
    if (!std::isfinite(edge2_sum))
      for (Index i = 0; i < n; ++i)
        for (int q = 0; q < f.corners; ++q)
          if (!f.facet(i)[q].allFinite() || f.facet(i)[q].cwiseAbs().maxCoeff() > 1e150)
            throw SolverError(fmt::format("contact search: master facet {} has a non-finite or huge corner ({}, {}, {})", i,
                                    f.facet(i)[q](0), f.facet(i)[q](1), f.facet(i)[q](2)));
    // The sorted axis: the one along which the centroids spread least.
    const Vec3 ext = hi - lo;
    axis_ = 0;
    for (int d = 1; d < 3; ++d)
      if (ext(d) < ext(axis_)) axis_ = d;
    u_ = (axis_ + 1) % 3, v_ = (axis_ + 2) % 3;
    const int a = axis_;
    const Real edge = std::sqrt(edge2_sum / (static_cast<Real>(n) * edges));  // root mean square
    cell_ = std::max(kCellEdges * edge, 1e-12 * std::max(1.0, ext.norm()));
    auto set_dims = [&] {
      inv_cell_ = 1 / cell_;
      dims_[0] = std::max<Index>(1, static_cast<Index>(ext(u_) / cell_) + 1);
      dims_[1] = std::max<Index>(1, static_cast<Index>(ext(v_) / cell_) + 1);
    };
    set_dims();
    // Keep the number of columns in proportion to the facets (thin or sparse surfaces); the
    // product in double (tiny facets spread far apart would overflow it in integers).
    while (static_cast<double>(dims_[0]) * static_cast<double>(dims_[1]) > 2.0 * n + 8) {
      cell_ *= 1.5;
      set_dims();
    }
    const Index ncol = dims_[0] * dims_[1];
    if (ncol >= static_cast<Index>(kTall)) throw Error("bucket_grid search: too many columns (use search method bvh)");
    // Each facet's column, by its centre as stored (single precision), which the pruning
    // measures from; kept in position_ until the counting sort turns it into the slot.
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      const Eigen::Vector3f m = centre(f.facet(i), f.corners);
      position_[i] = static_cast<std::int32_t>(coord(m(v_), dims_[1]) * dims_[0] + coord(m(u_), dims_[0]));
    }
    // Counting sort of the facets by column (start_ shifted by one during the fill, then back).
    start_.assign(ncol + 1, 0);
    for (Index i = 0; i < n; ++i) ++start_[position_[i] + 1];
    for (Index c = 0; c < ncol; ++c) start_[c + 1] += start_[c];
    for (Index i = 0; i < n; ++i) position_[i] = static_cast<std::int32_t>(start_[position_[i]]++);
    for (Index c = ncol; c > 0; --c) start_[c] = start_[c - 1];
    start_[0] = 0;
    // The bounds and ids written to their column's slots, reading the facets in their order
    // (ids increasing within a column: the fill above is serial).
    bounds_.resize(n + 3);
    const float r = f.corners == 2 ? write_bounds<2>(f) : f.corners == 3 ? write_bounds<3>(f) : write_bounds<4>(f);
    // Each column sorted by height, ties by id (the same order whatever the threads). A
    // column whose facets spread along the axis by more than a cell is "tall": a query
    // slices it by height; the others are tested whole, with their neighbours in the row.
#pragma omp parallel
    {
      std::vector<std::pair<Bound, std::int32_t>> col;  // per thread
#pragma omp for schedule(dynamic, 1024)
      for (Index c = 0; c < ncol; ++c) {
        // start_[c + 1] may be flagged by another thread meanwhile: both as atomics (relaxed).
        std::atomic_ref<std::uint32_t> first(start_[c]), next(start_[c + 1]);
        const Index b = first.load(std::memory_order_relaxed) & kSlot, e = next.load(std::memory_order_relaxed) & kSlot;
        if (e - b < 2) continue;
        auto before = [a](const Bound& x, std::int32_t ix, const Bound& y, std::int32_t iy) {
          return x.c[a] < y.c[a] || (x.c[a] == y.c[a] && ix < iy);
        };
        if (e - b <= 16) {  // insertion sort in place (most columns hold a few facets)
          for (Index k = b + 1; k < e; ++k) {
            const Bound x = bounds_[k];
            const std::int32_t ix = ids_[k];
            Index q = k;
            for (; q > b && before(x, ix, bounds_[q - 1], ids_[q - 1]); --q) {
              bounds_[q] = bounds_[q - 1];
              ids_[q] = ids_[q - 1];
            }
            bounds_[q] = x;
            ids_[q] = ix;
          }
        } else {
          col.clear();
          for (Index k = b; k < e; ++k) col.emplace_back(bounds_[k], ids_[k]);
          std::sort(col.begin(), col.end(),
                    [&](const auto& x, const auto& y) { return before(x.first, x.second, y.first, y.second); });
          for (Index k = b; k < e; ++k) std::tie(bounds_[k], ids_[k]) = col[k - b];
        }
        if (bounds_[e - 1].c[a] - bounds_[b].c[a] > cell_) first.fetch_or(kTall, std::memory_order_relaxed);
      }
    }
    // The slot of each facet (the queries' hints).
#pragma omp parallel for schedule(static)
    for (Index k = 0; k < n; ++k) position_[ids_[k]] = static_cast<std::int32_t>(k);
    rmax_ = r;
    ext_max_ = ext.maxCoeff() + rmax_;
    // The column ranges are measured on p - lo_ and on centres rounded from m - lo_, both in
    // double: an allowance of a few ulps of the absolute coordinates (a surface far from the
    // origin), with the float rounding of the centres covered by the radii's round-up.
    reach_slack_ = 8 * std::numeric_limits<Real>::epsilon() * (lo.cwiseAbs().maxCoeff() + ext_max_);
    // Padding read by the four-wide test past the last slot: NaN centres never pass.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (Index k = n; k < n + 3; ++k) bounds_[k] = Bound{{nan, nan, nan}, nan, {0, 0, 0}, 0};
  }

  // What the pruning knows of a facet, in single precision (half the memory traffic of the
  // hot loop): its bounding sphere, whose radius is measured from the rounded centre and
  // rounded up; the unit normal of a plane through the centre (a triangle's own; a
  // quadrilateral's from its diagonals) and the largest distance of a corner from that plane
  // (zero for a plane facet, a quadrilateral's warp otherwise: the facet lies in that slab).
  // The normal is zero for segments and degenerate facets: the test is then the sphere's.
  struct Bound {
    float c[3];
    float r;
    float n[3];
    float slab;
  };

  static Vec3 centroid(const Vec3* c, int corners) {
    Vec3 m = Vec3::Zero();
    for (int q = 0; q < corners; ++q) m += c[q];
    return m * (1.0 / corners);
  }
  // The centre of a facet as stored: relative to the grid's lower corner lo_, in single
  // precision (the same bits wherever it is computed).
  Eigen::Vector3f centre(const Vec3* c, int corners) const { return (centroid(c, corners) - lo_).cast<float>(); }
  template <int N>
  Bound make_bound(const Vec3* c) const {
    Bound b;
    const Eigen::Vector3f m = centre(c, N);
    const Vec3 cf = m.cast<Real>() + lo_;  // the stored centre, in absolute coordinates
    Real r2 = 0;
    for (int j = 0; j < N; ++j) r2 = std::max(r2, (c[j] - cf).squaredNorm());
    // Rounded up: float() and sqrtf err by 2^-24 relative at most, the product too,
    // (1 + 2^-21) more.
    b.r = std::sqrt(static_cast<float>(r2)) * (1 + 0x1p-21f);
    Vec3 nrm = Vec3::Zero();
    if constexpr (N == 3) nrm = (c[1] - c[0]).cross(c[2] - c[0]);
    if constexpr (N == 4) nrm = (c[2] - c[0]).cross(c[3] - c[1]);
    const Real len = nrm.norm();
    if (len > 0) nrm *= 1 / len;
    for (int d = 0; d < 3; ++d) {
      b.c[d] = m(d);
      b.n[d] = static_cast<float>(nrm(d));
    }
    // The slab about the stored plane (the rounded normal), rounded up like the radius.
    const Vec3 nf(b.n[0], b.n[1], b.n[2]);
    Real slab = 0;
    if (len > 0)
      for (int j = 0; j < N; ++j) slab = std::max(slab, std::abs(nf.dot(c[j] - cf)));
    b.slab = static_cast<float>(slab) * (1 + 0x1p-21f);
    return b;
  }
  // The bounds and ids written to their column's slots (position_), reading the facets in
  // their order; the largest radius.
  template <int N>
  float write_bounds(const SearchFacets& f) {
    float r = 0;
    const Index n = f.size();
#pragma omp parallel for schedule(static) reduction(max : r)
    for (Index i = 0; i < n; ++i) {
      const Index k = position_[i];
      // The slots are scattered: fetch ahead the lines written a few facets later.
      if (i + 16 < n) {
        __builtin_prefetch(&bounds_[position_[i + 16]], 1);
        __builtin_prefetch(&ids_[position_[i + 16]], 1);
      }
      const Bound bd = make_bound<N>(f.facet(i));
      bounds_[k] = bd;
      ids_[k] = static_cast<std::int32_t>(i);
      r = std::max(r, bd.r);
    }
    return r;
  }
  // The cell of coordinate x (relative to lo_), clamped to the grid (no floor needed:
  // below 0 is 0).
  Index coord(Real x, Index dim) const {
    const Real t = x * inv_cell_;
    if (!(t > 0)) return 0;
    return t < static_cast<Real>(dim - 1) ? static_cast<Index>(t) : dim - 1;
  }
  // The best facet so far: its distance, and a bound on its square that is never below
  // the square of a distance that could still win (squared distances are compared first,
  // the square root taken only for a facet that may be closer).
  struct Best {
    SearchHit hit;
    Real bound, bound2;
    void set_bound(Real b) {
      bound = b;
      bound2 = b * b * (1 + 1e-12);
    }
  };
  template <int N>
  [[gnu::always_inline]] inline void consider(Index r, const Vec3& p, Best& b) const {
    const std::int32_t id = ids_[r];
    const Real d2 = facet_distance2<N>(facets_->facet(id), p);
    if (d2 > b.bound2) return;
    const Real d = std::sqrt(d2);
    // At a tie the lower facet id: the answer does not depend on the visiting order.
    if (d < b.bound || (d == b.bound && (d < b.hit.distance || id < b.hit.facet))) {
      b.set_bound(d);
      b.hit = {id, d};
    }
  }
  // The first slot of [r, e) whose height is above h (or at/above it), by binary search.
  Index first_above(Index r, Index e, Real h, bool or_equal) const {
    const int a = axis_;
    for (Index len = e - r; len > 0;) {
      const Index half = len / 2;
      const Real x = bounds_[r + half].c[a];
      if (x < h || (!or_equal && x == h)) r += half + 1, len -= half + 1;
      else len = half;
    }
    return r;
  }
  // Best facet among those that can be closer than b.bound to p; q is p relative to lo_.
  // The row of columns holding p first, then outwards on either side: each row's extent is
  // that of the best distance found so far, which the nearest rows usually settle.
  template <int N>
  void scan(const Vec3& p, const Vec3& q, Best& b) const {
    const Real x = std::max(ext_max_, q.cwiseAbs().maxCoeff());  // scale of the test's rounding
    const Index jc = coord(q(v_), dims_[1]);
    auto reach = [&] { return b.bound + rmax_ + reach_slack_; };
    for (Index j = jc; j >= 0 && j >= coord(q(v_) - reach(), dims_[1]); --j) scan_row<N>(j, p, q, x, b);
    for (Index j = jc + 1; j < dims_[1] && j <= coord(q(v_) + reach(), dims_[1]); ++j) scan_row<N>(j, p, q, x, b);
  }
  // The columns of row j that can hold a facet closer than b.bound: the slices of the tall
  // ones at the query's height, the others whole, merged where contiguous.
  template <int N>
  void scan_row(Index j, const Vec3& p, const Vec3& q, Real x, Best& b) const {
    const Real reach = b.bound + rmax_ + reach_slack_;
    const Index c0 = j * dims_[0] + coord(q(u_) - reach, dims_[0]), c1 = j * dims_[0] + coord(q(u_) + reach, dims_[0]);
    const int a = axis_;
    const Real alo = q(a) - reach, ahi = q(a) + reach;
    Index rb = start_[c0] & kSlot, re = rb;  // the run of whole columns
    for (Index c = c0; c <= c1; ++c) {
      const std::uint32_t sc = start_[c];
      const Index e = start_[c + 1] & kSlot;
      if (!(sc & kTall)) {
        re = e;
        continue;
      }
      test_run<N>(rb, re, p, q, x, b);
      Index r = sc & kSlot, rend = e;
      if (bounds_[r].c[a] < alo) r = first_above(r, rend, alo, true);
      if (r < rend && bounds_[rend - 1].c[a] > ahi) rend = first_above(r, rend, ahi, false);
      test_run<N>(r, rend, p, q, x, b);
      rb = re = e;
    }
    test_run<N>(rb, re, p, q, x, b);
  }

  // The facets of slots [rb, re) that can be closer than b.bound get their exact distance.
  // A facet within the sphere of radius r about c and within the slab |n.(x - c)| <= s (n a
  // unit normal) is at a distance d >= sqrt(max(0, |h| - s)^2 + max(0, rho - r)^2) from p,
  // where h = n.(p - c) and rho is the length of (p - c) - h n, the in-plane offset (rho =
  // |p - c| and the bound is the sphere's when n = 0). r and s are measured in double from
  // the stored (rounded) centre and normal and rounded up. The test runs in single
  // precision on coordinates relative to lo_, whose size x is that of the surface, not of
  // its position: p is rounded (2^-24 relative) and so is the arithmetic (a few
  // 2^-24 (x + |d|)). h and rho are lowered by tol = 2^-16 (x + bound), about five times
  // what these errors add up to (counted, and replayed in float on 1e5 point-triangle
  // pairs), and the squared reach is enlarged by 1e-5 relative: no facet that can be closer
  // is skipped (a few more are measured exactly). With SSE2 four facets are tested at once; bounds_ is
  // padded with three records that never pass, so a group of four may run past re: the
  // extra slots are real facets or padding, and measuring a real facet is always correct.
  template <int N>
  [[gnu::always_inline]] inline void test_run(Index rb, Index re, const Vec3& p, const Vec3& q, Real x, Best& b) const {
    const float tol = to_float(0x1p-16 * (x + b.bound));
#ifdef __SSE2__
    if constexpr (Simd) {
      const __m128 px = _mm_set1_ps(to_float(q(0))), py = _mm_set1_ps(to_float(q(1))), pz = _mm_set1_ps(to_float(q(2))), tl = _mm_set1_ps(tol), zero = _mm_setzero_ps(),
                   sign = _mm_set1_ps(-0.0f);
      __m128 reach = _mm_set1_ps(reach2(b.bound));  // updated when the bound shrinks
      for (Index k = rb; k < re; k += 4) {
        __m128 cx = _mm_loadu_ps(bounds_[k].c), cy = _mm_loadu_ps(bounds_[k + 1].c), cz = _mm_loadu_ps(bounds_[k + 2].c),
               r = _mm_loadu_ps(bounds_[k + 3].c);
        _MM_TRANSPOSE4_PS(cx, cy, cz, r);  // centres' x, y, z and the radii of the four
        __m128 nx = _mm_loadu_ps(bounds_[k].n), ny = _mm_loadu_ps(bounds_[k + 1].n),
               nz = _mm_loadu_ps(bounds_[k + 2].n), slab = _mm_loadu_ps(bounds_[k + 3].n);
        _MM_TRANSPOSE4_PS(nx, ny, nz, slab);
        const __m128 dx = _mm_sub_ps(px, cx), dy = _mm_sub_ps(py, cy), dz = _mm_sub_ps(pz, cz);
        const __m128 h = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, nx), _mm_mul_ps(dy, ny)), _mm_mul_ps(dz, nz));
        const __m128 ex = _mm_sub_ps(dx, _mm_mul_ps(h, nx)), ey = _mm_sub_ps(dy, _mm_mul_ps(h, ny)),
                     ez = _mm_sub_ps(dz, _mm_mul_ps(h, nz));
        const __m128 rho = _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(ex, ex), _mm_mul_ps(ey, ey)), _mm_mul_ps(ez, ez)));
        const __m128 t = _mm_max_ps(zero, _mm_sub_ps(_mm_sub_ps(rho, r), tl));
        const __m128 hl = _mm_max_ps(zero, _mm_sub_ps(_mm_sub_ps(_mm_andnot_ps(sign, h), tl), slab));
        const __m128 lower2 = _mm_add_ps(_mm_mul_ps(hl, hl), _mm_mul_ps(t, t));
        int m = _mm_movemask_ps(_mm_cmple_ps(lower2, reach));
        if (m) {
          for (; m; m &= m - 1) consider<N>(k + __builtin_ctz(m), p, b);
          reach = _mm_set1_ps(reach2(b.bound));
        }
      }
      return;
    }
#endif
    for (Index k = rb; k < re; ++k) {
      const Bound& f = bounds_[k];
      const Vec3 d(q(0) - f.c[0], q(1) - f.c[1], q(2) - f.c[2]);
      const Vec3 nrm(f.n[0], f.n[1], f.n[2]);
      const Real h = nrm.dot(d);
      const Real t = std::max(0.0, (d - h * nrm).norm() - f.r - tol), hl = std::max(0.0, std::abs(h) - tol - f.slab);
      if (hl * hl + t * t <= reach2(b.bound)) consider<N>(k, p, b);
    }
  }
  // The squared reach of the test, enlarged for its rounding.
  static float reach2(Real bound) {
    const float r = to_float(bound);
    return r * r * (1 + 1e-5f);
  }
  // A bound or coordinate in single precision: beyond the float range it is the largest
  // float (a bound that passes every test), not an undefined conversion.
  static float to_float(Real x) {
    constexpr Real m = std::numeric_limits<float>::max();
    return static_cast<float>(std::clamp<Real>(x, -m, m));
  }
  template <int N>
  SearchHit query(const Vec3& p, Real dmax, Index hint) const {
    const Vec3 q = p - lo_;
    Best b;
    if (hint >= 0) {
      const Real d = std::sqrt(facet_distance2<N>(facets_->facet(ids_[hint]), p));
      if (d <= dmax) {
        b.hit = {ids_[hint], d};
        b.set_bound(d);
        scan<N>(p, q, b);
        return b.hit;
      }
    }
    // No usable hint: grow the search radius until a facet is found or dmax is reached.
    for (Real r = cell_;; r *= 2) {
      const Real limit = std::min(r, dmax);
      b.set_bound(std::nextafter(limit, kInf));
      scan<N>(p, q, b);
      if (b.hit.facet >= 0 || limit >= dmax) return b.hit;
    }
  }
  template <int N>
  void closest_n(const std::vector<Vec3>& pts, Real dmax, std::vector<SearchHit>& hits) const {
    hits.assign(pts.size(), SearchHit{});
    if (ids_.empty()) return;
#pragma omp parallel
    {
      Index hint = -1;
#pragma omp for schedule(static)
      for (Index i = 0; i < static_cast<Index>(pts.size()); ++i) {
        hits[i] = query<N>(pts[i], dmax, hint);
        if (hits[i].facet >= 0) hint = position_[hits[i].facet];
      }
    }
  }

  const SearchFacets* facets_ = nullptr;
  int corners_ = 3;
  int axis_ = 2, u_ = 0, v_ = 1;      // the sorted axis and the two axes of the columns
  std::vector<Bound> bounds_;         // in column order (the hot loop), three padding records
  std::vector<std::int32_t> ids_;       // facet id of each slot
  std::vector<std::int32_t> position_;  // slot of each facet
  // First slot of each column (kSlot bits), and kTall if the column is sliced by height.
  static constexpr std::uint32_t kTall = 0x80000000u, kSlot = 0x7fffffffu;
  // Column width in root-mean-square edge lengths (measured on the benchmark: 0.7 to 2
  // within 15 %).
  static constexpr Real kCellEdges = 0.7;
  std::vector<std::uint32_t> start_;
  Vec3 lo_ = Vec3::Zero();
  Real cell_ = 1, inv_cell_ = 1, rmax_ = 0, ext_max_ = 0;  // ext_max_: the grid's size
  Real reach_slack_ = 0;                                  // rounding allowance of the column ranges
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
  return std::sqrt(n == 2 ? facet_distance2<2>(c, p) : n == 3 ? facet_distance2<3>(c, p) : facet_distance2<4>(c, p));
}

const std::vector<std::string>& search_method_names() {
  static const std::vector<std::string> n{"bucket_grid", "bvh", "all_to_all"};
  return n;
}

std::unique_ptr<ContactSearch> make_search(const std::string& method) {
  if (method == "bucket_grid") return std::make_unique<BucketGrid<true>>();
  if (method == "bucket_grid_scalar") return std::make_unique<BucketGrid<false>>();  // for the tests
  if (method == "bvh") return std::make_unique<AabbTree>();
  if (method == "all_to_all") return std::make_unique<AllToAll>();
  throw Error("unknown search method '" + method + "' (bucket_grid, bvh, all_to_all)");
}

}  // namespace signorini
