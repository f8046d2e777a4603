// CalculiX decks run unchanged (issue 17, item 1): the harness's 2D Hertz decks; see
// calculix_runner.hpp for what is compared and the references.
#include "calculix_runner.hpp"

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
