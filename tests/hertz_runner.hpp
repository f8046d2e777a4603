// Runs a shipped Hertz example deck with another contact element size, and returns the
// deck's checks (p0, a, force) with the Newton residual history. Shared by the verification
// test and the long refinement study.
#pragma once
#include <filesystem>
#include <limits>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "deck_text.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/io/results_writer.hpp"

namespace signorini::test {

struct HertzRun {
  std::vector<CheckResult> checks;
  AnalysisSummary summary;
  Vec3 obstacle_displacement = Vec3::Zero();  // of the last rigid obstacle, if any
  Real min_closed_pressure = 0;                // the smallest written pressure of a closed slave node
  std::vector<std::pair<Vec3, Real>> closed;   // each closed slave node: reference position, written pressure
  Index unknowns = 0;                          // of the linear systems (displacements and multipliers)
};

// `example`: folder under examples/; the deck's "hc: <value>" is replaced by `hc`.
// Writes a deck to a temporary file of its own (tests run in parallel processes), reads it,
// solves it and evaluates its checks.
inline HertzRun run_deck_text(const std::string& deck, const std::string& stem) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  static int counter = 0;
  const fs::path tmp = fs::temp_directory_path() / ("signorini_" + stem + "_" + std::to_string(::getpid()) + "_" +
                                                     std::to_string(counter++) + ".yaml");
  std::ofstream(tmp) << deck;
  Registry r = default_registry();
  Model m = read_deck(tmp.string(), r);
  Analysis a(m);
  HertzRun out;
  out.summary = a.run();
  out.unknowns = a.num_unknowns();
  out.checks = evaluate_checks(a);
  for (auto& c : a.contacts())
    if (c->rigid()) out.obstacle_displacement = a.obstacle_displacement(*c);
  out.min_closed_pressure = std::numeric_limits<Real>::infinity();
  for (auto& c : a.contacts())
    for (const auto& ns : c->slave_states())
      if (ns.status == ContactInterface::closed) {
        out.min_closed_pressure = std::min(out.min_closed_pressure, ns.pressure);
        out.closed.emplace_back(a.model().mesh.nodes[ns.node], ns.pressure);
      }
  fs::remove(tmp);
  return out;
}

// A deck's text with its mesh path made absolute, since the temporary deck lives elsewhere.
inline std::string deck_text(const std::filesystem::path& src) {
  std::ifstream in(src);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string deck = ss.str();
  deck.insert(deck.find("file: ") + 6, (src.parent_path() / "").string());
  return deck;
}

// A shipped example's deck (examples/<example>/<example>.yaml), its mesh path absolute.
inline std::string example_deck_text(const std::string& example) {
  return deck_text(std::filesystem::path(SIGNORINI_SOURCE_DIR) / "examples" / example / (example + ".yaml"));
}

// `enforcement` (optional: deck lines, e.g. "enforcement: {method: penalty}\n    discretization:
// mortar") replaces the deck's "enforcement: {method: lagrange}", or goes after the first
// pair's name where the deck has none; `order` > 0 raises the mesh to that order.
inline HertzRun run_hertz(const std::string& example, Real hc, const std::string& enforcement = "", int order = 0) {
  std::string deck = example_deck_text(example);
  const size_t p = deck.find("hc: ");
  const size_t e = deck.find_first_of(",}", p);
  deck.replace(p, e - p, "hc: " + std::to_string(hc));
  if (order > 0) deck.insert(deck.find('}', p) + 1, ", order: " + std::to_string(order));
  if (!enforcement.empty()) {
    const size_t q = deck.find("enforcement: {method: lagrange}");
    if (q != std::string::npos) {
      deck.replace(q, std::string("enforcement: {method: lagrange}").size(), enforcement);
    } else {
      // A deck without that key (the default enforcement): the lines go after the first
      // pair's name.
      const size_t c = deck.find("contact:\n  - name: ");
      const size_t eol = c == std::string::npos ? c : deck.find('\n', c + 9);
      EXPECT_NE(eol, std::string::npos) << example << ": no place for '" << enforcement << "'";
      if (eol != std::string::npos) deck.insert(eol, "\n    " + enforcement);
    }
  }
  return run_deck_text(deck, example);
}

// Convergence order from the last three relative residuals above round-off (1e-12: the
// relative residual of these models floors at 1e-15..1e-13, and a last value there says
// nothing about the order).
inline Real newton_order(const std::vector<Real>& res) {
  for (size_t k = res.size() - 2; res.size() >= 3 && k >= 1; --k)
    if (res[k + 1] > 1e-12 && res[k] < 1e-2) return std::log(res[k + 1] / res[k]) / std::log(res[k] / res[k - 1]);
  return 0;
}

// The contraction of the last Newton step, C = r_n / r_{n-1}^2 with r the relative residuals:
// bounded for quadratic convergence (r_n <= C r_{n-1}^2), and = rate / r_{n-1} for a linear
// one, so with r_{n-1} <= 1e-5 a bound C <= 1e3 excludes linear rates above 1e-2. It needs
// only the last two residuals: with few iterations (a nearly linear problem, the step
// before the last still carrying an active-set change), the three-point order above is
// not yet asymptotic (measured on the axisymmetric Hertz sphere: residuals 8.6e-4, 2.1e-7,
// 7.3e-12, order 1.23, C 170).
inline Real newton_contraction(const std::vector<Real>& res) {
  if (res.size() < 2) return std::numeric_limits<Real>::infinity();
  const Real prev = res[res.size() - 2], last = res.back();
  return last / (prev * prev);
}

}  // namespace signorini::test
