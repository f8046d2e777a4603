// Refinement studies (ctest label `long`, run with `make test-long`): the axisymmetric Lamé
// cylinder on five meshes, printing the error table of docs/validation.md and asserting the
// asymptotic orders.
#include <gtest/gtest.h>

#include <cmath>

#include "lame_problem.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {
// Max nodal error of u_r relative to u_r(a), axisymmetric slice of n x n cells.
Real lame_error(ElementType type, int n) {
  using namespace signorini::test::lame;
  Model m = model(Dimension::axisymmetric, type, n);
  Analysis an(m);
  EXPECT_TRUE(an.run().completed);
  Real err = 0;
  for (Index nd = 0; nd < m.mesh.num_nodes(); ++nd)
    err = std::max(err, std::abs(an.displacement()(an.dofs().dof(nd, 0)) - ur(m.mesh.nodes[nd](0))) / ur(a));
  return err;
}
}  // namespace

TEST(LongRefinement, LameAxisymmetricTables) {
  for (ElementType t : {ElementType::quad4, ElementType::quad8, ElementType::quad9}) {
    Real prev = 0;
    std::printf("Lame axisymmetric, %s: n, max u_r error, order\n", element_info(t).name.c_str());
    for (int n : {4, 8, 16, 32, 64}) {
      const Real e = lame_error(t, n);
      const Real order = prev > 0 ? std::log2(prev / e) : 0;
      std::printf("  %3d  %.3e  %.2f\n", n, e, order);
      if (prev > 0 && e > 1e-11) {
        EXPECT_GT(order, element_info(t).order == 1 ? 1.8 : 2.8) << element_info(t).name << " n=" << n;
      }
      prev = e;
    }
  }
}

#include "hertz_runner.hpp"

TEST(LongRefinement, HertzTables) {
  for (const char* ex : {"hertz_cylinder", "hertz_sphere_axisymmetric"}) {
    std::printf("%s: hc, p0 error %%, a error %%, Newton iterations, seconds\n", ex);
    for (Real hc : {0.02, 0.01, 0.005, 0.0025}) {
      signorini::test::HertzRun r = signorini::test::run_hertz(ex, hc);
      ASSERT_TRUE(r.summary.completed) << r.summary.failure;
      std::printf("  %.4f  %7.3f  %7.3f  %3d  %.2f\n", hc, 100 * r.checks[0].error, 100 * r.checks[1].error,
                  r.summary.total_iterations, r.summary.total_seconds);
      if (hc == 0.0025) {
        EXPECT_LT(r.checks[0].error, 0.02) << ex;
        EXPECT_LT(r.checks[1].error, 0.03) << ex;
      }
    }
  }
}

TEST(LongRefinement, HertzSphere3D) {
  std::printf("hertz_sphere_3d: hc, p0 error %%, a error %%, Newton iterations, seconds\n");
  for (Real hc : {0.02, 0.015, 0.012, 0.01}) {
    signorini::test::HertzRun r = signorini::test::run_hertz("hertz_sphere_3d", hc);
    ASSERT_TRUE(r.summary.completed) << r.summary.failure;
    std::printf("  %.4f  %7.3f  %7.3f  %3d  %.2f\n", hc, 100 * r.checks[0].error, 100 * r.checks[1].error,
                r.summary.total_iterations, r.summary.total_seconds);
    EXPECT_LT(r.checks[1].error, 0.05);
    EXPECT_LT(r.checks[2].error, 1e-4);
  }
}
