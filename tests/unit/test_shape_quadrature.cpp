// Shape functions (partition of unity, Kronecker property, derivatives against central
// finite differences) and quadrature exactness on every reference element.
#include <gtest/gtest.h>

#include <cmath>

#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"

using namespace signorini;

namespace {
std::vector<ElementType> cell_and_facet_types() {
  std::vector<ElementType> v;
  for (auto t : all_element_types())
    if (element_info(t).dim >= 1) v.push_back(t);
  return v;
}
// A point inside the reference element, away from nodes.
Vec3 interior_point(const ElementInfo& e) {
  if (e.family == ShapeFamily::simplex) return Vec3(0.21, e.dim > 1 ? 0.17 : 0, e.dim > 2 ? 0.13 : 0);
  return Vec3(0.31, e.dim > 1 ? -0.47 : 0, e.dim > 2 ? 0.23 : 0);
}
Real factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }
}  // namespace

TEST(Shape, PartitionOfUnityAndKronecker) {
  for (ElementType t : cell_and_facet_types()) {
    const ElementInfo& e = element_info(t);
    VecX N;
    MatX dN;
    shape_functions(t, interior_point(e), N, dN);
    EXPECT_NEAR(N.sum(), 1.0, 1e-13) << e.name;
    for (int d = 0; d < e.dim; ++d) EXPECT_NEAR(dN.col(d).sum(), 0.0, 1e-12) << e.name;
    for (int i = 0; i < e.num_nodes; ++i) {
      shape_functions(t, e.ref_coords[i], N, dN);
      for (int j = 0; j < e.num_nodes; ++j) EXPECT_NEAR(N(j), i == j ? 1.0 : 0.0, 1e-13) << e.name << " " << i << "," << j;
    }
  }
}

TEST(Shape, DerivativesMatchCentralDifferences) {
  const Real h = 1e-6;
  for (ElementType t : cell_and_facet_types()) {
    const ElementInfo& e = element_info(t);
    const Vec3 x = interior_point(e);
    VecX N, Np, Nm;
    MatX dN, tmp;
    shape_functions(t, x, N, dN);
    for (int d = 0; d < e.dim; ++d) {
      Vec3 xp = x, xm = x;
      xp(d) += h;
      xm(d) -= h;
      shape_functions(t, xp, Np, tmp);
      shape_functions(t, xm, Nm, tmp);
      for (int i = 0; i < e.num_nodes; ++i)
        EXPECT_NEAR(dN(i, d), (Np(i) - Nm(i)) / (2 * h), 1e-8) << e.name << " node " << i << " dir " << d;
    }
  }
}

TEST(Shape, ReproducesLinearFields) {
  // Isoparametric completeness: sum N_i x_i = x for every element.
  for (ElementType t : cell_and_facet_types()) {
    const ElementInfo& e = element_info(t);
    VecX N;
    MatX dN;
    const Vec3 x = interior_point(e);
    shape_functions(t, x, N, dN);
    Vec3 s = Vec3::Zero();
    for (int i = 0; i < e.num_nodes; ++i) s += N(i) * e.ref_coords[i];
    EXPECT_NEAR((s - x).norm(), 0, 1e-13) << e.name;
  }
}

// Exact integral of x^a y^b z^c over the reference element.
static Real exact_monomial(const ElementInfo& e, int a, int b, int c) {
  if (e.family == ShapeFamily::simplex) {
    if (e.dim == 2) return factorial(a) * factorial(b) / factorial(a + b + 2);
    return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
  }
  auto line = [](int k) { return k % 2 ? 0.0 : 2.0 / (k + 1); };
  Real v = line(a);
  if (e.dim > 1) v *= line(b);
  if (e.dim > 2) v *= line(c);
  return v;
}

TEST(Quadrature, ExactForItsDegree) {
  for (ElementType t : cell_and_facet_types()) {
    const ElementInfo& e = element_info(t);
    for (int degree = 1; degree <= 6; ++degree) {
      const QuadratureRule rule = quadrature_rule(t, degree);
      for (int a = 0; a <= degree; ++a)
        for (int b = 0; b <= (e.dim > 1 ? degree : 0); ++b)
          for (int c = 0; c <= (e.dim > 2 ? degree : 0); ++c) {
            const bool simplex = e.family == ShapeFamily::simplex;
            if (simplex && a + b + c > degree) continue;
            Real q = 0;
            for (auto& p : rule)
              q += p.weight * std::pow(p.xi(0), a) * std::pow(p.xi(1), b) * std::pow(p.xi(2), c);
            EXPECT_NEAR(q, exact_monomial(e, a, b, c), 1e-13)
                << e.name << " degree " << degree << " monomial " << a << b << c;
          }
    }
  }
}

TEST(Quadrature, GaussLegendreWeightsSumToTwo) {
  for (int n = 1; n <= 10; ++n) {
    std::vector<Real> x, w;
    gauss_legendre(n, x, w);
    Real s = 0;
    for (Real v : w) s += v;
    EXPECT_NEAR(s, 2.0, 1e-14) << n;
    EXPECT_TRUE(std::is_sorted(x.begin(), x.end()));
  }
}
