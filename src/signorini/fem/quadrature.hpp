// Quadrature rules on the reference elements: Gauss-Legendre products on lines, quads
// and hexes; classical low-order rules and collapsed (Duffy) Gauss products on simplices.
#pragma once
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/mesh/element_type.hpp"

namespace signorini {

struct QuadraturePoint {
  Vec3 xi;
  Real weight;
};
using QuadratureRule = std::vector<QuadraturePoint>;

// Points and weights of the n-point Gauss-Legendre rule on [-1, 1].
void gauss_legendre(int n, std::vector<Real>& x, std::vector<Real>& w);
// A rule that integrates polynomials of total (simplex) or per-direction (tensor) degree
// `degree` exactly on the reference element of `type`.
QuadratureRule quadrature_rule(ElementType type, int degree);
// The default degree for the stiffness of an element: exact for affine elements.
int default_quadrature_degree(ElementType type);

}  // namespace signorini
