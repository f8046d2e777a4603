// Node-to-rigid-surface constraints against an analytic obstacle (plane, cylinder, sphere)
// displaced by `offset`: the gap is the signed distance, its gradient the unit normal at the
// closest point and its Hessian the normal's derivative, (I - n n) / rho for a curved
// obstacle of radius rho seen from outside (negative from inside). The obstacle's own
// displacement unknowns (`obstacle_dofs`, dim of them, -1: none) enter with the opposite
// gradient, since the gap depends on x - offset.
#pragma once
#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/surface.hpp"

namespace signorini {

void rigid_obstacle_constraints(const RigidObstacle& obstacle, const Vec3& offset, Index obstacle_dofs,
                                const SlaveSurface& slave, const std::vector<Vec3>& x, int dim, Real max_distance,
                                ConstraintSet& out);

}  // namespace signorini
