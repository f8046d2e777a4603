// Lamé's thick-walled cylinder under internal pressure, shared by the verification test and
// the long refinement study (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 28):
//   u_r = (1+nu)/E * p a^2/(b^2-a^2) * ((1-2nu) r + b^2/r)
//   sigma_theta = p a^2/(b^2-a^2) (1 + b^2/r^2)
#pragma once
#include <cmath>
#include <numbers>

#include "common.hpp"
#include "signorini/core/log.hpp"
#include "signorini/mesh/structured.hpp"

namespace signorini::test::lame {

constexpr Real a = 0.1, b = 0.2, p = 1e8, E = 210e9, nu = 0.3;
constexpr Real A = p * a * a / (b * b - a * a);
inline Real ur(Real r) { return (1 + nu) / E * A * ((1 - 2 * nu) * r + b * b / r); }
inline Real sigma_theta(Real r) { return A * (1 + b * b / (r * r)); }

// n x n cells: a quarter annulus (plane strain; x axis cut: "ymin", y axis cut: "ymax") or
// an axisymmetric slice of height 0.05 with u_z = 0 on both faces. Inner surface: "xmin".
inline Model model(Dimension dim, ElementType type, int n) {
  log::set_level(log::Level::warning);
  Mesh mesh = structured_rectangle(type, n, n, b - a, dim == Dimension::axisymmetric ? 0.05 : std::numbers::pi / 2);
  for (auto& x : mesh.nodes) {
    const Real r = a + x(0), t = x(1);
    x = dim == Dimension::axisymmetric ? Vec3(r, t, 0) : Vec3(r * std::cos(t), r * std::sin(t), 0);
  }
  AnalysisSettings s;
  s.dimension = dim;
  Model m = model_on(std::move(mesh), s, std::make_shared<LinearElastic>(E, nu));
  Step step;
  step.name = "pressure";
  step.dirichlet = dim == Dimension::axisymmetric ? std::vector{fix("ymin", 1), fix("ymax", 1)}
                                                  : std::vector{fix("ymin", 1), fix("ymax", 0)};
  Load l;
  l.kind = LoadKind::pressure;
  l.set = "xmin";
  l.pressure = p;
  step.loads = {l};
  m.steps = {step};
  return m;
}

}  // namespace signorini::test::lame
