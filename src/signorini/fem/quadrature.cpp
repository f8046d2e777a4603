#include "signorini/fem/quadrature.hpp"

#include <cmath>
#include <numbers>

#include "signorini/core/error.hpp"

namespace signorini {

void gauss_legendre(int n, std::vector<Real>& x, std::vector<Real>& w) {
  // Newton iteration on P_n from Chebyshev guesses (Golub-Welsch would also do).
  x.assign(n, 0);
  w.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    Real z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    for (int it = 0; it < 100; ++it) {
      Real p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        Real p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      Real dp = n * (z * p1 - p0) / (z * z - 1);
      Real dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) {
        w[i] = 2 / ((1 - z * z) * dp * dp);
        break;
      }
      w[i] = 2 / ((1 - z * z) * dp * dp);
    }
    x[i] = -z;  // ascending order
  }
}

namespace {

QuadratureRule tensor_rule(int dim, int n) {
  std::vector<Real> x, w;
  gauss_legendre(n, x, w);
  QuadratureRule r;
  const int ny = dim >= 2 ? n : 1, nz = dim >= 3 ? n : 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < n; ++i) {
        QuadraturePoint q;
        q.xi = Vec3(x[i], dim >= 2 ? x[j] : 0, dim >= 3 ? x[k] : 0);
        q.weight = w[i] * (dim >= 2 ? w[j] : 1) * (dim >= 3 ? w[k] : 1);
        r.push_back(q);
      }
  return r;
}

// Collapsed Gauss product on the unit simplex: x = u, y = v(1-u), z = w(1-u)(1-v).
QuadratureRule duffy_rule(int dim, int n) {
  std::vector<Real> x, w;
  gauss_legendre(n, x, w);
  QuadratureRule r;
  auto to01 = [](Real t) { return 0.5 * (t + 1); };
  if (dim == 2) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        Real u = to01(x[i]), v = to01(x[j]);
        r.push_back({Vec3(u, v * (1 - u), 0), 0.25 * w[i] * w[j] * (1 - u)});
      }
  } else {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          Real u = to01(x[i]), v = to01(x[j]), s = to01(x[k]);
          r.push_back({Vec3(u, v * (1 - u), s * (1 - u) * (1 - v)),
                       0.125 * w[i] * w[j] * w[k] * (1 - u) * (1 - u) * (1 - v)});
        }
  }
  return r;
}

}  // namespace

QuadratureRule quadrature_rule(ElementType type, int degree) {
  const ElementInfo& e = element_info(type);
  const int n = std::max(1, (degree + 2) / 2);
  switch (e.family) {
    case ShapeFamily::point:
      return {{Vec3::Zero(), 1.0}};
    case ShapeFamily::tensor:
    case ShapeFamily::serendipity:
      return tensor_rule(e.dim, n);
    case ShapeFamily::simplex:
      if (e.dim == 2) {
        if (degree <= 1) return {{Vec3(1. / 3, 1. / 3, 0), 0.5}};
        if (degree == 2)
          return {{Vec3(1. / 6, 1. / 6, 0), 1. / 6},
                  {Vec3(2. / 3, 1. / 6, 0), 1. / 6},
                  {Vec3(1. / 6, 2. / 3, 0), 1. / 6}};
        return duffy_rule(2, (degree + 3) / 2);
      }
      if (degree <= 1) return {{Vec3(0.25, 0.25, 0.25), 1. / 6}};
      if (degree == 2) {
        // 4-point rule, degree 2 (Zienkiewicz & Taylor vol. 1, table 6.4).
        const Real a = 0.5854101966249685, b = 0.1381966011250105;
        return {{Vec3(b, b, b), 1. / 24}, {Vec3(a, b, b), 1. / 24},
                {Vec3(b, a, b), 1. / 24}, {Vec3(b, b, a), 1. / 24}};
      }
      return duffy_rule(3, (degree + 4) / 2);
  }
  throw Error("no quadrature rule for " + e.name);
}

int default_quadrature_degree(ElementType type) {
  const ElementInfo& e = element_info(type);
  if (e.family == ShapeFamily::simplex) return e.order == 1 ? 1 : 2;
  return 2 * e.order;
}

}  // namespace signorini
