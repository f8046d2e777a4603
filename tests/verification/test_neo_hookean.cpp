// Finite-strain uniaxial tension and compression of a compressible Neo-Hookean bar against
// its closed form (homogeneous deformation, Bonet & Wood 2008, eq. 6.28): the lateral
// stretch s solves S_lat(lambda, s) = 0 and the force is P = lambda S_axial A0.
// Plane stress and axisymmetric give the same uniaxial state as 3D; plane strain keeps the
// out-of-plane stretch at 1. Also asserts quadratic convergence of Newton.
#include <gtest/gtest.h>

#include <cmath>

#include "common.hpp"
#include "signorini/core/log.hpp"
#include "signorini/mesh/structured.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

constexpr Real E = 1000, nu = 0.3;
const Real lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));

// PK2 stress component along a direction of stretch t, for principal stretches.
Real pk2(Real t, Real J) { return mu * (1 - 1 / (t * t)) + lam * std::log(J) / (t * t); }

// Lateral stretch for axial stretch l: both laterals equal (uniaxial) or one held at 1.
Real lateral(Real l, bool plane_strain) {
  Real lo = 0.2, hi = 3;
  for (int i = 0; i < 200; ++i) {
    const Real s = 0.5 * (lo + hi);
    const Real J = plane_strain ? l * s : l * s * s;
    (pk2(s, J) > 0 ? hi : lo) = s;
  }
  return 0.5 * (lo + hi);
}

struct Result {
  Real force, lateral_u, order;
};

Result run(Dimension dim, ElementType type, Real stretch) {
  log::set_level(log::Level::warning);
  const bool three = dim == Dimension::three_d;
  Mesh mesh = three ? structured_box(type, 2, 2, 2, 1, 1, 1) : structured_rectangle(type, 2, 2, 1, 1);
  AnalysisSettings s;
  s.dimension = dim;
  s.finite_strain = true;
  Model m = test::model_on(std::move(mesh), s, std::make_shared<NeoHookean>(E, nu));
  // Axisymmetric: the axis is x = 0 and the bar is stretched along y (z).
  const int axial = dim == Dimension::axisymmetric ? 1 : 0;
  const std::string lo = axial == 0 ? "xmin" : "ymin", hi = axial == 0 ? "xmax" : "ymax";
  Step step;
  step.name = "stretch";
  step.initial_increment = 0.25;
  step.max_increment = 0.25;
  step.dirichlet = {test::fix(lo, axial), test::fix(hi, axial, stretch - 1)};
  if (dim != Dimension::axisymmetric) step.dirichlet.push_back(test::fix("ymin", 1));
  else step.dirichlet.push_back(test::fix("xmin", 0));
  if (three) step.dirichlet.push_back(test::fix("zmin", 2));
  m.steps = {step};
  Analysis an(m);
  AnalysisSummary sum = an.run();
  EXPECT_TRUE(sum.completed) << sum.failure;
  Result r;
  r.force = an.reaction_sum(hi)(axial);
  // Lateral displacement of the corner at the far side.
  const int latc = axial == 0 ? 1 : 0;
  Real ul = 0;
  for (Index n = 0; n < m.mesh.num_nodes(); ++n)
    if (std::abs(m.mesh.nodes[n](latc) - 1) < 1e-12) ul = an.displacement()(an.dofs().dof(n, latc));
  r.lateral_u = ul;
  // Convergence order from the last three residuals above round-off of each increment:
  // p = log(r_{k+1}/r_k) / log(r_k/r_{k-1}).
  r.order = 10;
  for (auto& inc : sum.increments) {
    const auto& res = inc.residuals;
    if (std::getenv("SIGNORINI_TEST_VERBOSE"))
      for (Real v : res) std::printf("  inc %d residual %.3e\n", inc.increment, v);
    if (res.size() < 3) continue;
    for (size_t k = res.size() - 2; k >= 1; --k)
      if (res[k + 1] > 1e-13 && res[k] < 1e-2) {
        r.order = std::min(r.order, std::log(res[k + 1] / res[k]) / std::log(res[k] / res[k - 1]));
        break;
      }
  }
  return r;
}

void check(Dimension dim, ElementType type, Real stretch) {
  const bool ps = dim == Dimension::plane_strain;
  const Real s = lateral(stretch, ps);
  const Real J = ps ? stretch * s : stretch * s * s;
  // Reference area: 1 (3D, plane per unit thickness); axisymmetric: pi r^2 = pi.
  const Real area = dim == Dimension::axisymmetric ? M_PI : 1.0;
  const Real force = stretch * pk2(stretch, J) * area;
  Result r = run(dim, type, stretch);
  const std::string what = to_string(dim) + " " + element_info(type).name + " stretch " + std::to_string(stretch);
  EXPECT_NEAR(r.force, force, 1e-8 * std::abs(force)) << what;
  EXPECT_NEAR(r.lateral_u, s - 1, 1e-7) << what;  // residual tolerance 1e-8
  std::printf("%s: force %.6e (closed form %.6e), lateral stretch %.6f, Newton order >= %.2f\n", what.c_str(), r.force,
              force, 1 + r.lateral_u, r.order);
  EXPECT_GT(r.order, 1.8) << what << ": Newton is not converging quadratically";
}

}  // namespace

TEST(NeoHookeanUniaxial, ThreeDTensionAndCompression) {
  check(Dimension::three_d, ElementType::hex8, 2.0);
  check(Dimension::three_d, ElementType::tet10, 0.6);
}
TEST(NeoHookeanUniaxial, PlaneStress) { check(Dimension::plane_stress, ElementType::quad4, 1.8); }
TEST(NeoHookeanUniaxial, PlaneStrain) { check(Dimension::plane_strain, ElementType::quad8, 1.5); }
TEST(NeoHookeanUniaxial, Axisymmetric) { check(Dimension::axisymmetric, ElementType::quad4, 1.7); }
