// Force-controlled point contact from the undeformed state, the whole load in one increment:
// the family of cases the Newton step's penetration limit is designed for (docs/contact.md,
// "Newton steps that drive nodes through the master"). A body held only by contact touches at
// one point; the first Newton step, with that point as its only support, pushes it several
// facet sizes into the other body, and from there the active set of the semi-smooth Newton
// method (3D mortar above all) cycled: 25 iterations, a cutback, 80 s on the quarter sphere
// at hc = 0.02 before the limit, 6 iterations and 2.2 s with it.
//
// Each case is checked against Hertz (Johnson, Contact Mechanics, 1985, ch. 4; VALIDATION.md
// sec. 1): a = (3 F R / (4 E*))^(1/3), p0 = 3 F / (2 pi a^2), on a coarse mesh (hc = 0.035:
// p0 within 25 %, as the tet4 example's own tolerance, and the node-based contact radius within
// one facet size of a), and the force balance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "hertz_runner.hpp"

using namespace signorini;

namespace {

void replace(std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

struct SphereCase {
  std::string pair;    // deck lines after the pair's slave, e.g. "    discretization: mortar\n"
  Real load = 1;       // times the example's force (F = 1e4 on the whole sphere)
  Real length = 1;     // units: lengths times this
  Real stress = 1;     // and moduli times this (length^2 * stress = 1 keeps the force)
};

struct SphereResult {
  test::HertzRun run;
  Real p0 = 0, a = 0;          // computed, in the example's units
  Real p0_hertz = 0, a_hertz = 0;
};

// examples/hertz_sphere_3d (quarter model, tet4, R = 1, E* = 7.5e6) at hc = 0.035, its force
// times `load` in one increment (the deck's default: one increment, no smaller first one).
SphereResult run_sphere(const SphereCase& c) {
  std::string deck = test::example_deck_text("hertz_sphere_3d");
  const Real L = c.length;
  replace(deck, "parameters: {hc: 0.02}", fmt::format("parameters: {{hc: 0.035}}, scale: {:.17g}", L));
  replace(deck, "E: 1.40625e7", fmt::format("E: {:.17g}", 1.40625e7 * c.stress));
  replace(deck, "force: [0, 0, -2500]", fmt::format("force: [0, 0, {:.17g}]", -2500 * c.load));
  replace(deck, "    slave: SphereSurface\n", "    slave: SphereSurface\n" + c.pair);
  SphereResult out;
  out.run = test::run_deck_text(deck, "point_contact");
  if (out.run.checks.size() == 3) {
    out.p0 = out.run.checks[0].computed / c.stress;
    out.a = out.run.checks[1].computed / L;
  }
  const Real F = 1e4 * c.load, Estar = 7.5e6;
  out.a_hertz = std::cbrt(3 * F / (4 * Estar));
  out.p0_hertz = 3 * F / (2 * M_PI * out.a_hertz * out.a_hertz);
  return out;
}

void expect_point_contact(const SphereCase& c, int max_iterations) {
  const SphereResult r = run_sphere(c);
  ASSERT_TRUE(r.run.summary.completed) << c.pair << " load x" << c.load << ": " << r.run.summary.failure;
  ASSERT_EQ(r.run.checks.size(), 3u);
  const int its = r.run.summary.total_iterations;
  std::printf("%-50s load x%-4g: %d increment(s), %2d Newton iterations, p0 %+.2f %%, a %+.2f %%\n",
              c.pair.empty() ? "node_to_segment, lagrange (defaults)" : c.pair.substr(4, c.pair.size() - 5).c_str(),
              c.load, static_cast<int>(r.run.summary.increments.size()), its, 100 * (r.p0 / r.p0_hertz - 1),
              100 * (r.a / r.a_hertz - 1));
  EXPECT_EQ(r.run.summary.increments.size(), 1u) << "no cutback";
  EXPECT_LE(its, max_iterations);
  EXPECT_LT(std::abs(r.p0 / r.p0_hertz - 1), 0.25) << "p0 " << r.p0 << " (Hertz " << r.p0_hertz << ")";
  EXPECT_LT(std::abs(r.a - r.a_hertz), 0.035) << "a " << r.a << " (Hertz " << r.a_hertz << "): within a facet size";
  EXPECT_NEAR(r.run.checks[2].computed / (2500 * c.load), 1.0, 1e-4) << "force balance (to the Newton tolerance)";
}

}  // namespace

// Every discretization and enforcement method that takes a force-controlled sphere from its
// touching point, at a fifth, once and five times the example's force (a from 0.06 to 0.17
// of R, 2 to 5 facet sizes at the centre), in one increment.
TEST(ForceControlledPointContact, SphereInOneIncrementWithEveryMethod) {
  for (const char* pair : {"", "    discretization: mortar\n", "    discretization: segment_to_segment\n"})
    for (Real load : {0.2, 1.0, 5.0}) expect_point_contact({pair, load}, 10);
}

// The limit is in facet sizes, so the same model in other units takes the same steps: the
// quarter sphere with lengths x 1e-3 (the mesh's `scale`) and moduli x 1e6, as from (mm, MPa)
// to (m, Pa), gives the same p0 and a in the example's units to 1e-8, and with mortar and
// segment_to_segment the same iterations. Node-to-segment takes 9 iterations in the example's
// units and 7 in the scaled ones, with or without the limit (both limit the first step to the
// same 0.335): its residual stalls once at 2.7e-8, just above the tolerance, in the example's
// units (measured; not explained yet), so its count is printed, not asserted.
TEST(ForceControlledPointContact, SameStepsInOtherUnits) {
  for (const char* pair : {"", "    discretization: mortar\n", "    discretization: segment_to_segment\n"}) {
    const SphereResult a = run_sphere({pair, 1.0, 1.0, 1.0});
    const SphereResult b = run_sphere({pair, 1.0, 1e-3, 1e6});
    ASSERT_TRUE(a.run.summary.completed && b.run.summary.completed) << pair;
    if (*pair) EXPECT_EQ(a.run.summary.total_iterations, b.run.summary.total_iterations) << pair;
    EXPECT_NEAR(b.p0 / a.p0, 1.0, 1e-8) << pair;
    EXPECT_NEAR(b.a / a.a, 1.0, 1e-8) << pair;
    const std::string name = *pair ? std::string(pair + 20, std::strlen(pair) - 21) : "node_to_segment";
    std::printf("%s: %d and %d iterations, p0 ratio - 1 = %.2e, a ratio - 1 = %.2e\n", name.c_str(), a.run.summary.total_iterations, b.run.summary.total_iterations,
                b.p0 / a.p0 - 1, b.a / a.a - 1);
  }
}
