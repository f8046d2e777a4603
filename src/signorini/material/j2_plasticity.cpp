#include "signorini/material/j2_plasticity.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "signorini/core/error.hpp"

namespace signorini {

namespace {
const Real kSqrt23 = std::sqrt(2.0 / 3.0);

// Tensor inner product of two symmetric tensors in Voigt form (tensor components).
Real contract(const Vec6& a, const Vec6& b) {
  return a(0) * b(0) + a(1) * b(1) + a(2) * b(2) + 2 * (a(3) * b(3) + a(4) * b(4) + a(5) * b(5));
}

// The divided difference (g(a) - g(b)) / (a - b) of g(x) = ln(x) / x for a, b > 0, g'(b) when
// a = b. With a = b (1 + t): (log1p(t) / t - ln b) / (a b), free of cancellation as a -> b.
Real log_over_x_divided_difference(Real a, Real b) {
  const Real t = (a - b) / b;
  const Real r = t == 0 ? 1.0 : std::log1p(t) / t;
  return (r - std::log(b)) / (a * b);
}
}  // namespace

J2Plasticity::J2Plasticity(Real E, Real nu, Real yield_stress, J2Hardening hardening, bool finite,
                           J2Viscosity viscosity)
    : E_(E), nu_(nu), sy0_(yield_stress), h_(hardening), visc_(viscosity), finite_(finite) {
  if (!(viscosity.viscosity >= 0) || !(viscosity.rate_exponent > 0))
    throw Error("j2_plasticity: the viscosity must be >= 0 and the rate exponent > 0");
  if (finite && hardening.kinematic != 0)
    throw Error("j2_plasticity: kinematic hardening is for small strain only (the finite-strain model has "
                "isotropic hardening)");
  const Real lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  mu_ = E / (2 * (1 + nu));
  kappa_ = lambda + 2 * mu_ / 3;
  D_ = isotropic_elasticity(lambda, mu_);
}

void J2Plasticity::initialize_history(Real* h) const {
  for (int i = 0; i < history_size(); ++i) h[i] = 0;
  if (finite_) h[kPlasticDeformation] = h[kPlasticDeformation + 4] = h[kPlasticDeformation + 8] = 1;  // F_p = I
}

std::vector<std::string> J2Plasticity::history_names() const {
  if (finite_)
    return {"plastic_deformation_xx", "plastic_deformation_xy", "plastic_deformation_xz", "plastic_deformation_yx",
            "plastic_deformation_yy", "plastic_deformation_yz", "plastic_deformation_zx", "plastic_deformation_zy",
            "plastic_deformation_zz", "equivalent_plastic_strain", "plastic_work", "plastic_dissipation", "yielding"};
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

J2Plasticity::Return J2Plasticity::radial_return(Real norm, Real alpha, Real dt) const {
  Return r;
  if (!(norm - kSqrt23 * yield_stress(alpha) > 0)) return r;  // inside the yield surface
  if (visc_.viscosity > 0 && !(dt > 0)) return r;             // no time, no viscous flow
  // g(dg) = |xi_trial| - 2 mu dg - 2/3 H_k dg - sqrt(2/3) sigma_y(alpha + sqrt(2/3) dg) = 0
  // (Box 3.2, step 3). g is decreasing and convex for linear and Voce hardening, so Newton
  // from dg = 0 rises monotonically to the root.
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
  r.plastic = true;
  if (visc_.viscosity == 0) {
    r.dg = dg;
    r.slope = 2.0 / 3.0 * (h_.kinematic + yield_slope(alpha + kSqrt23 * dg));
    return r;
  }
  // Perzyna overstress, backward Euler: d(alpha) / dt = (1 / eta) (q / sigma_y(alpha) - 1)^m
  // (Perzyna 1966; de Souza Neto, Peric & Owen 2008, sec. 11.5), i.e. at the end of the
  // increment |xi| = sqrt(2/3) sigma_y(alpha) (1 + y) with the overstress ratio
  // y = (eta d(alpha) / dt)^(1/m). In y, with dg = c y^m and c = dt / (eta sqrt(2/3)),
  //   G(y) = |xi_trial| - (2 mu + 2/3 H_k) dg - sqrt(2/3) sigma_y(alpha + sqrt(2/3) dg) (1 + y) = 0,
  // G is decreasing (G' <= -sqrt(2/3) sigma_y < 0), G(0) = f_trial > 0 and G <= 0 at the
  // rate-independent dg (y >= 0 there): Newton safeguarded by bisection in that bracket.
  const Real m = visc_.rate_exponent, c = dt / (visc_.viscosity * kSqrt23);
  const Real lin = 2 * mu_ + 2.0 / 3.0 * h_.kinematic;
  auto G = [&](Real y, Real& dG) {
    const Real d = c * std::pow(y, m), a = alpha + kSqrt23 * d;
    const Real ddy = y > 0 ? m * d / y : (m == 1 ? c : 0.0);
    dG = -(lin + 2.0 / 3.0 * yield_slope(a) * (1 + y)) * ddy - kSqrt23 * yield_stress(a);
    return norm - lin * d - kSqrt23 * yield_stress(a) * (1 + y);
  };
  Real lo = 0, hi = std::pow(dg / c, 1 / m), y = 0, dG;
  Real g = G(y, dG);
  for (int it = 0;; ++it) {
    Real next = y - g / dG;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    y = next;
    g = G(y, dG);
    (g > 0 ? lo : hi) = y;
    if (std::abs(g) <= 1e-14 * norm || hi - lo <= 1e-15 * hi) break;
    if (it > 200) throw SolverError("j2_plasticity: the viscoplastic return map did not converge");
  }
  r.dg = c * std::pow(y, m);
  if (!(r.dg > 0)) return Return{};
  r.overstress = y;
  // slope = d/d(dg) [2/3 H_k dg + sqrt(2/3) sigma_y (1 + y)], with dy / d(dg) = y / (m dg).
  const Real a = alpha + kSqrt23 * r.dg;
  r.slope = 2.0 / 3.0 * (h_.kinematic + yield_slope(a) * (1 + y)) + kSqrt23 * yield_stress(a) * y / (m * r.dg);
  return r;
}

Real J2Plasticity::dissipation(Real alpha_new, const Return& r) const {
  return kSqrt23 * r.dg * (sy0_ + yield_stress(alpha_new) * r.overstress);
}

void J2Plasticity::compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const {
  if (in.finite != finite_)
    throw Error(std::string("j2_plasticity was set up for ") + (finite_ ? "finite" : "small") +
                " strain and called with the other kinematics");
  if (!in.history_old || !in.history_new) throw Error("j2_plasticity needs its history storage");
  if (finite_) compute_finite(in, stress, tangent);
  else compute_small(in, stress, tangent);
}

void J2Plasticity::compute_small(const MaterialInput& in, Vec6& stress, Mat6& tangent) const {
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
  const Return r = radial_return(norm, alpha, in.dt);
  if (!r.plastic) {
    stress = trial;
    tangent = D_;
    return;
  }
  const Real dg = r.dg, slope = r.slope;
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
  // d alpha = sqrt(2/3) d gamma), plus the viscous overstress's sigma_y y d alpha.
  h1[kWork] = h0[kWork] + dg * contract(stress, n);
  h1[kDissipation] = h0[kDissipation] + dissipation(h1[kAlpha], r);
  h1[kYielding] = 1;
  // Consistent tangent (Box 3.2, step 4): C = kappa 1 x 1 + 2 mu theta (I - 1/3 1 x 1)
  // - 2 mu theta_bar n x n, with theta = 1 - 2 mu dg / |xi_trial| and theta_bar =
  // 1 / (1 + (K' + H_k) / (3 mu)) - (1 - theta) = 2 mu / (2 mu + slope) - (1 - theta). In Voigt
  // form the symmetric identity maps engineering shears to tensor components with a factor 1/2.
  const Real theta = 1 - 2 * mu_ * dg / norm;
  const Real theta_bar = 2 * mu_ / (2 * mu_ + slope) - (1 - theta);
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

// Finite strain (see the header). With A = F_p,n^-1 the trial elastic right Cauchy-Green
// tensor is C_tr = A^T C A = sum_a x_a N_a N_a^T, its logarithmic strain eps_a = ln(x_a) / 2,
// and the Hencky law gives the principal Kirchhoff (= Mandel, by coaxiality) stresses
// tau_a = kappa tr(eps) + 2 mu dev(eps)_a. The radial return of the small-strain model on those
// principal values gives tau_a = kappa tr(eps) + 2 mu theta dev(eps)_a and the principal
// consistent moduli a_ab = d tau_a / d eps_b (Box 3.2's tangent in principal axes). Since
// F_p,n+1 = exp(dg n) F_p,n with n coaxial with C_tr,
//   S = F_p,n+1^-1 (tau C_e^-1) F_p,n+1^-T = A S~ A^T,  S~ = sum_a (tau_a / x_a) N_a N_a^T,
// an isotropic function of C_tr alone. Its derivative (e.g. Simo & Hughes 1998, sec. 9.5;
// Miehe, CMAME 134, 1996) is
//   dS~ = sum_ab (dS~_a / dx_b) (N_b . dC_tr N_b) N_a N_a^T
//       + sum_{a != b} (S~_a - S~_b) / (x_a - x_b) (N_a . dC_tr N_b) N_a N_b^T,
// with dS~_a / dx_b = a_ab / (2 x_a x_b) - delta_ab tau_a / x_a^2. As tau_a = P + Q eps_a with
// P = (kappa - 2 mu theta / 3) tr(eps) and Q = 2 mu theta, the divided difference is
// -P / (x_a x_b) + Q / 2 (g(x_a) - g(x_b)) / (x_a - x_b), g(x) = ln(x) / x, which is evaluated
// without cancellation (and is g' when the eigenvalues coincide). Pushed by A (m_a = A N_a,
// dC_tr = A^T dC A) and doubled (dS/dE = 2 dS/dC), it is the tangent returned.
void J2Plasticity::compute_finite(const MaterialInput& in, Vec6& stress, Mat6& tangent) const {
  const Real* h0 = in.history_old;
  Real* h1 = in.history_new;
  for (int i = 0; i < history_size(); ++i) h1[i] = h0[i];
  h1[kFiniteYielding] = 0;
  const Mat3 Fp = Eigen::Map<const Eigen::Matrix<Real, 3, 3, Eigen::RowMajor>>(h0 + kPlasticDeformation);
  const Mat3 A = Fp.inverse();
  const Mat3 C = Mat3::Identity() + 2 * from_voigt_strain(in.strain);
  Mat3 Ctr = A.transpose() * C * A;
  Ctr = 0.5 * (Ctr + Ctr.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Mat3> es(Ctr);
  const Vec3 x = es.eigenvalues();
  const Mat3 V = es.eigenvectors();
  if (!(x.minCoeff() > 0) || !std::isfinite(x.maxCoeff()))
    throw SolverError("j2_plasticity: the elastic stretch is not positive (an inverted or collapsed element)");
  Vec3 eps, s;
  for (int a = 0; a < 3; ++a) eps(a) = 0.5 * std::log(x(a));
  const Real tr = eps.sum();
  for (int a = 0; a < 3; ++a) s(a) = 2 * mu_ * (eps(a) - tr / 3);
  const Real norm = s.norm();
  const Real alpha = h0[kFiniteAlpha];
  const Return r = radial_return(norm, alpha, in.dt);
  const Real dg = r.dg, slope = r.slope;
  Real theta = 1, theta_bar = 0;
  Vec3 n = Vec3::Zero();
  if (r.plastic) {
    n = s / norm;
    theta = 1 - 2 * mu_ * dg / norm;
    theta_bar = 2 * mu_ / (2 * mu_ + slope) - (1 - theta);
  }
  Vec3 tau, St;
  for (int a = 0; a < 3; ++a) {
    tau(a) = kappa_ * tr + theta * s(a);
    St(a) = tau(a) / x(a);
  }
  Mat3 c, th = Mat3::Zero();  // dS~_a / dx_b, and the divided differences (a != b)
  const Real P = (kappa_ - 2 * mu_ * theta / 3) * tr, Q = 2 * mu_ * theta;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const Real ab = kappa_ + 2 * mu_ * theta * ((a == b) - 1.0 / 3.0) - 2 * mu_ * theta_bar * n(a) * n(b);
      c(a, b) = ab / (2 * x(a) * x(b)) - (a == b ? tau(a) / (x(a) * x(a)) : 0.0);
      if (a != b) th(a, b) = -P / (x(a) * x(b)) + 0.5 * Q * log_over_x_divided_difference(x(a), x(b));
    }
  const Mat3 m = A * V;  // columns m_a = A N_a
  Mat3 S = Mat3::Zero();
  for (int a = 0; a < 3; ++a) S += St(a) * m.col(a) * m.col(a).transpose();
  stress = to_voigt_stress(S);
  for (int p = 0; p < 6; ++p) {
    const int I = kVoigtI[p], J = kVoigtJ[p];
    for (int q = 0; q < 6; ++q) {
      const int K = kVoigtI[q], L = kVoigtJ[q];
      Real v = 0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          v += c(a, b) * m(I, a) * m(J, a) * m(K, b) * m(L, b);
          if (a != b) v += th(a, b) * m(I, a) * m(J, b) * 0.5 * (m(K, a) * m(L, b) + m(L, a) * m(K, b));
        }
      tangent(p, q) = 2 * v;
    }
  }
  if (!r.plastic) return;
  // F_p,n+1 = exp(dg n) F_p,n (n in the principal axes of C_tr): volume preserving.
  Mat3 expn = Mat3::Zero();
  for (int a = 0; a < 3; ++a) expn += std::exp(dg * n(a)) * V.col(a) * V.col(a).transpose();
  Eigen::Map<Eigen::Matrix<Real, 3, 3, Eigen::RowMajor>>(h1 + kPlasticDeformation) = expn * Fp;
  h1[kFiniteAlpha] = alpha + kSqrt23 * dg;
  // Plastic work tau : d(eps_p) and its dissipated part, as at small strain (per unit
  // reference volume: tau is the Kirchhoff stress).
  h1[kFiniteWork] = h0[kFiniteWork] + dg * tau.dot(n);
  h1[kFiniteDissipation] = h0[kFiniteDissipation] + dissipation(h1[kFiniteAlpha], r);
  h1[kFiniteYielding] = 1;
}

}  // namespace signorini
