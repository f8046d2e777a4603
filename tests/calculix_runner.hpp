// Runs the CalculiX harness decks (issue 17, item 1): the Hertz decks of the CalculiX harness
// (../shared/peers/calculix-hertz, scripts/make_deck.py; copied byte for byte under
// tests/data/calculix/runs with the coarse meshes its mesh2d.py / mesh3d.py write) give the
// same contact pressure as the YAML deck that says the same thing, and the pressure agrees
// with Hertz (Johnson 1985, eqs. 4.43 and 4.45 for the cylinder, 3.39-3.41 for the sphere;
// the harness's common.py) from the reaction Signorini computes.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"


namespace signorini::test {

namespace fs = std::filesystem;

inline const fs::path kData = fs::path(SIGNORINI_TEST_DATA) / "calculix";
constexpr Real kEstar = 200000.0 / (2 * (1 - 0.3 * 0.3));  // both bodies E = 200 GPa (MPa), nu = 0.3

struct Result {
  std::map<Index, Real> pressure;  // mesh node id -> pressure
  Real reaction = 0;               // on NTOP, along the load
  bool completed = false;
  AnalysisSummary summary;
};

inline Result run(const std::string& deck_path, int load_axis) {
  Registry r = default_registry();
  Model m = read_deck(deck_path, r);
  Analysis a(m);
  Result out;
  out.summary = a.run();
  out.completed = out.summary.completed;
  for (auto& c : a.contacts())
    for (const auto& ns : c->slave_states()) out.pressure[m.mesh.node_ids[ns.node]] = ns.pressure;
  out.reaction = std::abs(a.reaction_sum("NTOP")(load_axis));
  return out;
}

// The YAML deck saying what the harness's job.inp says (make_sig_deck.py's deck with the
// contact settings of the .inp), on the same .inp mesh.
inline std::string yaml_route(const std::string& mesh, bool three_d, const std::string& contact) {
  std::string d = "title: the same problem in YAML\n";
  d += three_d ? "analysis: {dimension: 3d}\n" : "analysis: {dimension: plane_strain, thickness: 1}\n";
  d += "mesh: {file: " + (kData / "meshes" / mesh).string() + "}\n";
  d += "materials:\n  steel: {model: linear_elastic, E: 200000, nu: 0.3}\n";
  d += std::string("bodies:\n  - {name: indenter, region: ") + (three_d ? "SPH" : "CYL") + ", material: steel}\n";
  d += "  - {name: block, region: BLOCK, material: steel}\n";
  d += "contact:\n  - {name: hertz, slave: SLAVE, master: MASTER, " + contact + "}\n";
  d += "steps:\n  - name: press\n    boundary:\n";
  if (three_d)
    d += "      - {set: NSYMX, ux: 0}\n      - {set: NSYMY, uy: 0}\n      - {set: NBOT, uz: 0}\n"
         "      - {set: NTOP, uz: -0.031}\n";
  else
    d += "      - {set: NSYM, ux: 0}\n      - {set: NBOT, uy: 0}\n      - {set: NTOP, uy: -0.0662}\n";
  return d;
}

// The YAML route of yaml_route run from a temporary file (`tag` names it).
inline Result run_yaml(const std::string& tag, const std::string& mesh, bool three_d, const std::string& contact) {
  const fs::path yaml = fs::temp_directory_path() / ("signorini_calculix_" + tag + "_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(yaml) << yaml_route(mesh, three_d, contact);
  Result r = run(yaml.string(), three_d ? 2 : 1);
  fs::remove(yaml);
  return r;
}

// Hertz's peak pressure for the total load P of the whole sphere (3D) or of the whole
// cylinder per unit length (2D), R = 8 (Johnson 1985, eqs. 3.39-3.41, 4.43, 4.45).
inline Real hertz_p0(Real P, bool three_d) {
  if (three_d) {
    const Real a = std::cbrt(3 * P * 8.0 / (4 * kEstar));
    return 3 * P / (2 * M_PI * a * a);
  }
  const Real a = std::sqrt(4 * P * 8.0 / (M_PI * kEstar));
  return 2 * P / (M_PI * a);
}

// The largest nodal contact pressure of a run.
inline Real peak_pressure(const Result& r) {
  Real peak = 0;
  for (const auto& [node, p] : r.pressure) peak = std::max(peak, p);
  return peak;
}

// The peak pressure's error against Hertz's p0 (relative) and the total load P of the
// whole cylinder (per unit length) or sphere.
struct Comparison {
  Real peak_error = 0;
  Real load = 0;
};

inline Comparison compare(const std::string& run_dir, const std::string& mesh, bool three_d, const std::string& contact) {
  log::set_level(log::Level::warning);
  const Result inp = run((kData / "runs" / run_dir / "job.inp").string(), three_d ? 2 : 1);
  const Result ref = run_yaml(run_dir, mesh, three_d, contact);
  EXPECT_TRUE(inp.completed && ref.completed) << run_dir;
  EXPECT_EQ(inp.pressure.size(), ref.pressure.size()) << run_dir;
  Real pmax = 0, diff = 0;
  for (auto& [node, p] : ref.pressure) {
    pmax = std::max(pmax, p);
    auto it = inp.pressure.find(node);
    if (it == inp.pressure.end()) {
      ADD_FAILURE() << run_dir << ": node " << node << " is not a slave node of the .inp run";
      continue;
    }
    diff = std::max(diff, std::abs(it->second - p));
  }
  EXPECT_LE(diff, 1e-8 * pmax) << run_dir << ": the .inp and the YAML deck disagree";
  EXPECT_NEAR(inp.reaction, ref.reaction, 1e-8 * ref.reaction) << run_dir;
  // Hertz from the reaction: the 2D model is half the cylinder, the 3D one a quarter sphere.
  const Real P = (three_d ? 4 : 2) * inp.reaction;
  const Real p0 = hertz_p0(P, three_d);
  const Real peak = peak_pressure(inp);
  std::printf("%s: .inp vs YAML max pressure difference %.3g of the peak; load P %.6g; peak %.6g against Hertz p0 "
              "%.6g (%+.3f %%)\n",
              run_dir.c_str(), diff / pmax, P, peak, p0, 100 * (peak / p0 - 1));
  return {peak / p0 - 1, P};
}

}  // namespace signorini::test

