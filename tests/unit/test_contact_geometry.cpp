// Contact geometry: closest-point projection on every facet type (inside, outside, curved
// facets), and the gap's first and second variations and the parameter's first variation
// and second variations against central differences of a fresh projection.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "signorini/contact/geometry/facet_projection.hpp"
#include "signorini/contact/geometry/hyper_dual.hpp"
#include "signorini/contact/geometry/rotation.hpp"
#include "signorini/contact/surface.hpp"
#include "signorini/fem/shape.hpp"

using namespace signorini;

namespace {

// A 5 x 5 grid of nodes (4 x 4 quads, outward +z) on a curved, slightly jittered surface with
// its bicubic patches (smoothing: hermite in 3D): the patches of an inner facet (16 nodes),
// of an edge facet (one side of ghosts) and of a corner facet (two).
struct CurvedGrid {
  MasterSurface m;
  std::vector<Vec3> x;
  CurvedGrid() {
    unsigned s = 7;
    auto rnd = [&]() {
      s = s * 1664525u + 1013904223u;
      return 2.0 * (s >> 8) / static_cast<Real>(1u << 24) - 1.0;
    };
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) {
        const Real u = 0.5 * (i - 2) + 0.03 * rnd(), v = 0.45 * (j - 2) + 0.03 * rnd();
        x.push_back(Vec3(u, v, 0.1 * u * u + 0.05 * v * v + 0.03 * u * v + 0.01 * rnd()));
      }
    m.node_facets.resize(x.size());
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const Index a = i + 5 * j;
        m.type.push_back(ElementType::quad4);
        m.facets.push_back({a, a + 1, a + 6, a + 5});
        for (Index n : m.facets.back()) m.node_facets[n].push_back(m.size() - 1);
      }
    smooth_master_surface(m, x);
  }
};
const CurvedGrid& curved_grid() {
  static const CurvedGrid g;
  return g;
}
// Facets of the grid: inner (cell 1,1), edge (cell 1,0), corner (cell 0,0).
FacetBasis grid_patch(int facet) { return curved_grid().m.basis(facet); }

// A distorted, curved facet: reference coordinates mapped into space, with a bump.
std::vector<Vec3> facet_nodes(const FacetBasis& t, int dim) {
  std::vector<Vec3> x;
  if (t.patch) {  // a bicubic patch of the curved grid: its nodes
    const CurvedGrid& g = curved_grid();
    for (Index f = 0; f < g.m.size(); ++f)
      if (&g.m.patch[f] == t.patch)
        for (Index n : g.m.patch_nodes[f]) x.push_back(g.x[n]);
    return x;
  }
  unsigned s = 99;
  auto rnd = [&]() {
    s = s * 1664525u + 1013904223u;
    return 2.0 * (s >> 8) / static_cast<Real>(1u << 24) - 1.0;
  };
  if (t.smooth) {  // a Hermite segment: nodes along a parabola, [prev], a, b, [next]
    for (Real r : {-3.0, -1.0, 1.0, 3.0}) {
      if ((r < -2 && !t.has_prev) || (r > 2 && !t.has_next)) continue;
      x.push_back(Vec3(0.7 * r + 0.05 * rnd(), 0.1 * r * r + 0.03 * rnd(), 0));
    }
    return x;
  }
  for (auto& r : element_info(t.type).ref_coords) {
    Vec3 p;
    if (dim == 2) p = Vec3(0.7 * r(0) + 0.05 * rnd(), 0.1 * r(0) * r(0) + 0.03 * rnd(), 0);
    else p = Vec3(0.8 * r(0) + 0.2 * r(1) + 0.04 * rnd(), 0.1 * r(0) + 0.9 * r(1) + 0.04 * rnd(),
                  0.15 * (r(0) * r(0) + 0.5 * r(1) * r(1)) + 0.03 * rnd());
    x.push_back(p);
  }
  // Linear facets stay planar/straight where they must (a tri3 is always planar).
  return x;
}

Vec3 interior_target(const FacetBasis& t, int dim, const std::vector<Vec3>& x, Real height) {
  const Vec3 xi = t.simplex() ? Vec3(0.3, 0.25, 0) : Vec3(0.2, dim == 3 ? -0.3 : 0, 0);
  VecX N;
  MatX dN;
  t.eval(xi, N, dN);
  Vec3 c = Vec3::Zero();
  for (size_t i = 0; i < x.size(); ++i) c += N(i) * x[i];
  return c + height * facet_normal(t, x, xi, dim);
}

struct GeoCase {
  FacetBasis type;
  int dim;
  Real height;
};

// The case's facet, its target point and the point's projection.
struct Projected {
  std::vector<Vec3> x;
  Vec3 p;
  FacetProjection fp;
};
Projected projected(const GeoCase& c) {
  Projected r;
  r.x = facet_nodes(c.type, c.dim);
  r.p = interior_target(c.type, c.dim, r.x, c.height);
  r.fp = project_on_facet(c.type, r.x, r.p, c.dim);
  return r;
}

std::string basis_name(const FacetBasis& b) {
  if (b.patch) return "bicubic" + std::to_string(b.num_nodes());
  if (!b.smooth) return element_info(b.type).name;
  return std::string("hermite") + (b.has_prev ? "_prev" : "") + (b.has_next ? "_next" : "");
}

std::string name_of(const ::testing::TestParamInfo<GeoCase>& i) {
  return basis_name(i.param.type) + (i.param.height > 0 ? "_open" : "_penetrating");
}

}  // namespace

class ContactGeometry : public ::testing::TestWithParam<GeoCase> {};

TEST_P(ContactGeometry, ProjectionIsOrthogonalAndInside) {
  const GeoCase c = GetParam();
  const auto x = facet_nodes(c.type, c.dim);
  const Vec3 p = interior_target(c.type, c.dim, x, c.height);
  FacetProjection fp = project_on_facet(c.type, x, p, c.dim);
  ASSERT_TRUE(fp.converged) << basis_name(c.type);
  EXPECT_TRUE(fp.inside);
  EXPECT_LT(fp.iterations, 10);
  for (int a = 0; a < c.dim - 1; ++a) EXPECT_NEAR(fp.a[a].dot(p - fp.point), 0, 1e-12);
  EXPECT_NEAR(std::abs(fp.gap), (p - fp.point).norm(), 1e-12);
  EXPECT_EQ(fp.gap > 0, c.height > 0) << "sign of the gap";
}

TEST_P(ContactGeometry, VariationsMatchCentralDifferences) {
  const GeoCase c = GetParam();
  const int dim = c.dim;
  auto [x, p, fp] = projected(c);
  ASSERT_TRUE(fp.converged);
  VecX grad;
  MatX hess, dxi;
  gap_variations(c.type, x, fp, dim, grad, hess, &dxi);
  const int n = static_cast<int>(grad.size());
  auto perturbed = [&](int k, Real h) {
    auto xx = x;
    Vec3 pp = p;
    const int node = k / dim, comp = k % dim;
    if (node == 0) pp(comp) += h;
    else xx[node - 1](comp) += h;
    return std::make_pair(xx, pp);
  };
  const Real h = 1e-6;
  Real err_g = 0, err_h = 0, err_xi = 0;
  for (int k = 0; k < n; ++k) {
    auto [xp, pp] = perturbed(k, h);
    auto [xm, pm] = perturbed(k, -h);
    FacetProjection fpp = project_on_facet(c.type, xp, pp, dim), fpm = project_on_facet(c.type, xm, pm, dim);
    err_g = std::max(err_g, std::abs((fpp.gap - fpm.gap) / (2 * h) - grad(k)));
    for (int a = 0; a < dim - 1; ++a) err_xi = std::max(err_xi, std::abs((fpp.xi(a) - fpm.xi(a)) / (2 * h) - dxi(k, a)));
    VecX gp, gm;
    MatX tmp;
    gap_variations(c.type, xp, fpp, dim, gp, tmp);
    gap_variations(c.type, xm, fpm, dim, gm, tmp);
    err_h = std::max(err_h, ((gp - gm) / (2 * h) - hess.col(k)).cwiseAbs().maxCoeff());
  }
  const std::string what = basis_name(c.type);
  EXPECT_LT(err_g, 1e-8) << what << ": gap gradient";
  EXPECT_LT(err_xi, 1e-7) << what << ": parameter gradient";
  EXPECT_LT(err_h, 1e-6 * std::max(1.0, hess.cwiseAbs().maxCoeff())) << what << ": gap Hessian";
  EXPECT_LT((hess - hess.transpose()).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, hess.cwiseAbs().maxCoeff()))
      << what << ": Hessian is not symmetric";
}

// The parameters' second variation (the tangent of the tangential slip needs it): central
// differences of the analytic first variation at fresh projections.
TEST_P(ContactGeometry, ParameterSecondVariationMatchesCentralDifferences) {
  const GeoCase c = GetParam();
  const int dim = c.dim;
  auto [x, p, fp] = projected(c);
  ASSERT_TRUE(fp.converged);
  MatX dxi;
  std::vector<MatX> d2xi;
  parameter_variations(c.type, x, fp, dim, dxi, d2xi);
  VecX grad;
  MatX hess, dxi_gap;
  gap_variations(c.type, x, fp, dim, grad, hess, &dxi_gap);
  EXPECT_LT((dxi - dxi_gap).cwiseAbs().maxCoeff(), 1e-12) << "the two first variations differ";
  const int n = static_cast<int>(dxi.rows());
  const Real h = 1e-6;
  Real err = 0, scale = 1;
  for (auto& m : d2xi) scale = std::max(scale, m.cwiseAbs().maxCoeff());
  for (int k = 0; k < n; ++k) {
    MatX dp, dm;
    std::vector<MatX> tmp;
    for (Real sgn : {1.0, -1.0}) {
      auto xx = x;
      Vec3 pp = p;
      const int node = k / dim, comp = k % dim;
      if (node == 0) pp(comp) += sgn * h;
      else xx[node - 1](comp) += sgn * h;
      FacetProjection f2 = project_on_facet(c.type, xx, pp, dim);
      ASSERT_TRUE(f2.converged);
      parameter_variations(c.type, xx, f2, dim, sgn > 0 ? dp : dm, tmp);
    }
    for (int b = 0; b < dim - 1; ++b)
      err = std::max(err, ((dp.col(b) - dm.col(b)) / (2 * h) - d2xi[b].col(k)).cwiseAbs().maxCoeff());
  }
  const std::string what = basis_name(c.type);
  EXPECT_LT(err, 1e-6 * scale) << what << ": parameter Hessian (scale " << scale << ")";
  for (int b = 0; b < dim - 1; ++b)
    EXPECT_LT((d2xi[b] - d2xi[b].transpose()).cwiseAbs().maxCoeff(), 1e-9 * scale) << what << ": not symmetric";
}

INSTANTIATE_TEST_SUITE_P(
    EveryFacet, ContactGeometry,
    ::testing::Values(GeoCase{ElementType::line2, 2, 0.2}, GeoCase{ElementType::line2, 2, -0.1},
                      GeoCase{ElementType::line3, 2, 0.2}, GeoCase{ElementType::line3, 2, -0.1},
                      GeoCase{ElementType::tri3, 3, 0.2}, GeoCase{ElementType::tri3, 3, -0.1},
                      GeoCase{ElementType::quad4, 3, 0.2}, GeoCase{ElementType::quad4, 3, -0.1},
                      GeoCase{ElementType::tri6, 3, 0.2}, GeoCase{ElementType::tri6, 3, -0.1},
                      GeoCase{ElementType::quad8, 3, 0.2}, GeoCase{ElementType::quad8, 3, -0.1},
                      GeoCase{ElementType::quad9, 3, 0.2}, GeoCase{ElementType::quad9, 3, -0.1},
                      GeoCase{FacetBasis::hermite(true, true), 2, 0.2},
                      GeoCase{FacetBasis::hermite(true, true), 2, -0.1},
                      GeoCase{FacetBasis::hermite(false, true), 2, 0.2},
                      GeoCase{FacetBasis::hermite(true, false), 2, -0.1},
                      GeoCase{FacetBasis::hermite(false, false), 2, 0.2},
                      GeoCase{grid_patch(5), 3, 0.2}, GeoCase{grid_patch(5), 3, -0.1},
                      GeoCase{grid_patch(1), 3, 0.2}, GeoCase{grid_patch(0), 3, -0.1}),
    name_of);

// Bicubic patches (3D smoothing): the grid's nodes enter with the right counts, each patch
// interpolates its facet's corner nodes, and neighbouring patches share position and normal
// along their common edge (C1 surface), where the faceted quads' normals jump.
TEST(ContactGeometry, BicubicPatchesAreC1AcrossEdges) {
  const CurvedGrid& g = curved_grid();
  EXPECT_EQ(g.m.patch_nodes[5].size(), 16u);  // inner
  EXPECT_EQ(g.m.patch_nodes[1].size(), 12u);  // one side of ghosts
  EXPECT_EQ(g.m.patch_nodes[0].size(), 9u);   // corner: two sides
  auto point_normal = [&](Index f, const Vec3& xi) {
    const FacetBasis b = g.m.basis(f);
    std::vector<Vec3> x;
    for (Index n : g.m.patch_nodes[f]) x.push_back(g.x[n]);
    VecX N;
    MatX dN;
    b.eval(xi, N, dN);
    Vec3 p = Vec3::Zero();
    for (size_t i = 0; i < x.size(); ++i) p += N(i) * x[i];
    return std::make_pair(p, facet_normal(b, x, xi, 3));
  };
  // Corners interpolated.
  const Vec3 corners[4] = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
  for (Index f : {0, 1, 5})
    for (int k = 0; k < 4; ++k) EXPECT_LT((point_normal(f, corners[k]).first - g.x[g.m.facets[f][k]]).norm(), 1e-14);
  // Shared edges: facet 5 (cell 1,1) with facet 6 (cell 2,1) along xi = +1 / -1, and with
  // facet 9 (cell 1,2) along eta = +1 / -1; facet 0 with facet 1 (ghost rows on both).
  Real dp = 0, dn = 0, faceted = 0;
  for (Real t = -1; t <= 1.0001; t += 0.25) {
    for (auto [f, xf, g2, xg] : {std::tuple{5, Vec3(1, t, 0), 6, Vec3(-1, t, 0)},
                                 std::tuple{5, Vec3(t, 1, 0), 9, Vec3(t, -1, 0)},
                                 std::tuple{0, Vec3(1, t, 0), 1, Vec3(-1, t, 0)}}) {
      const auto [pa, na] = point_normal(f, xf);
      const auto [pb, nb] = point_normal(g2, xg);
      dp = std::max(dp, (pa - pb).norm());
      dn = std::max(dn, (na - nb).norm());
      std::vector<Vec3> qa, qb;
      for (Index n : g.m.facets[f]) qa.push_back(g.x[n]);
      for (Index n : g.m.facets[g2]) qb.push_back(g.x[n]);
      faceted = std::max(faceted, (facet_normal(ElementType::quad4, qa, xf, 3) - facet_normal(ElementType::quad4, qb, xg, 3)).norm());
    }
  }
  EXPECT_LT(dp, 1e-13) << "position jump across an edge";
  EXPECT_LT(dn, 1e-12) << "normal jump across an edge";
  EXPECT_GT(faceted, 0.05) << "the faceted normals should jump on this curved grid";
}

TEST(ContactGeometry, PointsBeyondTheFacetAreNotInside) {
  std::vector<Vec3> seg{Vec3(0, 0, 0), Vec3(1, 0, 0)};
  // The outward normal of a line from (0,0) to (1,0) is (0, -1): the body lies above.
  FacetProjection fp = project_on_facet(ElementType::line2, seg, Vec3(1.5, -0.2, 0), 2);
  EXPECT_TRUE(fp.converged);
  EXPECT_FALSE(fp.inside);
  EXPECT_NEAR(fp.xi(0), 2.0, 1e-12);
  EXPECT_NEAR(fp.gap, 0.2, 1e-12);
  std::vector<Vec3> tri{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  fp = project_on_facet(ElementType::tri3, tri, Vec3(0.8, 0.8, 0.3), 3);
  EXPECT_FALSE(fp.inside);
  EXPECT_NEAR(fp.gap, 0.3, 1e-12);
}

TEST(ContactGeometry, PointGapVariations) {
  const Vec3 s(0.3, 0.4, 0.2), v(0.1, 0.1, 0.05), nref(0, 1, 0);
  for (int dim : {2, 3}) {
    Vec3 s2 = s, v2 = v;
    if (dim == 2) s2(2) = v2(2) = 0;
    VecX g;
    MatX H;
    PointGap pg = point_gap(s2, v2, nref, dim, &g, &H);
    EXPECT_GT(pg.gap, 0);
    const Real h = 1e-6;
    for (int k = 0; k < 2 * dim; ++k) {
      Vec3 sp = s2, sm = s2, vp = v2, vm = v2;
      (k < dim ? sp : vp)(k % dim) += h;
      (k < dim ? sm : vm)(k % dim) -= h;
      VecX gp, gm;
      const Real fp = point_gap(sp, vp, nref, dim, &gp, nullptr).gap, fm = point_gap(sm, vm, nref, dim, &gm, nullptr).gap;
      EXPECT_NEAR((fp - fm) / (2 * h), g(k), 1e-8);
      EXPECT_LT(((gp - gm) / (2 * h) - H.col(k)).cwiseAbs().maxCoeff(), 1e-6);
    }
  }
}

TEST(ContactGeometry, EdgeGapVariations) {
  // A slave point near a skew edge, above and below it (both signs), against central differences.
  const Vec3 a(0.1, -0.2, 0.05), b(0.9, 0.3, -0.1), nref = Vec3(0.2, 0.1, 1).normalized();
  for (Real side : {1.0, -1.0}) {
    const Vec3 s = 0.6 * a + 0.4 * b + side * Vec3(0.05, -0.1, 0.3);
    VecX g;
    MatX H;
    EdgeGap eg = edge_gap(s, a, b, nref, 3, &g, &H);
    EXPECT_GT(eg.eta, 0);
    EXPECT_LT(eg.eta, 1);
    EXPECT_EQ(eg.gap > 0, side > 0);
    EXPECT_NEAR(std::abs(eg.gap), (s - (1 - eg.eta) * a - eg.eta * b).norm(), 1e-14);
    const Real h = 1e-6;
    Real eg_err = 0, eh_err = 0;
    for (int k = 0; k < 9; ++k) {
      Vec3 p[2][3] = {{s, a, b}, {s, a, b}};
      p[0][k / 3](k % 3) += h;
      p[1][k / 3](k % 3) -= h;
      VecX gp, gm;
      const Real fp = edge_gap(p[0][0], p[0][1], p[0][2], nref, 3, &gp, nullptr).gap;
      const Real fm = edge_gap(p[1][0], p[1][1], p[1][2], nref, 3, &gm, nullptr).gap;
      eg_err = std::max(eg_err, std::abs((fp - fm) / (2 * h) - g(k)));
      eh_err = std::max(eh_err, ((gp - gm) / (2 * h) - H.col(k)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(eg_err, 1e-8);
    EXPECT_LT(eh_err, 1e-6 * std::max(1.0, H.cwiseAbs().maxCoeff()));
    EXPECT_LT((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
  }
}

#include "signorini/contact/discretization/node_to_segment.hpp"

TEST(ContactDetection, NoBlindSpotsAtMasterCorners) {
  // The course's blind spots, in 2D, around a master corner at the origin (nodes (0,-1),
  // (0,0), (-1,0)); a facet's outward normal is (t_y, -t_x): the body lies to its left.
  std::vector<Vec3> x{Vec3(0, -1, 0), Vec3(0, 0, 0), Vec3(-1, 0, 0), Vec3::Zero(), Vec3::Zero()};
  MasterSurface master;
  master.type = {ElementType::line2, ElementType::line2};
  master.node_facets.resize(5);
  master.node_facets[0] = {1};
  master.node_facets[1] = {0, 1};
  master.node_facets[2] = {0};
  master.nodes = {0, 1, 2};
  SlaveSurface slave;
  slave.nodes = {3, 4};
  slave.weights = {1, 1};
  ConstraintSet cs;

  // Convex corner: the body is the quadrant x < 0, y < 0 (normals +x on x = 0, +y on y = 0).
  master.facets = {{0, 1}, {1, 2}};
  ASSERT_NEAR(facet_normal(ElementType::line2, {x[0], x[1]}, Vec3::Zero(), 2).x(), 1, 1e-12);
  ASSERT_NEAR(facet_normal(ElementType::line2, {x[1], x[2]}, Vec3::Zero(), 2).y(), 1, 1e-12);
  x[3] = Vec3(0.1, 0.1, 0);      // outside, beyond the corner: no facet projects it
  x[4] = Vec3(-0.01, -0.02, 0);  // just inside the body near the corner
  node_to_segment(master, slave, x, 2, {0, 0}, cs);
  EXPECT_EQ(cs[0].kind, ConstraintKind::vertex);
  EXPECT_NEAR(cs[0].gap, std::sqrt(0.02), 1e-12);
  EXPECT_EQ(cs[1].kind, ConstraintKind::segment);
  EXPECT_NEAR(cs[1].gap, -0.01, 1e-12);  // the nearer face, x = 0

  // Re-entrant corner: the same polyline reversed, the body is everything but that quadrant.
  // A node deep in the body beyond both facets' ends projects inside neither: the blind
  // spot. It must be caught as penetrating (node-to-vertex). A node in the empty quadrant is
  // open.
  master.facets = {{2, 1}, {1, 0}};
  x[3] = Vec3(0.02, 0.05, 0);
  x[4] = Vec3(-0.05, -0.03, 0);
  node_to_segment(master, slave, x, 2, {0, 0}, cs);
  EXPECT_EQ(cs[0].kind, ConstraintKind::vertex) << "the blind-spot node was missed";
  EXPECT_NEAR(cs[0].gap, -std::hypot(0.02, 0.05), 1e-12);
  EXPECT_EQ(cs[1].kind, ConstraintKind::segment);
  EXPECT_NEAR(cs[1].gap, 0.03, 1e-12);
}

TEST(ContactDetection, HeldFacetKeepsItsNodeUpToItsTolerance) {
  // Two master facets meeting with a small kink at the origin: A from (0,0) to (-1,0), normal
  // +y, and B from (1,0.05) to (0,0), normal about +y. A node just right of the kink, 0.01
  // below, projects inside B and 2 % of A beyond A's end (A accepts 1 % when the closest facet
  // is chosen): B is its facet. Held on A (it went back and forth between A and B), it keeps A
  // up to kHeldFacetTolerance beyond A's end, with A's gap; farther, B again.
  std::vector<Vec3> x{Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(1, 0.05, 0), Vec3::Zero(), Vec3::Zero()};
  MasterSurface master;
  master.type = {ElementType::line2, ElementType::line2};
  master.facets = {{1, 0}, {2, 1}};
  master.node_facets.resize(5);
  master.node_facets[0] = {0};
  master.node_facets[1] = {0, 1};
  master.node_facets[2] = {1};
  master.nodes = {0, 1, 2};
  SlaveSurface slave;
  slave.nodes = {3, 4};
  slave.weights = {1, 1};
  x[3] = Vec3(0.02, -0.01, 0);                              // 2 % beyond A
  x[4] = Vec3(1.5 * kHeldFacetTolerance, -0.01, 0);         // 15 % beyond A
  const Vec3 nb = Vec3(-0.05, 1, 0).normalized();
  ConstraintSet cs;
  node_to_segment(master, slave, x, 2, {0, 0}, cs);
  ASSERT_EQ(cs[0].kind, ConstraintKind::segment);
  EXPECT_EQ(cs[0].facet, 1);
  EXPECT_NEAR(cs[0].gap, nb.dot(x[3]), 1e-12);
  EXPECT_EQ(cs[1].facet, 1);
  const std::vector<Index> held{0, 0};
  node_to_segment(master, slave, x, 2, {0, 0}, cs, nullptr, &held);
  ASSERT_EQ(cs[0].kind, ConstraintKind::segment);
  EXPECT_EQ(cs[0].facet, 0);
  EXPECT_NEAR(cs[0].gap, -0.01, 1e-12);  // on A's plane, y = 0
  EXPECT_NEAR(cs[0].normal.y(), 1, 1e-12);
  EXPECT_EQ(cs[1].facet, 1);  // beyond the held facet's tolerance: the closest facet again
  EXPECT_NEAR(cs[1].gap, nb.dot(x[4]), 1e-12);
  // A node held on a facet that is not its closest: the gap's variations are those of the
  // held facet (its first variation is the held facet's normal on the slave node's DOFs).
  EXPECT_NEAR(cs[0].grad(1), 1, 1e-12);
  EXPECT_NEAR(cs[0].grad(0), 0, 1e-12);
}

TEST(ContactDetection, NodeToEdgeAtAConvexRidge3D) {
  // Two master quads meeting at a convex ridge along the y axis: facet A in the plane z = -x
  // for x in [0, 1] (outward normal (1, 0, 1)/sqrt 2), facet B in z = x for x in [-1, 0]
  // (normal (-1, 0, 1)/sqrt 2); the body is below. A slave node right above the ridge projects
  // inside neither facet: node-to-edge, gap = its distance to the ridge. One just below the
  // ridge (penetrating) projects inside a facet: node-to-segment.
  std::vector<Vec3> x{Vec3(0, 0, 0),  Vec3(1, 0, -1), Vec3(1, 1, -1), Vec3(0, 1, 0),
                      Vec3(-1, 0, -1), Vec3(-1, 1, -1), Vec3::Zero(),   Vec3::Zero()};
  MasterSurface master;
  master.type = {ElementType::quad4, ElementType::quad4};
  master.facets = {{0, 1, 2, 3}, {0, 3, 5, 4}};
  master.node_facets.assign(8, {});
  for (Index f = 0; f < 2; ++f)
    for (Index n : master.facets[f]) master.node_facets[n].push_back(f);
  master.nodes = {0, 1, 2, 3, 4, 5};
  for (Index f = 0; f < 2; ++f) {
    std::vector<Vec3> xf;
    for (Index n : master.facets[f]) xf.push_back(x[n]);
    ASSERT_GT(facet_normal(ElementType::quad4, xf, Vec3::Zero(), 3).z(), 0.7) << "facet " << f << " faces down";
  }
  SlaveSurface slave;
  slave.nodes = {6, 7};
  slave.weights = {1, 1};
  x[6] = Vec3(0.02, 0.4, 0.1);     // above the ridge
  x[7] = Vec3(0.3, 0.6, -0.33);    // 0.03 below facet A, inside it
  ConstraintSet cs;
  node_to_segment(master, slave, x, 3, {0, 0}, cs);
  EXPECT_EQ(cs[0].kind, ConstraintKind::edge);
  EXPECT_NEAR(cs[0].gap, std::hypot(0.02, 0.1), 1e-12);
  EXPECT_EQ(cs[0].nodes.size(), 3u);
  EXPECT_EQ(cs[1].kind, ConstraintKind::segment);
  EXPECT_NEAR(cs[1].gap, (-0.33 + 0.3) / std::sqrt(2.0), 1e-12);
  // Just below the ridge the node projects inside both facets (equidistant): node-to-segment,
  // penetrating.
  x[6] = Vec3(0.0, 0.4, -0.05);
  node_to_segment(master, slave, x, 3, {0, 0}, cs);
  EXPECT_EQ(cs[0].kind, ConstraintKind::segment);
  EXPECT_NEAR(cs[0].gap, -0.05 / std::sqrt(2.0), 1e-12);
}

#include "signorini/mesh/structured.hpp"

// Axisymmetric slave weights: the integral of N r over the facets. On the axis the node of a
// quadratic (line3) facet gets exactly zero (it carries no contact force, and gets no
// constraint), where quadrature leaves a round-off residue; a linear facet's axis node keeps
// its positive h^2 / 6 (times 2 pi). The weights sum to the surface's area pi R^2.
TEST(ContactSurface, AxisymmetricWeightsOnTheAxis) {
  int cases = 0;
  for (ElementType type : {ElementType::quad9, ElementType::quad4})
    for (int n : {3, 7, 11, 19, 40})
      for (Real lx : {0.9, 0.37, 8.0, 0.011}) {
        Mesh mesh = structured_rectangle(type, n, 2, lx, 0.5);
        AnalysisSettings s;
        s.dimension = Dimension::axisymmetric;
        const SlaveSurface slave = make_slave_surface(mesh, "ymax", s);
        Real sum = 0, axis = -1;
        for (size_t j = 0; j < slave.nodes.size(); ++j) {
          sum += slave.weights[j];
          if (mesh.nodes[slave.nodes[j]].x() == 0 && mesh.nodes[slave.nodes[j]].y() == 0.5) axis = slave.weights[j];
        }
        EXPECT_NEAR(sum, std::numbers::pi * lx * lx, 1e-12 * lx * lx);
        const Real h = lx / n;
        if (type == ElementType::quad9) EXPECT_EQ(axis, 0.0) << "n " << n << " lx " << lx;
        else EXPECT_NEAR(axis, 2 * std::numbers::pi * h * h / 6, 1e-14 * h * h);
        ++cases;
      }
  EXPECT_EQ(cases, 40);
}

// The averaged 3D nodal normal and its derivative (MasterSurface::node_normal_jacobian_3d:
// segment_to_segment's slave normal, which 3D friction's tangent reads) against central
// differences of node_normal, at an inner, an edge and a corner node of curved, jittered
// surfaces of quad4, tri6, quad8 and quad9 facets (a 5 x 5 grid of nodes: 4 x 4 quad4 cells, or
// 2 x 2 quadratic cells, each split into two tri6), and at mid-side and centre nodes.
TEST(ContactSurface, NodalNormalJacobianMatchesCentralDifferences3D) {
  const std::vector<Vec3>& x0 = curved_grid().x;
  auto at = [](int i, int j) { return static_cast<Index>(i + 5 * j); };
  int checked = 0;
  for (ElementType type : {ElementType::quad4, ElementType::tri6, ElementType::quad8, ElementType::quad9}) {
    MasterSurface m;
    m.node_facets.resize(x0.size());
    auto add = [&](ElementType t, std::vector<Index> f) {
      m.type.push_back(t);
      m.facets.push_back(f);
      for (Index n : f) m.node_facets[n].push_back(m.size() - 1);
    };
    for (int J = 0; J < (type == ElementType::quad4 ? 4 : 2); ++J)
      for (int I = 0; I < (type == ElementType::quad4 ? 4 : 2); ++I) {
        if (type == ElementType::quad4) {
          add(type, {at(I, J), at(I + 1, J), at(I + 1, J + 1), at(I, J + 1)});
          continue;
        }
        const int i = 2 * I, j = 2 * J;
        const Index a = at(i, j), b = at(i + 2, j), c = at(i + 2, j + 2), d = at(i, j + 2);
        if (type == ElementType::tri6) {
          add(type, {a, b, c, at(i + 1, j), at(i + 2, j + 1), at(i + 1, j + 1)});
          add(type, {a, c, d, at(i + 1, j + 1), at(i + 1, j + 2), at(i, j + 1)});
        } else {
          std::vector<Index> f = {a, b, c, d, at(i + 1, j), at(i + 2, j + 1), at(i + 1, j + 2), at(i, j + 1)};
          if (type == ElementType::quad9) f.push_back(at(i + 1, j + 1));
          add(type, f);
        }
      }
    // Inner corner, edge, corner, and (quadratic) mid-side and centre nodes.
    for (Index node : {at(2, 2), at(2, 0), at(0, 0), at(1, 2), at(1, 1), at(3, 4)}) {
      if (m.node_facets[node].empty()) continue;
      std::vector<Vec3> x = x0;
      Vec3 n;
      std::vector<Index> nodes;
      MatX J;
      m.node_normal_jacobian_3d(node, x, n, nodes, J);
      EXPECT_LT((n - m.node_normal(node, x, 3)).norm(), 1e-14);
      ASSERT_EQ(J.cols(), 3 * static_cast<Index>(nodes.size()));
      const Real h = 1e-6;
      Real err = 0, scale = 0;
      for (size_t a = 0; a < nodes.size(); ++a)
        for (int d = 0; d < 3; ++d) {
          x[nodes[a]](d) += h;
          const Vec3 np = m.node_normal(node, x, 3);
          x[nodes[a]](d) -= 2 * h;
          const Vec3 nm = m.node_normal(node, x, 3);
          x[nodes[a]](d) += h;
          const Vec3 fd = (np - nm) / (2 * h);
          err = std::max(err, (fd - J.col(3 * static_cast<Index>(a) + d)).cwiseAbs().maxCoeff());
          scale = std::max(scale, fd.cwiseAbs().maxCoeff());
        }
      EXPECT_GT(scale, 0.1) << "the normal depends on its nodes";
      EXPECT_LT(err, 1e-7 * scale) << element_info(type).name << " node " << node;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 6 + 6 + 5 + 6);  // quad8 has no centre node
}

// ---------------------------------------------------------------------------------------
// Rotations (geometry/rotation.hpp): R against Eigen's angle-axis rotation, and its first and
// second derivatives, the spin operator T and its derivative against central differences, at
// angles on both sides of the series/closed-form switch (|theta| = 0.5), at zero and near pi.
TEST(Rotation, RodriguesAndItsDerivativesMatchCentralDifferences) {
  const std::vector<Vec3> angles = {Vec3::Zero(),          Vec3(1e-9, -2e-9, 3e-9), Vec3(0.01, -0.02, 0.005),
                                    Vec3(0.3, 0.2, -0.25), Vec3(0.28, 0.29, -0.2), Vec3(0.4, -0.3, 0.2),
                                    Vec3(1.2, -0.7, 2.0),  Vec3(0, 0, 3.1)};
  for (const Vec3& th : angles) {
    SCOPED_TRACE("theta = (" + std::to_string(th(0)) + ", " + std::to_string(th(1)) + ", " + std::to_string(th(2)) + ")");
    const Rotation r = rotation(th.data(), 3);
    const Mat3 ref = th.norm() > 0 ? Mat3(Eigen::AngleAxis<Real>(th.norm(), th.normalized())) : Mat3::Identity();
    EXPECT_LT((r.R - ref).cwiseAbs().maxCoeff(), 1e-15);
    const Real h = 1e-6;
    auto R_at = [&](const Vec3& t) { return rotation(t.data(), 3); };
    for (int i = 0; i < 3; ++i) {
      Vec3 p = th, m = th;
      p(i) += h;
      m(i) -= h;
      const Rotation rp = R_at(p), rm = R_at(m);
      EXPECT_LT((r.dR[i] - (rp.R - rm.R) / (2 * h)).cwiseAbs().maxCoeff(), 1e-9) << "dR/dtheta_" << i;
      for (int j = 0; j < 3; ++j)
        EXPECT_LT((r.d2R[i][j] - (rp.dR[j] - rm.dR[j]) / (2 * h)).cwiseAbs().maxCoeff(), 1e-8)
            << "d2R/dtheta_" << i << " dtheta_" << j;
      // T: the spin of a motion along theta_i, axial(dR R^T), against the rotation of the
      // increment R(theta + h e_i) R(theta - h e_i)^T (its axial vector / 2h).
      const Mat3 W = (rp.R * rm.R.transpose() - rm.R * rp.R.transpose()) / (4 * h);
      EXPECT_LT((r.T().col(i) - Vec3(W(2, 1), W(0, 2), W(1, 0))).norm(), 1e-9) << "T column " << i;
      EXPECT_LT((r.dT()[i] - (rp.T() - rm.T()) / (2 * h)).cwiseAbs().maxCoeff(), 1e-8) << "dT/dtheta_" << i;
    }
  }
  // Plane problems: one angle about z.
  const Real a = 0.7;
  const Rotation p = rotation(&a, 1);
  EXPECT_LT((p.R - Mat3(Eigen::AngleAxis<Real>(a, Vec3::UnitZ()))).cwiseAbs().maxCoeff(), 1e-15);
  const Real ap = a + 1e-6, am = a - 1e-6;
  EXPECT_LT((p.dR[0] - (rotation(&ap, 1).R - rotation(&am, 1).R) / 2e-6).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((p.d2R[0][0] - (rotation(&ap, 1).dR[0] - rotation(&am, 1).dR[0]) / 2e-6).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(p.T().col(0), Vec3::UnitZ());
}

// The hyper-dual numbers (geometry/hyper_dual.hpp) keep the upper triangle of the Hessian only
// (since session 62). A function using every operation (products, quotients, sqrt, sums with
// constants, negation), at N = 5 (odd: the packed rows' lengths 5, 4, ..., 1) and N = 8: its
// gradient against central differences of the value, its Hessian against central differences
// of the gradient, and the Hessian symmetric, hess(i, j) = hessian()(i, j).
template <int N>
HyperDual<N> hyper_dual_test_function(const Eigen::Matrix<Real, N, 1>& x) {
  using HD = HyperDual<N>;
  HD in[N];
  for (int i = 0; i < N; ++i) in[i] = HD::input(x(i), i);
  HD r = sqrt(in[0] * in[1] + in[2] * in[2] + 1.0) / (2.0 + in[N - 1] * in[0]);
  for (int i = 3; i < N; ++i) r += (-in[i]) * (1.0 - in[i - 1]) / (3.0 + in[i] * in[i]);
  HD squares = 1.0;
  for (int i = 0; i < N; ++i) squares += in[i] * in[i];
  return (0.5 * r - in[1] / in[2]) * sqrt(squares);  // every input coupled with every other
}

template <int N>
void check_hyper_dual_derivatives() {
  using V = Eigen::Matrix<Real, N, 1>;
  V x;
  for (int i = 0; i < N; ++i) x(i) = 0.3 + 0.17 * i - 0.05 * i * i;
  const HyperDual<N> f = hyper_dual_test_function<N>(x);
  const Eigen::Matrix<Real, N, N> H = f.hessian();
  const Real step = 1e-5;
  for (int i = 0; i < N; ++i) {
    V xp = x, xm = x;
    xp(i) += step;
    xm(i) -= step;
    const HyperDual<N> fp = hyper_dual_test_function<N>(xp), fm = hyper_dual_test_function<N>(xm);
    EXPECT_NEAR(f.g(i), (fp.v - fm.v) / (2 * step), 1e-7 * (1 + std::abs(f.g(i)))) << "N " << N << ", d/dx" << i;
    const V column = (fp.g - fm.g) / (2 * step);
    for (int j = 0; j < N; ++j) {
      EXPECT_NEAR(H(j, i), column(j), 1e-6 * (1 + std::abs(column(j)))) << "N " << N << ", H(" << j << ", " << i << ")";
      EXPECT_EQ(H(i, j), H(j, i));
      EXPECT_EQ(f.hess(i, j), H(i, j));
    }
  }
  EXPECT_GT(H.cwiseAbs().minCoeff(), 0) << "every entry of this function's Hessian is nonzero";
}

TEST(HyperDual, PackedHessianMatchesCentralDifferencesOfTheGradient) {
  check_hyper_dual_derivatives<5>();
  check_hyper_dual_derivatives<8>();
}
