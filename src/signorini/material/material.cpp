#include "signorini/material/material.hpp"

#include <cmath>

#include "signorini/core/error.hpp"

namespace signorini {

Mat6 isotropic_elasticity(Real lambda, Real mu) {
  Mat6 D = Mat6::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) D(i, j) = lambda;
    D(i, i) += 2 * mu;
    D(i + 3, i + 3) = mu;
  }
  return D;
}

static void lame(Real E, Real nu, Real& lambda, Real& mu) {
  lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  mu = E / (2 * (1 + nu));
}

LinearElastic::LinearElastic(Real E, Real nu) : E_(E), nu_(nu) {
  Real l, m;
  lame(E, nu, l, m);
  D_ = isotropic_elasticity(l, m);
}

void LinearElastic::compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const {
  stress = D_ * in.strain;
  tangent = D_;
}

NeoHookean::NeoHookean(Real E, Real nu) : E_(E), nu_(nu) {
  lame(E, nu, lambda_, mu_);
  D_ = isotropic_elasticity(lambda_, mu_);
}

void NeoHookean::compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const {
  if (!in.finite) {
    stress = D_ * in.strain;
    tangent = D_;
    return;
  }
  const Mat3 C = in.F.transpose() * in.F;
  const Real J = in.F.determinant();
  if (!(J > 0)) throw SolverError("neo_hookean: non-positive volume ratio J = " + std::to_string(J));
  const Mat3 Ci = C.inverse();
  const Real lnJ = std::log(J);
  stress = to_voigt_stress(mu_ * (Mat3::Identity() - Ci) + lambda_ * lnJ * Ci);
  // C_IJKL = lambda Ci_IJ Ci_KL + (mu - lambda lnJ)(Ci_IK Ci_JL + Ci_IL Ci_JK)
  const Real c2 = mu_ - lambda_ * lnJ;
  for (int a = 0; a < 6; ++a) {
    const int I = kVoigtI[a], J_ = kVoigtJ[a];
    for (int b = 0; b < 6; ++b) {
      const int K = kVoigtI[b], L = kVoigtJ[b];
      tangent(a, b) = lambda_ * Ci(I, J_) * Ci(K, L) + c2 * (Ci(I, K) * Ci(J_, L) + Ci(I, L) * Ci(J_, K));
    }
  }
}

}  // namespace signorini
