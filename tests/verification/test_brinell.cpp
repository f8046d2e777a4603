// Brinell indentation (VALIDATION.md sec. 9; Tabor, The Hardness of Metals, 1951; Johnson,
// Contact Mechanics, 1985, ch. 6): the example `brinell`, a rigid sphere (R = 1 mm) pressed
// 0.08 mm into an elastic-perfectly plastic half-space (E = 200 GPa, nu = 0.3, sigma_y =
// 400 MPa) with the finite-strain J2 model, axisymmetric, frictionless, then lifted off.
// Reference: fully plastic indentation has the mean pressure p_m = F / (pi a^2) ~ 2.8 sigma_y
// (Tabor's constraint factor; finite element studies of elastic-perfectly plastic solids give
// 2.7-3.0 once E a / (sigma_y R) is beyond about 40, e.g. Mesarovic & Fleck, Proc. R. Soc. A
// 455, 1999), asserted within 10 % from a/R = 0.3 on, with a the contact radius on the
// deformed surface (midway between the outermost closed slave node and the next open one).
// Also: the material piles up at the rim (perfect plasticity), the unloading is elastic (the
// residual depth is most of the maximum), and the sphere leaves the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

struct Sample {
  int step;
  Real depth, force, radius, pile_up;
  int closed;
};

// Contact radius on the deformed surface, the highest point of the surface, closed nodes.
void contact_zone(const Analysis& an, const ContactInterface& c, Real& radius, Real& top, int& closed) {
  const std::vector<Vec3> x = an.positions(an.displacement());
  const auto& cs = c.constraints();
  const auto& st = c.state();
  Real in = 0, out = std::numeric_limits<Real>::infinity();
  top = -std::numeric_limits<Real>::infinity();
  closed = 0;
  for (size_t j = 0; j < cs.size(); ++j) {
    const Vec3& p = x[cs[j].slave];
    top = std::max(top, p.y());
    if (st.active[j]) in = std::max(in, p.x()), ++closed;
  }
  for (size_t j = 0; j < cs.size(); ++j)
    if (!st.active[j] && x[cs[j].slave].x() > in) out = std::min(out, x[cs[j].slave].x());
  radius = std::isfinite(out) ? 0.5 * (in + out) : in;
}

}  // namespace

TEST(Brinell, MeanPressureIsTaborsConstraintFactor) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  const fs::path deck = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "brinell" / "brinell.yaml";
  Registry r = default_registry();
  Model m = read_deck(deck.string(), r);
  const Real sy = 400, R = 1, depth = 0.08;
  Index axis = 0;
  for (Index n = 0; n < m.mesh.num_nodes(); ++n)
    if (m.mesh.nodes[n].norm() < m.mesh.nodes[axis].norm()) axis = n;
  Analysis a(m);
  std::vector<Sample> samples;
  Real residual_depth = 0;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    const ContactInterface& c = *an.contacts().front();
    Sample s;
    s.step = rec.step;
    s.depth = depth * (rec.step == 0 ? rec.fraction : 1 - rec.fraction);
    s.force = -an.obstacle_reaction(c).y();
    contact_zone(an, c, s.radius, s.pile_up, s.closed);
    samples.push_back(s);
    residual_depth = -an.displacement()(an.dofs().dof(axis, 1));
  });
  const AnalysisSummary summary = a.run();
  ASSERT_TRUE(summary.completed) << summary.failure;
  int checked = 0;
  Real pm_last = 0, pile_up = 0;
  for (const Sample& s : samples) {
    if (s.step != 0) continue;
    const Real pm = s.force / (std::numbers::pi * s.radius * s.radius);
    std::printf("depth %.4f mm: F = %8.2f N, a = %.4f mm (a/R %.3f; without pile-up %.4f), p_m / sigma_y = %.3f, "
                "surface top %+.4f mm\n",
                s.depth, s.force, s.radius, s.radius / R, std::sqrt(2 * R * s.depth - s.depth * s.depth), pm / sy,
                s.pile_up);
    if (s.radius / R >= 0.3) {
      EXPECT_NEAR(pm / sy, 2.8, 0.28) << "depth " << s.depth;
      ++checked;
    }
    pm_last = pm;
    pile_up = s.pile_up;
  }
  EXPECT_GE(checked, 5);
  EXPECT_GT(pile_up, 0.01 * depth) << "perfect plasticity piles up at the rim";
  // Lifted off: no node closed at the end, and most of the depth remains.
  ASSERT_FALSE(samples.empty());
  EXPECT_EQ(samples.back().closed, 0);
  EXPECT_NEAR(samples.back().force, 0, 1e-6 * samples[0].force + 1e-9);
  std::printf("residual depth at the axis %.4f mm (%.1f %% of %.3f); last p_m / sigma_y %.3f\n", residual_depth,
              100 * residual_depth / depth, depth, pm_last / sy);
  EXPECT_GT(residual_depth, 0.8 * depth);
  EXPECT_LT(residual_depth, depth);
  int its = 0;
  for (const auto& rec : summary.increments) its += rec.iterations;
  std::printf("%zu increments, %d Newton iterations (and %d in attempts that were cut back)\n",
              summary.increments.size(), its, static_cast<int>(summary.failed_iterations));
}
