#include "signorini/contact/discretization/rigid_obstacle.hpp"

#include <cmath>

namespace signorini {

void rigid_obstacle_constraints(const RigidObstacle& ob, const Vec3& offset, const Rotation* rot,
                                Index obstacle_dofs, const SlaveSurface& slave, const std::vector<Vec3>& x, int dim,
                                Real max_distance, ConstraintSet& out) {
  const Mat3 R = rot ? rot->R : Mat3::Identity();
  const int na = rot && obstacle_dofs >= 0 ? rot->n : 0;  // angles among the unknowns
  const Index ns = static_cast<Index>(slave.nodes.size());
  out = open_constraints(slave);
  for (Index j = 0; j < ns; ++j) {
    Constraint& c = out[j];
    if (!(c.weight > 0)) continue;
    Vec3 d = x[c.slave] - (ob.point + offset);
    if (dim == 2) d(2) = 0;
    const Vec3 y = R.transpose() * d;  // in the obstacle's frame
    Vec3 n0;
    Mat3 H0 = Mat3::Zero();
    if (ob.shape == "plane") {
      n0 = ob.normal;
      c.gap = y.dot(n0);
    } else {
      Vec3 q = y;
      Mat3 P = Mat3::Identity();  // projector on the plane normal to the axis (cylinder in 3D)
      if (ob.shape == "cylinder" && dim == 3) {
        P -= ob.axis * ob.axis.transpose();
        q = P * q;
      }
      if (dim == 2) {
        q(2) = 0;
        P(2, 2) = 0;
      }
      const Real r = q.norm();
      if (!(r > 0)) continue;  // at the centre: the normal is undefined
      const Vec3 m = q / r;
      const Real s = ob.inside ? -1.0 : 1.0;
      n0 = s * m;
      c.gap = s * (r - ob.radius);
      // d2(s |P y|)/dy2 = s (P - m m) / r
      H0 = s * (P - m * m.transpose()) / r;
    }
    if (c.gap > max_distance) continue;  // far: no constraint
    c.normal = R * n0;
    const Mat3 H = R * H0 * R.transpose();
    c.kind = ConstraintKind::node;
    c.facet = -1;
    c.nodes = {c.slave};
    const int m = obstacle_dofs >= 0 ? 2 * dim + na : dim;
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
    for (int i = 0; i < na; ++i) {
      const Index t = 2 * dim + i;  // angle i's column
      c.extra_dofs.push_back(obstacle_dofs + dim + i);
      const Vec3 ri = rot->dR[i] * n0, yi = rot->dR[i].transpose() * d;
      c.grad(t) = ri.dot(d);
      const Vec3 cross = ri + R * (H0 * yi);
      for (int a = 0; a < dim; ++a) {
        c.hess(a, t) = c.hess(t, a) = cross(a);
        c.hess(dim + a, t) = c.hess(t, dim + a) = -cross(a);
      }
      for (int k = 0; k < na; ++k) {
        const Vec3 yk = rot->dR[k].transpose() * d;
        c.hess(t, 2 * dim + k) = (rot->d2R[i][k] * n0).dot(d) + yi.dot(H0 * yk);
      }
    }
    c.normal_jacobian = c.hess.topRows(dim);  // n = d gap / d x_s
  }
}

}  // namespace signorini
