// The CalculiX harness's 3D Hertz deck (quarter sphere, C3D10, SURFACE TO SURFACE, LINEAR
// K = 1e8) runs unchanged: see tests/verification/test_calculix.cpp. About 45 s per run.
#include "calculix_runner.hpp"

using namespace signorini;
using signorini::test::compare;

// The load against CalculiX's on this deck and mesh (the harness's results/sbs.md, row
// h3d_coarse_s2s: P = 2322.5 N), within 0.2 %. The peak nodal pressure is not compared with
// Hertz here: segment_to_segment's nodal pressures on tet10 facets at a/h = 5 swing between
// corner and mid-side nodes (measured +65 % at the peak; issue 14, docs/contact.md).
TEST(CalculixDeckLong, Hertz3dTet10SurfaceToSurface) {
  const auto c = compare("h3d", "hertz3d_coarse_c3d10.inp", true,
                         "discretization: segment_to_segment, enforcement: {method: penalty, penalty: 1e8}");
  EXPECT_NEAR(c.load, 2322.5, 2e-3 * 2322.5);
}
