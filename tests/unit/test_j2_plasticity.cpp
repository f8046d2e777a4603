// J2 plasticity (material/j2_plasticity): the consistent tangent against central differences
// of the return map (elastic, plastic loading, unloading, each hardening), one-sided at the
// yield surface, and the return map's closed forms (the state it returns lies on the yield
// surface; uniaxial loading follows E H / (E + H) for linear isotropic hardening).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "signorini/material/j2_plasticity.hpp"

using namespace signorini;

namespace {

struct State {
  Vec6 stress;
  Mat6 tangent;
  std::vector<Real> history;
};

State eval(const J2Plasticity& m, const Vec6& strain, const std::vector<Real>& old) {
  State s;
  s.history.assign(m.history_size(), 0);
  MaterialInput in;
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
Mat6 numeric_tangent(const J2Plasticity& m, const Vec6& strain, const std::vector<Real>& old, Real h) {
  Mat6 D;
  for (int b = 0; b < 6; ++b) {
    Vec6 e = Vec6::Zero();
    e(b) = h;
    D.col(b) = (eval(m, strain + e, old).stress - eval(m, strain - e, old).stress) / (2 * h);
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
