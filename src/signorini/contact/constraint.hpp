// The plain data between contact discretization and enforcement: one constraint per slave
// node with its weight (tributary area), gap, and the gap's gradient and Hessian over the
// involved nodes (slave first). Enforcement reads only this (DESIGN.md, "the one idea").
#pragma once
#include <vector>

#include "signorini/core/types.hpp"

namespace signorini {

enum class ConstraintKind { none, segment, edge, vertex, node };

struct Constraint {
  ConstraintKind kind = ConstraintKind::none;  // none: no master within reach
  Index slave = -1;        // slave node
  Index facet = -1;        // master facet (segment, edge: a facet along the edge), or master node (vertex, node)
  Real weight = 0;         // tributary area of the slave node
  Real gap = 0;
  Vec3 normal = Vec3::Zero();
  std::vector<Index> nodes;  // slave, then master nodes
  std::vector<Index> extra_dofs;  // unknowns after the nodes' (a rigid obstacle's displacement)
  VecX grad;                 // d gap / d x (dim per node, then the extra DOFs)
  MatX hess;                 // d2 gap / d x2
};

using ConstraintSet = std::vector<Constraint>;

}  // namespace signorini
