// The rolling ball of examples/rolling_ball (3D rotations of a rigid body), shared by the
// default suite's coarse run (verification/test_rolling.cpp) and the long run at the
// example's own resolution (long/test_rolling_ball.cpp).
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "example_deck.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"

// A rigid ball that turns in 3D (issue 16: three rotations): the example `rolling_ball`, a
// rigid sphere (R = 10 mm) pressed into an elastic block (steel, linear tetrahedra, Coulomb
// mu = 0.3), its rotation vector an unknown of its own.
// - roll: turned by psi = 0.1 rad about a = (-sin 30, cos 30, 0), free to move sideways: it
//   advances R psi along d = a x z but for a creep below mu a_H / R (no gross slip; a_H the
//   Hertz contact radius of a rigid sphere on a half-space from the computed P, (3 P R /
//   (4 E*))^(1/3), Johnson 1985, eq. 4.22), drifts across d by less than that, and the moment
//   that turns it is next to nothing (below 1e-3 P R);
// - twist: turned 0.1 rad more about the vertical: the whole patch slips and the moment about
//   the vertical is (3 pi / 16) mu P a_H, the moment of mu p over the Hertz pressure (Lubkin
//   1951), within 6 % (10 % on the coarse mesh; the patch is 6 to 10 nodes across);
// - ease: the rotation free and loaded by the moment (0, 0, 230) N mm: the ball turns back and
//   the contact forces' moment about the centre balances the moment.
// In every increment the reaction moment (T^-T of the angles' reactions; with the rotation
// loaded, the moment load) equals the moment of the contact forces about the ball's centre,
// taken here at the slave nodes, to 1e-6 P R: the angles' equilibrium. What separates them is
// the Newton tolerance (1e-8 of the force scale, the moment rows divided by the distance to
// the farthest slave node, 11.5 mm) and, on the meshed ball, the friction forces' points of
// action, their slip origins on the ball, up to a slip increment from the slave nodes (3e-7
// P R measured, 2.5e-8 on the analytic ball). A spin operator T off by the rotation's size
// (0.13 rad) would miss by 1e-3 P R.
namespace signorini::test {

struct BallView {
  std::function<Vec3(const Analysis&)> centre, rotation, moment;
};

struct BallSample {
  int step = 0;
  Vec3 centre = Vec3::Zero(), rotation = Vec3::Zero(), moment = Vec3::Zero(), contact_moment = Vec3::Zero();
  Real P = 0, radius = 0;
  int stick = 0, slip = 0;
};

// Runs the example deck, with the tetrahedra of size `hc` where the ball rolls (the .geo's
// constants `sizes`, e.g. "hc: 0.25", set to it) and increments no smaller than `increment`
// (the default suite's coarse run), and checks it.
inline void check_ball(const std::string& example, const BallView& view, Real hc, const std::string& sizes,
                       Real increment, Real twist_tolerance) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  const ExampleDeck ex = example_deck_with(example, sizes, increment);
  Registry r = default_registry();
  Model m = read_deck(ex.deck.string(), r);
  m.output.vtu = "none";
  m.output.directory = (ex.dir / "results").string();
  const Real R = 10, E = 200e3, nu = 0.3, mu = 0.3, psi = 0.1, twist = 0.1, eased = 230;
  const Real Estar = E / (1 - nu * nu);
  const Vec3 d(std::cos(M_PI / 6), std::sin(M_PI / 6), 0), axis(-std::sin(M_PI / 6), std::cos(M_PI / 6), 0);
  Analysis a(m);
  std::vector<BallSample> samples;
  Real worst_balance = 0, worst_at = 0, worst_residual = 0;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    const ContactInterface& c = *an.contacts()[0];
    BallSample s;
    s.step = rec.step;
    s.centre = view.centre(an);
    s.rotation = view.rotation(an);
    s.moment = view.moment(an);
    // The contact force on each slave node, w (p n - t), and its moment about the centre.
    const std::vector<Vec3> x = an.positions(an.displacement());
    std::vector<Vec3> closed;
    for (size_t j = 0; j < c.constraints().size(); ++j) {
      const Constraint& k = c.constraints()[j];
      if (k.kind == ConstraintKind::none || !c.state().active[j]) continue;
      const Vec3 f = k.weight * (c.state().pressure[j] * k.normal - c.state().traction[j]);
      s.contact_moment += (x[k.slave] - s.centre).cross(f);
      s.P -= f.z();
      closed.push_back(x[k.slave]);
      (c.state().slip[j] ? s.slip : s.stick) += 1;
    }
    for (const Vec3& p : closed) {
      const Vec3 r = p - s.centre;
      s.radius = std::max(s.radius, std::hypot(r.x(), r.y()));
    }
    // The angles' equilibrium: with the rotation prescribed, the reaction moment is the
    // contact forces'; loaded, the contact forces' moment is the load's.
    const Vec3 held = rec.step == 3 ? Vec3(0, 0, eased * rec.fraction) : s.moment;
    if ((held - s.contact_moment).norm() > worst_balance) {
      worst_balance = (held - s.contact_moment).norm();
      worst_at = rec.step + 1 + 0.01 * rec.increment;
      worst_residual = rec.residuals.empty() ? 0.0 : rec.residuals.back();
    }
    samples.push_back(s);
  });
  const AnalysisSummary sum = a.run();
  fs::remove_all(ex.dir);
  ASSERT_TRUE(sum.completed) << sum.failure;
  auto last_of = [&](int step) {
    BallSample s;
    for (const BallSample& x : samples)
      if (x.step == step) s = x;
    return s;
  };
  const BallSample press = last_of(0), roll = last_of(1), tw = last_of(2), ease = last_of(3);
  const Real P = press.P, a_hertz = std::cbrt(3 * P * R / (4 * Estar));
  std::printf("press: P = %.1f N, outermost closed node at %.3f mm, Hertz a = %.3f mm (mesh %.2f mm)\n", P, press.radius,
              a_hertz, hc);
  EXPECT_GT(press.radius, a_hertz - 1.5 * hc);
  EXPECT_LT(press.radius, a_hertz + 0.5 * hc);
  // Roll.
  const Vec3 advance = roll.centre - press.centre;
  const Real creep = advance.dot(d) / (R * psi) - 1, drift = advance.dot(axis) / (R * psi);
  std::printf("roll: rotation (%.5f, %.5f, %.5f), advanced %.5f mm along d (creep %.5f), %.5f across (%.5f); mu a / R = "
              "%.5f; moment %.3g N mm (%.1e of P R); %d stick, %d slip\n",
              roll.rotation.x(), roll.rotation.y(), roll.rotation.z(), advance.dot(d), creep, advance.dot(axis), drift,
              mu * a_hertz / R, roll.moment.norm(), roll.moment.norm() / (P * R), roll.stick, roll.slip);
  EXPECT_LT((roll.rotation - psi * axis).norm(), 1e-10) << "as prescribed (the deck's 10 digits)";
  EXPECT_LT(std::abs(creep), mu * a_hertz / R) << "gross slip";
  EXPECT_LT(std::abs(drift), mu * a_hertz / R);
  EXPECT_LT(roll.moment.norm(), 1e-3 * P * R);
  EXPECT_GT(roll.stick, roll.slip) << "free rolling sticks over most of the patch";
  // Twist.
  const Real Pt = tw.P, at = std::cbrt(3 * Pt * R / (4 * Estar)), lubkin = 3 * M_PI / 16 * mu * Pt * at;
  std::printf("twist: moment (%.2f, %.2f, %.2f) N mm, full slip (3 pi / 16) mu P a = %.2f (%+.2f %%); %d stick, %d slip\n",
              tw.moment.x(), tw.moment.y(), tw.moment.z(), lubkin, 100 * (tw.moment.z() / lubkin - 1), tw.stick, tw.slip);
  EXPECT_NEAR(tw.rotation.z(), twist, 1e-12);
  EXPECT_NEAR(tw.moment.z(), lubkin, twist_tolerance * lubkin);
  EXPECT_LT(std::hypot(tw.moment.x(), tw.moment.y()), 0.1 * tw.moment.z());
  EXPECT_EQ(tw.stick, 0) << "the whole patch slips";
  // Ease.
  std::printf("ease: rotation (%.5f, %.5f, %.5f), contact moment (%.3g, %.3g, %.3f); %d stick, %d slip; angles' "
              "balance %.1e of P R (step.increment %.2f, its last |R|/F %.1e)\n",
              ease.rotation.x(), ease.rotation.y(), ease.rotation.z(), ease.contact_moment.x(), ease.contact_moment.y(),
              ease.contact_moment.z(), ease.stick, ease.slip, worst_balance / (P * R), worst_at, worst_residual);
  EXPECT_LT(ease.rotation.z(), tw.rotation.z()) << "the ball turns back";
  EXPECT_LT((ease.contact_moment - Vec3(0, 0, eased)).norm(), 1e-6 * P * R);
  EXPECT_LT(worst_balance, 1e-6 * P * R);
  // The twist's curve for docs/validation.md (examples/rolling_cylinder/plot.py).
  const fs::path dir = fs::path(SIGNORINI_BINARY_DIR) / "curves";
  fs::create_directories(dir);
  std::ofstream out(dir / (example + ".csv"));
  out << "step,rotation_z,moment_z,contact_moment_z,P,stick,slip\n";
  for (const BallSample& x : samples)
    out << x.step << "," << x.rotation.z() << "," << x.moment.z() << "," << x.contact_moment.z() << "," << x.P << ","
        << x.stick << "," << x.slip << "\n";
}

inline BallView analytic_ball() {
  BallView v;
  v.centre = [](const Analysis& a) {
    return Vec3(a.contacts()[0]->settings().obstacle.point + a.obstacle_displacement(*a.contacts()[0]));
  };
  v.rotation = [](const Analysis& a) { return a.obstacle_rotation(*a.contacts()[0]); };
  v.moment = [](const Analysis& a) { return a.obstacle_moment(*a.contacts()[0]); };
  return v;
}

// The ball as a meshed rigid body (examples/rolling_rigid_ball): its centre the reference node.
inline BallView meshed_ball() {
  BallView v;
  v.centre = [](const Analysis& a) { return a.positions(a.displacement())[a.model().mesh.node_sets.at("Centre")[0]]; };
  v.rotation = [](const Analysis& a) { return a.body_rotation("ball"); };
  v.moment = [](const Analysis& a) { return a.body_moment("ball"); };
  return v;
}

}  // namespace signorini::test

