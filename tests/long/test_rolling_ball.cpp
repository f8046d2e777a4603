// examples/rolling_ball and rolling_rigid_ball at their own resolution (0.2 mm tetrahedra) and
// increments: the rigid ball (analytic, meshed) rolled, twisted and eased in 3D, against the
// references of tests/rolling_ball.hpp with the twist's moment within 6 % of the full-slip
// moment.
#include "rolling_ball.hpp"

using namespace signorini;

TEST(RigidRotation, BallRollsTwistsAndEasesIn3DOnTheExampleMesh) {
  test::check_ball("rolling_ball", test::analytic_ball(), 0.2, "hc: 0.2", 0.0, 0.06);
}

TEST(RigidRotation, MeshedRigidBallRollsTwistsAndEasesOnTheExampleMesh) {
  test::check_ball("rolling_rigid_ball", test::meshed_ball(), 0.2, "hc: 0.2, hb: 0.2", 0.0, 0.06);
}
