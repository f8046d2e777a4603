// Hertz contact (Johnson, Contact Mechanics, 1985, ch. 4; VALIDATION.md sec. 1) through the
// shipped example decks: peak pressure and contact half-width against the formulas, the
// force balance, and quadratic convergence of the semi-smooth Newton method once the active
// set has settled. The refinement tables are in tests/long (label `long`).
#include <gtest/gtest.h>

#include <cmath>

#include "hertz_runner.hpp"

using namespace signorini;

namespace {
void expect_hertz(const std::string& example, Real hc, Real p0_tol, Real a_tol) {
  test::HertzRun r = test::run_hertz(example, hc);
  ASSERT_TRUE(r.summary.completed) << r.summary.failure;
  ASSERT_EQ(r.checks.size(), 3u);
  EXPECT_LT(r.checks[0].error, p0_tol) << example << ": p0 " << r.checks[0].computed;
  EXPECT_LT(r.checks[1].error, a_tol) << example << ": a " << r.checks[1].computed;
  EXPECT_LT(r.checks[2].error, 1e-6) << example << ": force balance";
  const auto& res = r.summary.increments.back().residuals;
  const Real order = test::newton_order(res);
  std::printf("%s, hc = %g: p0 error %.3f %%, a error %.3f %%, %d Newton iterations, final order %.2f\n",
              example.c_str(), hc, 100 * r.checks[0].error, 100 * r.checks[1].error,
              r.summary.increments.back().iterations, order);
  EXPECT_GT(order, 1.8) << "the semi-smooth Newton method should converge quadratically at the end";
}
}  // namespace

TEST(Hertz, CylinderPlaneStrain) { expect_hertz("hertz_cylinder", 0.005, 0.02, 0.03); }
TEST(Hertz, SphereAxisymmetric) { expect_hertz("hertz_sphere_axisymmetric", 0.005, 0.02, 0.03); }
