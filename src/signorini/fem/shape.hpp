// Shape functions and their reference derivatives for every element type, computed from
// the reference node coordinates of the catalogue (so the node order cannot drift from it).
#pragma once
#include "signorini/core/types.hpp"
#include "signorini/mesh/element_type.hpp"

namespace signorini {

// N(i) for node i, dN(i, d) = dN_i/dxi_d (d < dim) at reference point xi.
void shape_functions(ElementType type, const Vec3& xi, VecX& N, MatX& dN);

}  // namespace signorini
