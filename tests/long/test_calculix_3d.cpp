// The CalculiX harness's 3D Hertz deck (quarter sphere, C3D10, SURFACE TO SURFACE, LINEAR
// K = 1e8) runs unchanged: see tests/verification/test_calculix.cpp. About 45 s per run.
#include "calculix_runner.hpp"

using namespace signorini;
using signorini::test::compare;

// The load against CalculiX's on this deck and mesh (the harness's results/sbs.md, row
// h3d_coarse_s2s: P = 2322.5 N), within 0.2 %, and the peak nodal pressure against Hertz's p0
// within 2 % (a/h = 5; measured -0.75 %, CalculiX -0.22 %). The written pressure is the
// multiplier (docs/contact.md, segment_to_segment): as the node's force per weight it read
// +65 %, 0 at the tri6 corners and about 1.6 p0 at the mid-side nodes.
TEST(CalculixDeckLong, Hertz3dTet10SurfaceToSurface) {
  const auto c = compare("h3d", "hertz3d_coarse_c3d10.inp", true,
                         "discretization: segment_to_segment, enforcement: {method: penalty, penalty: 1e8}");
  EXPECT_NEAR(c.load, 2322.5, 2e-3 * 2322.5);
  EXPECT_LT(std::abs(c.peak_error), 0.02);
}

// The same deck with Lagrange multipliers (PRESSURE-OVERCLOSURE=HARD's method). An integration
// point of the converged state sits on the edge between two master facets, where the contact
// force follows each facet's own normal, so the residual jumps there (by 1.06e-3 N at mesh node
// 3837, u_x, about 1e-5 of the force scale) and Newton cycled between the two sides: every
// attempt to reach the full load failed at 25 iterations and was cut back, the increments
// halving towards the end (11 cutbacks, 590 s, stopped by hand). Newton now accepts the
// stagnated state (within 1e-4 of the force scale) at the end of its iteration budget instead
// of cutting back, and says so: one increment.
TEST(CalculixDeckLong, Hertz3dTet10SurfaceToSurfaceLagrangeFinishesInOneIncrement) {
  log::set_level(log::Level::warning);
  const signorini::test::Result r = signorini::test::run_yaml(
      "h3d_lagrange", "hertz3d_coarse_c3d10.inp", true, "discretization: segment_to_segment, enforcement: {method: lagrange}");
  const AnalysisSummary& s = r.summary;
  ASSERT_TRUE(s.completed) << s.failure;
  ASSERT_EQ(s.increments.size(), 1u);
  const IncrementRecord& inc = s.increments[0];
  EXPECT_EQ(inc.cutbacks, 0);
  EXPECT_LE(inc.iterations, 25);  // stagnation is accepted at the end of the iteration budget
  if (inc.stagnated) {
    EXPECT_LE(inc.stagnated_residual, 1e-4);
  }
  // The load CalculiX computes on this deck (results/sbs.md, h3d_coarse_s2s: 2322.5 N) within
  // 0.3 %: penalty K = 1e8 there, exact non-penetration here (measured +0.13 %).
  const Real P = 4 * r.reaction;
  EXPECT_NEAR(P, 2322.5, 3e-3 * 2322.5);
  // The peak nodal pressure against Hertz's p0 for this load: within 2 % (measured -0.64 %).
  const Real peak = signorini::test::peak_pressure(r);
  const Real p0 = signorini::test::hertz_p0(P, true);
  EXPECT_NEAR(peak, p0, 0.02 * p0);
  std::printf("tet10 Lagrange: P %.6g, peak %.6g against Hertz p0 %.6g (%+.3f %%), %d iterations, stagnated %d (|R|/F "
              "%.3e)\n",
              P, peak, p0, 100 * (peak / p0 - 1), inc.iterations, static_cast<int>(inc.stagnated), inc.stagnated_residual);
}

// CalculiX's fine tet4 mesh with penalty and the augmented Lagrangian: in the default suite
// (tests/verification/test_calculix.cpp, CalculixDeck.EveryMethodInOneIncrementOnTheQuad4AndTet4Meshes).

// Nitsche's method (symmetric, gamma0 auto) on the same points: one increment without a
// cutback, the load within 0.2 % of CalculiX's, the peak nodal pressure within 2 % of Hertz's
// p0 and none negative. Measured: 18 Newton iterations, 15 s, P 2324.8, peak -0.65 % (Lagrange
// multipliers on the same points: -0.64 %); with the gap's whole second variation in the matrix
// the steps diverged from the second iteration (enforcement.cpp).
TEST(CalculixDeckLong, Hertz3dTet10Nitsche) {
  log::set_level(log::Level::warning);
  for (const std::string disc : {"segment_to_segment", "mortar"}) {
    const signorini::log::Timer timer;
    const signorini::test::Result r = signorini::test::run_yaml(
        "h3d_nitsche", "hertz3d_coarse_c3d10.inp", true, "discretization: " + disc + ", enforcement: {method: nitsche}");
    ASSERT_TRUE(r.completed) << disc << ": " << r.summary.failure;
    ASSERT_EQ(r.summary.increments.size(), 1u) << disc;
    EXPECT_EQ(r.summary.increments[0].cutbacks, 0) << disc;
    const Real P = 4 * r.reaction;
    EXPECT_NEAR(P, 2322.5, 2e-3 * 2322.5) << disc;
    const Real p0 = signorini::test::hertz_p0(P, true);
    Real lowest = 0;
    for (const auto& [node, p] : r.pressure) lowest = std::min(lowest, p);
    EXPECT_NEAR(signorini::test::peak_pressure(r), p0, 0.02 * p0) << disc;
    EXPECT_GE(lowest, 0) << disc;
    std::printf("tet10 nitsche on %s: P %.6g, peak %+.2f %% of Hertz p0, %d Newton iterations, %.1f s\n", disc.c_str(),
                P, 100 * (signorini::test::peak_pressure(r) / p0 - 1), r.summary.total_iterations, timer.seconds());
  }
}

namespace {

// Mortar with Lagrange multipliers on one of the harness's tet10 meshes: the load P of the
// whole sphere within 0.3 % of CalculiX's on that mesh (`ccx_load`), the peak nodal pressure
// within `p0_tolerance` of Hertz's p0 for P and no nodal pressure negative.
signorini::test::Result hertz_tet10_mortar(const std::string& mesh, Real ccx_load, Real p0_tolerance) {
  log::set_level(log::Level::warning);
  signorini::test::Result r = signorini::test::run_yaml("h3d_" + mesh, mesh, true,
                                                        "discretization: mortar, enforcement: {method: lagrange}");
  EXPECT_TRUE(r.completed) << r.summary.failure;
  if (!r.completed) return r;
  const Real P = 4 * r.reaction;
  const Real p0 = signorini::test::hertz_p0(P, true);
  Real lowest = 0;
  for (const auto& [node, p] : r.pressure) lowest = std::min(lowest, p);
  std::printf("%s, mortar: P %.6g (%+.3f %% of CalculiX), peak %+.3f %% of Hertz p0, lowest %.3g, %zu increments, %d "
              "Newton iterations\n",
              mesh.c_str(), P, 100 * (P / ccx_load - 1), 100 * (signorini::test::peak_pressure(r) / p0 - 1), lowest,
              r.summary.increments.size(), r.summary.total_iterations);
  EXPECT_NEAR(P, ccx_load, 3e-3 * ccx_load);
  EXPECT_NEAR(signorini::test::peak_pressure(r), p0, p0_tolerance * p0);
  // No negative pressure beyond round-off: since session 67 the coupled rows' multipliers are
  // recovered level by level (condensed_solve.hpp, LevelledRows), and on the coarse mesh one
  // node's came out at -5.7e-14 MPa (1.3e-17 of p0) where it had been >= 0 before.
  EXPECT_GE(lowest, -1e-12 * p0);
  return r;
}

}  // namespace

// Segment-based dual mortar (issue 14) on the same tet10 mesh: the sphere's tri6 facets slave,
// the dual basis built on their Bernstein basis (mortar_dual.hpp), Lagrange multipliers. The
// load within 0.3 % of CalculiX's (2322.5 N), the peak nodal pressure (the multiplier per
// reference area) within 2 % of Hertz's p0 and no nodal pressure negative.
TEST(CalculixDeckLong, Hertz3dTet10Mortar) { hertz_tet10_mortar("hertz3d_coarse_c3d10.inp", 2322.5, 0.02); }

// The harness's fine tet10 mesh (118 242 DOFs, a/h = 12: scripts/mesh3d.py fine of
// ../shared/peers/calculix-hertz, copied to tests/data), the yardstick for mortar. It had
// stopped converging without anyone seeing it (session 34: Cholesky of the reduced system
// failed at the fifth Newton iteration, the LU fallback on 32-bit indices ran out of its
// integers, the run gave up). One increment without a cutback, at most 8 Newton iterations
// (measured 5), P within 0.3 % of CalculiX's on this mesh (the harness's results/sbs.md,
// h3d_fine_s2s: 2320.6 N; measured +0.10 %), the peak nodal pressure within 0.3 % of Hertz's p0
// (the target; measured -0.19 %, CalculiX -0.23 %), none negative. About 150 s and
// 3.3 GB on the 2-core machine with CHOLMOD; since session 41 `auto` takes GAMG here (the factor
// would hold 1.25e8 entries, above direct_factor_limit): 7 iterations, 1.5 GB, 1.6x the time.
TEST(CalculixDeckLong, Hertz3dTet10MortarFine) {
  const signorini::test::Result r = hertz_tet10_mortar("hertz3d_fine_c3d10.inp", 2320.6, 3e-3);
  ASSERT_TRUE(r.completed);
  ASSERT_EQ(r.summary.increments.size(), 1u);
  EXPECT_EQ(r.summary.increments[0].cutbacks, 0);
  EXPECT_LE(r.summary.total_iterations, 8);
}
