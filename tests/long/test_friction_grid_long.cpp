// The friction robustness grid's long set (tests/friction_grid.hpp): Q/(mu P) = 0.9, a stick
// zone of about a quarter of the contact width, on the finer mesh (hc = 0.005 mm, 11
// elements across the stick zone), for every mu and method.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "deck_text.hpp"
#include "friction_grid.hpp"

using namespace signorini;

class LongFrictionGrid : public ::testing::TestWithParam<test::GridCase> {};

TEST_P(LongFrictionGrid, ConvergesWithDefaultsAndMatchesCattaneoMindlin) {
  const test::GridResult g = test::run_grid_case(GetParam());
  ASSERT_TRUE(g.run.summary.completed) << g.run.summary.failure;
  EXPECT_LE(g.cutbacks, 1);
  EXPECT_LE(g.iterations, 13 * g.increments);
  EXPECT_NEAR(g.ca, g.expected, 0.10 * g.expected) << "Cattaneo-Mindlin: c/a = sqrt(1 - Q/(mu P))";
}

std::vector<test::GridCase> fine_grid() {
  std::vector<test::GridCase> v;
  for (const char* m : {"lagrange", "augmented_lagrangian", "penalty"})
    for (Real mu : {0.1, 0.3, 0.8}) v.push_back({mu, 0.9, m, 0.005});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Fine, LongFrictionGrid, ::testing::ValuesIn(fine_grid()),
                         [](const auto& info) { return test::grid_name(info.param); });

// Cattaneo-Mindlin partial slip of a sphere on a block (examples/cattaneo_sphere_3d: tet4 half
// model, mu = 0.3, Q/(mu P) = 0.5, the example's increments) with mortar and the default
// enforcement (`lagrange`) instead of the example's penalty node-to-segment. Reference (Johnson
// 1985, sec. 7.2): c = a (1 - Q/(mu P))^(1/3), within the deck's 5 %; a within 5 %, P within 1 %.
// With the slip weighted by N~ (session 60 and before): c 11.3 % off and 64 Newton iterations
// with a cutback; with the dual basis's weights (mortar_dual.hpp, dual_slip_weights): 3.1 %, 42
// iterations over 9 increments, no cutback (170 s on the 2-core machine). Asserted: the
// tolerances, no cutback, at most 6 iterations per increment on average.
TEST(LongFriction3D, CattaneoSphereWithMortarMatchesCattaneoMindlin) {
  std::string deck = test::example_deck_text("cattaneo_sphere_3d");
  test::replace_in_text(deck, "enforcement: {method: penalty}", "discretization: mortar");
  const test::HertzRun r = test::run_deck_text(deck, "cattaneo_sphere_mortar");
  ASSERT_TRUE(r.summary.completed) << r.summary.failure;
  ASSERT_GE(r.checks.size(), 3u);
  EXPECT_LT(r.checks[0].error, 0.05) << "stick-zone radius c " << r.checks[0].computed;
  EXPECT_LT(r.checks[1].error, 0.05) << "contact radius a " << r.checks[1].computed;
  EXPECT_LT(r.checks[2].error, 0.01) << "normal force P " << r.checks[2].computed;
  int total = 0;
  for (const IncrementRecord& inc : r.summary.increments) {
    EXPECT_EQ(inc.cutbacks, 0) << "step " << inc.step;
    total += inc.iterations;
  }
  EXPECT_LE(total, 6 * static_cast<int>(r.summary.increments.size()));
  std::printf("c error %.2f %%, a error %.2f %%, P error %.2f %%, %d Newton iterations\n", 100 * r.checks[0].error,
              100 * r.checks[1].error, 100 * r.checks[2].error, total);
}
