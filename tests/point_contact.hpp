// The force-controlled point contact family (tests/verification/test_point_contact.cpp and
// its tet10 rows in tests/long): examples/hertz_sphere_3d, a quarter sphere (R = 1,
// E* = 7.5e6) pressed by a force from its touching point, the whole force in one increment,
// against Hertz (Johnson, Contact Mechanics, 1985, ch. 4; VALIDATION.md sec. 1):
// a = (3 F R / (4 E*))^(1/3), p0 = 3 F / (2 pi a^2).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hertz_runner.hpp"

namespace signorini::test {

struct SphereCase {
  std::string pair;    // deck lines after the pair's slave, e.g. "    discretization: mortar\n"
  Real load = 1;       // times the example's force (F = 1e4 on the whole sphere)
  Real length = 1;     // units: lengths times this
  Real stress = 1;     // and moduli times this (length^2 * stress = 1 keeps the force)
  Real hc = 0.035;     // the element size at the contact
  int order = 0;       // > 0: the mesh raised to this order (2: tet10)
  std::string solver;  // a `solver` map's entries for the deck, e.g. "residual_growth: 2" (none if empty)
};

struct SphereResult {
  HertzRun run;
  Real p0 = 0, a = 0;          // computed, in the example's units
  Real p0_hertz = 0, a_hertz = 0;
};

// examples/hertz_sphere_3d (quarter model, tet4 unless `order`) at `hc`, its force times
// `load` in one increment (the deck's default: one increment, no smaller first one).
inline SphereResult run_sphere(const SphereCase& c) {
  std::string deck = test::example_deck_text("hertz_sphere_3d");
  const Real L = c.length;
  replace_in_text(deck, "parameters: {hc: 0.02}",
                  fmt::format("parameters: {{hc: {}}}, scale: {:.17g}{}", c.hc, L,
                              c.order > 0 ? fmt::format(", order: {}", c.order) : std::string()));
  replace_in_text(deck, "E: 1.40625e7", fmt::format("E: {:.17g}", 1.40625e7 * c.stress));
  replace_in_text(deck, "force: [0, 0, -2500]", fmt::format("force: [0, 0, {:.17g}]", -2500 * c.load));
  replace_in_text(deck, "    slave: SphereSurface\n", "    slave: SphereSurface\n" + c.pair);
  if (!c.solver.empty()) deck += "solver: {" + c.solver + "}\n";
  SphereResult out;
  out.run = run_deck_text(deck, "point_contact");
  if (out.run.checks.size() == 3) {
    out.p0 = out.run.checks[0].computed / c.stress;
    out.a = out.run.checks[1].computed / L;
  }
  const Real F = 1e4 * c.load, Estar = 7.5e6;
  out.a_hertz = std::cbrt(3 * F / (4 * Estar));
  out.p0_hertz = 3 * F / (2 * M_PI * out.a_hertz * out.a_hertz);
  return out;
}

// One increment (no cutback), at most `max_iterations` Newton iterations, p0 within 25 % (the
// tet4 example's own tolerance), the node-based contact radius within one facet size of a,
// and the force balance to the Newton tolerance.
inline void expect_point_contact(const SphereCase& c, int max_iterations) {
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
  EXPECT_LT(std::abs(r.a - r.a_hertz), c.hc) << "a " << r.a << " (Hertz " << r.a_hertz << "): within a facet size";
  EXPECT_NEAR(r.run.checks[2].computed / (2500 * c.load), 1.0, 1e-4) << "force balance (to the Newton tolerance)";
}

}  // namespace signorini::test
