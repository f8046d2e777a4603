// 3D cantilever with a smooth exact solution, and the measured convergence order in the
// energy norm. With nu = 0 the plane-stress cantilever solution of Timoshenko & Goodier
// (Theory of Elasticity, 3rd ed., sec. 21) is an exact 3D elasticity solution (u_z = 0):
//   u = -P x^2 y/(2EI) + P y^3/(6IG) + (P L^2/(2EI) - P c^2/(2IG)) y
//   v =  P x^3/(6EI) - P L^2 x/(2EI) + P L^3/(3EI)
// The exact displacement is prescribed on both end faces; the lateral faces are traction
// free in the exact solution. Expected orders: h^1 (linear), h^2 (quadratic elements).
#include <gtest/gtest.h>

#include <cmath>

#include "common.hpp"
#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;

namespace {

constexpr Real kL = 4, kC = 0.5, kT = 0.5, kE = 1000, kP = 1;
constexpr Real kI = 2 * kC * kC * kC / 3, kG = kE / 2;

Vec3 exact_u(const Vec3& x) {
  const Real X = x(0), Y = x(1);
  return Vec3(-kP * X * X * Y / (2 * kE * kI) + kP * Y * Y * Y / (6 * kI * kG) +
                  (kP * kL * kL / (2 * kE * kI) - kP * kC * kC / (2 * kI * kG)) * Y,
              kP * X * X * X / (6 * kE * kI) - kP * kL * kL * X / (2 * kE * kI) + kP * kL * kL * kL / (3 * kE * kI), 0);
}
// Exact strain (Voigt, engineering shear).
Vec6 exact_strain(const Vec3& x) {
  const Real X = x(0), Y = x(1);
  Vec6 e = Vec6::Zero();
  e(0) = -kP * X * Y / (kE * kI);
  e(5) = -kP / (2 * kI * kG) * (kC * kC - Y * Y);
  return e;
}

struct Level {
  Real h;
  Real energy_error;
};

Level solve(ElementType type, int n) {
  StructuredOptions o;
  o.origin = Vec3(0, -kC, 0);
  Mesh mesh = structured_box(type, 8 * n, 2 * n, n, kL, 2 * kC, kT, o);
  AnalysisSettings s;
  s.dimension = Dimension::three_d;
  auto mat = std::make_shared<LinearElastic>(kE, 0.0);
  Body body("beam", mesh.regions["domain"], mat, s);
  DofMap dofs(mesh.num_nodes(), 3, test::cells_of(body));
  std::vector<char> fixed(mesh.num_nodes(), 0);
  for (const char* set : {"xmin", "xmax"})
    for (Index nd : mesh.node_sets[set]) fixed[nd] = 1;
  VecX u = test::solve_with_prescribed(body, mesh, dofs, fixed, exact_u, VecX::Zero(dofs.num_dofs()));
  // Energy norm of the error, with a quadrature well above the element's degree.
  const Mat6 D = isotropic_elasticity(0.0, kG);
  Real err2 = 0;
  for (auto& b : mesh.regions["domain"]) {
    const ElementInfo& info = element_info(b.type);
    const QuadratureRule rule = quadrature_rule(b.type, 6);
    for (Index e = 0; e < b.size(); ++e) {
      const Index* c = b.element(e);
      for (auto& q : rule) {
        VecX N;
        MatX dN;
        shape_functions(b.type, q.xi, N, dN);
        Mat3 J = Mat3::Zero();
        Vec3 x = Vec3::Zero();
        for (int a = 0; a < info.num_nodes; ++a) {
          x += N(a) * mesh.nodes[c[a]];
          for (int i = 0; i < 3; ++i)
            for (int d = 0; d < 3; ++d) J(i, d) += mesh.nodes[c[a]](i) * dN(a, d);
        }
        const Mat3 Ji = J.inverse();
        Mat3 H = Mat3::Zero();
        for (int a = 0; a < info.num_nodes; ++a) {
          Vec3 g = Ji.transpose() * dN.row(a).transpose();
          for (int i = 0; i < 3; ++i) H.row(i) += u(dofs.dof(c[a], i)) * g.transpose();
        }
        const Vec6 de = to_voigt_strain(0.5 * (H + H.transpose())) - exact_strain(x);
        err2 += de.dot(D * de) * J.determinant() * q.weight;
      }
    }
  }
  return {kT / n, std::sqrt(err2)};
}

void expect_order(ElementType type, int n0, Real min_order, Real max_order) {
  Level a = solve(type, n0), b = solve(type, 2 * n0);
  const Real order = std::log(a.energy_error / b.energy_error) / std::log(a.h / b.h);
  std::printf("%s: energy error %.4e (h=%.4g) -> %.4e (h=%.4g), order %.3f\n", element_info(type).name.c_str(),
              a.energy_error, a.h, b.energy_error, b.h, order);
  EXPECT_GT(a.energy_error, 0);
  EXPECT_GT(order, min_order) << element_info(type).name;
  EXPECT_LT(order, max_order) << element_info(type).name;
}

}  // namespace

TEST(Cantilever3D, Hex8ConvergesAtOrderOne) { expect_order(ElementType::hex8, 2, 0.9, 1.2); }
TEST(Cantilever3D, Tet4ConvergesAtOrderOne) { expect_order(ElementType::tet4, 2, 0.85, 1.2); }
TEST(Cantilever3D, Hex20ConvergesAtOrderTwo) { expect_order(ElementType::hex20, 1, 1.85, 2.3); }
TEST(Cantilever3D, Hex27ConvergesAtOrderTwo) { expect_order(ElementType::hex27, 1, 1.85, 2.3); }
TEST(Cantilever3D, Tet10ConvergesAtOrderTwo) { expect_order(ElementType::tet10, 1, 1.8, 2.3); }
