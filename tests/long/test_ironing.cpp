// Shallow ironing (VALIDATION.md sec. 4), ctest label `long`, decks in examples/long/shallow_ironing:
// - frictionless, the slab's top smoothed (about 5 minutes on two cores): completes the
//   indentation and the whole sliding (the faceted master gives up during the indentation,
//   README there), and without friction the horizontal force on the indenter in steady
//   sliding vanishes up to the discretization: |H| < 1 % of V at t = 1.5;
// - Coulomb friction mu = 0.3, with the solver's stabilization through the onset of gross
//   sliding (about 25 minutes), and without it, crossing that limit point and the later ones by
//   pseudo-transient continuation (about 30 minutes): each completes, and V, H and H/V at t = 1.5
//   lie within the spread of the published results (digitised in
//   shared/reference-data/shallow-ironing: V 3.37-4.21, H 1.0-1.9 in 1e8 units; H/V 0.30-0.53
//   as VALIDATION.md lists);
// - the same with mortar and Lagrange multipliers, no stabilization (about 3 minutes on one
//   core): completes without pseudo-transient continuation, within the same spread.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

struct IroningRun {
  double last_time = 0;
  double h = 0, v = 0;        // the IndenterTop reaction nearest to t = 1.5 (V > 0 pressing)
  double distance = 1e9;      // |t - 1.5| of that row
  fs::path out;
};

// Runs examples/long/shallow_ironing/<deck> and reads the IndenterTop reactions.
IroningRun run_ironing(const std::string& deck_name, const std::string& stem) {
  IroningRun r;
  const fs::path deck = fs::path(SIGNORINI_SOURCE_DIR) / "examples/long/shallow_ironing" / deck_name;
  r.out = fs::temp_directory_path() / stem;
  fs::remove_all(r.out);
  const int rc = std::system((std::string(SIGNORINI_BINARY) + " run -q " + deck.string() + " -o " + r.out.string() +
                              " > " + r.out.string() + ".log 2>&1")
                                 .c_str());
  EXPECT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 0) << "the run did not complete: see " << r.out.string() << ".log";
  std::ifstream csv(r.out / "reactions.csv");
  std::string line;
  while (std::getline(csv, line)) {
    if (line.find(",IndenterTop,") == std::string::npos) continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> c;
    while (std::getline(ss, cell, ',')) c.push_back(cell);
    const double t = std::stod(c[2]);
    r.last_time = t;
    if (std::abs(t - 1.5) < r.distance) r.distance = std::abs(t - 1.5), r.h = std::stod(c[5]), r.v = -std::stod(c[6]);
  }
  return r;
}

}  // namespace

TEST(LongIroning, FrictionlessSmoothedCompletesWithZeroHorizontalForce) {
  const IroningRun r = run_ironing("frictionless_smooth.yaml", "signorini_long_ironing");
  EXPECT_NEAR(r.last_time, 2.0, 1e-9) << "the sliding did not reach its end";
  ASSERT_LT(r.distance, 0.01);
  std::printf("frictionless ironing at t = 1.5: V = %.4e, H = %.4e, H/V = %.2e\n", r.v, r.h, r.h / r.v);
  EXPECT_GT(r.v, 3e8) << "the indenter should press with V of about 4e8";
  EXPECT_LT(r.v, 5e8);
  EXPECT_LT(std::abs(r.h), 0.01 * std::abs(r.v)) << "without friction the horizontal force should vanish in steady sliding";
}

// V, H and H/V at t = 1.5 within the published spread (VALIDATION.md; 3 % beyond its ends
// for V and H); returns the sliding's increments, iterations and cutbacks from summary.json.
struct Sliding {
  int increments = 0, iterations = 0, cutbacks = 0, continued = 0;
  double largest_ratio = 0, late_ratio = 0;  // the stabilization's |f_v|/F, overall and from t = 1.2
};

Sliding check_published_spread(const IroningRun& r, const char* label) {
  EXPECT_NEAR(r.last_time, 2.0, 1e-9) << label << ": the sliding did not reach its end";
  EXPECT_LT(r.distance, 0.01) << label;
  const double hv = r.h / r.v;
  std::printf("%s, at t = 1.5: V = %.4e, H = %.4e, H/V = %.3f\n", label, r.v, r.h, hv);
  EXPECT_GT(r.v, 3.37e8 * 0.97) << label;
  EXPECT_LT(r.v, 4.21e8 * 1.03) << label;
  EXPECT_GT(r.h, 1.0e8 * 0.97) << label;
  EXPECT_LT(r.h, 1.9e8 * 1.03) << label;
  EXPECT_GT(hv, 0.30) << label;
  EXPECT_LT(hv, 0.53) << label;
  Sliding s;
  const YAML::Node y = YAML::LoadFile((r.out / "summary.json").string());
  for (const auto& inc : y["increments"]) {
    if (inc["step"].as<int>() != 2) continue;
    ++s.increments;
    s.iterations += inc["iterations"].as<int>();
    s.cutbacks += inc["cutbacks"].as<int>();
    s.continued += inc["pseudo_transient"] ? 1 : 0;
    const double ratio = inc["stabilization_ratio"] ? inc["stabilization_ratio"].as<double>() : 0.0;
    s.largest_ratio = std::max(s.largest_ratio, ratio);
    if (inc["time"].as<double>() >= 1.2) s.late_ratio = std::max(s.late_ratio, ratio);
  }
  std::printf("%s, sliding: %d increments (%d by pseudo-transient continuation), %d cutbacks, %.2f Newton iterations "
              "per converged increment; stabilization |f_v|/F largest %.2e, largest from t = 1.2 on %.2e\n",
              label, s.increments, s.continued, s.cutbacks, double(s.iterations) / std::max(s.increments, 1),
              s.largest_ratio, s.late_ratio);
  EXPECT_GT(s.increments, 0) << label;
  return s;
}

TEST(LongIroning, FrictionalCompletesWithinThePublishedSpread) {
  const IroningRun r = run_ironing("shallow_ironing_stabilized.yaml", "signorini_long_ironing_mu");
  const Sliding s = check_published_spread(r, "ironing, mu = 0.3, stabilized");
  EXPECT_LT(s.late_ratio, 1e-2) << "the stabilization force should stay a small part of the forces in steady sliding";
}

// The same deck without stabilization: at the onset of gross sliding and at each slab node's
// passage under the indenter's corner the increment is cut back to its minimum and crossed by
// pseudo-transient continuation (docs/deck.md, Limit points), whose states are exact
// equilibria: no stabilizing force anywhere.
TEST(LongIroning, FrictionalWithoutStabilizationCompletesWithinThePublishedSpread) {
  const IroningRun r = run_ironing("shallow_ironing_continuation.yaml", "signorini_long_ironing_ptc");
  const Sliding s = check_published_spread(r, "ironing, mu = 0.3, no stabilization");
  EXPECT_EQ(s.largest_ratio, 0.0);
  EXPECT_GT(s.continued, 0) << "the onset of gross sliding is a limit point: crossed by continuation";
}

// With mortar (shallow_ironing_mortar.yaml: the indenter's arc and sides the slave, the slab's
// faceted top the master, Lagrange multipliers, no smoothing, no stabilization), issue 14's
// variant: it completes without stabilization and without pseudo-transient continuation, within
// the published spread. The issue asks for at most 6 Newton iterations per increment on
// average over the 500: measured 5.82 per converged sliding increment, 6.15 counting the failed
// attempts' iterations (docs/validation.md); the bound of 8 here guards against regressions, with
// room for the cutbacks that round-off may move.
TEST(LongIroning, FrictionalMortarCompletesWithinThePublishedSpread) {
  const IroningRun r = run_ironing("shallow_ironing_mortar.yaml", "signorini_long_ironing_mortar");
  const Sliding s = check_published_spread(r, "ironing, mu = 0.3, mortar");
  EXPECT_EQ(s.largest_ratio, 0.0);
  EXPECT_EQ(s.continued, 0) << "no increment should need pseudo-transient continuation";
  EXPECT_LT(double(s.iterations) / std::max(s.increments, 1), 8.0);
}
