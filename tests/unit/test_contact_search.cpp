// Contact search: every method returns the same closest facet distance as all-to-all, on
// curved non-matching surfaces, on random triangle soups, on 2D segments and quadrilaterals,
// with and without a detection distance; point-facet distances against brute force.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <limits>

#include "signorini/contact/search/sample_surfaces.hpp"
#include "signorini/core/error.hpp"

using namespace signorini;

namespace {

void expect_all_agree(const SearchFacets& facets, const std::vector<Vec3>& pts, Real dmax, const std::string& what) {
  auto ref_search = make_search("all_to_all");
  ref_search->build(facets);
  std::vector<SearchHit> ref;
  ref_search->closest(pts, dmax, ref);
  Index found = 0;
  for (auto& h : ref) found += h.facet >= 0;
  EXPECT_GT(found, 0) << what;
  // bucket_grid_scalar: the grid without SSE2 (what other processors run).
  for (const char* m : {"bucket_grid", "bucket_grid_scalar", "bvh"}) {
    auto s = make_search(m);
    for (int pass = 0; pass < 2; ++pass) {  // the second build reuses buffers
      s->build(facets);
      std::vector<SearchHit> hits;
      s->closest(pts, dmax, hits);
      ASSERT_EQ(hits.size(), ref.size());
      for (size_t i = 0; i < pts.size(); ++i) {
        ASSERT_EQ(hits[i].facet < 0, ref[i].facet < 0) << what << " " << m << " point " << i;
        if (ref[i].facet >= 0) {
          EXPECT_NEAR(hits[i].distance, ref[i].distance, 1e-15) << what << " " << m << " point " << i;
          // The facet found is at that distance (ties between facets may pick either).
          EXPECT_NEAR(point_facet_distance(facets.facet(hits[i].facet), facets.corners, pts[i]), ref[i].distance, 1e-15);
        }
      }
    }
  }
}

unsigned g_seed = 4242;
Real rnd() {
  g_seed = g_seed * 1664525u + 1013904223u;
  return (g_seed >> 8) / static_cast<Real>(1u << 24);
}

}  // namespace

TEST(ContactSearch, CurvedNonMatchingSurfaces) {
  SampleSurfaces s = sample_surfaces(3000, 4000);
  const Real h = s.master.mean_edge_length();
  expect_all_agree(s.master, s.slave_nodes, 2 * h, "curved, d_max = 2h");
  expect_all_agree(s.master, s.slave_nodes, 1.05e-3, "curved, d_max near the 1e-3 offset (some found)");
  expect_all_agree(s.master, s.slave_nodes, 10.0, "curved, large d_max");
}

TEST(ContactSearch, RandomTriangleSoupAndQuads) {
  SearchFacets tris;
  tris.corners = 3;
  for (int f = 0; f < 600; ++f) {
    const Vec3 c(rnd(), rnd(), rnd());
    for (int k = 0; k < 3; ++k) tris.points.push_back(c + 0.08 * Vec3(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5));
  }
  std::vector<Vec3> pts;
  for (int i = 0; i < 800; ++i) pts.emplace_back(1.2 * rnd() - 0.1, 1.2 * rnd() - 0.1, 1.2 * rnd() - 0.1);
  expect_all_agree(tris, pts, 0.1, "random triangles");
  SearchFacets quads;
  quads.corners = 4;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      auto z = [](Real x, Real y) { return 0.2 * std::sin(3 * x) * y; };
      const Real x0 = i / 20.0, x1 = (i + 1) / 20.0, y0 = j / 20.0, y1 = (j + 1) / 20.0;
      quads.points.insert(quads.points.end(), {Vec3(x0, y0, z(x0, y0)), Vec3(x1, y0, z(x1, y0)), Vec3(x1, y1, z(x1, y1)),
                                              Vec3(x0, y1, z(x0, y1))});
    }
  expect_all_agree(quads, pts, 0.2, "quadrilaterals");
}

TEST(ContactSearch, SegmentsIn2D) {
  SearchFacets segs;
  segs.corners = 2;
  const int n = 200;
  for (int i = 0; i < n; ++i) {
    const Real t0 = 2 * M_PI * i / n, t1 = 2 * M_PI * (i + 1) / n;
    segs.points.push_back(Vec3(std::cos(t0), std::sin(t0), 0));
    segs.points.push_back(Vec3(std::cos(t1), std::sin(t1), 0));
  }
  std::vector<Vec3> pts;
  for (int i = 0; i < 500; ++i) {
    const Real t = 2 * M_PI * rnd(), r = 0.9 + 0.2 * rnd();
    pts.emplace_back(r * std::cos(t), r * std::sin(t), 0);
  }
  // Nodes exactly on master vertices: ties between two segments.
  for (int i = 0; i < 10; ++i) pts.push_back(segs.points[2 * i]);
  expect_all_agree(segs, pts, 0.05, "circle of segments");
}

TEST(ContactSearch, PointFacetDistance) {
  const Vec3 tri[3] = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_NEAR(point_facet_distance(tri, 3, Vec3(0.2, 0.2, 0.5)), 0.5, 1e-15);        // above the face
  EXPECT_NEAR(point_facet_distance(tri, 3, Vec3(-1, -1, 0)), std::sqrt(2.0), 1e-15);   // nearest a vertex
  EXPECT_NEAR(point_facet_distance(tri, 3, Vec3(0.5, -2, 0)), 2.0, 1e-15);             // nearest an edge
  EXPECT_NEAR(point_facet_distance(tri, 3, Vec3(1, 1, 0)), std::sqrt(0.5), 1e-15);     // beyond the hypotenuse
  const Vec3 seg[2] = {Vec3(0, 0, 0), Vec3(2, 0, 0)};
  EXPECT_NEAR(point_facet_distance(seg, 2, Vec3(1, 3, 0)), 3.0, 1e-15);
  EXPECT_NEAR(point_facet_distance(seg, 2, Vec3(3, 0, 0)), 1.0, 1e-15);
}

// Degenerate facets (two corners at the same place, three on a line) have the distance of
// their edges, never NaN (a NaN would hide the facet from every method).
TEST(ContactSearch, DegenerateFacetsHaveTheirEdgesDistance) {
  const Vec3 o(0, 0, 0), x(1, 0, 0), h(0.5, 0, 0), p(0.5, 1, 0);
  for (const std::array<Vec3, 3>& t : {std::array<Vec3, 3>{o, o, x}, std::array<Vec3, 3>{o, x, x},
                                       std::array<Vec3, 3>{x, o, x}, std::array<Vec3, 3>{o, h, x}}) {
    EXPECT_DOUBLE_EQ(point_facet_distance(t.data(), 3, p), 1.0);
    const Vec3 q(2, 0, 0);  // beyond the segment's end
    EXPECT_DOUBLE_EQ(point_facet_distance(t.data(), 3, q), 1.0);
  }
  const Vec3 quad[4] = {o, o, x, Vec3(0, 1, 0)};  // a quadrilateral with a repeated corner
  EXPECT_NEAR(point_facet_distance(quad, 4, Vec3(0.25, 0.25, 2)), 2.0, 1e-15);
}

// A closed box: walls parallel to the grid's sorted axis put whole walls in few columns (the
// sorted slices must still find every closest facet), points inside and outside.
TEST(ContactSearch, ClosedBoxSurface) {
  SearchFacets box;
  box.corners = 3;
  const int n = 12;
  auto face = [&](const Vec3& o, const Vec3& u, const Vec3& v) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 a = o + u * i / n + v * j / n, b = a + u / n, c = a + u / n + v / n, d = a + v / n;
        box.points.insert(box.points.end(), {a, b, c, a, c, d});
      }
  };
  const Vec3 X(1, 0, 0), Y(0, 2, 0), Z(0, 0, 0.5), O(0, 0, 0);
  face(O, X, Y), face(O + Z, X, Y), face(O, X, Z), face(O + Y, X, Z), face(O, Y, Z), face(O + X, Y, Z);
  std::vector<Vec3> pts;
  for (int i = 0; i < 1500; ++i) pts.emplace_back(1.4 * rnd() - 0.2, 2.4 * rnd() - 0.2, 0.9 * rnd() - 0.2);
  expect_all_agree(box, pts, 0.15, "closed box");
}

// Far from the origin: the grid's single precision pruning works on coordinates relative to
// the surface's own corner, so a surface 1e6 away (a part placed in a large assembly) is
// searched as exactly as one at the origin.
TEST(ContactSearch, SurfaceFarFromTheOrigin) {
  SampleSurfaces s = sample_surfaces(3000, 4000);
  const Vec3 shift(1e6, -3e5, 2e4);
  for (Vec3& x : s.master.points) x += shift;
  for (Vec3& x : s.slave_nodes) x += shift;
  expect_all_agree(s.master, s.slave_nodes, 2 * s.master.mean_edge_length(), "shifted by 1e6");
}

// A long thin strip of small triangles (length / edge = 1e4) with points on it, 1e-12 above
// it and beside it: the pruning's rounding allowance, relative to the surface's size, stays
// below a facet and never hides the closest one.
TEST(ContactSearch, LongThinStripAndPointsOnIt) {
  SearchFacets strip;
  strip.corners = 3;
  const int n = 10000;
  const Real h = 1.0 / n;
  for (int i = 0; i < n; ++i) {
    const Real x0 = i * h, x1 = (i + 1) * h;
    const Vec3 a(x0, 0, 0), b(x1, 0, 0), c(x1, h, 0.1 * h), d(x0, h, 0.1 * h);
    strip.points.insert(strip.points.end(), {a, b, c, a, c, d});
  }
  std::vector<Vec3> pts;
  for (int i = 0; i < 3000; ++i) {
    const Real x = rnd(), y = h * rnd();
    const Real z = 0.1 * y;  // on the strip
    switch (i % 3) {
      case 0: pts.emplace_back(x, y, z); break;
      case 1: pts.emplace_back(x, y, z + 1e-12); break;
      default: pts.emplace_back(x, y + 3 * h * rnd(), z - 2 * h * rnd()); break;
    }
  }
  expect_all_agree(strip, pts, 5 * h, "thin strip");
}

// Warped quadrilaterals (corners up to half an edge off their mean plane): the grid bounds
// each by the slab about the plane of its diagonals, so points just above, below and beside
// them still find the closest.
TEST(ContactSearch, WarpedQuadrilaterals) {
  SearchFacets quads;
  quads.corners = 4;
  const int n = 30;
  const Real h = 1.0 / n;
  std::vector<Real> z((n + 1) * (n + 1));
  for (Real& v : z) v = 0.5 * h * (2 * rnd() - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto v = [&](int a, int b) { return Vec3(a * h, b * h, z[b * (n + 1) + a]); };
      quads.points.insert(quads.points.end(), {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  std::vector<Vec3> pts;
  for (int k = 0; k < 3000; ++k) pts.emplace_back(rnd(), rnd(), 1.2 * h * (2 * rnd() - 1));
  expect_all_agree(quads, pts, 2 * h, "warped quadrilaterals");
}

// The answer does not depend on the threads nor on the visiting order: at a tie (points on
// shared edges and vertices of a 3D triangulation, each as close to two to six facets) every
// method returns the lowest facet id, as all-to-all does, with one thread and with two.
TEST(ContactSearch, TiesGoToTheLowestFacetWhateverTheThreads) {
  SearchFacets tri;
  tri.corners = 3;
  const int n = 24;
  auto v = [&](int i, int j) { return Vec3(i / Real(n), j / Real(n), 0.1 * std::sin(i * 0.7) * std::cos(j * 0.4)); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) tri.points.insert(tri.points.end(), {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i, j + 1)});
  std::vector<Vec3> pts;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      pts.push_back(v(i, j));                                                      // vertices
      if (i < n) pts.push_back(0.5 * (v(i, j) + v(i + 1, j)));                     // edge midpoints
      if (i < n && j < n) pts.push_back(0.5 * (v(i, j) + v(i + 1, j + 1)));        // diagonals
    }
  auto all = make_search("all_to_all");
  all->build(tri);
  std::vector<SearchHit> ref;
  all->closest(pts, 0.1, ref);
  const int threads = omp_get_max_threads();
  for (const char* m : {"bucket_grid", "bucket_grid_scalar", "bvh"})
    for (int t : {1, 2}) {
      omp_set_num_threads(t);
      auto s = make_search(m);
      s->build(tri);
      std::vector<SearchHit> hits;
      s->closest(pts, 0.1, hits);
      for (size_t i = 0; i < pts.size(); ++i) {
        ASSERT_EQ(hits[i].facet, ref[i].facet) << m << " with " << t << " threads, point " << i;
        ASSERT_EQ(hits[i].distance, ref[i].distance) << m << " with " << t << " threads, point " << i;
      }
    }
  omp_set_num_threads(threads);
}

// Edge cases of the grid: no facet, one facet, coincident and zero-area facets, a rebuild
// with another count and another kind of facet into the same object, d_max 0 and infinite;
// a non-finite corner is an error, not a wrong answer.
TEST(ContactSearch, GridEdgeCases) {
  const Real inf = std::numeric_limits<Real>::infinity();
  std::vector<Vec3> pts{Vec3(0.2, 0.2, 0.5), Vec3(0, 0, 0), Vec3(5, -3, 2)};
  for (const char* m : {"bucket_grid", "bucket_grid_scalar", "bvh"}) {
    auto s = make_search(m);
    SearchFacets none;
    none.corners = 3;
    s->build(none);
    std::vector<SearchHit> hits;
    s->closest(pts, inf, hits);
    for (const auto& h : hits) EXPECT_EQ(h.facet, -1) << m;
    SearchFacets one;
    one.corners = 3;
    one.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    expect_all_agree(one, pts, inf, std::string(m) + " one facet");
    s->build(one);
    s->closest(pts, 0.0, hits);  // d_max 0: only the point on the facet
    EXPECT_EQ(hits[0].facet, -1) << m;
    EXPECT_EQ(hits[1].facet, 0) << m;
    SearchFacets degenerate;
    degenerate.corners = 3;
    for (int k = 0; k < 50; ++k) {
      const Vec3 a(0.1 * k, 0, 0);
      degenerate.points.insert(degenerate.points.end(), {a, a, a});                                      // a point
      degenerate.points.insert(degenerate.points.end(), {a, a + Vec3(0.05, 0, 0), a + Vec3(0.1, 0, 0)});  // a line
    }
    expect_all_agree(degenerate, pts, inf, std::string(m) + " degenerate facets");
    // Rebuilt in place: 1000 quadrilaterals after the triangles.
    SearchFacets quads;
    quads.corners = 4;
    for (int j = 0; j < 25; ++j)
      for (int i = 0; i < 40; ++i)
        quads.points.insert(quads.points.end(), {Vec3(i, j, 0), Vec3(i + 1, j, 0.3), Vec3(i + 1, j + 1, 0), Vec3(i, j + 1, 0.1)});
    s->build(quads);
    std::vector<SearchHit> ref;
    auto all = make_search("all_to_all");
    all->build(quads);
    const std::vector<Vec3> qp{Vec3(3.3, 4.4, 0.5), Vec3(39.9, 24.9, -1), Vec3(-2, 7, 0)};
    all->closest(qp, inf, ref);
    s->closest(qp, inf, hits);
    for (size_t i = 0; i < qp.size(); ++i) EXPECT_EQ(hits[i].facet, ref[i].facet) << m << " rebuilt, point " << i;
  }
  SearchFacets bad;
  bad.corners = 3;
  bad.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0), Vec3(0, 1, 0)};
  auto g = make_search("bucket_grid");
  try {
    g->build(bad);
    FAIL() << "a NaN corner was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("facet 1"), std::string::npos) << e.what();
  }
  std::vector<SearchHit> hits;
  g->closest(pts, inf, hits);  // after the error: an empty grid, not a half-built one
  for (const auto& h : hits) EXPECT_EQ(h.facet, -1);
}

// Tiny facets far apart (edges 1e-14 of the spread): the column count would overflow a
// 64-bit product; the grid coarsens its cells instead.
TEST(ContactSearch, TinyFacetsFarApart) {
  SearchFacets f;
  f.corners = 3;
  for (const Vec3& o : {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0.5, 0.2, 0)})
    f.points.insert(f.points.end(), {o, o + Vec3(1e-14, 0, 0), o + Vec3(0, 1e-14, 0)});
  expect_all_agree(f, {Vec3(0.9, 0.9, 0), Vec3(0.1, 0, 0), Vec3(0.5, 0.2, 1e-15)}, 10.0, "tiny facets");
}
