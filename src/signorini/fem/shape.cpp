#include "signorini/fem/shape.hpp"

#include <cmath>

namespace signorini {

namespace {

// 1D Lagrange basis on nodes {-1, 1} (order 1) or {-1, 0, 1} (order 2), for node at c.
inline void lagrange1d(int order, Real c, Real x, Real& l, Real& dl) {
  if (order == 1) {
    l = 0.5 * (1 + c * x);
    dl = 0.5 * c;
  } else if (std::abs(c) < 0.5) {
    l = 1 - x * x;
    dl = -2 * x;
  } else {
    l = 0.5 * x * (x + c);
    dl = x + 0.5 * c;
  }
}

}  // namespace

void shape_functions(ElementType type, const Vec3& xi, VecX& N, MatX& dN) {
  const ElementInfo& e = element_info(type);
  const int n = e.num_nodes, dim = e.dim;
  N.resize(n);
  dN.setZero(n, std::max(dim, 1));
  switch (e.family) {
    case ShapeFamily::point:
      N(0) = 1;
      return;
    case ShapeFamily::tensor:
      for (int i = 0; i < n; ++i) {
        Real l[3], dl[3];
        for (int d = 0; d < dim; ++d) lagrange1d(e.order, e.ref_coords[i](d), xi(d), l[d], dl[d]);
        N(i) = 1;
        for (int d = 0; d < dim; ++d) N(i) *= l[d];
        for (int d = 0; d < dim; ++d) {
          Real g = dl[d];
          for (int k = 0; k < dim; ++k)
            if (k != d) g *= l[k];
          dN(i, d) = g;
        }
      }
      return;
    case ShapeFamily::serendipity:
      // Quad8 / hex20 (Zienkiewicz & Taylor, The FEM vol. 1, 6th ed., sec. 6.4 and 6.6).
      for (int i = 0; i < n; ++i) {
        const Vec3& c = e.ref_coords[i];
        Real a[3], da[3];  // a_d = 1 + xi_d c_d, or 1 - xi_d^2 on the edge direction
        int zero_dir = -1;
        for (int d = 0; d < dim; ++d) {
          if (std::abs(c(d)) < 0.5) {
            zero_dir = d;
            a[d] = 1 - xi(d) * xi(d);
            da[d] = -2 * xi(d);
          } else {
            a[d] = 1 + xi(d) * c(d);
            da[d] = c(d);
          }
        }
        const Real scale = dim == 2 ? (zero_dir < 0 ? 0.25 : 0.5) : (zero_dir < 0 ? 0.125 : 0.25);
        Real prod = 1;
        for (int d = 0; d < dim; ++d) prod *= a[d];
        if (zero_dir < 0) {
          Real s = -(dim - 1);
          for (int d = 0; d < dim; ++d) s += xi(d) * c(d);
          N(i) = scale * prod * s;
          for (int d = 0; d < dim; ++d) {
            Real pd = da[d];
            for (int k = 0; k < dim; ++k)
              if (k != d) pd *= a[k];
            dN(i, d) = scale * (pd * s + prod * c(d));
          }
        } else {
          N(i) = scale * prod;
          for (int d = 0; d < dim; ++d) {
            Real pd = da[d];
            for (int k = 0; k < dim; ++k)
              if (k != d) pd *= a[k];
            dN(i, d) = scale * pd;
          }
        }
      }
      return;
    case ShapeFamily::simplex: {
      // Barycentric coordinates L_0 = 1 - sum(xi), L_k = xi_{k-1}.
      Real L[4];
      L[0] = 1;
      for (int d = 0; d < dim; ++d) {
        L[d + 1] = xi(d);
        L[0] -= xi(d);
      }
      auto dL = [&](int k, int d) -> Real { return k == 0 ? -1.0 : (k == d + 1 ? 1.0 : 0.0); };
      for (int i = 0; i < n; ++i) {
        const Vec3& c = e.ref_coords[i];
        Real b[4];
        b[0] = 1;
        for (int d = 0; d < dim; ++d) {
          b[d + 1] = c(d);
          b[0] -= c(d);
        }
        int k1 = -1, k2 = -1;  // vertex (b=1) or the two halves of an edge (b=1/2)
        for (int k = 0; k <= dim; ++k) {
          if (b[k] > 0.75) k1 = k;
          else if (b[k] > 0.25) (k1 < 0 ? k1 : k2) = k;
        }
        if (e.order == 1) {
          N(i) = L[k1];
          for (int d = 0; d < dim; ++d) dN(i, d) = dL(k1, d);
        } else if (k2 < 0) {
          N(i) = L[k1] * (2 * L[k1] - 1);
          for (int d = 0; d < dim; ++d) dN(i, d) = (4 * L[k1] - 1) * dL(k1, d);
        } else {
          N(i) = 4 * L[k1] * L[k2];
          for (int d = 0; d < dim; ++d) dN(i, d) = 4 * (dL(k1, d) * L[k2] + L[k1] * dL(k2, d));
        }
      }
      return;
    }
  }
}

}  // namespace signorini
