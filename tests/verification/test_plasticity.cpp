// J2 plasticity verified on the thick-walled cylinder under internal pressure (VALIDATION.md
// sec. 8; Hill 1950, ch. V; de Souza Neto, Peric & Owen 2008, sec. 7.5.1): plane strain,
// a = 100 mm, b = 200 mm, E = 210 GPa, nu = 0.3, perfectly plastic sigma_y = 240 MPa, the
// quarter model of examples/lame_cylinder (quad9). References:
//  - elastic (Lame, plane strain): u(b) = 2 p a^2 b (1 - nu^2) / (E (b^2 - a^2));
//  - elastic-plastic, plastic zone a <= r <= c (Hill, with k = sigma_y / sqrt(3), the plane-strain
//    von Mises shear yield stress): p = k [1 - c^2/b^2 + 2 ln(c/a)], and the elastic outer zone
//    gives u(b) = 2 (1 - nu^2) k c^2 / (E b);
//  - limit pressure (c = b): p_lim = (2 / sqrt 3) sigma_y ln(b/a) = 192.09 MPa.
// Hill's relation is exact for Tresca and for an incompressible von Mises solid; with nu = 0.3
// the axial stress differs a little from the mean of the in-plane ones. Measured (h = 5 mm,
// quad9): u(b) within 0.5 % of Hill's up to 0.94 p_lim and 2.6 % at 0.99 p_lim, where the curve
// is nearly flat (Hill's pressure for that displacement is 0.27 % higher); the plastic front 2-3 mm
// beyond Hill's (the measure is the outermost yielded cell's centroid); the last converged
// pressure on the way to 1.03 p_lim 0.9999 p_lim.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <fmt/format.h>

#include "deck_text.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/material/j2_plasticity.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

// The model of a deck given as text (written to a temporary file named after `stem`, read,
// removed).
Model model_from_text(const std::string& stem, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path tmp = fs::temp_directory_path() / ("signorini_" + stem + "_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(tmp) << text;
  Registry r = default_registry();
  Model m = read_deck(tmp.string(), r);
  fs::remove(tmp);
  return m;
}

// A curve for the docs' plots (examples/*/plot.py read them): build/curves/NAME.csv.
std::ofstream curve_file(const std::string& name, const std::string& header) {
  const std::filesystem::path dir = std::filesystem::path(SIGNORINI_BINARY_DIR) / "curves";
  std::filesystem::create_directories(dir);
  std::ofstream f(dir / (name + ".csv"));
  f << header << "\n";
  return f;
}

const Real kA = 0.1, kB = 0.2, kE = 210e9, kNu = 0.3, kSy = 240e6;
const Real kK = kSy / std::sqrt(3.0);
const Real kPlim = 2 / std::sqrt(3.0) * kSy * std::log(kB / kA);

Real hill_pressure(Real c) { return kK * (1 - c * c / (kB * kB) + 2 * std::log(c / kA)); }
// The plastic front for a pressure between first yield and the limit (bisection on Hill's relation).
Real hill_front(Real p) {
  Real lo = kA, hi = kB;
  for (int i = 0; i < 100; ++i) {
    const Real mid = 0.5 * (lo + hi);
    (hill_pressure(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
Real outer_displacement(Real p) {
  if (p <= hill_pressure(kA)) return 2 * p * kA * kA * kB * (1 - kNu * kNu) / (kE * (kB * kB - kA * kA));
  const Real c = hill_front(p);
  return 2 * (1 - kNu * kNu) * kK * c * c / (kE * kB);
}

// The pressure at which Hill's curve reaches the outer displacement u (bisection; u below its
// value at p_lim).
Real hill_pressure_for(Real u) {
  Real lo = 0, hi = kPlim;
  for (int i = 0; i < 100; ++i) {
    const Real mid = 0.5 * (lo + hi);
    (outer_displacement(mid) < u ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string deck(Real p, Real h, const std::string& increments, bool finite) {
  const std::string geo =
      (std::filesystem::path(SIGNORINI_SOURCE_DIR) / "examples" / "lame_cylinder" / "lame_cylinder.geo").string();
  return "title: thick cylinder, J2 perfectly plastic\n"
         "analysis: {dimension: plane_strain, kinematics: " + std::string(finite ? "finite_strain" : "small_strain") + "}\n"
         "mesh: {file: " + geo + ", parameters: {h: " + std::to_string(h) + "}}\n"
         "materials:\n  steel: {model: j2_plasticity, E: 210e9, nu: 0.3, yield_stress: 240e6}\n"
         "bodies:\n  - {name: cylinder, region: Cylinder, material: steel}\n"
         "steps:\n  - name: pressurize\n    increments: " + increments + "\n"
         "    boundary:\n      - {set: SymX, uy: 0}\n      - {set: SymY, ux: 0}\n"
         "    loads:\n      - {set: Inner, pressure: " + fmt::format("{:.17g}", p) + "}\n"
         "output: {vtu: none}\n";
}

struct Point {
  Real p, ua, ub, front;
};

struct CylinderRun {
  AnalysisSummary summary;
  std::vector<Point> curve;
};

CylinderRun run_cylinder(Real p, Real h, const std::string& increments, bool finite = false,
                         bool continuation = true, int max_iterations = 0) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  Model m = model_from_text("plastic_cylinder", deck(p, h, increments, finite));
  m.newton.pseudo_transient = continuation;
  if (max_iterations > 0) m.newton.max_iterations = max_iterations;  // (0: the deck's)
  Analysis a(m);
  CylinderRun out;
  // The outer node on the x axis, and each cell's centroid radius.
  Index outer = 0, inner = 0;
  for (Index n = 0; n < m.mesh.num_nodes(); ++n) {
    if ((m.mesh.nodes[n] - Vec3(kB, 0, 0)).norm() < (m.mesh.nodes[outer] - Vec3(kB, 0, 0)).norm()) outer = n;
    if ((m.mesh.nodes[n] - Vec3(kA, 0, 0)).norm() < (m.mesh.nodes[inner] - Vec3(kA, 0, 0)).norm()) inner = n;
  }
  const Body& body = *m.bodies.front();
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    Point pt;
    pt.p = rec.fraction * p;
    pt.ub = an.displacement()(an.dofs().dof(outer, 0));
    pt.ua = an.displacement()(an.dofs().dof(inner, 0));
    // Plastic front: the outermost cell centroid with plastic strain at some quadrature point.
    pt.front = kA;
    const QuadratureHistory& hist = an.history(0);
    for (size_t bi = 0; bi < body.blocks().size(); ++bi) {
      const ElementBlock& b = body.blocks()[bi];
      const Index nq = body.points_per_element(bi);
      for (Index e = 0; e < b.size(); ++e) {
        const Real* v = hist.committed(bi, e);
        bool plastic = false;
        const int slot = static_cast<const J2Plasticity&>(body.material()).alpha_slot();
        for (Index q = 0; q < nq; ++q) plastic = plastic || v[q * hist.per_point() + slot] > 0;
        if (!plastic) continue;
        Vec3 c = Vec3::Zero();
        for (int k = 0; k < b.nodes_per_element(); ++k) c += m.mesh.nodes[b.element(e)[k]];
        pt.front = std::max(pt.front, (c / b.nodes_per_element()).head<2>().norm());
      }
    }
    out.curve.push_back(pt);
  });
  out.summary = a.run();
  return out;
}


void follows_hill(bool finite, Real up_to) {
  const Real h = 0.005;
  const CylinderRun r = run_cylinder(up_to * kPlim, h, "{initial: 0.05, max: 0.05}", finite);
  ASSERT_TRUE(r.summary.completed) << r.summary.failure;
  int plastic_points = 0;
  std::ofstream csv = curve_file(finite ? "thick_cylinder_finite" : "thick_cylinder_small", "p,u_b,front");
  for (const Point& pt : r.curve) {
    csv << fmt::format("{:.10g},{:.10g},{:.10g}\n", pt.p, pt.ub, pt.front);
    const Real ref = outer_displacement(pt.p);
    std::printf("p = %7.2f MPa (%.3f p_lim): u(b) = %.5f mm, Hill %.5f mm (%+.2f %%; Hill's p for it %+.2f %%); plastic "
                "front %.1f mm, Hill %.1f mm\n",
                pt.p / 1e6, pt.p / kPlim, pt.ub * 1e3, ref * 1e3, 100 * (pt.ub - ref) / ref,
                100 * (hill_pressure_for(pt.ub) - pt.p) / pt.p, pt.front * 1e3,
                pt.p > hill_pressure(kA) ? hill_front(pt.p) * 1e3 : kA * 1e3);
    // Near p_lim the curve is nearly flat (u grows without bound), so it is compared in
    // pressure: the pressure at which Hill's curve has the computed displacement.
    EXPECT_NEAR(hill_pressure_for(pt.ub), pt.p, 0.01 * pt.p) << "p = " << pt.p;
    EXPECT_NEAR(pt.ub, ref, 0.03 * ref) << "p = " << pt.p;
    if (pt.p > hill_pressure(kA)) {
      ++plastic_points;
      // The front lies between cell centroids: within one and a half elements (quad9 of size h).
      EXPECT_NEAR(pt.front, hill_front(pt.p), 1.5 * h) << "p = " << pt.p;
    } else {
      EXPECT_EQ(pt.front, kA) << "no plastic strain below first yield, p = " << pt.p;
    }
  }
  EXPECT_GE(plastic_points, 8);
  // Newton's iterations per increment stay few (the consistent tangent): logged.
  int its = 0;
  for (const auto& rec : r.summary.increments) its += rec.iterations;
  std::printf("%zu increments, %d Newton iterations\n", r.summary.increments.size(), its);
  EXPECT_LE(its, 6 * static_cast<int>(r.summary.increments.size()));
}

void limit_pressure(bool finite) {
  // (Without pseudo-transient continuation, the last resort at a limit point: it finds no
  // equilibrium either, and would add its 200 iterations to the test's time. Newton's iterations
  // capped at 12, twice what an increment takes below the limit: each of the seven cut-back
  // increments near p_lim fails at the cap, and with the default 25 the two tests took 20 and
  // 26 s of the suite; the last converged pressures are the same with 25, 12 and 8.)
  const CylinderRun r =
      run_cylinder(1.03 * kPlim, 0.005, "{initial: 0.05, max: 0.05, min: 1e-3}", finite, /*continuation=*/false, 12);
  EXPECT_FALSE(r.summary.completed) << "1.03 p_lim carried";
  ASSERT_FALSE(r.curve.empty());
  const Real last = r.curve.back().p;
  std::printf("last converged pressure %.3f MPa = %.4f p_lim (p_lim %.3f MPa); u(b) there %.4f mm (elastic limit %.4f)\n",
              last / 1e6, last / kPlim, kPlim / 1e6, r.curve.back().ub * 1e3, outer_displacement(hill_pressure(kA)) * 1e3);
  // At finite strain the follower pressure acts on the deformed bore, and the limit is that of
  // the deformed section, (2 / sqrt 3) sigma_y ln((b + u_b) / (a + u_a)) (0.4 % below p_lim).
  const Point& pt = r.curve.back();
  const Real limit = finite ? 2 / std::sqrt(3.0) * kSy * std::log((kB + pt.ub) / (kA + pt.ua)) : kPlim;
  if (finite) std::printf("the deformed section's limit %.3f MPa = %.4f p_lim\n", limit / 1e6, limit / kPlim);
  EXPECT_GT(last, 0.99 * limit);
  EXPECT_LT(last, 1.01 * limit);
}

}  // namespace

TEST(Plasticity, ThickCylinderFollowsHillUpToTheLimitPressure) { follows_hill(false, 0.99); }

// The same with the multiplicative finite-strain model (F = F_e F_p, Hencky, exponential map)
// and the follower pressure, up to 0.95 p_lim: there the geometry has hardly changed (the bore
// grows by 0.2 %), so Hill's small-strain solution is the reference with the same tolerances
// (measured: u(b) +1.8 % at 0.94 p_lim). Closer to p_lim the deformed section's lower limit
// (0.4 % below) takes over; the limit test below checks that one.
TEST(Plasticity, ThickCylinderFollowsHillAtFiniteStrain) { follows_hill(true, 0.95); }

// Beyond the limit pressure no equilibrium exists: asked for 1.03 p_lim, the run cuts its
// increments back and gives up with its last converged pressure within 1 % of p_lim (the
// issue's check that the limit pressure is reached within 1 %; a locking discretization would
// carry more).
TEST(Plasticity, ThickCylinderCannotCarryMoreThanTheLimitPressure) { limit_pressure(false); }
TEST(Plasticity, ThickCylinderCannotCarryMoreThanTheLimitPressureAtFiniteStrain) { limit_pressure(true); }

// ---- Viscoplasticity through the analysis (examples/viscoplastic_bar) ----
//
// The example's bar (uniaxial stress, E = 200e3, sigma_y = 200, eta = 5000, rate 1e-4 over a
// step of time 100), with finer increments (0.2 s, a 25th of the time constant eta sigma_y / E
// = 5 s), then held for 50 s. Closed forms (de Souza Neto, Peric & Owen 2008, sec. 11.5):
//  - pull: sigma = E rate t up to t_y = 10 s, then s_ss + (sigma_y - s_ss) exp(-(t - t_y) / tc)
//    with s_ss = sigma_y (1 + eta rate) = 300;
//  - hold: sigma relaxes to sigma_y as sigma_y + (sigma_0 - sigma_y) exp(-t / tc).
// Backward Euler is first-order accurate: within 3 % of the overstress on the way; the steady
// and relaxed values to 1e-4. With the viscosity 1e-6 of that the bar carries sigma_y (the
// rate-independent limit).
namespace {

struct BarPoint {
  Real t, force;
};

std::vector<BarPoint> run_bar(const std::string& material_extra, bool hold, AnalysisSummary& summary) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  const fs::path dir = fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "viscoplastic_bar";
  std::ifstream in(dir / "viscoplastic_bar.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace = [&](const std::string& a, const std::string& b) { test::replace_in_text(text, a, b); };
  replace("viscosity: 5000", material_extra);
  replace("increments: {initial: 0.01, max: 0.01}", "increments: {initial: 0.002, max: 0.002}");
  replace("../neo_hookean_bar/", (dir / ".." / "neo_hookean_bar").string() + "/");
  replace("output: {directory: results/viscoplastic_bar, vtu: last}", "output: {vtu: none}");
  if (hold)
    replace("output:", "  - name: hold\n    time: 50\n    increments: {initial: 0.004, max: 0.004}\n    boundary:\n"
                       "      - {set: XMin, ux: 0}\n      - {set: YMin, uy: 0}\n      - {set: ZMin, uz: 0}\n"
                       "      - {set: XMax, ux: 0.01}\noutput:");
  Model m = model_from_text("viscoplastic_bar", text);
  Analysis a(m);
  std::vector<BarPoint> out;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    const Real t = rec.step == 0 ? 100 * rec.fraction : 100 + 50 * rec.fraction;
    out.push_back({t, an.reaction_sum("XMax").x()});
  });
  summary = a.run();
  return out;
}

const Real kBarE = 200e3, kBarSy = 200, kBarEta = 5000, kBarRate = 1e-4;

}  // namespace

TEST(Viscoplasticity, BarFollowsTheClosedFormAndRelaxes) {
  AnalysisSummary summary;
  const std::vector<BarPoint> curve = run_bar("viscosity: 5000", true, summary);
  ASSERT_TRUE(summary.completed) << summary.failure;
  const Real tc = kBarEta * kBarSy / kBarE, ty = kBarSy / (kBarE * kBarRate), s_ss = kBarSy * (1 + kBarEta * kBarRate);
  Real worst = 0, at_end_of_pull = 0;
  std::ofstream csv = curve_file("viscoplastic_bar", "t,stress");
  for (const BarPoint& p : curve) {
    csv << fmt::format("{:.10g},{:.10g}\n", p.t, p.force);
    Real exact;
    if (p.t <= ty) exact = kBarE * kBarRate * p.t;
    else if (p.t <= 100 + 1e-9) exact = s_ss + (kBarSy - s_ss) * std::exp(-(p.t - ty) / tc);
    else {
      const Real s100 = s_ss + (kBarSy - s_ss) * std::exp(-(100 - ty) / tc);
      exact = kBarSy + (s100 - kBarSy) * std::exp(-(p.t - 100) / tc);
    }
    worst = std::max(worst, std::abs(p.force - exact));
    if (std::abs(p.t - 100) < 1e-9) at_end_of_pull = p.force;
  }
  std::printf("%zu increments; end of pull %.6f (closed form %.6f), after the hold %.6f (sigma_y %.1f); worst error "
              "%.3g of the overstress\n",
              curve.size(), at_end_of_pull, s_ss, curve.back().force, kBarSy, worst / (s_ss - kBarSy));
  EXPECT_NEAR(at_end_of_pull, s_ss, 1e-4 * s_ss);
  EXPECT_NEAR(curve.back().force, kBarSy, 1e-4 * kBarSy);
  EXPECT_LT(worst, 0.03 * (s_ss - kBarSy));
  int its = 0;
  for (const auto& rec : summary.increments) its += rec.iterations;
  std::printf("%d Newton iterations\n", its);
  EXPECT_LE(its, 3 * static_cast<int>(summary.increments.size()));
}

TEST(Viscoplasticity, BarTendsToTheRateIndependentModelAsTheViscosityVanishes) {
  AnalysisSummary summary;
  const std::vector<BarPoint> curve = run_bar("viscosity: 5e-3", false, summary);
  ASSERT_TRUE(summary.completed) << summary.failure;
  // eta rate = 5e-7: the steady overstress is 5e-7 of sigma_y, reached long before the end.
  EXPECT_NEAR(curve.back().force, kBarSy * (1 + 5e-3 * kBarRate), 1e-9 * kBarSy);
  EXPECT_NEAR(curve.back().force, kBarSy, 1e-6 * kBarSy);
}

// ---- Centrifugal load (a rotating annular disk, plane stress) ----
//
// Timoshenko & Goodier, Theory of Elasticity, 3rd ed., 1970, sec. 32: a disk a <= r <= b
// spinning at omega, free at both radii, plane stress:
//   sigma_r = (3 + nu)/8 rho omega^2 (b^2 + a^2 - a^2 b^2 / r^2 - r^2),
//   sigma_t = (3 + nu)/8 rho omega^2 (b^2 + a^2 + a^2 b^2 / r^2 - (1 + 3 nu)/(3 + nu) r^2),
//   u = r (sigma_t - nu sigma_r) / E.
// The quarter annulus of the Lame example (a = 0.1 m, b = 0.2 m, quad9 h = 5 mm), steel
// (E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3) at omega = 1000 rad/s; u(a) and u(b) within 0.1 %.
TEST(Centrifugal, RotatingDiskMatchesTheClosedForm) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  const Real a = 0.1, b = 0.2, E = 210e9, nu = 0.3, rho = 7800, omega = 1000;
  const std::string geo =
      (fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "lame_cylinder" / "lame_cylinder.geo").string();
  const std::string text =
      "title: rotating disk\n"
      "analysis: {dimension: plane_stress, thickness: 0.01}\n"
      "mesh: {file: " + geo + ", parameters: {h: 0.005}}\n"
      "materials:\n  steel: {model: linear_elastic, E: 210e9, nu: 0.3}\n"
      "bodies:\n  - {name: disk, region: Cylinder, material: steel}\n"
      "steps:\n  - name: spin\n    boundary:\n      - {set: SymX, uy: 0}\n      - {set: SymY, ux: 0}\n"
      "    loads:\n      - {body: disk, centrifugal: {density: 7800, omega: 1000}}\n"
      "output: {vtu: none}\n";
  Model m = model_from_text("rotating_disk", text);
  Analysis an(m);
  const AnalysisSummary s = an.run();
  ASSERT_TRUE(s.completed) << s.failure;
  const Real k = (3 + nu) / 8 * rho * omega * omega;
  auto u = [&](Real rr) {
    const Real sr = k * (b * b + a * a - a * a * b * b / (rr * rr) - rr * rr);
    const Real st = k * (b * b + a * a + a * a * b * b / (rr * rr) - (1 + 3 * nu) / (3 + nu) * rr * rr);
    return rr * (st - nu * sr) / E;
  };
  for (Real rr : {a, b}) {
    Index best = 0;
    for (Index n = 0; n < m.mesh.num_nodes(); ++n)
      if ((m.mesh.nodes[n] - Vec3(rr, 0, 0)).norm() < (m.mesh.nodes[best] - Vec3(rr, 0, 0)).norm()) best = n;
    const Real computed = an.displacement()(an.dofs().dof(best, 0));
    std::printf("u(%.1f) = %.6e m, closed form %.6e (%+.3f %%)\n", rr, computed, u(rr), 100 * (computed / u(rr) - 1));
    EXPECT_NEAR(computed, u(rr), 1e-3 * u(rr));
  }
}
