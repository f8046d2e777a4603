// Large sliding at finite strain (node-to-segment): a Neo-Hookean block (slave, 20 facets of
// 0.05) pressed on a Neo-Hookean foundation whose top (master) has facets of 0.1, then dragged
// by its top 3.0 to the right, frictionless, in ONE increment: every slave node crosses 30
// master facets in that Newton solve. On a flat foundation far from its ends the result must
// be the pressed state translated by 3: no node lets go or jumps, every gap is closed, and
// each node's pressure and position match the pressed state's (up to the foundation's end
// effects, which differ by the block's distance to the ends).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "hertz_runner.hpp"

using namespace signorini;

namespace {

std::string sliding_deck(bool slide) {
  std::string deck = std::string("title: block sliding 30 master facets in one increment\n"
                                 "analysis: {dimension: plane_strain, kinematics: finite_strain}\n"
                                 "mesh: {file: ") +
                     SIGNORINI_TEST_DATA +
                     "/sliding_block.geo}\n"
                     "materials:\n"
                     "  soft: {model: neo_hookean, E: 1000, nu: 0.3}\n"
                     "bodies:\n"
                     "  - {name: block, region: Block, material: soft}\n"
                     "  - {name: foundation, region: Foundation, material: soft}\n"
                     "contact:\n"
                     "  - name: slide\n"
                     "    master: FoundationTop\n"
                     "    slave: BlockBottom\n"
                     "    enforcement: {method: lagrange}\n"
                     "    search: {method: bucket_grid, update: iteration}\n"
                     "output: {vtu: none}\n"
                     "steps:\n"
                     "  - name: press\n"
                     "    boundary:\n"
                     "      - {set: FoundationBottom, u: [0, 0]}\n"
                     "      - {set: BlockTop, ux: 0}\n"
                     "    loads:\n"
                     "      - {set: BlockTop, pressure: 20}\n";
  if (slide)
    deck += "  - name: slide\n"
            "    increments: {initial: 1, max: 1}\n"
            "    boundary:\n"
            "      - {set: FoundationBottom, u: [0, 0]}\n"
            "      - {set: BlockTop, ux: {ramp: [0, 3]}}\n"
            "    loads:\n"
            "      - {set: BlockTop, pressure: 20}\n";
  return deck;
}

struct SlaveResult {
  std::vector<ContactInterface::SlaveState> states;
  std::vector<Real> ux;  // per state: the slave node's horizontal displacement
  AnalysisSummary summary;
};

SlaveResult run(bool slide) {
  const std::filesystem::path tmp = std::filesystem::temp_directory_path() /
                                    ("signorini_sliding_" + std::to_string(slide) + "_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(tmp) << sliding_deck(slide);
  log::set_level(log::Level::warning);
  Registry reg = default_registry();
  Model m = read_deck(tmp.string(), reg);
  Analysis a(m);
  SlaveResult r;
  r.summary = a.run();
  std::filesystem::remove(tmp);
  r.states = a.contacts()[0]->slave_states();
  for (const auto& st : r.states) r.ux.push_back(a.displacement()(a.dofs().dof(st.node, 0)));
  return r;
}

}  // namespace

TEST(LargeSliding, NeoHookeanBlockCrosses30MasterFacetsInOneIncrement) {
  const SlaveResult pressed = run(false), slid = run(true);
  ASSERT_TRUE(pressed.summary.completed) << pressed.summary.failure;
  ASSERT_TRUE(slid.summary.completed) << slid.summary.failure;
  // The slide is one increment, without cutback, in a few Newton iterations.
  const auto& last = slid.summary.increments.back();
  ASSERT_EQ(last.step, 1);
  EXPECT_EQ(last.increment, 1) << "the slide took more than one increment";
  EXPECT_EQ(last.cutbacks, 0);
  EXPECT_LE(last.iterations, 10);
  std::printf("slide of 3.0 (30 master facets): %d Newton iterations, %lld slave nodes closed\n", last.iterations,
              (long long)last.contact[0].active);
  ASSERT_EQ(pressed.states.size(), slid.states.size());
  Real mean_p = 0;
  for (const auto& st : pressed.states) mean_p += st.pressure / pressed.states.size();
  ASSERT_GT(mean_p, 10.0);
  Real worst_p = 0, worst_x = 0;
  for (size_t k = 0; k < slid.states.size(); ++k) {
    const auto &a = pressed.states[k], &b = slid.states[k];
    ASSERT_EQ(a.node, b.node);
    EXPECT_EQ(b.status, 2) << "slave node " << b.node << " is not closed after the slide";
    EXPECT_LT(std::abs(b.gap), 1e-9) << "node " << b.node;
    worst_p = std::max(worst_p, std::abs(b.pressure - a.pressure) / mean_p);
    worst_x = std::max(worst_x, std::abs(slid.ux[k] - pressed.ux[k] - 3.0));
  }
  std::printf("against the pressed state: pressure within %.2e of the mean pressure, positions within %.2e\n", worst_p,
              worst_x);
  EXPECT_LT(worst_p, 1e-3) << "the pressures changed: a node jumped or the sliding lost contact";
  EXPECT_LT(worst_x, 1e-4) << "the block did not translate by 3";
}
