// Taylor's contact patch test (Taylor & Papadopoulos 1991; VALIDATION.md sec. 2): a punch
// 2 x 2 on a foundation 8 x 5, plane strain, E = 1000, nu = 0.4, frictionless, a uniform
// pressure p = 10 on the punch top and on the uncovered foundation top. The exact state is
// uniform: sigma_yy = -10 everywhere and a contact pressure of 10.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

struct PatchResult {
  bool completed = false;
  Real pressure_min = 0, pressure_max = 0, pressure_mean = 0;
  Real syy_spread = 0;  // max |sigma_yy + 10| over all cells
  Real stretch = 1;     // the punch bottom's current length over its reference length
};

// Facets of `set` whose nodes all have x in [x0, x1].
std::vector<ElementBlock> facets_between(const Mesh& m, const std::string& set, Real x0, Real x1) {
  std::vector<ElementBlock> out;
  for (const ElementBlock& b : m.facet_sets.at(set)) {
    ElementBlock nb{b.type, {}, {}};
    for (Index e = 0; e < b.size(); ++e) {
      bool in = true;
      for (int k = 0; k < b.nodes_per_element(); ++k) {
        const Real x = m.nodes[b.element(e)[k]](0);
        in = in && x >= x0 - 1e-9 && x <= x1 + 1e-9;
      }
      if (in) nb.add(std::vector<Index>(b.element(e), b.element(e) + b.nodes_per_element()), b.ids[e]);
    }
    if (nb.size()) out.push_back(nb);
  }
  return out;
}

// `punch_ux`: x displacement of the punch-top support node. The exact solution gives the
// foundation 4 eps_xx at x = 4, so `punch_ux = 4 eps_xx` keeps the interface nodes where they
// are; 0 makes the punch slide by 4 eps_xx = 0.0224 against the foundation, which changes the
// constraint layout (the punch's end node then projects on the foundation facet left of x = 4).
PatchResult run(const std::string& discretization, int passes, const std::string& method, int punch_cells,
                Real punch_ux = 0, const std::string& smoothing = "none", ElementType punch_type = ElementType::quad4,
                ElementType foundation_type = ElementType::quad4, Real slide = 0, bool finite = false, Real mu = 0,
                int theta = 1) {
  log::set_level(std::getenv("SIGNORINI_TEST_VERBOSE") ? log::Level::info : log::Level::warning);
  // Foundation [0, 8] x [0, 5] (8 x 5 cells), punch [4, 6] x [5, 7].
  Mesh f = structured_rectangle(foundation_type, 8, 5, 8, 5);
  StructuredOptions o;
  o.origin = Vec3(4 - slide, 5, 0);  // `slide`: the punch starts that far left and is moved there
  Mesh p = structured_rectangle(punch_type, punch_cells, punch_cells, 2, 2, o);
  Mesh m;
  m.dim = 2;
  m.nodes = f.nodes;
  m.nodes.insert(m.nodes.end(), p.nodes.begin(), p.nodes.end());
  for (Index i = 0; i < m.num_nodes(); ++i) m.node_ids.push_back(i + 1);
  const Index shift = f.num_nodes();
  auto shifted = [&](std::vector<ElementBlock> v, Index sh) {
    for (auto& b : v)
      for (auto& c : b.conn) c += sh;
    return v;
  };
  m.regions["foundation"] = f.regions["domain"];
  m.regions["punch"] = shifted(p.regions["domain"], shift);
  m.facet_sets["foundation_top"] = f.facet_sets["ymax"];
  m.facet_sets["foundation_free_left"] = facets_between(f, "ymax", 0, 4);
  m.facet_sets["foundation_free_right"] = facets_between(f, "ymax", 6, 8);
  m.facet_sets["punch_bottom"] = shifted(p.facet_sets["ymin"], shift);
  m.facet_sets["punch_top"] = shifted(p.facet_sets["ymax"], shift);
  m.node_sets["foundation_bottom"] = f.node_sets["ymin"];
  m.node_sets["corner"] = {f.node_sets["ymin"].front()};
  m.node_sets["punch_top_node"] = {p.node_sets["ymax"].front() + shift};
  m.complete_node_sets();
  AnalysisSettings s;
  s.dimension = Dimension::plane_strain;
  s.finite_strain = finite;
  Model model;
  model.settings = s;
  model.mesh = std::move(m);
  orient_facets(model.mesh);
  std::shared_ptr<Material> mat;
  if (finite) mat = std::make_shared<NeoHookean>(1000, 0.4);
  else mat = std::make_shared<LinearElastic>(1000, 0.4);
  model.bodies.push_back(std::make_unique<Body>("foundation", model.mesh.regions["foundation"], mat, s));
  model.bodies.push_back(std::make_unique<Body>("punch", model.mesh.regions["punch"], mat, s));
  ContactPairSettings cs;
  cs.name = "patch";
  cs.master = "foundation_top";
  cs.slave = "punch_bottom";
  cs.discretization = discretization;
  cs.passes = passes;
  cs.method = method;
  cs.smoothing = smoothing;
  cs.nitsche_theta = theta;
  if (mu > 0) {
    cs.friction = "coulomb";
    cs.friction_parameter = mu;
  }
  model.contacts = {cs};
  Step st;
  st.dirichlet = {test::fix("foundation_bottom", 1), test::fix("corner", 0), test::fix("punch_top_node", 0, punch_ux)};
  for (const char* set : {"punch_top", "foundation_free_left", "foundation_free_right"}) {
    Load l;
    l.kind = LoadKind::pressure;
    l.set = set;
    l.pressure = 10;
    st.loads.push_back(l);
  }
  // Mortar: Newton to 1e-11 (it converges quadratically; the default 1e-8 leaves the state
  // 1e-8 from the uniform one, the test's tolerance).
  if (discretization == "mortar") model.newton.residual_tolerance = 1e-11;
  if (slide > 0) st.initial_increment = st.max_increment = 0.1;  // slide one foundation cell per 5 increments
  model.steps = {st};
  Analysis a(model);
  AnalysisSummary sum = a.run();
  PatchResult r;
  r.completed = sum.completed;
  if (!sum.completed) {
    std::printf("patch test %s passes %d %s: %s\n", discretization.c_str(), passes, method.c_str(), sum.failure.c_str());
    return r;
  }
  // The reported pressure of every closed slave node of both passes (the normal contact force
  // on the node from all the pair's constraints per tributary area).
  r.pressure_min = 1e300;
  r.pressure_max = -1e300;
  Index n = 0;
  for (const auto& c : a.contacts())
    for (const auto& ns : c->slave_states()) {
      if (ns.status != 2) continue;
      r.pressure_min = std::min(r.pressure_min, ns.pressure);
      r.pressure_max = std::max(r.pressure_max, ns.pressure);
      r.pressure_mean += ns.pressure;
      ++n;
    }
  r.pressure_mean /= n;
  {
    const std::vector<Vec3> x = a.positions(a.displacement());
    Real lo = 1e300, hi = -1e300, X0 = 1e300, X1 = -1e300;
    for (const ElementBlock& b : model.mesh.facet_sets.at("punch_bottom"))
      for (Index node : b.conn) {
        lo = std::min(lo, x[node](0)), hi = std::max(hi, x[node](0));
        X0 = std::min(X0, model.mesh.nodes[node](0)), X1 = std::max(X1, model.mesh.nodes[node](0));
      }
    r.stretch = (hi - lo) / (X1 - X0);
  }
  for (auto& b : model.bodies) {
    CellResults cr = b->results(model.mesh.nodes, a.displacement(), a.dofs());
    for (auto& sg : cr.stress) r.syy_spread = std::max(r.syy_spread, std::abs(sg(1) + 10));
  }
  std::printf("patch test %-16s passes %d %-9s punch %d %s cells on %s: pressure %.10g .. %.10g, (max-min)/mean %.2e, "
              "max |sigma_yy + 10| %.2e\n",
              discretization.c_str(), passes, method.c_str(), punch_cells, element_info(punch_type).name.c_str(),
              element_info(foundation_type).name.c_str(), r.pressure_min, r.pressure_max,
              (r.pressure_max - r.pressure_min) / r.pressure_mean, r.syy_spread);
  return r;
}

}  // namespace

TEST(ContactPatch, NodeToNodeMatchingMeshIsExact) {
  for (const char* method : {"lagrange", "penalty"}) {
    PatchResult r = run("node_to_node", 1, method, 2);  // punch nodes at 4, 5, 6: matching
    ASSERT_TRUE(r.completed) << method;
    if (std::string(method) == "lagrange") {
      EXPECT_NEAR(r.pressure_min, 10, 1e-8 * 10);
      EXPECT_NEAR(r.pressure_max, 10, 1e-8 * 10);
      EXPECT_LT(r.syy_spread, 1e-8 * 10);
    } else {
      // Penalty: the pressure is uniform too (penetration uniform), to round-off.
      EXPECT_LT((r.pressure_max - r.pressure_min) / r.pressure_mean, 1e-8);
    }
  }
}

// Two-pass node-to-segment with multipliers on the non-matching interface (punch 3, 5 and 7
// cells on 2 foundation cells): the uniform state is exact. With the end nodes coincident,
// each end keeps one constraint (two identical ones make the multiplier system singular); the
// other pass's constraints then supply the missing share of the end nodes' force.
TEST(ContactPatch, TwoPassNodeToSegmentIsExact) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;  // nu (1 + nu) p / E
  for (int cells : {3, 5, 7}) {
    PatchResult r = run("node_to_segment", 2, "lagrange", cells, 4 * exx);
    ASSERT_TRUE(r.completed) << cells;
    EXPECT_LT(r.syy_spread, 1e-8 * 10) << cells;
    EXPECT_NEAR(r.pressure_min, 10, 1e-8 * 10) << cells;
    EXPECT_NEAR(r.pressure_max, 10, 1e-8 * 10) << cells;
  }
}

// The same with both surfaces smoothed (smoothing: hermite), reported: the surfaces stay
// straight, but a slave node's force now goes to the four nodes of its Hermite segment with
// the Catmull-Rom weights, two of them beyond the segment, so the master nodes next to the
// punch's ends get loads the exact state does not have; the uniform state is lost (measured:
// max |sigma_yy + p| = 1.8 % and 2.9 % of p, nodal pressures 9.91-10.18 and 9.72-10.44 for
// p = 10, with 3 and 5 punch cells). Smoothing is for
// curved, sliding masters; docs/validation.md. The bounds hold the measured behaviour.
TEST(ContactPatch, TwoPassSmoothedNodeToSegmentReported) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;
  for (int cells : {3, 5}) {
    PatchResult r = run("node_to_segment", 2, "lagrange", cells, 4 * exx, "hermite");
    ASSERT_TRUE(r.completed) << cells;
    EXPECT_GT(r.pressure_min, 0.9 * 10) << cells;
    EXPECT_LT(r.pressure_max, 1.1 * 10) << cells;
    EXPECT_LT(r.syy_spread, 0.05 * 10) << cells;
  }
}

// Node-to-segment: one pass, and two passes with the punch sliding, reported, not hidden
// (docs/validation.md). One pass fails the patch test, as the literature says (Zavarise &
// De Lorenzis 2009). Two passes with the punch sliding by 4 eps_xx: the punch's end node now
// projects on the foundation facet left of x = 4 and pushes a foundation node that the exact
// state leaves unloaded; there are then fewer multipliers than independent equilibrium
// equations on the interface. The bounds below hold the measured behaviour so that a
// regression shows.
TEST(ContactPatch, NodeToSegmentReported) {
  for (int passes : {1, 2})
    for (const char* method : {"lagrange", "penalty"}) {
      PatchResult r = run("node_to_segment", passes, method, 3);
      ASSERT_TRUE(r.completed) << passes << " " << method;
      EXPECT_GT(r.pressure_min, 0) << passes << " " << method;
      EXPECT_LT(r.syy_spread, passes == 1 ? 0.35 : 0.15) << passes << " " << method;
      EXPECT_NEAR(r.pressure_max, 10, passes == 1 ? 0.4 : 0.25) << passes << " " << method;
    }
}

// Two-pass with penalty and no sliding: penalty lets the surfaces interpenetrate by p / k, and
// the two passes' penetrations compete, so the state is near-uniform only (reported).
TEST(ContactPatch, TwoPassPenaltyReported) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;
  PatchResult r = run("node_to_segment", 2, "penalty", 3, 4 * exx);
  ASSERT_TRUE(r.completed);
  EXPECT_LT(r.syy_spread, 0.06);
  EXPECT_GT(r.pressure_min, 0);
}

// Dual mortar (one pass, non-matching): the weighted gaps make the uniform state exact, on
// linear and quadratic facets on either side (line3 slave on line2 master, the reverse,
// line3 on line3), with Lagrange multipliers, where the punch stays and after it slid by two
// foundation cells (2 = 3 to 6 punch cells: the interface's segments all change) while the
// load came on (the final state of a frictionless elastic problem does not depend on the
// path). The dual basis sums to one, so a uniform pressure is in the multiplier space (Popp
// et al. 2010). Penalty, reported: its uniform penetration g = -p/eps enters the weighted
// gap's variation through the slave's current length, a tangential force of order p g at the
// punch's ends (measured: sigma_yy within 0.2 % of p, nodal pressures spread by 0.05-0.3 %).
// A punch and foundation pairing of the 2D patch and the punch's cells (3: non-matching).
struct PatchPair {
  ElementType punch, foundation;
  int cells;
};
// The mortar patch tests' pairings: linear and quadratic facets on either side, and a finer punch.
const std::vector<PatchPair>& mortar_patch_pairs() {
  static const std::vector<PatchPair> pairs = {
      {ElementType::quad4, ElementType::quad4, 3}, {ElementType::quad4, ElementType::quad4, 7},
      {ElementType::quad9, ElementType::quad4, 3}, {ElementType::quad4, ElementType::quad9, 3},
      {ElementType::quad8, ElementType::quad8, 3}};
  return pairs;
}

TEST(ContactPatch, MortarIsExact) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;
  for (const PatchPair& k : mortar_patch_pairs())
    for (Real slide : {0.0, 2.0})
      for (const char* method : {"lagrange", "penalty"}) {
        if (slide > 0 && std::string(method) == "penalty") continue;
        const std::string what = std::string(element_info(k.punch).name) + " on " + element_info(k.foundation).name +
                                 " " + std::to_string(k.cells) + " " + method + " slide " + std::to_string(slide);
        PatchResult r = run("mortar", 1, method, k.cells, slide + 4 * exx, "none", k.punch, k.foundation, slide);
        ASSERT_TRUE(r.completed) << what;
        if (std::string(method) == "lagrange") {
          EXPECT_LT(r.syy_spread, 1e-8 * 10) << what;
          EXPECT_NEAR(r.pressure_min, 10, 1e-8 * 10) << what;
          EXPECT_NEAR(r.pressure_max, 10, 1e-8 * 10) << what;
        } else {
          EXPECT_LT(r.syy_spread, 5e-3 * 10) << what;
          EXPECT_LT((r.pressure_max - r.pressure_min) / r.pressure_mean, 5e-3) << what;
        }
      }
}


// Segment-to-segment (Gauss points of the slave facets, non-matching): not exact, since a
// master node inside a slave facet puts a kink in the gap between Gauss points; uniform to 2 %
// with each method (measured on quad4: pressures 9.95 .. 10.10 with all three, sigma_yy within
// 0.52 %; quad9 9.96 .. 10.04). Newton used to stall here (|R|/F 8e-6 at 30 % of the load, then
// gave up; penalty: the line search halved each step towards the jump): a Gauss point on a
// master node makes the residual jump, and the stagnated residual is accepted within 1e-4 of
// the force scale (docs/architecture.md).
TEST(ContactPatch, SegmentToSegmentCarriesTheUniformState) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;
  for (ElementType punch : {ElementType::quad4, ElementType::quad9})
    for (const char* method : {"lagrange", "penalty", "augmented_lagrangian"}) {
      const std::string what = std::string(element_info(punch).name) + " " + method;
      PatchResult r = run("segment_to_segment", 1, method, 3, 4 * exx, "none", punch);
      ASSERT_TRUE(r.completed) << what;
      EXPECT_NEAR(r.pressure_min, 10, 0.2) << what;
      EXPECT_NEAR(r.pressure_max, 10, 0.2) << what;
      EXPECT_LT(r.syy_spread, 0.2) << what;
    }
}

// Nitsche's method on the same integration points: consistent (at the uniform state, p = 10
// from the stress and g = 0, its point terms are those of the uniform pressure), but the
// master's share of each point's force is the master shape functions at the projected points,
// which the slave facet's Gauss rule does not integrate exactly across a master node inside
// the facet (the kink of segment_to_segment): uniform within the same 2 % as the multipliers
// (measured: pressures 9.95 .. 10.08, sigma_yy within 0.023 .. 0.114 of 10), on quad4 and quad9
// punches, with each variant (theta 1, 0, -1), also after the punch slid by 4 eps_xx
// (punch_ux = 0: its points meet other master facets). Segment-based integration (mortar) is
// what makes the test exact.
TEST(ContactPatch, NitscheCarriesTheUniformState) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;
  for (ElementType punch : {ElementType::quad4, ElementType::quad9})
    for (int theta : {1, 0, -1})
      for (Real ux : {4 * exx, 0.0}) {
        const std::string what = std::string(element_info(punch).name) + " theta " + std::to_string(theta) +
                                 (ux == 0 ? " slid" : "");
        PatchResult r = run("segment_to_segment", 1, "nitsche", 3, ux, "none", punch, ElementType::quad4, 0, false, 0,
                            theta);
        ASSERT_TRUE(r.completed) << what;
        EXPECT_NEAR(r.pressure_min, 10, 0.2) << what;
        EXPECT_NEAR(r.pressure_max, 10, 0.2) << what;
        EXPECT_LT(r.syy_spread, 0.2) << what;
      }
}

// Nitsche on mortar integration (discretization: mortar, method: nitsche): the same points'
// terms on mortar's segments, which end where master nodes project onto the slave facet, so
// that the master's shape functions and the gap are polynomials on each segment and the Gauss
// rule integrates them exactly: the uniform state to round-off (asserted 1e-8 of p), with each
// variant, on MortarIsExact's pairs of linear and quadratic facets, where the punch stays and
// after it slid by two foundation cells while the load came on (a fifth of a cell per
// increment: the segments are cut again at every Newton iterate, so the converged state is
// integrated on its own). With the segments of the increment's start the slid punch ended 1 %
// from the uniform state.
TEST(ContactPatch, NitscheOnMortarIntegrationIsExact) {
  const Real exx = 0.4 * 1.4 * 10 / 1000;
  for (const PatchPair& k : mortar_patch_pairs())
    for (Real slide : {0.0, 2.0})
      for (int theta : {1, 0, -1}) {
        const std::string what = std::string(element_info(k.punch).name) + " on " + element_info(k.foundation).name +
                                 " " + std::to_string(k.cells) + " theta " + std::to_string(theta) + " slide " +
                                 std::to_string(slide);
        PatchResult r =
            run("mortar", 1, "nitsche", k.cells, slide + 4 * exx, "none", k.punch, k.foundation, slide, false, 0, theta);
        ASSERT_TRUE(r.completed) << what;
        std::printf("%s: pressure %.12g .. %.12g, sigma_yy spread %.2e\n", what.c_str(), r.pressure_min,
                    r.pressure_max, r.syy_spread);
        EXPECT_NEAR(r.pressure_min, 10, 1e-8 * 10) << what;
        EXPECT_NEAR(r.pressure_max, 10, 1e-8 * 10) << what;
        EXPECT_LT(r.syy_spread, 1e-8 * 10) << what;
      }
}

// Dual mortar at finite strain (Neo-Hookean, E = 1000, nu = 0.4; the pressures follow the
// surfaces): the exact state is still homogeneous, F = diag(lx, ly, 1) with Cauchy sigma_xx = 0
// and sigma_yy = -10 in both blocks, and so must be the computed one, before and after the
// punch slid by two foundation cells, on linear and quadratic facets (Lagrange multipliers).
// With sigma = (mu (b - I) + Lambda ln J I) / J (material.cpp's Neo-Hookean): mu (lx^2 - 1) +
// Lambda ln J = 0 and mu (ly^2 - 1) + Lambda ln J = -10 J, solved by Newton here (lx = 1.0056).
// The punch is held at the foundation's homogeneous x = 4 lx (plus the slide), as the small
// strain test holds it at 4 (1 + eps_xx); the reported pressure is the contact force per
// reference area, 10 lx. With Coulomb friction (mu = 0.3, the punch held) the state is the
// same: both sides stretch alike, so no point of the interface slips and the friction traction
// is zero; a slip that measured absolute motion or lost translation invariance would shear it.
// The lateral stretch lx of the finite-strain patch (Neo-Hookean, E = 1000, nu = 0.4, p = 10 in
// plane strain): mu (lx^2 - 1) + Lambda ln J = 0 and mu (ly^2 - 1) + Lambda ln J = -10 J, J = lx ly.
Real finite_patch_stretch() {
  const Real E = 1000, nu = 0.4, mu = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  Real lx = 1, ly = 1;
  for (int it = 0; it < 50; ++it) {
    const Real J = lx * ly, f1 = mu * (lx * lx - 1) + lam * std::log(J), f2 = mu * (ly * ly - 1) + lam * std::log(J) + 10 * J;
    const Real a11 = 2 * mu * lx + lam / lx, a12 = lam / ly, a21 = lam / lx + 10 * ly, a22 = 2 * mu * ly + lam / ly + 10 * lx;
    const Real det = a11 * a22 - a12 * a21;
    lx -= (a22 * f1 - a12 * f2) / det;
    ly -= (a11 * f2 - a21 * f1) / det;
  }
  return lx;
}

// The finite-strain patch with mortar and `method` (theta: Nitsche's): the homogeneous state on
// quad4, quad9 and quad8 pairs, the punch held, slid by two foundation cells, and held with
// Coulomb friction (mu 0.3): the stretch to 1e-9, sigma_yy and the pressure 10 lx to 1e-8 of p.
void check_finite_patch(const std::string& method, int theta) {
  const Real lx = finite_patch_stretch();
  for (const PatchPair& k : {PatchPair{ElementType::quad4, ElementType::quad4, 3},
                             PatchPair{ElementType::quad9, ElementType::quad4, 3},
                             PatchPair{ElementType::quad8, ElementType::quad8, 3}})
    for (auto [slide, mu] : {std::pair{0.0, 0.0}, std::pair{2.0, 0.0}, std::pair{0.0, 0.3}}) {
      const std::string what = method + ", " + element_info(k.punch).name + " on " + element_info(k.foundation).name +
                               " slide " + std::to_string(slide) + " mu " + std::to_string(mu);
      PatchResult r = run("mortar", 1, method, k.cells, slide + 4 * (lx - 1), "none", k.punch, k.foundation, slide,
                          true, mu, theta);
      ASSERT_TRUE(r.completed) << what;
      std::printf("%s: pressure %.12g .. %.12g (exact %.12g), sigma_yy spread %.2e, stretch %.10f (exact %.10f)\n",
                  what.c_str(), r.pressure_min, r.pressure_max, 10 * lx, r.syy_spread, r.stretch, lx);
      EXPECT_NEAR(r.stretch, lx, 1e-9) << what;
      EXPECT_LT(r.syy_spread, 1e-8 * 10) << what;
      EXPECT_NEAR(r.pressure_min, 10 * lx, 1e-8 * 10) << what;
      EXPECT_NEAR(r.pressure_max, 10 * lx, 1e-8 * 10) << what;
    }
}

TEST(ContactPatch, MortarIsExactAtFiniteStrain) { check_finite_patch("lagrange", 1); }

// Nitsche at finite strain (theta 0, docs/contact.md: the nominal traction F S n against the
// facet's current normal), on mortar integration: the homogeneous state of MortarIsExactAtFiniteStrain
// to round-off (asserted 1e-8 of p; the stretch to 1e-9), on the same pairs, the punch held,
// slid by two foundation cells, and held with Coulomb friction (mu 0.3: no point slips).
TEST(ContactPatch, NitscheOnMortarIntegrationIsExactAtFiniteStrain) { check_finite_patch("nitsche", 0); }

// Multi-body contact built by contact: {auto: {surfaces: [...]}} (examples/plate_stack): three
// plates stacked, frictional (mu = 0.1). The pairs: bottom-middle and middle-top (the finer
// surface slave), not bottom-top (out of reach). Equilibrium: the support reaction and the
// force through each interface equal the load (100 N/mm) to 1e-8; no closed node penetrates.
TEST(MultiBody, PlateStackPairsAndEquilibrium) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  Registry r = default_registry();
  Model m = read_deck((fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "plate_stack" / "plate_stack.yaml").string(), r);
  ASSERT_EQ(m.contacts.size(), 2u);
  EXPECT_EQ(m.contacts[0].name, "stack_BottomSurface_MiddleSurface");
  EXPECT_EQ(m.contacts[0].slave, "MiddleSurface");
  EXPECT_EQ(m.contacts[1].name, "stack_MiddleSurface_TopSurface");
  EXPECT_EQ(m.contacts[1].slave, "TopSurface");
  for (const auto& c : m.contacts) EXPECT_EQ(c.friction, "coulomb");
  Analysis a(m);
  const AnalysisSummary s = a.run();
  ASSERT_TRUE(s.completed) << s.failure;
  EXPECT_NEAR(a.reaction_sum("BottomBase").y(), 100, 1e-8 * 100);
  Real worst_gap = 0;
  int stick = 0, slip = 0;
  for (const auto& c : a.contacts()) {
    EXPECT_NEAR(c->slave_force().y(), 100, 1e-8 * 100) << c->settings().name;
    const auto& st = c->state();
    for (size_t j = 0; j < c->constraints().size(); ++j)
      if (st.active[j]) {
        worst_gap = std::min(worst_gap, c->constraints()[j].gap);
        (st.slip[j] ? slip : stick) += 1;
      }
  }
  std::printf("closed nodes: %d stick, %d slip; deepest penetration %.3e mm; %d Newton iterations\n", stick, slip,
              -worst_gap, s.total_iterations);
  EXPECT_GT(worst_gap, -1e-9);
  EXPECT_GT(stick + slip, 20);
  // The interfaces' pressure and status for docs/validation.md (examples/plate_stack/plot.py).
  const fs::path dir = fs::path(SIGNORINI_BINARY_DIR) / "curves";
  fs::create_directories(dir);
  std::ofstream out(dir / "plate_stack.csv");
  out << "pair,x,pressure,status\n";
  for (const auto& c : a.contacts())
    for (const auto& st : c->slave_states())
      out << c->settings().name << "," << m.mesh.nodes[st.node].x() << "," << st.pressure << "," << st.status << "\n";
}
