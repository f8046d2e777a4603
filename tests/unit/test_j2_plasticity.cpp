// J2 plasticity (material/j2_plasticity): the consistent tangent against central differences
// of the return map (elastic, plastic loading, unloading, each hardening), one-sided at the
// yield surface, and the return map's closed forms (the state it returns lies on the yield
// surface; uniaxial loading follows E H / (E + H) for linear isotropic hardening).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "signorini/core/error.hpp"
#include "signorini/material/j2_plasticity.hpp"

using namespace signorini;

namespace {

struct State {
  Vec6 stress;
  Mat6 tangent;
  std::vector<Real> history;
};

// The material's response to a strain (small, or Green-Lagrange with `finite`) over a time dt.
State eval(const J2Plasticity& m, const Vec6& strain, const std::vector<Real>& old, bool finite = false, Real dt = 0) {
  State s;
  s.history.assign(m.history_size(), 0);
  MaterialInput in;
  in.finite = finite;
  in.dt = dt;
  in.strain = strain;
  in.history_old = old.data();
  in.history_new = s.history.data();
  m.compute(in, s.stress, s.tangent);
  return s;
}

Real mises(const Vec6& s) {
  const Real p = (s(0) + s(1) + s(2)) / 3;
  Real q = 0;
  for (int i = 0; i < 3; ++i) q += (s(i) - p) * (s(i) - p);
  for (int i = 3; i < 6; ++i) q += 2 * s(i) * s(i);
  return std::sqrt(1.5 * q);
}

// Central differences of the stress in the strain (Voigt, engineering shears).
Mat6 numeric_tangent(const J2Plasticity& m, const Vec6& strain, const std::vector<Real>& old, Real h,
                     bool finite = false, Real dt = 0) {
  Mat6 D;
  for (int b = 0; b < 6; ++b) {
    Vec6 e = Vec6::Zero();
    e(b) = h;
    D.col(b) = (eval(m, strain + e, old, finite, dt).stress - eval(m, strain - e, old, finite, dt).stress) / (2 * h);
  }
  return D;
}

const Real kE = 210000, kNu = 0.3, kSy = 240;

std::vector<J2Hardening> hardenings() {
  J2Hardening perfect, linear, voce, kinematic, mixed;
  linear.H = 2000;
  voce.voce = true, voce.saturation = 400, voce.rate = 50, voce.H = 500;
  kinematic.kinematic = 5000;
  mixed = voce;
  mixed.kinematic = 3000;
  return {perfect, linear, voce, kinematic, mixed};
}

// A strain of about 3 x the yield strain in a general direction (all six components).
const Vec6 kDirection = (Vec6() << 1.0, -0.4, 0.25, 0.3, -0.2, 0.5).finished();

}  // namespace

TEST(J2Plasticity, TangentMatchesCentralDifferences) {
  const Real ey = kSy / kE;
  for (const J2Hardening& h : hardenings()) {
    const J2Plasticity m(kE, kNu, kSy, h);
    std::vector<Real> virgin(m.history_size(), 0.0);
    // Elastic: half the yield strain.
    const Vec6 small = 0.3 * ey * kDirection;
    State s = eval(m, small, virgin);
    EXPECT_EQ(s.history[J2Plasticity::kYielding], 0);
    EXPECT_LT((s.tangent - numeric_tangent(m, small, virgin, 1e-9)).norm(), 1e-6 * s.tangent.norm());
    // Plastic loading from the virgin state.
    const Vec6 big = 3 * ey * kDirection;
    s = eval(m, big, virgin);
    EXPECT_EQ(s.history[J2Plasticity::kYielding], 1);
    const Mat6 num = numeric_tangent(m, big, virgin, 1e-9);
    EXPECT_LT((s.tangent - num).norm(), 1e-6 * s.tangent.norm()) << "hardening H " << h.H << " voce " << h.voce
                                                                   << " kinematic " << h.kinematic;
    // Plastic loading again from that state (history with plastic strain and back stress).
    const Vec6 further = big + 2 * ey * Vec6(0.2, 0.7, -0.4, 0.1, 0.3, -0.6);
    State t = eval(m, further, s.history);
    EXPECT_EQ(t.history[J2Plasticity::kYielding], 1);
    EXPECT_LT((t.tangent - numeric_tangent(m, further, s.history, 1e-9)).norm(), 1e-6 * t.tangent.norm());
    // Unloading from it: elastic, the elastic tangent.
    const Vec6 back = big - 1.0 * ey * kDirection;
    State u = eval(m, back, s.history);
    EXPECT_EQ(u.history[J2Plasticity::kYielding], 0);
    EXPECT_LT((u.tangent - numeric_tangent(m, back, s.history, 1e-9)).norm(), 1e-6 * u.tangent.norm());
    EXPECT_LT((u.tangent - isotropic_elasticity(kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), kE / (2 * (1 + kNu))))
                  .norm(),
              1e-9 * u.tangent.norm());
  }
}

// On the yield surface (the converged state of a plastic step): a further strain along the
// loading direction follows the elasto-plastic tangent, one back along it the elastic one
// (one-sided differences; the kink is there).
TEST(J2Plasticity, OneSidedDerivativesAtTheYieldSurface) {
  const Real ey = kSy / kE;
  for (const J2Hardening& h : hardenings()) {
    const J2Plasticity m(kE, kNu, kSy, h);
    std::vector<Real> virgin(m.history_size(), 0.0);
    const Vec6 big = 3 * ey * kDirection;
    const State s = eval(m, big, virgin);          // plastic step: its state is on the surface
    const State on = eval(m, big + 1e-9 * ey * kDirection, s.history);  // just beyond: plastic branch
    const State elastic = eval(m, 0.5 * ey * kDirection, virgin);
    const Real step = 1e-7 * ey;
    const Vec6 d = kDirection.normalized();
    const Vec6 forward = (eval(m, big + step * d, s.history).stress - eval(m, big, s.history).stress) / step;
    const Vec6 backward = (eval(m, big, s.history).stress - eval(m, big - step * d, s.history).stress) / step;
    EXPECT_LT((forward - on.tangent * d).norm(), 1e-5 * (on.tangent * d).norm()) << "loading side";
    EXPECT_LT((backward - elastic.tangent * d).norm(), 1e-5 * (elastic.tangent * d).norm()) << "unloading side";
    EXPECT_GT((on.tangent * d - elastic.tangent * d).norm(), 1e-3 * (elastic.tangent * d).norm())
        << "the two sides must differ for the test to mean anything";
  }
}

// The returned stress lies on the current yield surface: |s - beta| = sqrt(2/3) sigma_y(alpha),
// i.e. the von Mises stress of s - beta is sigma_y(alpha); the plastic strain is deviatoric;
// the dissipation is sigma_y0 alpha and the plastic work at least that.
TEST(J2Plasticity, ReturnedStateLiesOnTheYieldSurface) {
  const Real ey = kSy / kE;
  for (const J2Hardening& h : hardenings()) {
    const J2Plasticity m(kE, kNu, kSy, h);
    std::vector<Real> virgin(m.history_size(), 0.0);
    const State s = eval(m, 4 * ey * kDirection, virgin);
    const Real alpha = s.history[J2Plasticity::kAlpha];
    ASSERT_GT(alpha, 0);
    Vec6 beta;
    for (int i = 0; i < 6; ++i) beta(i) = s.history[J2Plasticity::kBackStress + i];
    EXPECT_NEAR(mises(s.stress - beta), m.yield_stress(alpha), 1e-10 * kSy);
    const Real tr = s.history[0] + s.history[1] + s.history[2];
    EXPECT_NEAR(tr, 0, 1e-14);
    EXPECT_NEAR(s.history[J2Plasticity::kDissipation], kSy * alpha, 1e-12 * kSy);
    EXPECT_GE(s.history[J2Plasticity::kWork], s.history[J2Plasticity::kDissipation] * (1 - 1e-12));
  }
}

// Uniaxial stress with linear isotropic hardening: beyond yield, d sigma / d eps = E H / (E + H)
// (de Souza Neto, Peric & Owen 2008, sec. 6.3.1). The lateral strains are solved so that the
// lateral stresses vanish (a few Newton steps with the material's own tangent).
TEST(J2Plasticity, UniaxialHardeningModulus) {
  J2Hardening h;
  h.H = 10000;
  const J2Plasticity m(kE, kNu, kSy, h);
  std::vector<Real> hist(m.history_size(), 0.0);
  Real lateral = 0, last_stress = 0, last_strain = 0;
  std::vector<Real> stresses, strains;
  for (int inc = 1; inc <= 20; ++inc) {
    const Real exx = inc * 0.25 * kSy / kE;
    State s;
    for (int it = 0; it < 20; ++it) {
      const Vec6 e = (Vec6() << exx, lateral, lateral, 0, 0, 0).finished();
      s = eval(m, e, hist);
      const Real r = s.stress(1);
      if (std::abs(r) < 1e-10 * kSy) break;
      lateral -= r / (s.tangent(1, 1) + s.tangent(1, 2));
    }
    hist = s.history;
    stresses.push_back(s.stress(0));
    strains.push_back(exx);
    last_stress = s.stress(0);
    last_strain = exx;
  }
  const Real slope = (last_stress - stresses[stresses.size() - 2]) / (last_strain - strains[strains.size() - 2]);
  EXPECT_NEAR(slope, kE * h.H / (kE + h.H), 1e-8 * kE);
  EXPECT_NEAR(stresses.front(), 0.25 * kSy, 1e-9 * kSy) << "elastic at a quarter of the yield strain";
}

// ---- Finite strain (F = F_e F_p, Hencky elasticity, exponential map) ----

namespace {

Vec6 green_lagrange(const Mat3& F) { return to_voigt_strain(0.5 * (F.transpose() * F - Mat3::Identity())); }

// The material's response to a deformation gradient (through E = (F^T F - I) / 2).
State eval_finite(const J2Plasticity& m, const Mat3& F, const std::vector<Real>& old) {
  return eval(m, green_lagrange(F), old, true);
}

std::vector<Real> virgin_history(const J2Plasticity& m) {
  std::vector<Real> h(m.history_size());
  m.initialize_history(h.data());
  return h;
}


Mat3 plastic_deformation(const std::vector<Real>& h) {
  Mat3 Fp;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Fp(i, j) = h[J2Plasticity::kPlasticDeformation + 3 * i + j];
  return Fp;
}

// A rotation (about an oblique axis) times a stretch: strains of tens of percent.
Mat3 large_deformation(Real scale) {
  const Mat3 R = Eigen::AngleAxis<Real>(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Mat3 U;
  U << 1 + 0.30 * scale, 0.08 * scale, -0.05 * scale, 0.08 * scale, 1 - 0.12 * scale, 0.10 * scale, -0.05 * scale,
      0.10 * scale, 1 - 0.06 * scale;
  return R * U;
}

std::vector<J2Hardening> isotropic_hardenings() {
  std::vector<J2Hardening> out;
  for (const J2Hardening& h : hardenings())
    if (h.kinematic == 0) out.push_back(h);
  return out;
}

}  // namespace

// dS/dE against central differences: at the undeformed state (three equal eigenvalues), in
// the elastic range, in plastic loading from the virgin state and from a plastic state (F_p not
// I), at two equal principal stretches, and in elastic unloading from a plastic state.
TEST(J2PlasticityFinite, TangentMatchesCentralDifferences) {
  for (const J2Hardening& h : isotropic_hardenings()) {
    const J2Plasticity m(kE, kNu, kSy, h, true);
    const std::vector<Real> virgin = virgin_history(m);
    const auto check = [&](const Vec6& E, const std::vector<Real>& old, int yielding, const char* what) {
      const State s = eval(m, E, old, true);
      EXPECT_EQ(s.history[J2Plasticity::kFiniteYielding], yielding) << what;
      const Mat6 num = numeric_tangent(m, E, old, 1e-7, true);
      EXPECT_LT((s.tangent - num).norm(), 1e-6 * s.tangent.norm())
          << what << " (hardening H " << h.H << " voce " << h.voce << ")\n" << s.tangent << "\n\n" << num;
      return s;
    };
    const State zero = check(Vec6::Zero(), virgin, 0, "undeformed");
    const Mat6 D = isotropic_elasticity(kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), kE / (2 * (1 + kNu)));
    EXPECT_LT((zero.tangent - D).norm(), 1e-12 * D.norm()) << "the small-strain elasticity at F = I";
    check(green_lagrange(large_deformation(0.002)), virgin, 0, "elastic");
    const State p = check(green_lagrange(large_deformation(1.0)), virgin, 1, "plastic loading from virgin");
    check(green_lagrange(large_deformation(1.0) * Eigen::AngleAxis<Real>(0.3, Vec3::UnitZ()).toRotationMatrix() *
                         Vec3(1.1, 0.97, 1.02).asDiagonal()),
          p.history, 1, "plastic loading from a plastic state");
    check(green_lagrange(Vec3(1.2, 0.93, 0.93).asDiagonal()), virgin, 1, "two equal stretches");
    check(green_lagrange(large_deformation(0.995)), p.history, 0, "elastic unloading from a plastic state");
  }
}

// Small strains: the finite-strain model's stress and plastic strain approach the small-strain
// model's (a yield strain of 1e-6 so that the difference, of the order of the strain, is small).
TEST(J2PlasticityFinite, AgreesWithTheSmallStrainModelAtSmallStrains) {
  const Real sy = 0.21, ey = sy / kE;  // yield strain 1e-6
  for (const J2Hardening& h0 : isotropic_hardenings()) {
    J2Hardening h = h0;
    h.saturation *= sy / kSy;  // Voce: keep saturation / yield as before
    const J2Plasticity small(kE, kNu, sy, h), finite(kE, kNu, sy, h, true);
    const Vec6 strain = 3 * ey * kDirection;
    const State a = eval(small, strain, std::vector<Real>(small.history_size(), 0.0));
    const State b = eval(finite, strain, virgin_history(finite), true);
    EXPECT_EQ(b.history[J2Plasticity::kFiniteYielding], 1);
    EXPECT_LT((a.stress - b.stress).norm(), 1e-4 * a.stress.norm());
    EXPECT_NEAR(b.history[J2Plasticity::kFiniteAlpha], a.history[J2Plasticity::kAlpha],
                1e-4 * a.history[J2Plasticity::kAlpha]);
    EXPECT_LT((a.tangent - b.tangent).norm(), 1e-4 * a.tangent.norm());
  }
}

// The returned state lies on the yield surface: the von Mises stress of the Kirchhoff stress
// tau = F S F^T is sigma_y(alpha); plastic flow preserves volume (det F_p = 1); the
// dissipation is sigma_y0 alpha. Checked after two plastic steps in different directions.
TEST(J2PlasticityFinite, ReturnedStateLiesOnTheYieldSurface) {
  for (const J2Hardening& h : isotropic_hardenings()) {
    const J2Plasticity m(kE, kNu, kSy, h, true);
    const State s = eval_finite(m, large_deformation(1.0), virgin_history(m));
    const Mat3 F2 = large_deformation(0.5) * Vec3(0.9, 1.15, 1.0).asDiagonal();
    const State t = eval_finite(m, F2, s.history);
    for (const auto& [st, F] : {std::pair{&s, large_deformation(1.0)}, std::pair{&t, F2}}) {
      const Real alpha = st->history[J2Plasticity::kFiniteAlpha];
      ASSERT_GT(alpha, 0);
      const Mat3 tau = F * from_voigt_stress(st->stress) * F.transpose();
      EXPECT_NEAR(mises(to_voigt_stress(tau)), m.yield_stress(alpha), 1e-10 * kSy);
      EXPECT_NEAR(plastic_deformation(st->history).determinant(), 1, 1e-12);
      EXPECT_NEAR(st->history[J2Plasticity::kFiniteDissipation], kSy * alpha, 1e-10 * kSy);
      EXPECT_GE(st->history[J2Plasticity::kFiniteWork], st->history[J2Plasticity::kFiniteDissipation] * (1 - 1e-10));
    }
    EXPECT_GT(t.history[J2Plasticity::kFiniteAlpha], s.history[J2Plasticity::kFiniteAlpha]);
  }
}

// Uniaxial tension to a logarithmic strain of 0.5 (65 % elongation): with fixed principal axes
// the logarithmic strains add up exactly, so the exponential map reproduces the closed form at
// any step size: Kirchhoff stress tau = sigma_y(alpha), total axial log strain
// eps = tau / E + alpha, lateral log strain -nu tau / E - alpha / 2 (Hencky elasticity, plastic
// incompressibility). The lateral stretches are set from the closed form and the lateral
// stresses must come out zero; one step and twenty steps give the same state.
TEST(J2PlasticityFinite, UniaxialTensionIsExactAtLargeStrain) {
  for (const J2Hardening& h : isotropic_hardenings()) {
    const J2Plasticity m(kE, kNu, kSy, h, true);
    // alpha from eps = sigma_y(alpha) / E + alpha (increasing in alpha: bisection).
    const auto closed_form = [&](Real eps, Real& alpha, Real& tau, Real& lateral) {
      Real lo = 0, hi = eps;
      for (int i = 0; i < 200; ++i) {
        const Real mid = 0.5 * (lo + hi);
        (m.yield_stress(mid) / kE + mid < eps ? lo : hi) = mid;
      }
      alpha = 0.5 * (lo + hi);
      tau = m.yield_stress(alpha);
      lateral = -kNu * tau / kE - alpha / 2;
    };
    for (int steps : {1, 20}) {
      std::vector<Real> hist = virgin_history(m);
      State s;
      s.stress.setZero();
      Real alpha = 0, tau = 0, lateral = 0;
      for (int k = 1; k <= steps; ++k) {
        const Real eps = 0.5 * k / steps;
        closed_form(eps, alpha, tau, lateral);
        const Mat3 F = Vec3(std::exp(eps), std::exp(lateral), std::exp(lateral)).asDiagonal();
        s = eval_finite(m, F, hist);
        hist = s.history;
      }
      const Real stretch = std::exp(0.5);
      EXPECT_NEAR(s.stress(0) * stretch * stretch, tau, 1e-9 * tau) << steps << " steps, H " << h.H << " voce " << h.voce;
      EXPECT_NEAR(s.stress(1), 0, 1e-9 * tau);
      EXPECT_NEAR(s.stress(2), 0, 1e-9 * tau);
      EXPECT_NEAR(s.history[J2Plasticity::kFiniteAlpha], alpha, 1e-9 * alpha);
      EXPECT_NEAR(std::log(s.history[J2Plasticity::kPlasticDeformation]), alpha, 1e-9 * alpha) << "axial F_p";
    }
  }
}

TEST(J2PlasticityFinite, KinematicHardeningIsRefused) {
  J2Hardening h;
  h.kinematic = 1000;
  EXPECT_THROW(J2Plasticity(kE, kNu, kSy, h, true), Error);
  const J2Plasticity m(kE, kNu, kSy, J2Hardening{}, true);
  std::vector<Real> hist = virgin_history(m);
  EXPECT_EQ(plastic_deformation(hist), Mat3::Identity());
  State s;
  s.history.assign(m.history_size(), 0);
  MaterialInput in;  // small strain input to a finite-strain material
  in.history_old = hist.data();
  in.history_new = s.history.data();
  EXPECT_THROW(m.compute(in, s.stress, s.tangent), Error);
}

// ---- Viscoplasticity (Perzyna overstress) ----


// The viscoplastic tangent against central differences (small and finite strain, rate
// exponents 1 and 3, every hardening), with an overstress of the order of the yield stress.
TEST(J2Viscoplasticity, TangentMatchesCentralDifferences) {
  const Real ey = kSy / kE;
  for (bool finite : {false, true})
    for (Real m : {1.0, 3.0})
      for (const J2Hardening& h : finite ? isotropic_hardenings() : hardenings()) {
        const J2Plasticity mat(kE, kNu, kSy, h, finite, J2Viscosity{20, m});
        std::vector<Real> old(mat.history_size());
        mat.initialize_history(old.data());
        const Vec6 strain = 3 * ey * kDirection;
        const Real dt = 0.1;
        const State s = eval(mat, strain, old, finite, dt);
        ASSERT_EQ(s.history[mat.yielding_slot()], 1);
        const Mat6 num = numeric_tangent(mat, strain, old, 1e-9, finite, dt);
        EXPECT_LT((s.tangent - num).norm(), 1e-6 * s.tangent.norm())
            << (finite ? "finite" : "small") << " m " << m << " H " << h.H << " voce " << h.voce << " kin " << h.kinematic;
        // The overstress is real: the stress is outside the rate-independent yield surface.
        const J2Plasticity ri(kE, kNu, kSy, h, finite);
        const State r = eval(ri, strain, old, finite, dt);
        EXPECT_GT(s.history[mat.alpha_slot()], 0);
        EXPECT_LT(s.history[mat.alpha_slot()], 0.9 * r.history[ri.alpha_slot()]) << "viscosity slows the flow";
      }
}

// Viscosity -> 0 recovers the rate-independent return; viscosity 0 is it; no time (dt = 0, an
// output evaluation) means no viscous flow.
TEST(J2Viscoplasticity, RateIndependentLimitAndNoFlowWithoutTime) {
  const Real ey = kSy / kE;
  for (const J2Hardening& h : hardenings()) {
    const J2Plasticity ri(kE, kNu, kSy, h);
    std::vector<Real> old(ri.history_size(), 0.0);
    const Vec6 strain = 3 * ey * kDirection;
    const State r = eval(ri, strain, old, false, 1.0);
    const State zero = eval(J2Plasticity(kE, kNu, kSy, h, false, J2Viscosity{0, 2}), strain, old, false, 1.0);
    EXPECT_EQ((r.stress - zero.stress).norm(), 0);
    for (Real m : {1.0, 4.0}) {
      const J2Plasticity v(kE, kNu, kSy, h, false, J2Viscosity{1e-10, m});
      const State s = eval(v, strain, old, false, 1.0);
      EXPECT_LT((s.stress - r.stress).norm(), 1e-6 * r.stress.norm() * (m == 1 ? 1 : 1e3)) << "m " << m;
      const State none = eval(v, strain, old, false, 0.0);
      EXPECT_EQ(none.history[J2Plasticity::kYielding], 0);
      EXPECT_EQ(none.history[J2Plasticity::kAlpha], 0);
    }
  }
}

// Uniaxial stress at a constant strain rate, perfectly plastic, m = 1: after yield
// d(sigma)/dt = E (rate - (1 / eta) (sigma / sigma_y - 1)), so sigma tends to the steady
// overstress sigma_y (1 + eta rate) with the time constant eta sigma_y / E:
// sigma(t) = s_ss + (sigma_y - s_ss) exp(-E (t - t_y) / (eta sigma_y)). Backward Euler reaches
// the steady state exactly; on the way it is first-order accurate (50 steps per time constant:
// within 2 % of the overstress). The dissipation equals the plastic work (nothing stored).
TEST(J2Viscoplasticity, UniaxialConstantStrainRate) {
  const Real eta = 2.0, rate = 2e-4;
  const J2Plasticity m(kE, kNu, kSy, J2Hardening{}, false, J2Viscosity{eta, 1});
  const Real tc = eta * kSy / kE, ty = kSy / (kE * rate), s_ss = kSy * (1 + eta * rate);
  const Real dt = tc / 50;
  std::vector<Real> hist(m.history_size(), 0.0);
  Real lateral = 0, worst = 0;
  State s;
  s.stress.setZero();
  for (int k = 1; k * dt < ty + 10 * tc; ++k) {
    const Real t = k * dt, exx = rate * t;
    for (int it = 0; it < 30; ++it) {
      s = eval(m, (Vec6() << exx, lateral, lateral, 0, 0, 0).finished(), hist, false, dt);
      if (std::abs(s.stress(1)) < 1e-11 * kSy) break;
      lateral -= s.stress(1) / (s.tangent(1, 1) + s.tangent(1, 2));
    }
    hist = s.history;
    const Real exact = t < ty ? kE * exx : s_ss + (kSy - s_ss) * std::exp(-(t - ty) / tc);
    worst = std::max(worst, std::abs(s.stress(0) - exact));
  }
  std::printf("steady stress %.6f (closed form %.6f); worst error on the way %.3g of the overstress\n", s.stress(0), s_ss,
              worst / (s_ss - kSy));
  EXPECT_NEAR(s.stress(0), s_ss, 1e-4 * (s_ss - kSy));
  EXPECT_LT(worst, 0.02 * (s_ss - kSy));
  EXPECT_NEAR(hist[J2Plasticity::kDissipation], hist[J2Plasticity::kWork], 1e-9 * hist[J2Plasticity::kWork]);
}
