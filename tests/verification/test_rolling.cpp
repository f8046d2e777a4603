// A rigid roller that turns (issue 16: rigid bodies that rotate): the example
// `rolling_cylinder`, a rigid cylinder (R = 10 mm) pressed into an elastic block (steel, plane
// strain, Coulomb mu = 0.3) and rolled by prescribing its angle, its horizontal translation free;
// and `rolling_rigid_mesh`, the same roller as a meshed rigid body turning about its reference
// node. Both against the same references:
// - press: Hertz's half-width for a rigid cylinder on an elastic half-space, a^2 = 4 P R /
//   (pi E*), E* = E / (1 - nu^2) (Johnson, Contact Mechanics, 1985, eq. 4.43 with a rigid
//   body), from the computed P, within 5 % (nodes 0.05 mm apart, a = 0.62 mm);
// - roll (free rolling, no horizontal force): the roller advances R times its turn but for a
//   creep smaller than mu a / R (no gross slip; a rigid roller on steel creeps in free rolling,
//   Dundurs' beta = -0.29 couples the pressure to tangential tractions: Johnson 1985, sec.
//   8.2), most of the patch sticks, and the moment that turns it is next to nothing (below
//   1e-3 of P R: an elastic body has no rolling resistance);
// - hold_back and drive (a horizontal force Q = 1000 N/mm, Q / (mu P) = 0.50, holds it back;
//   the contact force on the block balances it, the deck's check):
//   the reaction moment equals the moment of the contact forces about the roller's centre to
//   1e-6 (the turning unknown's equilibrium; exact), and Q R within 3 % (the normal forces pass
//   through the centre; their horizontal part, the patch's small offset, makes the difference);
//   against free rolling the roller advances less per turn: the creep is negative, and of
//   the size of Carter's xi = -(mu a / R)(1 - sqrt(1 - Q/(mu P))) (Carter 1926; Johnson 1985,
//   sec. 8.4) within 35 % (Carter's theory is for elastically similar bodies; a rigid roller
//   on steel couples normal and tangential tractions).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>

#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"
#include "rolling_ball.hpp"

using namespace signorini;

namespace {

struct Sample {
  int step = 0;
  Real ux = 0, theta = 0, moment = 0, contact_moment = 0, Qx = 0, P = 0, half_width = 0;
  int stick = 0, slip = 0;
};

// The roller's translation, angle, reaction moment and centre: an analytic obstacle's or a
// meshed rigid body's.
struct RollerView {
  std::function<Real(const Analysis&)> ux, theta, moment;
  std::function<Vec3(const Analysis&)> centre;
};

void check_roller(const std::string& example, const RollerView& view, Real creep_tolerance) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  Registry r = default_registry();
  Model m = read_deck((fs::path(SIGNORINI_SOURCE_DIR) / "examples" / example / (example + ".yaml")).string(), r);
  m.output.vtu = "none";
  const Real R = 10, E = 200e3, nu = 0.3, mu = 0.3, Q = 1000;
  const Real Estar = E / (1 - nu * nu);
  Analysis a(m);
  std::vector<Sample> samples;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    const ContactInterface& c = *an.contacts()[0];
    Sample s;
    s.step = rec.step;
    s.ux = view.ux(an);
    s.theta = view.theta(an);
    s.moment = view.moment(an);
    // The contact force on each slave node, w (p n - t) (ContactInterface::slave_force), and
    // the moment of these forces about the roller's centre.
    const Vec3 centre = view.centre(an);
    const std::vector<Vec3> x = an.positions(an.displacement());
    Real xmin = 1e300, xmax = -1e300;
    for (size_t j = 0; j < c.constraints().size(); ++j) {
      const Constraint& k = c.constraints()[j];
      if (k.kind == ConstraintKind::none || !c.state().active[j]) continue;
      const Vec3 f = k.weight * (c.state().pressure[j] * k.normal - c.state().traction[j]);
      const Index n = k.slave;
      s.contact_moment += (x[n] - centre).cross(f).z();
      s.Qx += f.x();
      s.P += f.y();
      {
        xmin = std::min(xmin, x[n].x()), xmax = std::max(xmax, x[n].x());
        (c.state().slip[j] ? s.slip : s.stick) += 1;
      }
    }
    s.half_width = (xmax - xmin) / 2 + 0.05 / 2;  // to midway between the outermost closed node and the next
    samples.push_back(s);
  });
  const AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  auto last_of = [&](int step) {
    Sample s;
    for (const Sample& x : samples)
      if (x.step == step) s = x;
    return s;
  };
  // Press.
  const Sample press = last_of(0);
  const Real P = std::abs(press.P);
  const Real a_hertz = std::sqrt(4 * P * R / (M_PI * Estar));
  std::printf("press: P = %.1f N/mm, half-width %.4f mm, Hertz %.4f (%+.1f %%)\n", P, press.half_width, a_hertz,
              100 * (press.half_width / a_hertz - 1));
  EXPECT_NEAR(press.half_width, a_hertz, 0.05 * a_hertz);
  // The creep ratio in the second half of a step (steady rolling): advance / (R turn) - 1.
  auto creep_of = [&](int step) {
    std::vector<Sample> d;
    for (const Sample& x : samples)
      if (x.step == step) d.push_back(x);
    EXPECT_GE(d.size(), 6u);
    const Sample &s0 = d[d.size() / 2], &s1 = d.back();
    return (s1.ux - s0.ux) / (-(s1.theta - s0.theta) * R) - 1;
  };
  // Free rolling.
  const Sample roll = last_of(1);
  const Real turn = -(roll.theta - press.theta), free_creep = creep_of(1);
  std::printf("roll: turned %.4f rad, advanced %.5f mm, creep %.5f (mu a / R = %.5f); moment %.3g N mm/mm (%.2e of "
              "P R); %d stick, %d slip\n",
              turn, roll.ux - press.ux, free_creep, mu * a_hertz / R, roll.moment, std::abs(roll.moment) / (P * R),
              roll.stick, roll.slip);
  EXPECT_NEAR(turn, 0.3, 1e-12);
  EXPECT_LT(std::abs(free_creep), mu * a_hertz / R) << "gross slip";
  EXPECT_GT(roll.stick, roll.slip) << "free rolling sticks over most of the patch";
  EXPECT_LT(std::abs(roll.moment), 1e-3 * P * R);
  // Driven against Q.
  Real worst = 0;
  for (const Sample& s : samples)
    if (s.step >= 2) worst = std::max(worst, std::abs(s.moment - s.contact_moment) / std::abs(s.moment));
  const Sample drive = last_of(3);
  std::printf("drive: reaction moment %.2f, moment of the contact forces %.2f (balance %.1e), Q R = %.1f (%+.2f %%); "
              "%d stick, %d slip\n",
              drive.moment, drive.contact_moment, worst, Q * R, 100 * (std::abs(drive.moment) / (Q * R) - 1), drive.stick,
              drive.slip);
  EXPECT_LT(worst, 1e-6);
  EXPECT_NEAR(drive.Qx, -Q, 1e-5 * Q) << "the contact force on the block holds the roller against Q";
  EXPECT_NEAR(std::abs(drive.moment), Q * R, 0.03 * Q * R);
  // Creep of the driven roller against free rolling (steady, the second half of each step).
  const Real creep = creep_of(3) - free_creep;
  const Real carter = -(mu * a_hertz / R) * (1 - std::sqrt(1 - Q / (mu * P)));
  std::printf("creep against free rolling %.5f, Carter %.5f (%+.0f %%)\n", creep, carter, 100 * (creep / carter - 1));
  EXPECT_LT(creep, 0);
  EXPECT_NEAR(creep, carter, creep_tolerance * std::abs(carter));
  // The curves for docs/validation.md (examples/rolling_cylinder/plot.py).
  const fs::path dir = fs::path(SIGNORINI_BINARY_DIR) / "curves";
  fs::create_directories(dir);
  std::ofstream out(dir / (example + ".csv"));
  out << "step,turn,advance,moment,contact_moment,P,Q\n";
  for (const Sample& x : samples)
    out << x.step << "," << -(x.theta - press.theta) << "," << x.ux - press.ux << "," << x.moment << ","
        << x.contact_moment << "," << x.P << "," << x.Qx << "\n";
}

}  // namespace

TEST(RigidRotation, RollerRollsWithoutSlipAndCarriesTheMomentOfItsTraction) {
  RollerView v;
  v.ux = [](const Analysis& a) { return a.obstacle_displacement(*a.contacts()[0]).x(); };
  v.theta = [](const Analysis& a) { return a.obstacle_rotation(*a.contacts()[0]).z(); };
  v.moment = [](const Analysis& a) { return a.obstacle_moment(*a.contacts()[0]).z(); };
  v.centre = [](const Analysis& a) {
    return Vec3(a.contacts()[0]->settings().obstacle.point + a.obstacle_displacement(*a.contacts()[0]));
  };
  check_roller("rolling_cylinder", v, 0.35);
}

// The same roller as a meshed rigid body (examples/rolling_rigid_mesh: rigid: true, its centre
// the reference node, its angle prescribed by rotation: on that node set), its rim a polygon
// of 0.05 mm facets where it rolls: the same references and tolerances.
TEST(RigidRotation, MeshedRigidRollerRollsLikeTheAnalyticOne) {
  auto centre_dof = [](const Analysis& a, int d) {
    return a.dofs().dof(a.model().mesh.node_sets.at("Centre")[0], d);
  };
  RollerView v;
  v.ux = [=](const Analysis& a) { return a.displacement()(centre_dof(a, 0)); };
  v.theta = [](const Analysis& a) { return a.body_rotation("roller").z(); };
  v.moment = [](const Analysis& a) { return a.body_moment("roller").z(); };
  v.centre = [](const Analysis& a) {
    return a.positions(a.displacement())[a.model().mesh.node_sets.at("Centre")[0]];
  };
  check_roller("rolling_rigid_mesh", v, 0.35);
}

// A rigid ball that turns in 3D: examples/rolling_ball on 0.25 mm tetrahedra, half steps
// (tests/rolling_ball.hpp has the references; the example's own 0.2 mm mesh runs in the long
// suite).
TEST(RigidRotation, BallRollsTwistsAndEasesIn3D) {
  test::check_ball("rolling_ball", test::analytic_ball(), 0.25, "hc: 0.25", 0.5, 0.10);
}

// The same ball as a meshed rigid body (examples/rolling_rigid_ball: the sphere's cap meshed,
// its centre the reference node; rotation: and moment: on that node set), coarse: the same
// references and tolerances.
TEST(RigidRotation, MeshedRigidBallRollsTwistsAndEasesLikeTheAnalyticOne) {
  test::check_ball("rolling_rigid_ball", test::meshed_ball(), 0.25, "hc: 0.25, hb: 0.25", 0.5, 0.10);
}
