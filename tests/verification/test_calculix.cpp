// CalculiX decks run unchanged (issue 17, item 1): the harness's 2D Hertz decks; see
// calculix_runner.hpp for what is compared and the references.
#include <fmt/format.h>

#include <sstream>

#include "calculix_runner.hpp"
#include "hertz_runner.hpp"

using namespace signorini;
using signorini::test::compare;

// The load CalculiX computes for this deck on this mesh: results/sbs.md of the harness,
// rows h2d_coarse_s2s (P = 2728.0 N/mm) and h2d_coarse_n2s (2728.5): the same stiffness and
// boundary conditions give the same force for the prescribed approach, within 0.1 %.
constexpr Real kCalculixLoad2d = 2728.0;

// Surface to surface, PRESSURE-OVERCLOSURE=LINEAR with K = 1e8 MPa/mm (the harness's default).
TEST(CalculixDeck, Hertz2dSurfaceToSurfaceLinear) {
  const auto c = compare("h2d", "hertz2d_coarse_cpe4.inp", false,
                         "discretization: segment_to_segment, enforcement: {method: penalty, penalty: 1e8}");
  EXPECT_LT(std::abs(c.peak_error), 0.01) << "peak pressure against Hertz p0";  // coarse: a/h = 16
  EXPECT_NEAR(c.load, kCalculixLoad2d, 1e-3 * kCalculixLoad2d);
}

// PRESSURE-OVERCLOSURE=HARD: Lagrange multipliers.
TEST(CalculixDeck, Hertz2dSurfaceToSurfaceHard) {
  const auto c = compare("h2d_hard", "hertz2d_coarse_cpe4.inp", false,
                         "discretization: segment_to_segment, enforcement: {method: lagrange}");
  EXPECT_LT(std::abs(c.peak_error), 0.01);
  EXPECT_NEAR(c.load, kCalculixLoad2d, 1e-3 * kCalculixLoad2d);
}

// Node to surface, LINEAR with the harness's tension at clearance (ignored, with a notice).
TEST(CalculixDeck, Hertz2dNodeToSurface) {
  const auto c = compare("h2d_n2s", "hertz2d_coarse_cpe4.inp", false,
                         "discretization: node_to_segment, enforcement: {method: penalty, penalty: 1e8}");
  EXPECT_LT(std::abs(c.peak_error), 0.01);
  EXPECT_NEAR(c.load, kCalculixLoad2d, 1e-3 * kCalculixLoad2d);
}

// Nitsche's method on segment_to_segment's integration points (docs/contact.md), the same mesh
// and prescribed approach: the load within 0.1 % of CalculiX's, the peak nodal pressure (the
// points' pressures averaged with positive weights) within 1 % of Hertz's p0 for that load
// (measured +0.30 %; Lagrange multipliers on the same points: -0.13 %), no negative nodal
// pressure, one increment (measured 17 Newton iterations: see enforcement.cpp on the bounded
// geometric term).
TEST(CalculixDeck, Hertz2dNitsche) {
  for (const std::string disc : {"segment_to_segment", "mortar"})
    for (int theta : {1, -1}) {
      const std::string what = disc + " theta " + std::to_string(theta);
      const test::Result r = test::run_yaml("h2d_nitsche", "hertz2d_coarse_cpe4.inp", false,
                                            "discretization: " + disc + ", enforcement: {method: nitsche, theta: " +
                                                std::to_string(theta) + "}");
      ASSERT_TRUE(r.completed) << what;
      EXPECT_EQ(r.summary.increments.size(), 1u) << what;
      const Real P = 2 * r.reaction;
      EXPECT_NEAR(P, kCalculixLoad2d, 1e-3 * kCalculixLoad2d) << what;
      const Real p0 = test::hertz_p0(P, false);
      Real lowest = 0;
      for (const auto& [node, p] : r.pressure) lowest = std::min(lowest, p);
      EXPECT_NEAR(test::peak_pressure(r), p0, 0.01 * p0) << what;
      EXPECT_GE(lowest, 0) << what;
      std::printf("nitsche on %s: P %.6g (%+.3f %% of CalculiX's), peak %.6g against Hertz p0 %.6g (%+.2f %%), %d "
                  "Newton iterations\n",
                  what.c_str(), P, 100 * (P / kCalculixLoad2d - 1), test::peak_pressure(r), p0,
                  100 * (test::peak_pressure(r) / p0 - 1), r.summary.total_iterations);
    }
}

// Nitsche in other units: the same problem in (m, Pa) as in (mm, MPa), the mesh scaled by 1e-3
// and E by 1e6: gamma0 E / h and the stress pressure scale alike, so the Newton iterations are
// the same and the pressures and the force per thickness agree to 1e-8 relative (measured:
// 17 iterations each, peak 3464.6693064 MPa either way).
TEST(CalculixDeck, Hertz2dNitscheIsUnitInvariant) {
  namespace fs = std::filesystem;
  const std::string tag = std::to_string(::getpid());
  const fs::path mesh_si = fs::temp_directory_path() / ("signorini_nitsche_si_" + tag + ".inp");
  {
    std::ifstream in(test::kData / "meshes" / "hertz2d_coarse_cpe4.inp");
    std::ofstream out(mesh_si);
    bool nodes = false;
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line[0] == '*') {
        nodes = line.rfind("*NODE", 0) == 0;
        out << line << "\n";
        continue;
      }
      if (!nodes || line.find(',') == std::string::npos) {
        out << line << "\n";
        continue;
      }
      std::stringstream ss(line);
      std::string field;
      std::getline(ss, field, ',');
      out << field;
      while (std::getline(ss, field, ',')) out << ", " << fmt::format("{:.17g}", 1e-3 * std::stod(field));
      out << "\n";
    }
  }
  std::string deck = test::yaml_route("hertz2d_coarse_cpe4.inp", false,
                                      "discretization: segment_to_segment, enforcement: {method: nitsche}");
  auto replace = [&](const std::string& a, const std::string& b) { test::replace_in_text(deck, a, b); };
  replace((test::kData / "meshes" / "hertz2d_coarse_cpe4.inp").string(), mesh_si.string());
  replace("E: 200000", "E: 2e11");
  replace("uy: -0.0662", "uy: -0.0662e-3");
  const fs::path yaml = fs::temp_directory_path() / ("signorini_nitsche_si_" + tag + ".yaml");
  std::ofstream(yaml) << deck;
  const test::Result si = test::run(yaml.string(), 1);
  fs::remove(yaml);
  fs::remove(mesh_si);
  const test::Result mm = test::run_yaml("h2d_nitsche_mm", "hertz2d_coarse_cpe4.inp", false,
                                         "discretization: segment_to_segment, enforcement: {method: nitsche}");
  ASSERT_TRUE(si.completed && mm.completed);
  EXPECT_EQ(si.summary.total_iterations, mm.summary.total_iterations);
  EXPECT_NEAR(si.reaction, 1e3 * mm.reaction, 1e-8 * 1e3 * mm.reaction) << "N/m against N/mm (thickness 1 m, 1 mm)";
  EXPECT_NEAR(test::peak_pressure(si), 1e6 * test::peak_pressure(mm), 1e-8 * 1e6 * test::peak_pressure(mm));
  ASSERT_EQ(si.pressure.size(), mm.pressure.size());
  for (const auto& [node, p] : mm.pressure)
    EXPECT_NEAR(si.pressure.at(node), 1e6 * p, 1e-8 * 1e6 * test::peak_pressure(mm)) << "node " << node;
}

// Every enforcement with node_to_segment on CalculiX's Hertz meshes, displacement-controlled
// from zero in one increment: the 2D coarse quad4 mesh and the fine tet4 one (16 530 DOFs). On
// the tet4 mesh penalty and the augmented Lagrangian took 25 and 27 iterations, accepted as
// stagnated at |R|/F 5.6e-7: a slave node's facet choice flipped between a facet it lay over
// and a neighbour's 1 % extension (node_to_segment.cpp). Checked: one increment, no cutback, no
// stagnation, the last step quadratic (newton_contraction, hertz_runner.hpp), the load within
// 0.5 % of Lagrange multipliers' and the peak nodal pressure within 1 % (2D, a/h = 16) or 10 %
// (tet4: node-to-segment's nodal pressures follow the irregular tributary areas, +7.4 % with
// multipliers; CalculiX node-to-surface +7.9 %) of Hertz's p0 for that load. Iterations
// (measured: lagrange 6 and 5, penalty 11 and 9, augmented_lagrangian 13 and 11): issue 13's
// target is 10 for every method; the guards are 10, 12 and 14 (the penalty systems miss it by
// up to 3: docs/contact.md, Enforcement).
TEST(CalculixDeck, EveryMethodInOneIncrementOnTheQuad4AndTet4Meshes) {
  log::set_level(log::Level::warning);
  for (const bool three_d : {false, true}) {
    const std::string mesh = three_d ? "hertz3d_fine_c3d4.inp" : "hertz2d_coarse_cpe4.inp";
    Real lagrange_load = 0;
    for (const std::string method : {"lagrange", "penalty", "augmented_lagrangian"}) {
      const std::string what = mesh + " " + method;
      const test::Result r = test::run_yaml(method, mesh, three_d, "enforcement: {method: " + method + "}");
      ASSERT_TRUE(r.completed) << what << ": " << r.summary.failure;
      ASSERT_EQ(r.summary.increments.size(), 1u) << what;
      const IncrementRecord& inc = r.summary.increments[0];
      EXPECT_EQ(inc.cutbacks, 0) << what;
      EXPECT_FALSE(inc.stagnated) << what;
      const int guard = method == "lagrange" ? 10 : method == "penalty" ? 12 : 14;
      EXPECT_LE(inc.iterations, guard) << what;
      const std::vector<Real>& res = inc.residuals;
      ASSERT_GE(res.size(), 2u) << what;
      EXPECT_LT(test::newton_contraction(res), 1e3) << what << ": last residuals " << res[res.size() - 2] << ", " << res.back();
      const Real P = (three_d ? 4 : 2) * r.reaction;
      if (method == "lagrange") lagrange_load = P;
      EXPECT_NEAR(P, lagrange_load, 5e-3 * lagrange_load) << what;
      const Real p0 = test::hertz_p0(P, three_d);
      EXPECT_NEAR(test::peak_pressure(r), p0, (three_d ? 0.10 : 0.01) * p0) << what;
      std::printf("%s: %d iterations, last residuals %.2e %.2e, P %.6g, peak %+.2f %% of Hertz p0\n", what.c_str(),
                  inc.iterations, res[res.size() - 2], res.back(), P, 100 * (test::peak_pressure(r) / p0 - 1));
    }
  }
}
