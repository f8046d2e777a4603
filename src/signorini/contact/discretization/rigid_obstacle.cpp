#include "signorini/contact/discretization/rigid_obstacle.hpp"

#include <cmath>

namespace signorini {

Mat3 rotation_z(Real theta) {
  Mat3 R = Mat3::Identity();
  R(0, 0) = R(1, 1) = std::cos(theta);
  R(1, 0) = std::sin(theta);
  R(0, 1) = -R(1, 0);
  return R;
}

void rigid_obstacle_constraints(const RigidObstacle& ob, const Vec3& offset, Real theta, Index obstacle_dofs,
                                bool rotates, const SlaveSurface& slave, const std::vector<Vec3>& x, int dim,
                                Real max_distance, ConstraintSet& out) {
  const Vec3 plane_normal = rotates ? Vec3(rotation_z(theta) * ob.normal) : ob.normal;
  const Index ns = static_cast<Index>(slave.nodes.size());
  out = open_constraints(slave);
  for (Index j = 0; j < ns; ++j) {
    Constraint& c = out[j];
    if (!(c.weight > 0)) continue;
    const Vec3 p = x[c.slave];
    Mat3 H = Mat3::Zero();
    if (ob.shape == "plane") {
      c.normal = plane_normal;
      c.gap = (p - (ob.point + offset)).dot(plane_normal);
    } else {
      Vec3 d = p - (ob.point + offset);
      Mat3 P = Mat3::Identity();  // projector on the plane normal to the axis (cylinder in 3D)
      if (ob.shape == "cylinder" && dim == 3) {
        P -= ob.axis * ob.axis.transpose();
        d = P * d;
      }
      if (dim == 2) d(2) = 0;
      const Real r = d.norm();
      if (!(r > 0)) continue;  // at the centre: the normal is undefined
      const Vec3 m = d / r;
      const Real s = ob.inside ? -1.0 : 1.0;
      c.normal = s * m;
      c.gap = s * (r - ob.radius);
      // d2(s |P d|)/dx2 = s (P - m m) / r
      H = s * (P - m * m.transpose()) / r;
    }
    if (c.gap > max_distance) continue;  // far: no constraint
    c.kind = ConstraintKind::node;
    c.facet = -1;
    c.nodes = {c.slave};
    const int m = obstacle_dofs >= 0 ? 2 * dim + (rotates ? 1 : 0) : dim;
    c.grad.setZero(m);
    c.hess.setZero(m, m);
    for (int a = 0; a < dim; ++a) {
      c.grad(a) = c.normal(a);
      for (int b = 0; b < dim; ++b) c.hess(a, b) = H(a, b);
    }
    if (obstacle_dofs >= 0) {
      // g(x - offset): d/d offset = -d/dx; the Hessian has blocks [[H, -H], [-H, H]].
      for (int a = 0; a < dim; ++a) {
        c.extra_dofs.push_back(obstacle_dofs + a);
        c.grad(dim + a) = -c.normal(a);
        for (int b = 0; b < dim; ++b) {
          c.hess(a, dim + b) = -H(a, b);
          c.hess(dim + a, b) = -H(a, b);
          c.hess(dim + a, dim + b) = H(a, b);
        }
      }
    }
    if (obstacle_dofs >= 0 && rotates) {
      const Index t = 2 * dim;  // the angle's column
      c.extra_dofs.push_back(obstacle_dofs + dim);
      if (ob.shape == "plane") {
        const Vec3 jn(-c.normal.y(), c.normal.x(), 0);
        const Vec3 d = p - (ob.point + offset);
        c.grad(t) = d.dot(jn);
        c.hess(t, t) = -c.gap;
        for (int a = 0; a < dim; ++a) {
          c.hess(a, t) = c.hess(t, a) = jn(a);
          c.hess(dim + a, t) = c.hess(t, dim + a) = -jn(a);
        }
      }
    }
    c.normal_jacobian = c.hess.topRows(dim);  // n = d gap / d x_s
  }
}

}  // namespace signorini
