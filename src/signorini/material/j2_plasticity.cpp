#include "signorini/material/j2_plasticity.hpp"

#include <cmath>

#include "signorini/core/error.hpp"

namespace signorini {

namespace {
const Real kSqrt23 = std::sqrt(2.0 / 3.0);

// Tensor inner product of two symmetric tensors in Voigt form (tensor components).
Real contract(const Vec6& a, const Vec6& b) {
  return a(0) * b(0) + a(1) * b(1) + a(2) * b(2) + 2 * (a(3) * b(3) + a(4) * b(4) + a(5) * b(5));
}
}  // namespace

J2Plasticity::J2Plasticity(Real E, Real nu, Real yield_stress, J2Hardening hardening)
    : E_(E), nu_(nu), sy0_(yield_stress), h_(hardening) {
  const Real lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  mu_ = E / (2 * (1 + nu));
  kappa_ = lambda + 2 * mu_ / 3;
  D_ = isotropic_elasticity(lambda, mu_);
}

std::vector<std::string> J2Plasticity::history_names() const {
  return {"plastic_strain_xx", "plastic_strain_yy", "plastic_strain_zz", "plastic_strain_yz", "plastic_strain_xz",
          "plastic_strain_xy", "equivalent_plastic_strain", "back_stress_xx", "back_stress_yy", "back_stress_zz",
          "back_stress_yz", "back_stress_xz", "back_stress_xy", "plastic_work", "plastic_dissipation", "yielding"};
}

Real J2Plasticity::yield_stress(Real alpha) const {
  Real s = sy0_ + h_.H * alpha;
  if (h_.voce) s += (h_.saturation - sy0_) * (1 - std::exp(-h_.rate * alpha));
  return s;
}

Real J2Plasticity::yield_slope(Real alpha) const {
  Real d = h_.H;
  if (h_.voce) d += (h_.saturation - sy0_) * h_.rate * std::exp(-h_.rate * alpha);
  return d;
}

void J2Plasticity::compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const {
  if (in.finite) throw Error("j2_plasticity is a small-strain model (kinematics: small_strain)");
  if (!in.history_old || !in.history_new) throw Error("j2_plasticity needs its history storage");
  const Real* h0 = in.history_old;
  Real* h1 = in.history_new;
  for (int i = 0; i < history_size(); ++i) h1[i] = h0[i];
  h1[kYielding] = 0;
  const Vec6 eps_p = Eigen::Map<const Vec6>(h0 + kPlasticStrain);
  const Vec6 beta = Eigen::Map<const Vec6>(h0 + kBackStress);
  const Real alpha = h0[kAlpha];
  // Elastic trial state (Box 3.2, step 1).
  const Vec6 trial = D_ * (in.strain - eps_p);
  const Real p = (trial(0) + trial(1) + trial(2)) / 3;
  Vec6 s = trial;
  for (int i = 0; i < 3; ++i) s(i) -= p;
  const Vec6 xi = s - beta;
  const Real norm = std::sqrt(contract(xi, xi));
  const Real f = norm - kSqrt23 * yield_stress(alpha);
  if (f <= 0 || norm == 0) {
    stress = trial;
    tangent = D_;
    return;
  }
  // Return map: g(dg) = |xi_trial| - 2 mu dg - 2/3 H_k dg - sqrt(2/3) sigma_y(alpha + sqrt(2/3) dg)
  // = 0 (Box 3.2, step 3). g is decreasing and convex for linear and Voce hardening, so
  // Newton from dg = 0 rises monotonically to the root.
  Real dg = 0;
  for (int it = 0;; ++it) {
    const Real a = alpha + kSqrt23 * dg;
    const Real g = norm - 2 * mu_ * dg - 2.0 / 3.0 * h_.kinematic * dg - kSqrt23 * yield_stress(a);
    const Real dgdx = -2 * mu_ - 2.0 / 3.0 * (h_.kinematic + yield_slope(a));
    const Real step = -g / dgdx;
    dg += step;
    if (std::abs(step) <= 1e-14 * std::max(dg, 1e-300) || std::abs(g) <= 1e-14 * norm) break;
    if (it > 50) throw SolverError("j2_plasticity: the return map did not converge");
  }
  const Vec6 n = xi / norm;
  stress = trial - 2 * mu_ * dg * n;
  Vec6 deps_p = dg * n;
  deps_p.tail<3>() *= 2;  // engineering shears
  Eigen::Map<Vec6>(h1 + kPlasticStrain) = eps_p + deps_p;
  Eigen::Map<Vec6>(h1 + kBackStress) = beta + 2.0 / 3.0 * h_.kinematic * dg * n;
  h1[kAlpha] = alpha + kSqrt23 * dg;
  // Plastic work sigma : d eps_p (backward Euler). Of it, the hardening stores
  // int (sigma_y - sigma_y0) d alpha (isotropic) and the back stress's energy (kinematic);
  // the rest, sigma_y0 d alpha, is dissipated (from |s - beta| = sqrt(2/3) sigma_y and
  // d alpha = sqrt(2/3) d gamma).
  h1[kWork] = h0[kWork] + dg * contract(stress, n);
  h1[kDissipation] = h0[kDissipation] + sy0_ * kSqrt23 * dg;
  h1[kYielding] = 1;
  // Consistent tangent (Box 3.2, step 4): C = kappa 1 x 1 + 2 mu theta (I - 1/3 1 x 1)
  // - 2 mu theta_bar n x n, with theta = 1 - 2 mu dg / |xi_trial| and theta_bar =
  // 1 / (1 + (K' + H_k) / (3 mu)) - (1 - theta). In Voigt form the symmetric identity maps
  // engineering shears to tensor components with a factor 1/2.
  const Real theta = 1 - 2 * mu_ * dg / norm;
  const Real theta_bar = 1 / (1 + (yield_slope(h1[kAlpha]) + h_.kinematic) / (3 * mu_)) - (1 - theta);
  Mat6 dev = Mat6::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) dev(i, j) = -1.0 / 3.0;
    dev(i, i) += 1;
    dev(i + 3, i + 3) = 0.5;
  }
  Mat6 vol = Mat6::Zero();
  vol.topLeftCorner<3, 3>().setOnes();
  tangent = kappa_ * vol + 2 * mu_ * theta * dev - 2 * mu_ * theta_bar * n * n.transpose();
}

}  // namespace signorini
