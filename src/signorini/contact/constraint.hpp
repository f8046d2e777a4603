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
  // The reported pressure per multiplier where the discretization reports the multiplier
  // (Discretization::pressure_is_multiplier): 1, or for 3D mortar on quadratic slave facets
  // int_c N~_j dA / int N~_j dA0, its current covered weight over its reference one (the
  // multiplier is per current area, the reported pressure per reference area).
  Real pressure_factor = 1;
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

// One integration point of a slave facet that found the master (segment_to_segment for
// Nitsche's method, enforcement/enforcement.hpp): its gap and the gap's variations, and the
// slave body's normal pressure p = -n.sigma.n at the point from the stress of the cell that
// owns the facet (fem/boundary_traction.hpp) with its gradient.
struct PointConstraint {
  Index facet = -1;    // slave facet
  Real weight = 0;     // quadrature weight times the reference area element (x thickness or 2 pi r)
  Real gap = 0;
  std::vector<Index> nodes;  // the facet's nodes (facet_nodes of them), the master nodes, the cell's other nodes
  int facet_nodes = 0;
  VecX grad;                 // d gap / d x over `nodes` (dim each; zero on the cell's other nodes)
  MatX hess;                 // d2 gap / d x2 over the first gap_nodes of `nodes` (the others': zero)
  int gap_nodes = 0;
  Real pressure = 0;         // p = -n.sigma.n (compression positive)
  VecX pressure_grad;        // dp / du over `nodes`
  Real stiffness = 0;        // Nitsche's parameter 1/gamma = gamma0 E / h (pressure per length)
  int q = 0;                 // the facet's integration point
  // The master point it projects on, as master nodes and their shape functions there (friction's
  // slip origin, taken at the start of the increment).
  std::vector<std::pair<Index, Real>> master_point;
  // Friction (a point with a slip origin): the slave facet's reference unit normal nu (outward),
  // the slave body's traction t = sigma.nu and dt/du over `nodes` (dim rows), and the slip of the
  // increment d = x_s(xi_q) - x_0 (x_0 the origin's master material point) with D = dd/dz over
  // `nodes` (dim rows, constant). Small strain: nu is fixed, the tangential parts are
  // (I - nu nu^T) of these. Finite strain: nu is the facet's current unit normal at the point,
  // normal_jacobian = d nu / dx over `nodes` (dim rows; empty at small strain), t the nominal
  // traction (per reference area) and p = -nu.t.
  bool has_slip = false;
  Vec3 normal = Vec3::Zero();
  MatX normal_jacobian;
  Vec3 traction = Vec3::Zero();
  MatX traction_grad;
  Vec3 slip = Vec3::Zero();
  MatX slip_jacobian;
  // Per slave node of the facet (index into the pair's slave nodes): N+_j(xi_q) weight / w+_j,
  // N+ = max(N~, 0) the positive part of the modified basis and w+_j its integral over the
  // node's facets: the share of the point's pressure in node j's reported pressure, a
  // positive-weighted average (the dual basis, whose functions change sign, gave negative
  // pressures next to the edge of the contact zone).
  std::vector<std::pair<Index, Real>> shares;
};

}  // namespace signorini
