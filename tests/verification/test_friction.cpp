// Coulomb friction on the block of examples/friction_block (VALIDATION.md: "a block on a plane
// under normal then tangential load"): pressed by q = 10 (N = 10 per unit thickness), then
// pushed by a tangential traction T on its top. Below mu N it sticks, the friction force
// equals T; above mu N there is no static equilibrium: the run gives up, its last converged
// load just below mu N (the exact onset of sliding).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "hertz_runner.hpp"

using namespace signorini;

namespace {

// The deck of examples/<name>/<name>.yaml with its mesh path made absolute.
std::string example_deck(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / name;
  std::ifstream in(dir / (name + ".yaml"));
  std::stringstream ss;
  ss << in.rdbuf();
  std::string deck = ss.str();
  const std::string mesh = "file: " + name + ".geo";
  deck.replace(deck.find(mesh), mesh.size(), "file: " + (dir / (name + ".geo")).string());
  return deck;
}

std::string block_deck(const std::string& drag_step) {
  std::string deck = example_deck("friction_block");
  const size_t a = deck.find("  - name: drag"), b = deck.find("checks:");
  deck.replace(a, b - a, drag_step);
  return deck;
}

}  // namespace

TEST(Friction, BlockOnPlaneSticksBelowMuNAndSlidesAbove) {
  const Real mu = 0.3, N = 10;
  for (const std::string method : {"penalty", "lagrange"})
  for (Real ratio : {0.95, 1.05}) {
    const Real T = ratio * mu * N;  // traction on a top of length 1: total force T
    const std::string step = "  - name: push\n"
                             "    increments: {initial: 0.1, max: 0.1, min: 1e-4}\n"
                             "    loads:\n"
                             "      - {set: Top, pressure: 10}\n"
                             "      - {set: Top, traction: [" +
                             std::to_string(T) + ", 0]}\n";
    std::string deck = block_deck(step);
    deck.replace(deck.find("{method: penalty}"), 17, "{method: " + method + "}");
    test::HertzRun r = test::run_deck_text(deck, "friction_block");
    const auto& last = r.summary.increments.back();
    const Real reached = last.step == 1 ? last.fraction * T : 0.0;
    std::printf("%s, T = %.2f mu N: %s, last converged tangential load %.6f (mu N = %.1f), friction force %.6f\n",
                method.c_str(), ratio, r.summary.completed ? "completed" : "gave up", reached, mu * N,
                r.summary.completed ? -r.checks[0].computed : 0.0);
    if (ratio < 1) {
      ASSERT_TRUE(r.summary.completed) << r.summary.failure;
      EXPECT_NEAR(r.checks[0].computed, -T, 1e-6 * T) << "the friction force balances the load";
      EXPECT_NEAR(r.checks[1].computed, N, 1e-6 * N);
    } else {
      EXPECT_FALSE(r.summary.completed) << "a load above mu N cannot be held";
      EXPECT_LE(reached, mu * N * (1 + 1e-9));
      EXPECT_GT(reached, 0.99 * mu * N) << "the onset of sliding is at mu N";
    }
  }
}

// The same block above mu N on a floor that turns (its angle an unknown, held at 0): the
// block slides away and the analysis gives up, as on a fixed floor. The floor's moment grows
// with the lever arm of the sliding block without bound; it must not enter the force scale of
// the convergence test (it did once: the slide "converged" at a displacement of 1e11).
TEST(Friction, BlockSlidesOffATurningFloorAboveMuN) {
  const Real mu = 0.3, N = 10, T = 1.05 * mu * N;
  const std::string step = "  - name: push\n"
                           "    increments: {initial: 0.1, max: 0.1, min: 1e-4}\n"
                           "    boundary:\n"
                           "      - {contact: floor, rotation: 0}\n"
                           "    loads:\n"
                           "      - {set: Top, pressure: 10}\n"
                           "      - {set: Top, traction: [" + std::to_string(T) + ", 0]}\n";
  std::string deck = block_deck(step);
  deck.replace(deck.find("{method: penalty}"), 17, "{method: lagrange}");
  test::HertzRun r = test::run_deck_text(deck, "friction_block_turning");
  const auto& last = r.summary.increments.back();
  const Real reached = last.step == 1 ? last.fraction * T : 0.0;
  EXPECT_FALSE(r.summary.completed) << "a load above mu N cannot be held";
  EXPECT_LE(reached, mu * N * (1 + 1e-9));
  EXPECT_GT(reached, 0.99 * mu * N) << "the onset of sliding is at mu N";
  // No equilibrium beyond mu N: pseudo-transient continuation, the last resort, is tried (at
  // most four attempts) and fails too, and the message says so.
  EXPECT_NE(r.summary.failure.find("pseudo-transient continuation failed too"), std::string::npos)
      << r.summary.failure;
  EXPECT_NE(r.summary.failure.find("failed too"), std::string::npos) << r.summary.failure;
}

TEST(Friction, AugmentedLagrangianSticksWithoutElasticSlip) {
  // The same block with the augmented Lagrangian at T = 0.95 mu N: the friction force equals
  // T, and the Uzawa updates remove the penalty's elastic slip of the sticking nodes (within
  // 1e-3 of the facet size, the gap tolerance).
  std::string deck = block_deck("  - name: push\n"
                                "    increments: {initial: 0.1, max: 0.1}\n"
                                "    loads:\n"
                                "      - {set: Top, pressure: 10}\n"
                                "      - {set: Top, traction: [2.85, 0]}\n");
  deck.replace(deck.find("{method: penalty}"), 17, "{method: augmented_lagrangian}");
  test::HertzRun r = test::run_deck_text(deck, "friction_al");
  ASSERT_TRUE(r.summary.completed) << r.summary.failure;
  EXPECT_NEAR(r.checks[0].computed, -2.85, 1e-6 * 2.85);
  int updates = 0;
  for (auto& inc : r.summary.increments) updates += inc.uzawa_updates;
  EXPECT_GT(updates, 0) << "no Uzawa update: the test checks nothing beyond penalty";
}

TEST(Friction, LagrangeMultipliersStickWithoutSlip) {
  // The block at T = 0.95 mu N with Lagrange multipliers (semi-smooth Newton on the
  // tangential complementarity function): the friction force equals T, and the sticking
  // nodes do not slip at all in the last increment (the penalty's elastic slip t / eps_T is
  // gone), while the penalty method gives them a slip of that order.
  const std::string step = "  - name: push\n"
                           "    increments: {initial: 0.1, max: 0.1}\n"
                           "    loads:\n"
                           "      - {set: Top, pressure: 10}\n"
                           "      - {set: Top, traction: [2.85, 0]}\n";
  Real stick_slip[2] = {0, 0};
  Index sticking[2] = {0, 0};
  int k = 0;
  for (const std::string method : {"lagrange", "penalty"}) {
    std::string text = block_deck(step);
    text.replace(text.find("{method: penalty}"), 17, "{method: " + method + "}");
    const std::filesystem::path tmp = std::filesystem::temp_directory_path() /
                                      ("signorini_friction_lm_" + method + std::to_string(::getpid()) + ".yaml");
    std::ofstream(tmp) << text;
    Registry reg = default_registry();
    Model m = read_deck(tmp.string(), reg);
    Analysis a(m);
    const AnalysisSummary s = a.run();
    std::filesystem::remove(tmp);
    ASSERT_TRUE(s.completed) << method << ": " << s.failure;
    const auto checks = evaluate_checks(a);
    EXPECT_NEAR(checks[0].computed, -2.85, 1e-6 * 2.85) << method;
    for (const auto& st : a.contacts()[0]->slave_states())
      if (st.status == 2) {
        ++sticking[k];
        stick_slip[k] = std::max(stick_slip[k], st.slip_increment);
      }
    ++k;
  }
  std::printf("largest slip of a sticking node in the last increment: lagrange %.3e (%lld nodes), penalty %.3e "
              "(%lld nodes)\n",
              stick_slip[0], (long long)sticking[0], stick_slip[1], (long long)sticking[1]);
  ASSERT_GT(sticking[0], 0) << "no sticking node: nothing checked";
  EXPECT_LT(stick_slip[0], 1e-12) << "a sticking node slipped (block of size 1)";
  EXPECT_GT(stick_slip[1], 1e3 * std::max(stick_slip[0], 1e-15)) << "penalty's elastic slip should be visible";
}

TEST(Friction, DraggedBlockFrictionForceIsMuN) {
  // The example itself: displacement-driven, all nodes slip at the end; its checks hold
  // (friction force mu N to 1e-6) and the force never exceeds mu N on the way.
  test::HertzRun r = test::run_deck_text(block_deck(
                                             "  - name: drag\n"
                                             "    increments: {initial: 0.05, max: 0.05}\n"
                                             "    boundary:\n"
                                             "      - {set: Top, ux: {ramp: [0, 0.02]}}\n"
                                             "    loads:\n"
                                             "      - {set: Top, pressure: 10}\n"),
                                         "friction_drag");
  ASSERT_TRUE(r.summary.completed) << r.summary.failure;
  for (auto& c : r.checks) EXPECT_TRUE(c.pass) << c.check.name << " " << c.computed;
  Index stick_seen = 0, stick_slip = 0;
  for (auto& inc : r.summary.increments)
    for (auto& c : inc.contact) {
      EXPECT_LE(std::abs(c.force(0)), 3 * (1 + 1e-9)) << "friction above mu N";
      stick_seen += c.sticking;
      stick_slip += c.stick_slip_changes;
      // The nodes that changed status are named (for the log), one per change.
      EXPECT_EQ(static_cast<Index>(c.changed_nodes.size()), c.changes + c.stick_slip_changes);
    }
  EXPECT_GT(stick_seen, 0) << "the block should stick before it slides";
  EXPECT_GT(stick_slip, 0) << "nodes go from stick to slip while the block is dragged";
  EXPECT_EQ(r.summary.increments.back().contact[0].sticking, 0) << "all nodes slip at the end";
}

TEST(Friction, LagrangeMultipliersOnASymmetryPlane) {
  // Klang's pin (examples/klang_pin, coarsened to 2 mm) with Lagrange multipliers: the slave
  // node on the load line (x = 0, ux fixed on both bodies) sits over the hole's node on that
  // line, so its tangential slip is prescribed (zero) but for sin(tilt) of the normal relative
  // displacement (the master facet next to the axis is tilted by half its chord angle). Without
  // releasing that tangential multiplier the stick row duplicates the normal constraint: the
  // node's status flips on round-off, the run cuts back and gives up at 62 % of the load. With
  // it, the run completes without cutback and the pressure at 0 degrees agrees with the
  // penalty method's on the same mesh.
  std::string base = example_deck("klang_pin");
  base.replace(base.find("h: 0.0005"), 9, "h: 0.002");
  Real p0[2] = {0, 0};
  int k = 0;
  for (const std::string method : {"lagrange", "penalty"}) {
    std::string deck = base;
    deck.replace(deck.find("{method: penalty}"), 17, "{method: " + method + "}");
    test::HertzRun r = test::run_deck_text(deck, "klang_" + method);
    ASSERT_TRUE(r.summary.completed) << method << ": " << r.summary.failure;
    int cutbacks = 0;
    for (auto& inc : r.summary.increments) cutbacks += inc.cutbacks;
    p0[k++] = r.checks[0].computed;  // the pressure at 0 degrees
    std::printf("%s: %d cutbacks, %d Newton iterations, pressure at 0 deg %.5e\n", method.c_str(), cutbacks,
                r.summary.total_iterations, r.checks[0].computed);
    if (method == "lagrange") {
      EXPECT_EQ(cutbacks, 0);
    }
  }
  EXPECT_NEAR(p0[0], p0[1], 0.01 * p0[1]);
}
