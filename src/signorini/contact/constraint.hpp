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
  // d normal / d x (dim rows, the columns of grad): the normal's variation, which friction's
  // tangent needs. Node-to-segment and the rigid obstacles have n = d gap / d x_s, so it is the
  // first dim rows of hess; node-to-node freezes the normal (zero); mortar's averaged nodal
  // normals have their own.
  MatX normal_jacobian;
  // The closest master point as a combination of nodes[1..] (friction: where the slave node
  // touches the master material).
  std::vector<Real> master_weights;
  // The slave node's own coefficient in that combination's counterpart: the slip origin is
  // x_s - (slave_coefficient x_s + ...); 1 but for segment-to-segment, whose weighted slave
  // point is a combination of the slave facets' nodes (master_weights then holds minus the
  // other slave nodes' coefficients too).
  Real slave_coefficient = 1;
  // Friction kinematics, set by the contact interface for a pair with friction: d = x_s - x_0
  // with x_0 the master material point that was closest at the start of the increment (its
  // tangential part is the slip of the increment, course: g_t dt = delta rho(xi)), and
  // D = dd/dz over the DOFs of `nodes` then `extra_dofs` (dim rows; constant but for a turning
  // obstacle, see slip_hessian).
  bool has_slip = false;
  Vec3 slip = Vec3::Zero();
  MatX slip_jacobian;
  // d2 d_i / dz2 (i < dim, over the columns of grad) where D is not constant (a rigid obstacle
  // that turns: its material point moves on a circle); empty: D is constant.
  std::vector<MatX> slip_hessian;
  // The tangential part of d: the slip of the increment (a sticking node's elastic slip).
  Vec3 tangential_slip() const { return slip - normal * normal.dot(slip); }
};

using ConstraintSet = std::vector<Constraint>;

}  // namespace signorini
