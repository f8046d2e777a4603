// Material stress and tangent against central finite differences of the strain energy and
// of the stress (Neo-Hookean, linear elastic), and the elastic constants they stand for.
#include <gtest/gtest.h>

#include <cmath>

#include "signorini/material/material.hpp"

using namespace signorini;

namespace {

// Neo-Hookean strain energy (Bonet & Wood eq. 6.27), to check the stress against.
Real nh_energy(Real E, Real nu, const Mat3& C) {
  const Real lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const Real lnJ = 0.5 * std::log(C.determinant());
  return 0.5 * mu * (C.trace() - 3) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
}

// A deformation gradient whose right Cauchy-Green tensor is I + 2E (F = L^T, C = L L^T).
Mat3 f_from_strain(const Mat3& E) {
  Mat3 C = Mat3::Identity() + 2 * E;
  Eigen::LLT<Mat3> llt(C);
  return llt.matrixL().transpose();
}

// Perturbation of E along Voigt component a by h (engineering shear).
Mat3 voigt_direction(int a, Real h) {
  Mat3 d = Mat3::Zero();
  const int i = kVoigtI[a], j = kVoigtJ[a];
  if (i == j) d(i, i) = h;
  else d(i, j) = d(j, i) = h / 2;
  return d;
}

void eval(const Material& m, const Mat3& E, bool finite, Vec6& S, Mat6& D) {
  MaterialInput in;
  in.finite = finite;
  in.F = f_from_strain(E);
  in.strain = to_voigt_strain(E);
  m.compute(in, S, D);
}

const Mat3 kStrain = (Mat3() << 0.08, 0.02, -0.015, 0.02, -0.05, 0.03, -0.015, 0.03, 0.11).finished();

}  // namespace

TEST(Material, NeoHookeanStressIsEnergyGradient) {
  NeoHookean m(1000, 0.3);
  Vec6 S;
  Mat6 D;
  eval(m, kStrain, true, S, D);
  const Real h = 1e-6;
  for (int a = 0; a < 6; ++a) {
    const Real wp = nh_energy(1000, 0.3, Mat3::Identity() + 2 * (kStrain + voigt_direction(a, h)));
    const Real wm = nh_energy(1000, 0.3, Mat3::Identity() + 2 * (kStrain - voigt_direction(a, h)));
    EXPECT_NEAR(S(a), (wp - wm) / (2 * h), 1e-6 * 1000) << "component " << a;
  }
}

TEST(Material, TangentsMatchCentralDifferences) {
  NeoHookean nh(1000, 0.3);
  LinearElastic le(1000, 0.3);
  for (const Material* m : {static_cast<const Material*>(&nh), static_cast<const Material*>(&le)})
    for (bool finite : {false, true}) {
      Vec6 S, Sp, Sm;
      Mat6 D, tmp;
      eval(*m, kStrain, finite, S, D);
      const Real h = 1e-6;
      for (int b = 0; b < 6; ++b) {
        eval(*m, kStrain + voigt_direction(b, h), finite, Sp, tmp);
        eval(*m, kStrain - voigt_direction(b, h), finite, Sm, tmp);
        for (int a = 0; a < 6; ++a)
          EXPECT_NEAR(D(a, b), (Sp(a) - Sm(a)) / (2 * h), 1e-5 * 1000)
              << m->model() << (finite ? " finite" : " small") << " D(" << a << "," << b << ")";
      }
    }
}

TEST(Material, NeoHookeanLinearizesToHooke) {
  NeoHookean nh(1000, 0.3);
  LinearElastic le(1000, 0.3);
  Vec6 S1, S2;
  Mat6 D1, D2;
  eval(nh, Mat3::Zero(), true, S1, D1);
  eval(le, Mat3::Zero(), false, S2, D2);
  EXPECT_NEAR(S1.norm(), 0, 1e-12);
  EXPECT_NEAR((D1 - D2).norm(), 0, 1e-9 * D2.norm());
}

TEST(Material, UniaxialStressRecoversYoungsModulusAndPoisson) {
  // Inverting the elasticity matrix: a uniaxial stress sigma gives eps = sigma/E and -nu eps laterally.
  const Real E = 210e9, nu = 0.28;
  LinearElastic le(E, nu);
  Vec6 S;
  Mat6 D;
  eval(le, Mat3::Zero(), false, S, D);
  Vec6 sig = Vec6::Zero();
  sig(0) = 1e6;
  Vec6 eps = D.lu().solve(sig);
  EXPECT_NEAR(eps(0), 1e6 / E, 1e-12 * 1e6 / E * 1e3);
  EXPECT_NEAR(-eps(1) / eps(0), nu, 1e-12);
  EXPECT_NEAR(-eps(2) / eps(0), nu, 1e-12);
}
