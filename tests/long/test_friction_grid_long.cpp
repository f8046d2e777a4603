// The friction robustness grid's long set (tests/friction_grid.hpp): Q/(mu P) = 0.9, a stick
// zone of about a quarter of the contact width, on the finer mesh (hc = 0.005 mm, 11
// elements across the stick zone), for every mu and method.
#include <gtest/gtest.h>

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
