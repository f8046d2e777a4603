// Rotations of rigid bodies and rigid obstacles, with their first and second derivatives in
// the angles (the contact chain rule and the moment loads need both).
//  - Plane problems: one angle theta about z, R = [[cos, -sin], [sin, cos]].
//  - 3D: the rotation vector theta (axis times angle), R = exp([theta]x) by Rodrigues' formula
//      R = I + a(t) K + b(t) K^2,  K = [theta]x,  t = |theta|^2,
//      a = sin(s)/s,  b = (1 - cos s)/s^2,  s = sqrt(t)
//    (Argyris 1982, "An excursion into large rotations", CMAME 32, eq. 8). a and b are smooth
//    in t, so the derivatives are taken in t (their power series below |theta| = 0.5), and
//    R's derivatives follow exactly by forward automatic differentiation (hyper_dual.hpp).
//    The parametrization is one-to-one for |theta| < pi and singular at |theta| = 2 pi.
// The spin of the body, omega = axial(dR/dt R^T), is T(theta) dtheta/dt, column i of T being
// axial(dR/dtheta_i R^T) (Cardona & Geradin 1988, "A beam finite element non-linear theory with
// finite rotations", IJNME 26, sec. 2): a moment M does the virtual work M . T dtheta, so its
// generalized force on the angles is T^T M, and a generalized reaction f is the moment T^-T f.
#pragma once
#include <array>

#include "signorini/core/types.hpp"

namespace signorini {

struct Rotation {
  int n = 0;  // angles: 1 (plane, about z) or 3 (rotation vector)
  Mat3 R = Mat3::Identity();
  std::array<Mat3, 3> dR{};                  // dR/dtheta_i
  std::array<std::array<Mat3, 3>, 3> d2R{};  // d2R/dtheta_i dtheta_j
  // T: spin per angle rate (3 x n, in the first n columns); dT[j] = dT/dtheta_j.
  Mat3 T() const;
  std::array<Mat3, 3> dT() const;
};

// The rotation by the n angles at `theta` (n = 1: about z; n = 3: rotation vector).
Rotation rotation(const Real* theta, int n);

// The rotation by theta about the z axis (plane problems).
Mat3 rotation_z(Real theta);

}  // namespace signorini
