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

// Where the peak pressure error of the 3D tet4 Hertz example comes from (issue: p0 <= 3 % on
// the project's tet4 mesh). On the shipped mesh (hc 0.02, a / hc = 5) the closed slave nodes'
// pressures are compared with Hertz's p0 sqrt(1 - r^2 / a^2) inside r < 0.8 a (the edge nodes
// left out, as the CalculiX harness's fit does): their mean deviation (the contact radius), rms
// (node-to-node noise) and largest. Node-to-segment, mortar and segment-to-segment on the tet4
// mesh, and mortar on the same mesh raised to tet10 (mid-side nodes on the sphere). Measured
// (session 35; p0 error, mean, rms, max deviation): node-to-segment +16.5, +0.1, 13.2, +24.7 %;
// mortar +7.7, +2.6, 6.3, +17.1 %; segment-to-segment +8.1, +2.6, 6.3, +17.5 %; tet10 mortar
// -0.6, -0.3, 1.5, +4.6 %. Two ways of integrating the contact giving the same noise, and the
// tet10 mesh of the same vertices removing it, put the rest in the tet4 mesh (a faceted sphere,
// constant-stress tetrahedra), not in the contact discretization.
namespace {
struct PressureNoise {
  Real p0_error, mean, rms, max;
};
PressureNoise pressure_noise(const signorini::test::HertzRun& r) {
  const Real a = 0.1, p0 = 4.77465e5;  // the example's Hertz values (its deck)
  Real sum = 0, sum2 = 0, mx = -1;
  int n = 0;
  for (const auto& [x, p] : r.closed) {
    const Real rr = std::hypot(x(0), x(1));
    if (rr >= 0.8 * a) continue;
    const Real d = p / (p0 * std::sqrt(1 - rr * rr / (a * a))) - 1;
    sum += d;
    sum2 += d * d;
    mx = std::max(mx, d);
    ++n;
  }
  EXPECT_GT(n, 10) << "closed nodes inside 0.8 a";
  return {r.checks[0].computed / p0 - 1, sum / n, std::sqrt(sum2 / n), mx};
}
}  // namespace

TEST(LongRefinement, HertzSphere3DPressureNoise) {
  struct Case {
    const char* name;
    const char* discretization;
    int order;
  };
  std::printf("hertz_sphere_3d, hc 0.02: p0 error %%, nodal deviation from Hertz inside 0.8 a: mean, rms, max %%\n");
  std::vector<PressureNoise> out;
  Real a_tet10 = 1;
  for (const Case& c : {Case{"node_to_segment tet4", "", 0}, Case{"mortar tet4", "discretization: mortar", 0},
                        Case{"segment_to_segment tet4", "discretization: segment_to_segment", 0},
                        Case{"mortar tet10", "discretization: mortar", 2}}) {
    signorini::test::HertzRun r = signorini::test::run_hertz("hertz_sphere_3d", 0.02, c.discretization, c.order);
    ASSERT_TRUE(r.summary.completed) << c.name << ": " << r.summary.failure;
    EXPECT_LT(r.checks[2].error, 1e-4) << c.name << ": force balance";
    out.push_back(pressure_noise(r));
    if (c.order == 2) a_tet10 = r.checks[1].error;
    std::printf("  %-24s %+7.2f %+7.2f %6.2f %+7.2f  (%d iterations)\n", c.name, 100 * out.back().p0_error,
                100 * out.back().mean, 100 * out.back().rms, 100 * out.back().max, r.summary.total_iterations);
  }
  // Mortar halves node-to-segment's noise on tet4, and integrating by points instead changes
  // nothing (the noise is the mesh's).
  EXPECT_LT(out[1].rms, 0.6 * out[0].rms);
  EXPECT_NEAR(out[2].rms, out[1].rms, 0.01);
  EXPECT_LT(std::abs(out[1].mean), 0.03);
  // On tet10 the same vertices give the quadratic-mesh accuracy.
  EXPECT_LT(std::abs(out[3].p0_error), 0.01);
  EXPECT_LT(a_tet10, 0.01) << "contact radius";
  EXPECT_LT(out[3].rms, 0.03);
}
