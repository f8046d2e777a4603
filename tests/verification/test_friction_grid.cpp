// The friction robustness grid at the coarse level (tests/friction_grid.hpp): every method
// converges from zero load with the default increments, without a cutback, and gives the
// Cattaneo-Mindlin stick zone within 10 %. Q/(mu P) = 0.9 (a stick zone of a quarter of a,
// 5 elements at hc = 0.01) needs the finer mesh: in the long tests.
#include <gtest/gtest.h>
#include <omp.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "friction_grid.hpp"
#include "signorini/solver/linear_solver.hpp"

using namespace signorini;

class FrictionGrid : public ::testing::TestWithParam<test::GridCase> {};

// Runs a case: it completes without a cutback, within `per_increment` Newton iterations per
// increment on average, c/a within 10 % of Cattaneo-Mindlin and Q in equilibrium with the load.
// `used`: the linear solver the last increment must report (empty: any).
void check_grid_case(const test::GridCase& c, Real per_increment, const std::string& used = "") {
  const test::GridResult g = test::run_grid_case(c);
  ASSERT_TRUE(g.run.summary.completed) << g.run.summary.failure;
  if (!used.empty()) {
    EXPECT_EQ(g.run.summary.increments.back().linear_solver, used);
  }
  EXPECT_EQ(g.cutbacks, 0) << "the default first increment of each step should converge";
  EXPECT_LE(g.iterations, per_increment * g.increments) << "Newton iterations per increment on average";
  EXPECT_NEAR(g.ca, g.expected, 0.10 * g.expected) << "Cattaneo-Mindlin: c/a = sqrt(1 - Q/(mu P))";
  // (SI: forces per unit thickness in N/m, 1e3 times those in N/mm.)
  EXPECT_NEAR(g.Q, c.ratio * c.mu * 388.4 / c.unit, 1e-6 * g.Q) << "equilibrium with the load";
}

TEST_P(FrictionGrid, ConvergesWithDefaultsAndMatchesCattaneoMindlin) {
  // Targets (issue 13): no cutback, and 8 Newton iterations per increment on average.
  // Measured on this machine (one run each, hc 0.01): the multipliers 5.5-7 per increment;
  // the penalty and the augmented Lagrangian 4.5-7 with the stick predictor (press 5, 7 and 8
  // iterations at mu 0.8, 0.3 and 0.1; push 4 and 6 at Q/(mu P) 0.2 and 0.6), 10.5-11.5 at
  // mu 0.1 without it (FrictionGridStickPredictor below). The guard is the target, with half
  // an iteration for the multipliers: runs are reproducible bit for bit on one machine
  // (Reproducible.SameNewtonPathWithOneAndTwoThreads), but the factorization's round-off
  // depends on the BLAS (its build and its thread count), and at mu 0.3, Q/(mu P) 0.6 one node
  // sits at the stick/slip kink: measured 15 iterations on the machine of session 14, 16
  // and 17 on Debian 12's OpenBLAS of 2026-11-25 with one and two BLAS threads (the push step
  // stalls three iterations in a stick/slip 2-cycle before it converges; issue 13).
  check_grid_case(GetParam(), GetParam().method == "lagrange" ? 8.5 : 8);
}
// The stick predictor (friction.stick_predictor, penalty and augmented Lagrangian): in the
// increment where the contact zone forms, a node that closes sticks while the normal statuses
// change, then slips freely (ContactInterface::end_stick_predictor). It changes the Newton
// path, not the solution: the press-then-shear case where it matters most (mu 0.1: without it, nodes sent into slip by the
// first iterates of the press come back to stick one per iteration under the line search)
// run with and without it gives the same c/a, P and Q to the Newton tolerance (asserted 1e-6
// relative), in fewer iterations with it (measured: 14 against 23 for both steps).
TEST(FrictionGridStickPredictor, ChangesTheNewtonPathNotTheSolution) {
  for (const char* method : {"penalty", "augmented_lagrangian"}) {
    test::GridCase with{0.1, 0.6, method, 0.01};
    test::GridCase without = with;
    without.stick_predictor = false;
    const test::GridResult a = test::run_grid_case(with), b = test::run_grid_case(without);
    ASSERT_TRUE(a.run.summary.completed && b.run.summary.completed) << method;
    EXPECT_EQ(a.cutbacks, 0) << method;
    EXPECT_NEAR(a.ca, b.ca, 1e-6 * b.ca) << method << ": the stick zone";
    EXPECT_NEAR(a.P, b.P, 1e-6 * b.P) << method << ": the normal force";
    EXPECT_NEAR(a.Q, b.Q, 1e-6 * b.Q) << method << ": the tangential force";
    EXPECT_LT(a.iterations, b.iterations) << method << ": the predictor saves the press's stick/slip switches";
  }
}
std::vector<test::GridCase> coarse_grid() {
  std::vector<test::GridCase> v;
  for (const char* m : {"lagrange", "augmented_lagrangian", "penalty"})
    for (Real mu : {0.1, 0.3, 0.8})
      for (Real ratio : {0.2, 0.6}) v.push_back({mu, ratio, m, 0.01});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Coarse, FrictionGrid, ::testing::ValuesIn(coarse_grid()),
                         [](const auto& info) { return test::grid_name(info.param); });

// The multipliers with GAMG (a build with PETSc): each closed node's normal and tangential
// multipliers one block, condensed by a local elimination and block pivots for GMRES over
// algebraic multigrid (multiplier_blocks.hpp), as `auto` does on large 3D models. The family
// at three points, one of them in SI units (the thresholds of the blocks' singular values are
// relative): the same guards as the factorized whole system's. Measured (one run each): 5.5, 7
// and 7.5 Newton iterations per increment (the whole system: 5.5, 7 and 6.5), no cutback, the
// same c/a.
class FrictionGridGamg : public ::testing::TestWithParam<test::GridCase> {};

TEST_P(FrictionGridGamg, ConvergesWithDefaultsAndMatchesCattaneoMindlin) {
  if (!petsc_available()) GTEST_SKIP() << "built without PETSc";
  check_grid_case(GetParam(), 8.5, "condensed+gamg");
}

INSTANTIATE_TEST_SUITE_P(Coarse, FrictionGridGamg,
                         ::testing::Values(test::GridCase{0.1, 0.2, "lagrange", 0.01, 1.0, "node_to_segment", true, "gamg"},
                                           test::GridCase{0.3, 0.6, "lagrange", 0.01, 1e-3, "node_to_segment", true, "gamg"},
                                           test::GridCase{0.8, 0.6, "lagrange", 0.01, 1.0, "node_to_segment", true, "gamg"}),
                         [](const auto& info) { return test::grid_name(info.param); });

// Segment-to-segment (integration-point contact, 2D friction): the same family, each method at
// two points of the grid. Its slip per slave node (the relative motion of the slave facets'
// Gauss points and the master points they project on, averaged with the node's shape function)
// gives the Cattaneo-Mindlin stick zone within 10 % (measured, every method: -4.4 % at mu 0.3,
// Q/(mu P) 0.6, one node short of node-to-segment's -0.8 %; -1.2 % at mu 0.8, 0.2, as
// node-to-segment), with no cutback. Measured Newton iterations per increment: 9 and 6 with
// multipliers (node-to-segment 7 and 5.5; the push at mu 0.3 takes 11), 8 and 6 with the
// penalty systems and the stick predictor (14.5 and 10.5 without it). The guards are those
// counts (runs are reproducible bit for bit): the target of 8, and 9 for the
// multipliers, above it.
class FrictionGridSegmentToSegment : public ::testing::TestWithParam<test::GridCase> {};

TEST_P(FrictionGridSegmentToSegment, ConvergesWithDefaultsAndMatchesCattaneoMindlin) {
  check_grid_case(GetParam(), GetParam().method == "lagrange" ? 9 : 8);
}

// Each method at two points of the grid, with the given discretization.
std::vector<test::GridCase> two_point_grid(const std::string& discretization) {
  std::vector<test::GridCase> v;
  for (const char* m : {"lagrange", "augmented_lagrangian", "penalty"})
    for (auto [mu, ratio] : {std::pair{0.3, 0.6}, std::pair{0.8, 0.2}})
      v.push_back({mu, ratio, m, 0.01, 1.0, discretization});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Coarse, FrictionGridSegmentToSegment, ::testing::ValuesIn(two_point_grid("segment_to_segment")),
                         [](const auto& info) { return test::grid_name(info.param); });

// Nitsche's method with Coulomb friction (segment_to_segment's integration points, small
// strain): the same family at the same two points. Each point's tangential traction is the
// slave body's, returned onto the disc mu [P]_+ with Q = sigma_T - eps s (docs/contact.md,
// "nitsche"); the nodal stick/slip status that the stick zone is measured with is the
// majority of the node's active points. Measured (one run each, no cutback): c/a -4.4 % at
// mu 0.3, Q/(mu P) 0.6 and -3.8 % at mu 0.8, 0.2 (segment_to_segment's multipliers: -4.4 and
// -1.2 %; at mu 0.3 the same stick zone to 1e-6); P 388.390 N/mm against their 388.396;
// Newton iterations 17 + 11 and 11 + 8 with the line search that Nitsche's friction takes
// (ContactInterface::full_newton_steps; 14 + 11 and 14 + 8 with full steps; the press takes 12
// without friction: the bound on the gap's second variation, docs/contact.md). The guard is 15
// per increment.
class FrictionGridNitsche : public ::testing::TestWithParam<test::GridCase> {};

TEST_P(FrictionGridNitsche, ConvergesWithDefaultsAndMatchesCattaneoMindlin) { check_grid_case(GetParam(), 15); }

INSTANTIATE_TEST_SUITE_P(Coarse, FrictionGridNitsche,
                         ::testing::Values(test::GridCase{0.3, 0.6, "nitsche", 0.01, 1.0, "segment_to_segment"},
                                           test::GridCase{0.8, 0.2, "nitsche", 0.01, 1.0, "segment_to_segment"}),
                         [](const auto& info) { return test::grid_name(info.param); });

// Dual mortar with friction (2D): the same family, each method at two points of the grid. Its
// slip per slave node is x_s - x_m(chi) over the segments of the node's facets weighted like
// the weighted gap by the dual function (mortar_dual.hpp, dual_slip_weights) and frozen as a
// combination of nodes at the slip origin. Measured (session 61, one run each, every method
// without a cutback): c/a -0.8 % (multipliers) and -0.7 % (penalty systems) at mu 0.3,
// Q/(mu P) 0.6; +1.4 % at mu 0.8, 0.2; 6.5 and 5.5 Newton iterations per increment with
// multipliers, 8 and 6.5 with the penalty systems (with the N~ weights before: c/a -4.4 % and
// -3.8 % with multipliers, 9.5 and 6.5 iterations; 9 and 7 with the penalty systems). The
// guards are the target of 8 with multipliers and 9 with the penalty systems.
class FrictionGridMortar : public ::testing::TestWithParam<test::GridCase> {};

TEST_P(FrictionGridMortar, ConvergesWithDefaultsAndMatchesCattaneoMindlin) {
  check_grid_case(GetParam(), GetParam().method == "lagrange" ? 8 : 9);
}

INSTANTIATE_TEST_SUITE_P(Coarse, FrictionGridMortar, ::testing::ValuesIn(two_point_grid("mortar")),
                         [](const auto& info) { return test::grid_name(info.param); });

// The same deck in (mm, N, MPa) and in (m, N, Pa), the mesh drawn in mm and scaled: the same
// stick and contact zones and forces to 1e-8 relative (issue 13). The two are different
// floating-point computations (every length 1e-3, every stress 1e6 times the other's), so
// their residuals differ in the last bits and one may need one more Newton iteration than the
// other to pass the same relative tolerance (measured: 15 and 14, or 16-17 and 14 with another
// BLAS, see below; c/a, a and P equal to 12 digits; reproducible bit for bit on one machine
// since the assembly is coloured). A unit error (a length
// or a penalty not scaled) moves c/a by percents.
TEST(FrictionGridUnits, SameResultInMillimetresAndMetres) {
  const test::GridResult mm = test::run_grid_case({0.3, 0.6, "lagrange", 0.01, 1.0});
  const test::GridResult si = test::run_grid_case({0.3, 0.6, "lagrange", 0.01, 1e-3});
  ASSERT_TRUE(mm.run.summary.completed && si.run.summary.completed);
  EXPECT_EQ(mm.cutbacks, 0);
  EXPECT_EQ(si.cutbacks, 0);
  std::printf("mm: c/a %.12g, a %.12g, P %.12g, %d iterations; m: c/a %.12g, a %.12g (x 1e3), P %.12g (/ 1e3), %d "
              "iterations\n",
              mm.ca, mm.a, mm.P, mm.iterations, si.ca, 1e3 * si.a, 1e-3 * si.P, si.iterations);
  EXPECT_NEAR(si.ca, mm.ca, 1e-8 * mm.ca);
  EXPECT_NEAR(si.a, 1e-3 * mm.a, 1e-8 * 1e-3 * mm.a);
  EXPECT_NEAR(si.P, 1e3 * mm.P, 1e-8 * 1e3 * mm.P);
  // The counts: equal but for round-off. At this case's stick/slip kink the round-off of one
  // unit system can cost a 2-cycle of a node's stick/slip status (measured on Debian 12's
  // OpenBLAS of 2026-11-25: mm 16 or 17 with one or two BLAS threads, m 14; 15 and 14 on the
  // machine of session 14). A unit error shows in c/a, a and P above, not only here.
  EXPECT_LE(std::abs(mm.iterations - si.iterations), 3) << "the round-off of the two systems, not another path";
}

// The 3D case of the family: Cattaneo-Mindlin partial slip of a sphere on a block
// (examples/cattaneo_sphere_3d, tet4 half model, mu = 0.3, Q/(mu P) = 0.5), with
// the default enforcement (`lagrange`) and the default increments (one per step) instead of the
// example's penalty and hand-set increments. Reference (Johnson 1985, sec. 7.2): c = a (1 -
// Q/(mu P))^(1/3), within the deck's 5 %; P within 1 %. Measured: 7 + 6 Newton iterations (session
// 31; 9 + 7 when first measured), no cutback, c 4.2 % below, 13 s. Asserted: the targets, no cutback and 8 iterations per
// increment on average.
TEST(FrictionGrid3D, CattaneoSphereWithLagrangeAndDefaultIncrements) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "cattaneo_sphere_3d";
  std::ifstream in(dir / "cattaneo_sphere_3d.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string deck;
  for (std::string line; std::getline(ss, line);)
    if (line.find("increments:") == std::string::npos) deck += line + "\n";
  const std::string mesh = "file: cattaneo_sphere_3d.geo", method = "{method: penalty}";
  ASSERT_NE(deck.find(mesh), std::string::npos);
  ASSERT_NE(deck.find(method), std::string::npos);
  deck.replace(deck.find(mesh), mesh.size(), "file: " + (dir / "cattaneo_sphere_3d.geo").string());
  deck.replace(deck.find(method), method.size(), "{method: lagrange}");
  const test::HertzRun r = test::run_deck_text(deck, "cattaneo_sphere_lagrange");
  ASSERT_TRUE(r.summary.completed) << r.summary.failure;
  ASSERT_GE(r.checks.size(), 3u);
  EXPECT_LT(r.checks[0].error, 0.05) << "stick-zone radius c " << r.checks[0].computed;
  EXPECT_LT(r.checks[1].error, 0.05) << "contact radius a " << r.checks[1].computed;
  EXPECT_LT(r.checks[2].error, 0.01) << "normal force P " << r.checks[2].computed;
  int total = 0;
  for (const IncrementRecord& inc : r.summary.increments) {
    EXPECT_EQ(inc.cutbacks, 0) << "step " << inc.step;
    total += inc.iterations;
    std::printf("step %d increment %d: %d Newton iterations, %d cutbacks\n", inc.step + 1, inc.increment,
                inc.iterations, inc.cutbacks);
  }
  EXPECT_LE(total, 8 * static_cast<int>(r.summary.increments.size())) << "8 Newton iterations per increment on average";
  std::printf("c error %.2f %%, a error %.2f %%, P error %.2f %%\n", 100 * r.checks[0].error,
              100 * r.checks[1].error, 100 * r.checks[2].error);
}

// Reproducibility: the assembly colours its cells and contact constraints (fem/coloring.hpp),
// so every matrix and residual entry is summed in one fixed order. The same frictional run with
// one and with two OpenMP threads must then take the same Newton path bit for bit: the same
// residual at every iteration and the same stick zone. With the atomic adds it replaced, two
// threads summed in a varying order and this case (the grid's flakiest: mu 0.8, Q/(mu P) 0.6,
// multipliers) took 13 to 30 iterations from run to run; the residuals differ in the last bits
// at the first iteration already, so a return of unordered sums fails this test.
TEST(Reproducible, SameNewtonPathWithOneAndTwoThreads) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const test::GridResult one = test::run_grid_case({0.8, 0.6, "lagrange", 0.01, 1.0});
  omp_set_num_threads(2);
  const test::GridResult two = test::run_grid_case({0.8, 0.6, "lagrange", 0.01, 1.0});
  omp_set_num_threads(threads);
  ASSERT_TRUE(one.run.summary.completed && two.run.summary.completed);
  ASSERT_EQ(one.run.summary.increments.size(), two.run.summary.increments.size());
  for (size_t i = 0; i < one.run.summary.increments.size(); ++i) {
    const auto& a = one.run.summary.increments[i].residuals;
    const auto& b = two.run.summary.increments[i].residuals;
    ASSERT_EQ(a.size(), b.size()) << "increment " << i;
    for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << "increment " << i << ", iteration " << k;
  }
  EXPECT_EQ(one.ca, two.ca);
  EXPECT_EQ(one.P, two.P);
  EXPECT_EQ(one.Q, two.Q);
}
