// Node-to-rigid-surface constraints against an analytic obstacle (plane, cylinder, sphere)
// displaced by `offset`: the gap is the signed distance, its gradient the unit normal at the
// closest point and its Hessian the normal's derivative, (I - n n) / rho for a curved
// obstacle of radius rho seen from outside (negative from inside).
#pragma once
#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/surface.hpp"

namespace signorini {

void rigid_obstacle_constraints(const RigidObstacle& obstacle, const Vec3& offset, const SlaveSurface& slave,
                                const std::vector<Vec3>& x, int dim, Real max_distance, ConstraintSet& out);

}  // namespace signorini
