// Restart (issue 17, item 7): a run continued from the restart file written after a step
// ends in the same state as the uninterrupted run, on a frictional contact case (penalty and
// Lagrange multipliers: the contact pair's committed records and the multipliers) and on J2
// plasticity unloaded (the quadrature-point history); a file of another model or a truncated
// one is refused with the file and the reason.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "hertz_runner.hpp"
#include "signorini/core/error.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;
namespace fs = std::filesystem;

namespace {

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("signorini_restart_" + std::to_string(::getpid()) + "_" + name);
}

Model model_of(const std::string& deck, const std::string& name) {
  const fs::path p = temp(name + ".yaml");
  std::ofstream(p) << deck;
  Registry r = default_registry();
  Model m = read_deck(p.string(), r);
  fs::remove(p);
  return m;
}

// Runs the deck through, writing a restart file after `after_step` (1-based); then a second
// analysis of the same deck continues from that file. Both complete; returns the largest
// difference of their unknowns relative to the largest unknown.
Real restart_difference(const std::string& deck, int after_step, const std::string& name) {
  log::set_level(log::Level::warning);
  const fs::path file = temp(name + ".bin");
  Model m1 = model_of(deck, name + "_a");
  Analysis a(m1);
  a.on_step([&](const Analysis& an, int step) {
    if (step + 1 == after_step) an.write_restart(file.string());
  });
  const AnalysisSummary sa = a.run();
  EXPECT_TRUE(sa.completed) << name << ": " << sa.failure;
  Model m2 = model_of(deck, name + "_b");
  Analysis b(m2);
  b.read_restart(file.string());
  EXPECT_EQ(b.first_step(), after_step);
  const AnalysisSummary sb = b.run();
  EXPECT_TRUE(sb.completed) << name << ": " << sb.failure;
  EXPECT_EQ(sb.first_step, after_step);
  EXPECT_FALSE(sb.increments.empty());
  if (!sb.increments.empty()) {
    EXPECT_EQ(sb.increments.front().step, after_step);  // 0-based: the next step
  }
  fs::remove(file);
  const VecX& ua = a.displacement();
  const VecX& ub = b.displacement();
  if (ua.size() != ub.size()) return 1;
  return (ua - ub).cwiseAbs().maxCoeff() / ua.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(Restart, FrictionalContactContinuesToTheSameState) {
  // Pressed, then dragged twice by a tenth of the example's drag, mostly sticking: the state
  // after the third step depends on the tangential tractions and statuses committed before
  // the restart (written after the second step).
  std::string deck = test::example_deck_text("friction_block");
  deck.replace(deck.find("ux: {ramp: [0, 0.02]}"), 21, "ux: {ramp: [0, 0.002]}");
  const std::string drag2 = "  - name: drag2\n    boundary:\n      - {set: Top, ux: {ramp: [0.002, 0.004]}}\n"
                            "    loads:\n      - {set: Top, pressure: 10}\n";
  deck = deck.substr(0, deck.find("checks:")) + drag2;
  EXPECT_LT(restart_difference(deck, 2, "penalty"), 1e-12);
  std::string lagrange = deck;
  lagrange.replace(lagrange.find("enforcement: {method: penalty}"), 30, "enforcement: {method: lagrange}");
  EXPECT_LT(restart_difference(lagrange, 2, "lagrange"), 1e-12);
}

TEST(Restart, PlasticHistoryContinuesThroughUnloading) {
  // Pressurized into the plastic range, then unloaded: the residual displacement comes from
  // the plastic strain carried by the restart file.
  std::string deck = test::example_deck_text("thick_cylinder_plastic");
  deck = deck.substr(0, deck.find("output:")) +
         "  - name: unload\n    boundary:\n      - {set: SymX, uy: 0}\n      - {set: SymY, ux: 0}\n"
         "    loads:\n      - {set: Inner, pressure: 0}\n";
  EXPECT_LT(restart_difference(deck, 1, "plastic"), 1e-12);
}

TEST(Restart, AFileOfAnotherModelOrTruncatedIsRefused) {
  log::set_level(log::Level::warning);
  const std::string deck = test::example_deck_text("friction_block");
  const fs::path file = temp("refused.bin");
  {
    Model m = model_of(deck, "refused_a");
    Analysis a(m);
    a.on_step([&](const Analysis& an, int step) {
      if (step == 0) an.write_restart(file.string());
    });
    ASSERT_TRUE(a.run().completed);
  }
  auto message = [&](const std::string& deck_text, const fs::path& f) {
    Model m = model_of(deck_text, "refused_b");
    Analysis b(m);
    try {
      b.read_restart(f.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "accepted " << f;
    return std::string();
  };
  // Another mesh (the hertz cylinder's).
  std::string m = message(test::example_deck_text("hertz_cylinder"), file);
  EXPECT_NE(m.find(file.string()), std::string::npos) << m;
  EXPECT_NE(m.find("nodes"), std::string::npos) << m;
  // Truncated.
  const auto size = fs::file_size(file);
  fs::resize_file(file, size / 2);
  m = message(deck, file);
  EXPECT_NE(m.find("ends early"), std::string::npos) << m;
  // Not a restart file at all.
  std::ofstream(file) << "title: a deck\n";
  m = message(deck, file);
  EXPECT_NE(m.find("not a Signorini restart file"), std::string::npos) << m;
  fs::remove(file);
}
