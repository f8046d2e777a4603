// A run stopped by SIGINT/SIGTERM (core/interrupt.hpp) keeps its last converged increment and
// says so in summary.json; the Newton iterations of cut-back attempts are counted there.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "signorini/core/interrupt.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/io/results_writer.hpp"

using namespace signorini;

namespace {
std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

TEST(Interrupt, SigtermKeepsTheLastConvergedIncrementAndSaysInterrupted) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  const fs::path deck = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "friction_block" / "friction_block.yaml";
  Registry r = default_registry();
  Model m = read_deck(deck.string(), r);
  const fs::path dir = fs::temp_directory_path() / ("signorini_interrupt_" + std::to_string(::getpid()));
  ResultsWriter writer(m, dir.string());
  Analysis a(m);
  writer.write_initial(a);
  VecX converged;
  int seen = 0;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    writer.write_increment(an, rec);
    converged = an.displacement();
    // The signal arrives during the third increment (as from `kill` or Ctrl-C).
    if (++seen == 2) set_interrupt(SIGTERM);
  });
  AnalysisSummary s = a.run();
  const int sig = interrupt_signal();
  set_interrupt(0);
  writer.finish(a, s, {});
  EXPECT_EQ(sig, SIGTERM);
  EXPECT_FALSE(s.completed);
  EXPECT_TRUE(s.interrupted);
  EXPECT_EQ(s.increments.size(), 2u);
  EXPECT_NE(s.failure.find("SIGTERM"), std::string::npos) << s.failure;
  EXPECT_EQ((a.displacement() - converged).cwiseAbs().maxCoeff(), 0.0) << "the state is the last converged one";
  const std::string json = read(dir / "summary.json");
  EXPECT_NE(json.find("\"status\": \"interrupted\""), std::string::npos) << json.substr(0, 300);
  fs::remove_all(dir);
}

TEST(Interrupt, FailedAttemptsIterationsAreCounted) {
  // The block dragged well beyond mu N (5 against 3): increments fail and are cut back until
  // the run gives up; their iterations are counted apart from the converged ones. (At 3.3 the
  // abandoned increment's attempts stop at their first solve, the all-slip tangent being
  // singular, and leave nothing beyond the increments' own count to check; the path is the
  // same in every run since the assembly is deterministic.)
  namespace fs = std::filesystem;
  log::set_level(log::Level::error);
  const fs::path src = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "friction_block";
  std::string text = read(src / "friction_block.yaml");
  text.replace(text.find("file: friction_block.geo"), 24, "file: " + (src / "friction_block.geo").string());
  const size_t a0 = text.find("  - name: drag"), b0 = text.find("checks:");
  text.replace(a0, b0 - a0,
               "  - name: push\n    increments: {initial: 0.25, max: 0.25, min: 0.01}\n    loads:\n"
               "      - {set: Top, pressure: 10}\n      - {set: Top, traction: [5, 0]}\n");
  text = text.substr(0, text.find("checks:"));
  const fs::path tmp = fs::temp_directory_path() / ("signorini_failed_its_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(tmp) << text;
  Registry r = default_registry();
  Model m = read_deck(tmp.string(), r);
  Analysis an(m);
  AnalysisSummary s = an.run();
  fs::remove(tmp);
  ASSERT_FALSE(s.completed) << "a load above mu N cannot be held";
  EXPECT_GT(s.failed_iterations, 0);
  int per_increment = 0, converged = 0;
  for (const auto& rec : s.increments) per_increment += rec.failed_iterations, converged += rec.iterations;
  EXPECT_EQ(converged, s.total_iterations);
  // The attempts of the last (abandoned) increment are in the total but in no increment.
  EXPECT_GT(s.failed_iterations, per_increment);
}

// Issue 17, item 5: a load in the wrong units (5e30 for 5) is solved at small strain, but the
// answer's displacements dwarf the model, and the run says so (the command prints it).
TEST(Interrupt, DisplacementsLargerThanTheModelAreReported) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  const fs::path src = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "cantilever_3d" / "cantilever_3d.yaml";
  std::string deck = read(src);
  deck.insert(deck.find("file: ") + 6, (src.parent_path() / "").string());
  for (const std::string load : {"-1", "-5e30"}) {
    std::string d = deck;
    d.replace(d.find("traction: [0, -1, 0]"), 20, "traction: [0, " + load + ", 0]");
    const fs::path p = fs::temp_directory_path() / ("signorini_oversized_" + std::to_string(::getpid()) + ".yaml");
    std::ofstream(p) << d;
    Registry r = default_registry();
    Model m = read_deck(p.string(), r);
    fs::remove(p);
    Analysis a(m);
    ASSERT_TRUE(a.run().completed);
    const std::string w = oversized_displacement(a);
    if (load == "-1") EXPECT_EQ(w, "");
    else EXPECT_NE(w.find("is larger than the model"), std::string::npos) << w;
  }
}
