// Shallow ironing, frictionless, with the slab's top smoothed (ctest label `long`: about
// 5 minutes on two cores): the run of examples/wip/shallow_ironing/frictionless_smooth.yaml
// completes the indentation and the whole sliding (the faceted master gives up during the
// indentation, README there), and without friction the horizontal force on the indenter
// during steady sliding is zero up to the discretization: |H| < 1 % of V at t = 1.5
// (VALIDATION.md sec. 4, "also the frictionless variant (H ~ 0)").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace fs = std::filesystem;

TEST(LongIroning, FrictionlessSmoothedCompletesWithZeroHorizontalForce) {
  const fs::path deck = fs::path(SIGNORINI_SOURCE_DIR) / "examples/wip/shallow_ironing/frictionless_smooth.yaml";
  const fs::path out = fs::temp_directory_path() / "signorini_long_ironing";
  fs::remove_all(out);
  const int rc = std::system(
      (std::string(SIGNORINI_BINARY) + " run -q " + deck.string() + " -o " + out.string() + " > " + out.string() +
       ".log 2>&1")
          .c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  ASSERT_EQ(WEXITSTATUS(rc), 0) << "the run did not complete: see " << out.string() << ".log";
  // The IndenterTop reaction nearest to t = 1.5.
  std::ifstream csv(out / "reactions.csv");
  std::string line;
  double best = 1e9, fx = 0, fy = 0, last_time = 0;
  while (std::getline(csv, line)) {
    if (line.find(",IndenterTop,") == std::string::npos) continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> c;
    while (std::getline(ss, cell, ',')) c.push_back(cell);
    const double t = std::stod(c[2]);
    last_time = t;
    if (std::abs(t - 1.5) < best) best = std::abs(t - 1.5), fx = std::stod(c[5]), fy = std::stod(c[6]);
  }
  EXPECT_NEAR(last_time, 2.0, 1e-9) << "the sliding did not reach its end";
  ASSERT_LT(best, 0.01);
  std::printf("frictionless ironing at t = 1.5: V = %.4e, H = %.4e, H/V = %.2e\n", -fy, fx, fx / -fy);
  EXPECT_GT(-fy, 3e8) << "the indenter should press with V of about 4e8";
  EXPECT_LT(-fy, 5e8);
  EXPECT_LT(std::abs(fx), 0.01 * std::abs(fy)) << "without friction the horizontal force should vanish in steady sliding";
}
