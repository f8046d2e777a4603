// Node-to-rigid-surface constraints against an analytic obstacle (plane, cylinder, sphere)
// displaced by `offset` and turned by `rot` (null: it does not turn) about its point (a
// plane's point, a cylinder's axis point, a sphere's centre): the gap is the signed distance,
// its gradient the unit normal at the closest point and its Hessian the normal's derivative,
// (I - n n) / rho for a curved obstacle of radius rho seen from outside (negative from inside).
// The obstacle's own unknowns (`obstacle_dofs`, -1: none: dim translations, then rot->n
// angles) enter by the chain rule through the obstacle's frame: with d = x - p0 - offset the
// gap is g0(y) of the unturned obstacle at y = R^T d, so (n0 = grad g0, H0 its Hessian)
//   dg/dx = R n0 = n,  dg/d offset = -n,  dg/dtheta_i = (R_,i n0) . d,
//   d2g/dx2 = R H0 R^T = d2g/d offset2 = -d2g/dx d offset,
//   d2g/dx dtheta_i = R_,i n0 + R H0 R_,i^T d  (and its opposite for the offset),
//   d2g/dtheta_i dtheta_j = (R_,ij n0) . d + (R_,i^T d) . H0 (R_,j^T d).
// A circle or sphere turned about its centre is the same shape: its gap does not depend on the
// angles (friction's slip does: Discretization::add_slip).
#pragma once
#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/geometry/rotation.hpp"
#include "signorini/contact/surface.hpp"

namespace signorini {

void rigid_obstacle_constraints(const RigidObstacle& obstacle, const Vec3& offset, const Rotation* rot,
                                Index obstacle_dofs, const SlaveSurface& slave, const std::vector<Vec3>& x, int dim,
                                Real max_distance, ConstraintSet& out);

}  // namespace signorini
