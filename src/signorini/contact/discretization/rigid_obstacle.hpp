// Node-to-rigid-surface constraints against an analytic obstacle (plane, cylinder, sphere)
// displaced by `offset` and, in plane problems, turned by `theta` about its point (a plane's
// point, a cylinder's centre): the gap is the signed distance, its gradient the unit normal at
// the closest point and its Hessian the normal's derivative, (I - n n) / rho for a curved
// obstacle of radius rho seen from outside (negative from inside). The obstacle's own
// unknowns (`obstacle_dofs`, -1: none: dim translations, then with `rotates` the angle)
// enter with the opposite gradient for the translations, since the gap depends on x - offset.
// Turning moves a plane's normal, n = R(theta) n0: with d = x - p0 - offset and J the
// quarter turn (J n = (-n_y, n_x)), dg/dtheta = d . J n, d2g/dtheta2 = -g, d2g/dx dtheta = J n
// (and -J n for the offset). A circle turned about its centre is the same circle: its gap does
// not depend on theta (friction's slip does: Discretization::add_slip).
#pragma once
#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/surface.hpp"

namespace signorini {

void rigid_obstacle_constraints(const RigidObstacle& obstacle, const Vec3& offset, Real theta, Index obstacle_dofs,
                                bool rotates, const SlaveSurface& slave, const std::vector<Vec3>& x, int dim,
                                Real max_distance, ConstraintSet& out);

// The rotation by theta about the z axis (plane problems).
Mat3 rotation_z(Real theta);

}  // namespace signorini
