// The friction robustness family (issue 13): plane-strain press-then-shear of a steel cylinder
// (R = 10 mm) on a steel block, the geometry of examples/cattaneo_cylinder. Step `press`: the
// cylinder's top moves down by 0.01 mm (P = 388.4 N/mm, a = 0.21 mm); step `push`: the top
// held at that height (no rolling) and pushed sideways by Q = ratio mu P_nominal. Both steps
// with the default increments (one increment per step, cut back only if Newton fails). For
// identical materials the normal and tangential problems are uncoupled, and the stick zone
// has the half-width c = a sqrt(1 - Q/(mu P)) (Cattaneo 1938, Mindlin 1949; Johnson 1985,
// sec. 7.2), checked with the P, Q and a the run measures.
#pragma once
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "hertz_runner.hpp"

namespace signorini::test {

struct GridCase {
  Real mu = 0.3;
  Real ratio = 0.6;              // Q / (mu P)
  std::string method = "lagrange";
  Real hc = 0.01;                // element size at the contact (mm)
  Real unit = 1;                 // 1: mm, N, MPa; 1e-3: m, N, Pa (the same mesh, scaled)
  std::string discretization = "node_to_segment";
  bool stick_predictor = true;   // friction.stick_predictor (penalty and augmented Lagrangian)
  std::string linear;            // solver.linear (empty: the default, auto)
};

inline std::string grid_name(const GridCase& c) {
  std::string s = fmt::format("{}{}_mu{:g}_ratio{:g}_hc{:g}{}",
                              c.discretization == "node_to_segment" ? "" : c.discretization + "_", c.method, c.mu,
                              c.ratio, c.hc, c.unit == 1 ? "" : "_SI");
  if (!c.stick_predictor) s += "_no_stick_predictor";
  if (!c.linear.empty()) s += "_" + c.linear;
  for (char& ch : s)
    if (ch == '.') ch = 'p';
  return s;
}

inline std::string grid_deck(const GridCase& c) {
  namespace fs = std::filesystem;
  const fs::path geo = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "cattaneo_cylinder" / "cattaneo_cylinder.geo";
  const Real d = 0.01, p_nominal = 388.4;
  const Real q = c.ratio * c.mu * p_nominal / 20;  // traction on the top (length 2R = 20 mm)
  // In SI the lengths scale by 1e-3 and the stresses by 1e6 (the forces per unit thickness
  // by 1e3): the same problem.
  const Real L = c.unit, S = 1 / (c.unit * c.unit);
  return fmt::format(R"(title: friction grid {name}
analysis: {{dimension: plane_strain}}
mesh: {{file: {geo}, parameters: {{hc: {hc}}}, scale: {L}}}
materials:
  steel: {{model: linear_elastic, E: {E:.17g}, nu: 0.3}}
bodies:
  - {{name: cylinder, region: Cylinder, material: steel}}
  - {{name: block, region: Block, material: steel}}
contact:
  - name: cm
    master: auto
    surfaces: [CylinderSurface, BlockTop]
    discretization: {discretization}
    enforcement: {{method: {method}}}
    friction: {{law: coulomb, mu: {mu}{predictor}}}
steps:
  - name: press
    boundary:
      - {{set: BlockBottom, u: [0, 0]}}
      - {{set: CylinderTop, u: [0, {dy:.17g}]}}
  - name: push
    boundary:
      - {{set: BlockBottom, u: [0, 0]}}
      - {{set: CylinderTop, uy: {dy:.17g}}}
    loads:
      - {{set: CylinderTop, traction: [{q:.17g}, 0]}}
checks:
  - {{name: c, quantity: contact_stick_half_width, pair: cm, at: [0, 0], component: x, expected: 1, tolerance: 1e30}}
  - {{name: a, quantity: contact_half_width, pair: cm, at: [0, 0], component: x, expected: 1, tolerance: 1e30}}
  - {{name: P, quantity: contact_force, pair: cm, component: y, expected: 1, tolerance: 1e30}}
  - {{name: Q, quantity: contact_force, pair: cm, component: x, expected: 1, tolerance: 1e30}}
{solver})",
                     fmt::arg("name", grid_name(c)), fmt::arg("geo", geo.string()), fmt::arg("hc", c.hc),
                     fmt::arg("L", L), fmt::arg("E", 210000 * S), fmt::arg("method", c.method), fmt::arg("mu", c.mu),
                     fmt::arg("dy", -d * L), fmt::arg("q", q * S),
                     fmt::arg("discretization", c.discretization),
                     fmt::arg("predictor", c.stick_predictor ? "" : ", stick_predictor: false"),
                     fmt::arg("solver", c.linear.empty() ? "" : "solver: {linear: " + c.linear + "}\n"));
}

struct GridResult {
  HertzRun run;
  Real c = 0, a = 0, P = 0, Q = 0;
  Real ca = 0, expected = 0;  // c/a measured, sqrt(1 - Q/(mu P))
  int cutbacks = 0, increments = 0, iterations = 0;
};

inline GridResult run_grid_case(const GridCase& c) {
  GridResult g;
  g.run = run_deck_text(grid_deck(c), "grid_" + grid_name(c));
  if (g.run.checks.size() == 4) {
    g.c = g.run.checks[0].computed;
    g.a = g.run.checks[1].computed;
    g.P = -g.run.checks[2].computed;
    g.Q = g.run.checks[3].computed;
    g.ca = g.a > 0 ? g.c / g.a : 0;
    g.expected = std::sqrt(std::max(0.0, 1 - g.Q / (c.mu * g.P)));
  }
  for (const auto& r : g.run.summary.increments) {
    g.cutbacks += r.cutbacks;
    g.iterations += r.iterations;
    ++g.increments;
  }
  std::printf("%s: %s, %d increments, %d cutbacks, %d Newton iterations (%.1f per increment), P = %.3f, Q = %.3f, "
              "c/a = %.4f against sqrt(1 - Q/(mu P)) = %.4f (%+.1f %%)\n",
              grid_name(c).c_str(), g.run.summary.completed ? "completed" : "gave up", g.increments, g.cutbacks,
              g.iterations, g.increments ? double(g.iterations) / g.increments : 0.0, g.P, g.Q, g.ca, g.expected,
              g.expected > 0 ? 100 * (g.ca - g.expected) / g.expected : 0.0);
  return g;
}

}  // namespace signorini::test
