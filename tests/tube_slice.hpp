// examples/tube_crush_3d against examples/tube_crush (3D self-contact), shared by the default
// suite's coarse run (verification/test_self_contact.cpp) and the long run on the example's
// own mesh (long/test_tube_crush_3d.cpp).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "example_deck.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"

// 3D self-contact: examples/tube_crush_3d, the same ring as a slice one layer of hexahedra
// deep, its faces held in z, crushed by two rigid cylinders until its inner wall folds: the 3D
// self-contact search (facets facing each node, own and neighbouring facets excluded), the
// node-to-segment constraints on quadrilateral facets and their tributary areas must give the
// plane strain ring's answer per unit depth. Checks: at every closure both runs reached (most
// increments; a status that round-off decides, a node at zero gap, may cut one run back and
// not the other) the same bar force as the plane strain run (1e-8) and as many closed fold
// nodes as the plane strain run times the slice's layers of nodes; the same end; in every
// increment no penetration, equilibrium to 1e-8 (the bars, the symmetry plane) and the fold's
// net force zero. Coarse (linear cells, 24 and 20
// along the wall) in the default suite; the example's own quadratic mesh in the long suite.
namespace signorini::test {

inline const ContactInterface& tube_pair(const Analysis& a, const std::string& name) {
  for (const auto& c : a.contacts())
    if (c->settings().name == name) return *c;
  throw std::runtime_error("no pair " + name);
}

struct TubeSample {
  Real closure = 0, force = 0, worst_gap = 0, balance = 0, internal = 0;
  Index fold_closed = 0;
  Real peak_pressure = 0;  // the fold's largest reported pressure
};

// The example run (`fold`: another entry for the fold pair, e.g. with mortar), one sample per
// increment.
inline std::vector<TubeSample> crush_tube(const std::string& example, const std::string& parameters,
                                          const std::string& fold_entry = "") {
  log::set_level(log::Level::warning);
  const ExampleDeck ex = example_deck_with(example, parameters);
  const std::string entry = "{name: fold, surface: Inner, self: true}";
  if (!fold_entry.empty()) {
    EXPECT_TRUE(replace_in_deck(ex, entry, fold_entry)) << "no fold entry " << entry << " in the example";
  }
  Registry r = default_registry();
  Model m = read_deck(ex.deck.string(), r);
  m.output.vtu = "none";
  m.output.directory = (ex.dir / "results").string();
  Analysis a(m);
  std::vector<TubeSample> out;
  a.on_increment([&](const Analysis& an, const IncrementRecord&) {
    const ContactInterface &top = tube_pair(an, "top"), &bottom = tube_pair(an, "bottom"), &fold = tube_pair(an, "fold");
    TubeSample s;
    s.closure = -2 * an.obstacle_displacement(top).y();
    s.force = an.obstacle_reaction(top).y();
    const Real scale = std::max(std::abs(s.force), 1e-300);
    s.balance = std::abs(s.force + an.obstacle_reaction(bottom).y() + an.reaction_sum("Mid").y()) / scale;
    s.internal = fold.slave_force().norm() / scale;
    for (size_t j = 0; j < fold.constraints().size(); ++j) {
      if (fold.constraints()[j].kind == ConstraintKind::none) continue;
      s.worst_gap = std::min(s.worst_gap, fold.constraints()[j].gap);
      s.fold_closed += fold.state().active[j] ? 1 : 0;
    }
    for (const ContactInterface::SlaveState& st : fold.slave_states()) s.peak_pressure = std::max(s.peak_pressure, st.pressure);
    out.push_back(s);
  });
  const AnalysisSummary sum = a.run();
  std::filesystem::remove_all(ex.dir);
  EXPECT_TRUE(sum.completed) << example << ": " << sum.failure;
  return out;
}

inline void compare_tube_slice_with_plane_strain(const std::string& parameters, int node_layers) {
  const std::vector<TubeSample> plane = crush_tube("tube_crush", parameters), slice = crush_tube("tube_crush_3d", parameters);
  // Increments are compared where both runs reached the same closure: a status decided by
  // round-off (a node at zero gap) may cut one run's increment back and not the other's.
  ASSERT_FALSE(plane.empty());
  ASSERT_FALSE(slice.empty());
  EXPECT_NEAR(slice.back().closure, plane.back().closure, 1e-12) << "both reach the end";
  Real worst_force = 0, worst_gap = 0, worst_balance = 0, worst_internal = 0;
  Index fold_closed = 0, matched = 0;
  for (const TubeSample& t : slice) {
    worst_gap = std::min(worst_gap, t.worst_gap);
    worst_balance = std::max(worst_balance, t.balance);
    worst_internal = std::max(worst_internal, t.internal);
    fold_closed = std::max(fold_closed, t.fold_closed);
    for (const TubeSample& p : plane)
      if (std::abs(p.closure - t.closure) < 1e-12) {
        ++matched;
        worst_force = std::max(worst_force, std::abs(t.force - p.force) / std::abs(plane.back().force));
        EXPECT_EQ(t.fold_closed, node_layers * p.fold_closed) << "at a closure of " << t.closure;
      }
  }
  EXPECT_GE(2 * matched, static_cast<Index>(plane.size())) << "most increments at the same closures";
  std::printf("3D slice against plane strain (%s): %zu and %zu increments, %lld at the same closure; final bar force "
              "%.8g against %.8g N per mm of depth (worst difference %.1e of it); up to %lld closed fold nodes; deepest "
              "fold gap %.2e mm; balance %.1e, fold's net force %.1e\n",
              parameters.empty() ? "the example's mesh" : parameters.c_str(), slice.size(), plane.size(),
              (long long)matched, slice.back().force, plane.back().force, worst_force, (long long)fold_closed, worst_gap,
              worst_balance, worst_internal);
  EXPECT_GT(fold_closed, 0) << "the inner wall never touched itself";
  EXPECT_LT(worst_force, 1e-8);
  EXPECT_GT(worst_gap, -1e-9 * 10);
  EXPECT_LT(worst_balance, 1e-8);
  EXPECT_LT(worst_internal, 1e-8);
}

// Self-contact with mortar: the tube with its fold as dual mortar (`method`: penalty or
// augmented_lagrangian), against the same tube with node-to-segment and Lagrange multipliers
// (the example's fold), on the same mesh. Checks: the same end; the final bar force within
// `force_tolerance` of node-to-segment's (the augmented Lagrangian: the discretizations differ,
// both exact in the gap; penalty: its penetration softens the fold); the fold closes and takes
// a good part of the bars' load; in every increment equilibrium to 1e-8 (the bars and the
// symmetry plane) and the fold's net force zero to 1e-8 (each weighted gap's gradient sums to
// zero over its nodes); its deepest weighted gap above -max_penetration; the final peak
// reported pressure (a nodal force over its weight) within `pressure_tolerance` of
// node-to-segment's (a peak on a few closed nodes: a looser check than the force).
// `csv`: a file name in build/curves/ for both runs' bar force against closure
// (examples/tube_crush/plot.py).
// `friction`: a friction entry for both folds (e.g. "friction: {law: coulomb, mu: 0.3}").
// `example`: tube_crush (plane strain) or tube_crush_3d (the slice).
inline void compare_mortar_fold(const std::string& parameters, const std::string& method, Real force_tolerance,
                                Real max_penetration, Real pressure_tolerance, const std::string& csv = "",
                                const std::string& friction = "", const std::string& example = "tube_crush") {
  const std::string extra = friction.empty() ? "" : ", " + friction;
  const std::vector<TubeSample> nts = crush_tube(example, parameters,
                                                 friction.empty() ? "" : "{name: fold, surface: Inner, self: true" + extra + "}"),
                                mortar = crush_tube(example, parameters,
                                                    "{name: fold, surface: Inner, self: true, discretization: mortar, "
                                                    "enforcement: {method: " + method + "}" + extra + "}");
  ASSERT_FALSE(nts.empty());
  ASSERT_FALSE(mortar.empty());
  EXPECT_NEAR(mortar.back().closure, nts.back().closure, 1e-12) << "both reach the end";
  auto touch = [](const std::vector<TubeSample>& run) {
    for (const TubeSample& t : run)
      if (t.fold_closed > 0) return t.closure;
    return -1.0;
  };
  Real worst_gap = 0, worst_balance = 0, worst_internal = 0;
  Index fold_closed = 0;
  for (const TubeSample& t : mortar) {
    worst_gap = std::min(worst_gap, t.worst_gap);
    worst_balance = std::max(worst_balance, t.balance);
    worst_internal = std::max(worst_internal, t.internal);
    fold_closed = std::max(fold_closed, t.fold_closed);
  }
  const Real force = std::abs(mortar.back().force), reference = std::abs(nts.back().force);
  std::printf("%s: fold as mortar (%s, %s%s) against node_to_segment: %zu and %zu increments; final bar force %.6g against "
              "%.6g N/mm (%+.3f %%); fold closed at a closure of %.4g against %.4g mm, up to %lld closed nodes; final "
              "peak pressure %.4g against %.4g MPa; deepest weighted gap %.2e mm; balance %.1e, fold's net force %.1e\n",
              example.c_str(), parameters.empty() ? "the example's mesh" : parameters.c_str(), method.c_str(), extra.c_str(),
              mortar.size(),
              nts.size(),
              force, reference, 100 * (force / reference - 1), touch(mortar), touch(nts), (long long)fold_closed,
              mortar.back().peak_pressure, nts.back().peak_pressure, worst_gap, worst_balance, worst_internal);
  if (!csv.empty()) {
    const std::filesystem::path dir = std::filesystem::path(SIGNORINI_BINARY_DIR) / "curves";
    std::filesystem::create_directories(dir);
    std::ofstream out(dir / csv);
    out << "discretization,closure,force\n";
    for (const TubeSample& t : nts) out << "node_to_segment," << t.closure << "," << 2 * std::abs(t.force) << "\n";
    for (const TubeSample& t : mortar) out << "mortar," << t.closure << "," << 2 * std::abs(t.force) << "\n";
  }
  EXPECT_NEAR(force, reference, force_tolerance * reference);
  EXPECT_NEAR(mortar.back().peak_pressure, nts.back().peak_pressure, pressure_tolerance * nts.back().peak_pressure);
  EXPECT_GT(fold_closed, 0) << "the inner wall never touched itself";
  EXPECT_GT(touch(mortar), 0);
  EXPECT_GT(worst_gap, -max_penetration);
  EXPECT_LT(worst_balance, 1e-8);
  EXPECT_LT(worst_internal, 1e-8);
}

}  // namespace signorini::test

