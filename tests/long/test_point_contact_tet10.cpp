// The force-controlled point contact family on quadratic tetrahedra (label `long`: 20-30 s per
// row): examples/hertz_sphere_3d raised to tet10 at hc = 0.04, 3D mortar on tri6 slave facets,
// the force in one increment (tests/point_contact.hpp; validation.md, "Force-controlled point
// contact"). Before the Newton step's penetration limit the row at the example's force cut
// back once and took 211 s; with it, 7 iterations and 24 s.
#include <gtest/gtest.h>

#include "point_contact.hpp"

using namespace signorini;

TEST(ForceControlledPointContactLong, Tet10SphereWithMortarInOneIncrement) {
  for (Real load : {0.2, 1.0, 5.0}) {
    test::SphereCase c{"    discretization: mortar\n", load};
    c.hc = 0.04;
    c.order = 2;
    test::expect_point_contact(c, 10);
  }
}
