// Taylor's contact patch test in 3D (Taylor & Papadopoulos 1991; VALIDATION.md sec. 2) for the
// integral discretization segment_to_segment with linear and quadratic facets: a punch
// [1, 3]^2 x [2, 4] (2 x 2 x 2 cells: matching, or 3 x 3 x 2: non-matching) on a foundation
// [0, 4]^2 x [0, 2] (4 x 4 x 2 cells, so that the punch covers whole foundation facets),
// E = 1000, nu = 0.4,
// frictionless, a uniform pressure p = 10 on the punch top and on the uncovered foundation
// top. The exact state is uniform: sigma_zz = -10 everywhere, u_x = nu p / E x and
// u_y = nu p / E y in both bodies (no relative sliding), and a contact pressure of 10 at every
// slave node, corner and mid-side alike.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "common.hpp"
#include "signorini/core/log.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

struct Patch3dCase {
  ElementType punch, foundation;
  int punch_cells;     // 2: the punch's nodes above the foundation's (spacing 1); 3: non-matching
  const char* method;
  Real tolerance;      // on the pressure and the stress, relative to p
  const char* discretization = "segment_to_segment";
};

std::string case_name(const ::testing::TestParamInfo<Patch3dCase>& i) {
  return element_info(i.param.punch).name + "_on_" + element_info(i.param.foundation).name + "_" +
         (i.param.punch_cells == 2 ? "matching_" : "nonmatching_") + i.param.method +
         (std::string(i.param.discretization) == "mortar" ? "_mortar" : "");
}

// Facets of `set` whose nodes all lie inside (or all outside) the square [x0, x0 + 2] x [1, 3].
std::vector<ElementBlock> facets_in_footprint(const Mesh& m, const std::string& set, bool inside, Real x0 = 1) {
  std::vector<ElementBlock> out;
  for (const ElementBlock& b : m.facet_sets.at(set)) {
    ElementBlock nb{b.type, {}, {}};
    for (Index e = 0; e < b.size(); ++e) {
      bool all_in = true, all_out = true;
      for (int k = 0; k < b.nodes_per_element(); ++k) {
        const Vec3& x = m.nodes[b.element(e)[k]];
        const bool in = x(0) > x0 - 1e-9 && x(0) < x0 + 2 + 1e-9 && x(1) > 1 - 1e-9 && x(1) < 3 + 1e-9;
        const bool strictly_in =
            x(0) > x0 + 1e-9 && x(0) < x0 + 2 - 1e-9 && x(1) > 1 + 1e-9 && x(1) < 3 - 1e-9;
        all_in = all_in && in;
        all_out = all_out && !strictly_in;
      }
      if (inside ? all_in : (all_out && !all_in))
        nb.add(std::vector<Index>(b.element(e), b.element(e) + b.nodes_per_element()), b.ids[e]);
    }
    if (nb.size()) out.push_back(nb);
  }
  return out;
}

}  // namespace

class ContactPatch3d : public ::testing::TestWithParam<Patch3dCase> {};

namespace {

// The patch test's model: the two blocks, the pair (`discretization`, `method`), the pressure
// p on the punch top and on the uncovered foundation top, the rigid motions held where the exact
// state puts them (u_x = exx x, u_y = exx y). `slide`: the punch starts that far in -x and is
// moved there while the load comes on (the master then the whole foundation top). `stretch`:
// the exact lateral stretch at finite strain (0: small strain, exx = nu p / E). `cells`: the
// foundation is [0, cells]^2 x [0, 2] in cells x cells x 2; `x0`: the punch ends on
// [x0, x0 + 2] x [1, 3] (x0 a whole number, so that the footprint covers whole foundation facets).
Model patch_model(const Patch3dCase& c, Real E, Real nu, Real p, Real slide = 0, Real stretch = 0, int cells = 4,
                  Real x0 = 1) {
  const Real exx = stretch > 0 ? stretch - 1 : nu * p / E;
  Mesh m = test::two_blocks(c.foundation, cells, c.punch_cells, cells, 2, Vec3(x0 - slide, 1, 2), true, c.punch, 2,
                            2);
  auto node_at = [&](const Vec3& x) {
    for (Index i = 0; i < m.num_nodes(); ++i)
      if ((m.nodes[i] - x).norm() < 1e-9) return i;
    ADD_FAILURE() << "no node at " << x.transpose();
    return Index(0);
  };
  m.facet_sets["foundation_top"] = facets_in_footprint(m, "lower_zmax", true, x0);
  m.facet_sets["foundation_free"] = facets_in_footprint(m, "lower_zmax", false, x0);
  m.node_sets["origin"] = {node_at(Vec3(0, 0, 0))};
  m.node_sets["x_axis"] = {node_at(Vec3(cells, 0, 0))};
  m.node_sets["punch_a"] = {node_at(Vec3(x0 - slide, 1, 4))};
  m.node_sets["punch_b"] = {node_at(Vec3(x0 + 2 - slide, 1, 4))};
  m.complete_node_sets();
  AnalysisSettings s;
  s.dimension = Dimension::three_d;
  s.finite_strain = stretch > 0;
  Model model;
  model.settings = s;
  model.mesh = std::move(m);
  EXPECT_EQ(model.mesh.facet_sets["foundation_free"].empty(), false);
  orient_facets(model.mesh);
  std::shared_ptr<Material> mat;
  if (stretch > 0) mat = std::make_shared<NeoHookean>(E, nu);
  else mat = std::make_shared<LinearElastic>(E, nu);
  model.bodies.push_back(std::make_unique<Body>("foundation", model.mesh.regions["lower_domain"], mat, s));
  model.bodies.push_back(std::make_unique<Body>("punch", model.mesh.regions["upper_domain"], mat, s));
  ContactPairSettings cs;
  cs.name = "patch";
  cs.master = slide > 0 ? "lower_zmax" : "foundation_top";
  cs.slave = "upper_zmin";
  cs.discretization = c.discretization;
  cs.method = c.method;
  if (s.finite_strain) cs.nitsche_theta = 0;  // Nitsche at finite strain (the deck's default there)
  model.contacts = {cs};
  Step st;
  st.dirichlet = {test::fix("lower_zmin", 2), test::fix("origin", 0), test::fix("origin", 1),
                  test::fix("x_axis", 1), test::fix("punch_a", 0, exx * x0 + slide), test::fix("punch_a", 1, exx * 1),
                  test::fix("punch_b", 1, exx * 1)};
  if (slide > 0) st.initial_increment = st.max_increment = 0.1 / slide;  // a tenth of a foundation cell per increment
  for (const char* set : {"upper_zmax", "foundation_free"}) {
    Load l;
    l.kind = LoadKind::pressure;
    l.set = set;
    l.pressure = p;
    st.loads.push_back(l);
  }
  model.steps = {st};
  return model;
}

}  // namespace

namespace {

// The patch's state after a run: the closed slave nodes' reported pressures, max |sigma_zz + p|
// and max |sigma_xx| over both bodies' cells.
struct PatchState {
  int closed = 0;
  Real pmin = 1e300, pmax = -1e300, szz = 0, sxx = 0;
};
PatchState patch_state(const Analysis& a, const Model& model, Real p) {
  PatchState s;
  for (const auto& ct : a.contacts())
    for (const auto& ns : ct->slave_states()) {
      if (ns.status != 2) continue;
      s.pmin = std::min(s.pmin, ns.pressure);
      s.pmax = std::max(s.pmax, ns.pressure);
      ++s.closed;
    }
  for (auto& b : model.bodies) {
    CellResults cr = b->results(model.mesh.nodes, a.displacement(), a.dofs());
    for (auto& sg : cr.stress) s.szz = std::max(s.szz, std::abs(sg(2) + p)), s.sxx = std::max(s.sxx, std::abs(sg(0)));
  }
  return s;
}

void check_uniform_state(const Patch3dCase& c) {
  log::set_level(std::getenv("SIGNORINI_TEST_VERBOSE") ? log::Level::info : log::Level::warning);
  const Real E = 1000, nu = 0.4, p = 10;
  Model model = patch_model(c, E, nu, p);
  // Matching meshes: Newton to 1e-11, so that the state is exact to the test's 1e-8.
  if (c.tolerance < 1e-6) model.newton.residual_tolerance = 1e-11;
  Analysis a(model);
  const AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  [[maybe_unused]] const auto [closed, pmin, pmax, szz, sxx] = patch_state(a, model, p);
  std::printf("3D patch %s %s: %d closed slave nodes, pressure %.10g .. %.10g, max |sigma_zz + p| %.2e\n",
              element_info(c.punch).name.c_str(), element_info(c.foundation).name.c_str(), closed, pmin, pmax, szz);
  EXPECT_GT(closed, 0);
  EXPECT_NEAR(pmin, p, c.tolerance * p);
  EXPECT_NEAR(pmax, p, c.tolerance * p);
  EXPECT_LT(szz, c.tolerance * p);
}

}  // namespace

TEST_P(ContactPatch3d, SegmentToSegmentCarriesTheUniformState) { check_uniform_state(GetParam()); }

// Matching meshes: exact, and every slave node of a tri6 or quad8 facet reports p (the
// multiplier; the force per weight read 0 at tri6 corners and 5/3 p at mid-side nodes).
// Non-matching: segment_to_segment integrates each slave facet with Gauss points, and the gap
// has kinks inside a facet where master edges cross it, so the state is not exact. Measured
// (pressure spread, max |sigma_zz + p|, relative to p): tet10 on hex8 0.38 % and 0.23 %,
// hex20 on tet4 0.39 % and 0.50 %, tet4 on hex20 0.25 % and 0.11 %; asserted within 1 %. The
// exact non-matching patch test needs segment-based integration (3D mortar, issue 14). A quad9
// punch (hex27) on a tet10 foundation stagnated above 1e-4 of the force scale and was cut back
// until it gave up, until the points were held on their master facet (integration_point_gaps):
// now 2 Newton iterations, but the least accurate of the table: pressures 9.41 to 10.21 (the
// quad9 slave's dual basis on its own shape functions, whose corner integrals are small, and
// tri6 master edges crossing its facets), max |sigma_zz + p| 1.2 % of p; asserted within 7 %.
// Nitsche, hex8 punches on tet4 and tet10 foundations: the nodes match, but the master
// triangles' diagonals cross the quad4 slave facets (through three of their nine Gauss points),
// so the integration is not exact either. Measured: pressure spread 0.42 % and 0.32 %, max
// |sigma_zz + p| 0.75 % and 1.7 % of p; asserted within 2 %. Before the points were held on
// their master facet (integration_point_gaps' `held`) the points on the diagonals changed facet
// from one iterate to the next and Newton cycled: 25 iterations to 4e-6 on tet4, no
// convergence on tet10 (cut back to the minimum increment); now 2 and 4 iterations.
INSTANTIATE_TEST_SUITE_P(
    Facets, ContactPatch3d,
    ::testing::Values(Patch3dCase{ElementType::tet10, ElementType::hex8, 2, "lagrange", 1e-8},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 2, "penalty", 1e-8},
                      Patch3dCase{ElementType::hex20, ElementType::hex8, 2, "lagrange", 1e-8},
                      Patch3dCase{ElementType::tet4, ElementType::hex20, 2, "lagrange", 1e-8},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 3, "lagrange", 1e-2},
                      Patch3dCase{ElementType::hex20, ElementType::tet4, 3, "lagrange", 1e-2},
                      Patch3dCase{ElementType::tet4, ElementType::hex20, 3, "lagrange", 1e-2},
                      Patch3dCase{ElementType::hex27, ElementType::tet10, 3, "lagrange", 7e-2},
                      Patch3dCase{ElementType::hex8, ElementType::tet4, 2, "nitsche", 2e-2},
                      Patch3dCase{ElementType::hex8, ElementType::tet10, 2, "nitsche", 2e-2}),
    case_name);

// Segment-based mortar (linear facets): the master facets clipped on each slave facet and the
// cells integrated exactly, so the non-matching patch is exact as well (issue 14: uniform
// pressure to 1e-8 relative) with Lagrange multipliers: hex8 or tet4 punches of 3 x 3 x 2 cells
// on hex8 or tet4 foundations of 4 x 4 x 2, every pairing of tri3 and quad4 facets, the
// matching hex8 pair, and linear punches on quadratic foundations (hex20, tet10, hex27: tri6,
// quad8, quad9 masters). Penalty and the augmented Lagrangian, reported: as in 2D
// (ContactPatch.MortarIsExact), the penetration g = -p / eps enters the weighted gaps'
// variation through the slave's current area, a tangential force of order p g at the punch's
// edges; measured pressures within 0.4 % (penalty, hex8 on tet4) and 0.01 % (augmented
// Lagrangian, tet4 on tet4) of p, max |sigma_zz + p| 2.1 % and 0.7 % of p; asserted within 5 %.
class ContactPatch3dMortar : public ::testing::TestWithParam<Patch3dCase> {};
TEST_P(ContactPatch3dMortar, MortarCarriesTheUniformState) { check_uniform_state(GetParam()); }
INSTANTIATE_TEST_SUITE_P(
    Facets, ContactPatch3dMortar,
    ::testing::Values(Patch3dCase{ElementType::hex8, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::tet4, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::tet4, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::hex8, 2, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::tet4, 3, "penalty", 5e-2, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::tet4, 3, "augmented_lagrangian", 5e-2, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::hex20, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::tet10, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::hex27, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex20, ElementType::tet4, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex27, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::tet10, ElementType::tet10, 3, "lagrange", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::tet4, 2, "nitsche", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::tet10, 2, "nitsche", 1e-8, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::hex8, 3, "nitsche", 1e-8, "mortar"},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 3, "nitsche", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex20, ElementType::tet4, 3, "nitsche", 1e-8, "mortar"},
                      Patch3dCase{ElementType::hex27, ElementType::tet10, 3, "nitsche", 1e-8, "mortar"}),
    case_name);

// The 3D mortar patch after sliding (issue 14: the patch "before and after the upper block
// slides by several element lengths at finite strain"): on a foundation of 6 x 6 x 2 cells the
// punch starts at x = 0 and is moved by 3 foundation cells (4.5 of its own cells: 3 x 3 on a
// 2 x 2 face) onto [3, 5] x [1, 3], on the whole foundation top as master, while the load comes
// on, a tenth of a cell per increment, so that every cell of the interface changes many times.
// The final state of a frictionless hyperelastic problem does not depend on the path, so it is
// the uniform one. Small strain: as above. Finite strain (Neo-Hookean, the pressures
// following the surfaces): F = diag(l, l, lz), Cauchy sigma_xx = sigma_yy = 0 and sigma_zz = -p
// in both blocks, mu (l^2 - 1) + Lambda ln J = 0 and mu (lz^2 - 1) + Lambda ln J = -p J,
// J = l^2 lz (material.cpp's Neo-Hookean), solved by Newton here (l = 1.0040217); the punch held at
// the foundation's homogeneous x = 3 l, y = l (plus the slide), the reported pressure the contact
// force per reference area, p l^2. Lagrange multipliers; hex8 and tet4 punches on hex8 and tet4
// foundations, and a quadratic slave (tet10: tri6 facets, the dual basis on the transformed
// one) on hex8; Newton to 1e-11. Measured (30 increments each): every slave node closed,
// pressures equal to the exact value to 10 digits, |sigma_zz + p| and |sigma_xx| below 1.5e-10,
// the stretch to 10 digits; 61-67 Newton iterations on the linear punches, 74 on tet10. With a
// third of a cell per increment (10 increments, 34-42 iterations) tet10 at small strain ended
// at 1.7e-8 of p: Newton's 1e-11 on the residual is not 1e-8 on the multipliers there.
struct SlidingPatchCase {
  Patch3dCase c;
  bool finite;
};
class ContactPatch3dMortarSliding : public ::testing::TestWithParam<SlidingPatchCase> {};

TEST_P(ContactPatch3dMortarSliding, SlidPunchCarriesTheUniformState) {
  const auto [c, finite] = GetParam();
  log::set_level(std::getenv("SIGNORINI_TEST_VERBOSE") ? log::Level::info : log::Level::warning);
  const Real E = 1000, nu = 0.4, p = 10, mu = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  Real l = 1, lz = 1;
  for (int it = 0; it < 50; ++it) {
    const Real J = l * l * lz, f1 = mu * (l * l - 1) + lam * std::log(J),
               f2 = mu * (lz * lz - 1) + lam * std::log(J) + p * J;
    const Real a11 = 2 * mu * l + 2 * lam / l, a12 = lam / lz;
    const Real a21 = 2 * lam / l + 2 * p * l * lz, a22 = 2 * mu * lz + lam / lz + p * l * l;
    const Real det = a11 * a22 - a12 * a21;
    l -= (a22 * f1 - a12 * f2) / det;
    lz -= (a11 * f2 - a21 * f1) / det;
  }
  const int cells = 6;
  const Real x0 = 3, slide = 3;
  const std::string what = element_info(c.punch).name + " on " + element_info(c.foundation).name +
                           (finite ? ", finite strain" : ", small strain");
  Model model = patch_model(c, E, nu, p, slide, finite ? l : 0, cells, x0);
  model.newton.residual_tolerance = 1e-11;
  Analysis a(model);
  const AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << what << ": " << sum.failure;
  const Real expected = finite ? p * l * l : p;
  const auto [closed, pmin, pmax, szz, sxx] = patch_state(a, model, p);
  // The lateral stretch: the foundation's node at (cells, 0, 0) moves by cells (l - 1) along x.
  const Index corner = model.mesh.node_sets.at("x_axis").front();
  const Real stretch = 1 + a.displacement()(a.dofs().dof(corner, 0)) / cells;
  int iterations = 0;
  for (const auto& inc : sum.increments) iterations += inc.iterations;
  std::printf("3D mortar patch after sliding, %s: %d closed, pressure %.10g .. %.10g (exact %.10g), max |sigma_zz "
              "+ p| %.1e, max |sigma_xx| %.1e, stretch %.10f (exact %.10f); %zu increments, %d iterations\n",
              what.c_str(), closed, pmin, pmax, expected, szz, sxx, stretch, finite ? l : 1 + nu * p / E,
              sum.increments.size(), iterations);
  std::set<Index> slave_nodes;
  for (const ElementBlock& b : model.mesh.facet_sets.at("upper_zmin")) slave_nodes.insert(b.conn.begin(), b.conn.end());
  EXPECT_EQ(closed, static_cast<int>(slave_nodes.size())) << what << ": every slave node closed";
  EXPECT_NEAR(pmin, expected, 1e-8 * p) << what;
  EXPECT_NEAR(pmax, expected, 1e-8 * p) << what;
  EXPECT_LT(szz, 1e-8 * p) << what;
  EXPECT_LT(sxx, 1e-8 * p) << what;
  EXPECT_NEAR(stretch, finite ? l : 1 + nu * p / E, 1e-9) << what;
}

INSTANTIATE_TEST_SUITE_P(
    Facets, ContactPatch3dMortarSliding,
    ::testing::Values(SlidingPatchCase{{ElementType::hex8, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"}, false},
                      SlidingPatchCase{{ElementType::hex8, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"}, true},
                      SlidingPatchCase{{ElementType::tet4, ElementType::tet4, 3, "lagrange", 1e-8, "mortar"}, false},
                      SlidingPatchCase{{ElementType::tet4, ElementType::tet4, 3, "lagrange", 1e-8, "mortar"}, true},
                      SlidingPatchCase{{ElementType::tet10, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"}, false},
                      SlidingPatchCase{{ElementType::tet10, ElementType::hex8, 3, "lagrange", 1e-8, "mortar"}, true},
                      // Nitsche on mortar integration (small strain: Nitsche's limit), its cells
                      // cut again at every Newton iterate.
                      SlidingPatchCase{{ElementType::hex8, ElementType::hex8, 3, "nitsche", 1e-8, "mortar"}, false},
                      SlidingPatchCase{{ElementType::tet4, ElementType::tet4, 3, "nitsche", 1e-8, "mortar"}, false},
                      SlidingPatchCase{{ElementType::tet10, ElementType::hex8, 3, "nitsche", 1e-8, "mortar"}, false},
                      SlidingPatchCase{{ElementType::hex8, ElementType::hex8, 3, "nitsche", 1e-8, "mortar"}, true},
                      SlidingPatchCase{{ElementType::tet4, ElementType::tet4, 3, "nitsche", 1e-8, "mortar"}, true}),
    [](const ::testing::TestParamInfo<SlidingPatchCase>& i) {
      return element_info(i.param.c.punch).name + "_on_" + element_info(i.param.c.foundation).name +
             (i.param.finite ? "_finite_strain" : "_small_strain") +
             (std::string(i.param.c.method) == "nitsche" ? "_nitsche" : "");
    });

// The same patch with Coulomb friction (mu = 0.2, segment_to_segment in 3D: the slip of each
// slave node averaged over its facets' integration points, against the slave's averaged normal
// and its variation, MasterSurface::node_normal_jacobian_3d; mortar: averaged over its facets'
// cells, non-matching tri3 and quad4 pairings, one per method), the whole foundation top as
// master: pressed as above, then the punch top is moved by 0.1 along x (the punch's elastic
// shear takes some 0.01) with the foundation's bottom held in x and y, so that every contact
// node slips. Coulomb's law then holds at every node, |t_j| = mu p_j, and the force on the
// punch top balances the friction forces: their magnitudes sum to mu P (P = 4 p) and they point
// against the motion, so Q_x <= mu P, and close to it: the held top tilts the pressure towards
// the leading edge and the punch's y-anchors give the slips a y part (measured: Q_x 2.1 to
// 3.7 % below mu P, Q_y 0.1 to 0.5 % of P). Asserted: every closed node slipping,
// |t_j| = mu p_j to 1e-6, 0.9 mu P < Q_x <= mu P. Linear punches on quadratic foundations too
// (tet10, hex20, hex27: tri6, quad8, quad9 master facets; Q_x 3.0 to 3.7 % below mu P). Until
// session 33 the slide held the foundation at one bottom node only: on quadratic cells that
// node gave way, the foundation's top followed the punch, one to three slave nodes stayed in
// stick and Q_x ended 25 to 50 % below mu P, which the compatibility table took for a defect of
// friction on quadratic masters and refused.
namespace {
// The friction patch's model: the press above with Coulomb friction mu, the whole foundation
// top as master (the punch slides beyond the footprint), then a step that moves the punch top
// by 0.1 along x.
Model sliding_patch_model(const Patch3dCase& c, Real E, Real nu, Real p, Real mu) {
  const Real exx = nu * p / E;
  Model model = patch_model(c, E, nu, p);
  model.contacts[0].friction = "coulomb";
  model.contacts[0].friction_parameter = mu;
  model.contacts[0].master = "lower_zmax";
  Step slide = model.steps[0];
  // The foundation's bottom held in x and y where the press left it (one pinned node gives way
  // on quadratic cells and the foundation's top then follows the punch).
  DirichletCondition hold_x = test::fix("lower_zmin", 0), hold_y = test::fix("lower_zmin", 1);
  hold_x.hold = hold_y.hold = true;
  slide.dirichlet = {test::fix("lower_zmin", 2), hold_x, hold_y, test::fix("upper_zmax", 0, 0.1),
                     test::fix("punch_a", 1, exx * 1), test::fix("punch_b", 1, exx * 1)};
  model.steps.push_back(slide);
  return model;
}
}  // namespace

class ContactPatch3dFriction : public ::testing::TestWithParam<Patch3dCase> {};

TEST_P(ContactPatch3dFriction, SlidingPunchObeysCoulombAtEveryNode) {
  const Patch3dCase c = GetParam();
  log::set_level(std::getenv("SIGNORINI_TEST_VERBOSE") ? log::Level::info : log::Level::warning);
  const Real E = 1000, nu = 0.4, p = 10, mu = 0.2, P = 4 * p;
  Model model = sliding_patch_model(c, E, nu, p, mu);
  Analysis a(model);
  const AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  int closed = 0, slipping = 0;
  Real coulomb = 0, pmax = 0;
  // Coulomb's law holds between the multipliers, the pressure and the traction the enforcement
  // solved for. Mortar reports another pressure (the normal nodal force per reference weight,
  // ContactInterface::set_reported_pressure: its normal force at a node gathers its neighbours'
  // multipliers through their weighted gaps' variations), 1.2 % off the multiplier here.
  const bool mortar = std::string(c.discretization) == "mortar";
  for (const auto& ct : a.contacts()) {
    const std::vector<ContactInterface::SlaveState> states = ct->slave_states();
    for (size_t j = 0; j < states.size(); ++j) {
      const auto& ns = states[j];
      if (ns.status < 2) continue;
      ++closed;
      slipping += ns.status == 3;
      const Real pj = mortar ? ct->state().pressure[j] : ns.pressure;
      coulomb = std::max(coulomb, ns.status == 3 ? std::abs(ns.traction.norm() - mu * pj)
                                                 : std::max(0.0, ns.traction.norm() - mu * pj));
      pmax = std::max(pmax, pj);
    }
  }
  const Vec3 Q = a.reaction_sum("upper_zmax");
  int iterations = 0;
  for (const auto& inc : sum.increments) iterations += inc.iterations;
  std::printf("3D sliding patch %s on %s (%s): %d closed, %d slipping; max ||t_j| - mu p_j| / (mu max p) %.1e; "
              "Q_x / (mu P) - 1 = %.3e, Q_y / P = %.1e; %zu increments, %d Newton iterations\n",
              element_info(c.punch).name.c_str(), element_info(c.foundation).name.c_str(), c.method, closed, slipping,
              coulomb / (mu * pmax), Q(0) / (mu * P) - 1, Q(1) / P, sum.increments.size(), iterations);
  EXPECT_GT(closed, 0);
  EXPECT_EQ(slipping, closed) << "every contact node slips";
  EXPECT_LT(coulomb, 1e-6 * mu * pmax) << "Coulomb's law at every node";
  EXPECT_LE(Q(0), mu * P * (1 + 1e-6)) << "the friction forces' magnitudes sum to mu P";
  EXPECT_GT(Q(0), 0.9 * mu * P) << "and they point against the motion";
}

// The same sliding patch with Nitsche's method (segment_to_segment's integration points, small
// strain; docs/contact.md (N2)): Coulomb's law is per integration point, the slave body's
// traction returned onto mu [P]_+, and the nodal values written are averages of the points'.
// Asserted: every active point slips (the enforcement's status), its trial traction
// Q = P_T (t - eps d), recomputed here from the point's traction and slip, outside its disc
// mu [P]_+ (to 1e-6: the status agrees with the point's data), and 0.9 mu P < Q_x <= mu P
// for the force on the punch top as above. Linear and quadratic punches on linear and
// quadratic foundations, matching and not. Measured: Q_x 1.7 to 3.7 % below mu P; 10 to 28
// Newton iterations for the press and the slide together (the non-matching tet4 punch's slide
// stagnated at 9.5e-7 and took 3 + 25 before the points were held on their master facet,
// integration_point_gaps; now 12).
class ContactPatch3dFrictionNitsche : public ::testing::TestWithParam<Patch3dCase> {};

TEST_P(ContactPatch3dFrictionNitsche, SlidingPunchObeysCoulombAtEveryIntegrationPoint) {
  const Patch3dCase c = GetParam();
  log::set_level(std::getenv("SIGNORINI_TEST_VERBOSE") ? log::Level::info : log::Level::warning);
  const Real E = 1000, nu = 0.4, p = 10, mu = 0.2, P = 4 * p;
  Model model = sliding_patch_model(c, E, nu, p, mu);
  Analysis a(model);
  const AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  ASSERT_EQ(a.contacts().size(), 1u);
  const ContactInterface& ct = *a.contacts()[0];
  const std::vector<PointConstraint>* pts = ct.integration_points();
  ASSERT_NE(pts, nullptr);
  const std::vector<signed char>& status = ct.state().point_slip;
  ASSERT_EQ(status.size(), pts->size());
  int active = 0, slipping = 0;
  Real coulomb = 0, pmax = 0;
  for (size_t q = 0; q < pts->size(); ++q) {
    const PointConstraint& pc = (*pts)[q];
    const Real Pq = pc.pressure - pc.stiffness * pc.gap;
    if (!(Pq > 0) || !pc.has_slip) continue;
    ++active;
    slipping += status[q] == 1;
    // The point's trial traction Q = P_T (t - eps d); slipping, tau = mu P Q / |Q|: |Q| >= mu P.
    const Vec3 nu_q = pc.normal;
    Vec3 Q = pc.traction - pc.stiffness * pc.slip;
    Q -= nu_q * nu_q.dot(Q);
    coulomb = std::max(coulomb, std::max(0.0, mu * Pq - Q.norm()));
    pmax = std::max(pmax, Pq);
  }
  const Vec3 F = a.reaction_sum("upper_zmax");
  int iterations = 0;
  for (const auto& inc : sum.increments) iterations += inc.iterations;
  std::printf("3D sliding patch, nitsche, %s on %s: %d active points, %d slipping; max <mu P_q - |Q_q|>_+ / (mu max P) "
              "%.1e; Q_x / (mu P) - 1 = %.3e, Q_y / P = %.1e; %zu increments, %d Newton iterations\n",
              element_info(c.punch).name.c_str(), element_info(c.foundation).name.c_str(), active, slipping,
              coulomb / (mu * pmax), F(0) / (mu * P) - 1, F(1) / P, sum.increments.size(), iterations);
  EXPECT_GT(active, 0);
  EXPECT_EQ(slipping, active) << "every active integration point slips";
  EXPECT_LT(coulomb, 1e-6 * mu * pmax) << "each slipping point's trial traction outside its disc";
  EXPECT_LE(F(0), mu * P * (1 + 1e-6)) << "the friction forces' magnitudes sum to mu P";
  EXPECT_GT(F(0), 0.9 * mu * P) << "and they point against the motion";
}

INSTANTIATE_TEST_SUITE_P(
    Facets, ContactPatch3dFrictionNitsche,
    ::testing::Values(Patch3dCase{ElementType::hex8, ElementType::hex8, 2, "nitsche", 0},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 2, "nitsche", 0},
                      Patch3dCase{ElementType::tet4, ElementType::hex8, 3, "nitsche", 0},
                      Patch3dCase{ElementType::hex8, ElementType::hex27, 2, "nitsche", 0},
                      Patch3dCase{ElementType::tet10, ElementType::hex20, 2, "nitsche", 0},
                      Patch3dCase{ElementType::hex8, ElementType::tet10, 2, "nitsche", 0},
                      Patch3dCase{ElementType::hex8, ElementType::tet4, 2, "nitsche", 0},
                      Patch3dCase{ElementType::tet10, ElementType::tet10, 2, "nitsche", 0},
                      Patch3dCase{ElementType::hex8, ElementType::tet10, 3, "nitsche", 0}),
    case_name);

INSTANTIATE_TEST_SUITE_P(
    Facets, ContactPatch3dFriction,
    ::testing::Values(Patch3dCase{ElementType::hex8, ElementType::hex8, 2, "lagrange", 0},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 2, "lagrange", 0},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 2, "penalty", 0},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 2, "augmented_lagrangian", 0},
                      Patch3dCase{ElementType::tet4, ElementType::hex8, 3, "lagrange", 0},
                      Patch3dCase{ElementType::hex8, ElementType::tet10, 2, "lagrange", 0},
                      Patch3dCase{ElementType::hex8, ElementType::hex20, 2, "penalty", 0},
                      Patch3dCase{ElementType::tet10, ElementType::hex27, 2, "augmented_lagrangian", 0},
                      Patch3dCase{ElementType::hex8, ElementType::hex8, 3, "lagrange", 0, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::tet4, 3, "lagrange", 0, "mortar"},
                      Patch3dCase{ElementType::hex8, ElementType::tet4, 3, "penalty", 0, "mortar"},
                      Patch3dCase{ElementType::tet4, ElementType::hex8, 3, "augmented_lagrangian", 0, "mortar"},
                      Patch3dCase{ElementType::tet10, ElementType::hex8, 3, "lagrange", 0, "mortar"},
                      Patch3dCase{ElementType::hex20, ElementType::hex8, 3, "augmented_lagrangian", 0, "mortar"},
                      Patch3dCase{ElementType::hex27, ElementType::tet4, 3, "penalty", 0, "mortar"}),
    case_name);
