#include "signorini/contact/geometry/rotation.hpp"

#include <cmath>

#include "signorini/contact/geometry/hyper_dual.hpp"

namespace signorini {

namespace {

using HD = HyperDual<3>;

// a(t) = sin(s)/s and b(t) = (1 - cos s)/s^2 with s = sqrt(t), and their first two
// derivatives in t: out = {a, a', a'', b, b', b''}.
std::array<Real, 6> rodrigues_coefficients(Real t) {
  if (t < 0.25) {
    // a = sum (-t)^k / (2k+1)!, b = sum (-t)^k / (2k+2)!, term by term.
    std::array<Real, 6> r{};
    Real fa = 1, fb = 2;  // (2k+1)!, (2k+2)!
    for (int k = 0; k <= 10; ++k) {
      if (k > 0) {
        fa *= (2 * k) * (2 * k + 1);
        fb *= (2 * k + 1) * (2 * k + 2);
      }
      const Real sign = (k % 2) ? -1.0 : 1.0;
      const Real p0 = std::pow(t, k), p1 = k >= 1 ? k * std::pow(t, k - 1) : 0.0,
                 p2 = k >= 2 ? k * (k - 1) * std::pow(t, k - 2) : 0.0;
      r[0] += sign * p0 / fa;
      r[1] += sign * p1 / fa;
      r[2] += sign * p2 / fa;
      r[3] += sign * p0 / fb;
      r[4] += sign * p1 / fb;
      r[5] += sign * p2 / fb;
    }
    return r;
  }
  const Real s = std::sqrt(t), sn = std::sin(s), cs = std::cos(s);
  const Real s2 = t, s3 = s2 * s, s4 = s2 * s2, s5 = s4 * s, s6 = s4 * s2;
  return {sn / s,
          (s * cs - sn) / (2 * s3),
          (-s2 * sn - 3 * s * cs + 3 * sn) / (4 * s5),
          (1 - cs) / s2,
          (0.5 * s * sn - 1 + cs) / s4,
          (s2 * cs - 5 * s * sn + 8 - 8 * cs) / (4 * s6)};
}

Vec3 axial(const Mat3& W) { return Vec3(0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)), 0.5 * (W(1, 0) - W(0, 1))); }

}  // namespace

Mat3 rotation_z(Real theta) {
  Mat3 R = Mat3::Identity();
  R(0, 0) = R(1, 1) = std::cos(theta);
  R(1, 0) = std::sin(theta);
  R(0, 1) = -R(1, 0);
  return R;
}

Rotation rotation(const Real* theta, int n) {
  Rotation r;
  r.n = n;
  for (auto& m : r.dR) m.setZero();
  for (auto& row : r.d2R)
    for (auto& m : row) m.setZero();
  if (n == 1) {
    r.R = rotation_z(theta[0]);
    const Real c = std::cos(theta[0]), s = std::sin(theta[0]);
    r.dR[0](0, 0) = r.dR[0](1, 1) = -s;
    r.dR[0](1, 0) = c;
    r.dR[0](0, 1) = -c;
    r.d2R[0][0] = -r.R;
    r.d2R[0][0](2, 2) = 0;
    return r;
  }
  const HD x = HD::input(theta[0], 0), y = HD::input(theta[1], 1), z = HD::input(theta[2], 2);
  const HD t = x * x + y * y + z * z;
  const auto c = rodrigues_coefficients(t.v);
  const HD a = t.apply(c[0], c[1], c[2]), b = t.apply(c[3], c[4], c[5]);
  // K = [theta]x; K^2 = theta theta^T - t I.
  const HD zero(0.0);
  const HD K[3][3] = {{zero, -z, y}, {z, zero, -x}, {-y, x, zero}};
  const HD th[3] = {x, y, z};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      HD k2 = th[i] * th[j];
      if (i == j) k2 -= t;
      HD e = a * K[i][j] + b * k2;
      if (i == j) e += HD(1.0);
      r.R(i, j) = e.v;
      for (int p = 0; p < 3; ++p) {
        r.dR[p](i, j) = e.g(p);
        for (int q = 0; q < 3; ++q) r.d2R[p][q](i, j) = e.hess(p, q);
      }
    }
  return r;
}

Mat3 Rotation::T() const {
  Mat3 t = Mat3::Zero();
  if (n == 1) {
    t(2, 0) = 1;
    return t;
  }
  for (int i = 0; i < n; ++i) t.col(i) = axial(dR[i] * R.transpose());
  return t;
}

std::array<Mat3, 3> Rotation::dT() const {
  std::array<Mat3, 3> d{};
  for (auto& m : d) m.setZero();
  if (n == 1) return d;
  // d/dtheta_j axial(dR_i R^T) = axial(d2R_ij R^T + dR_i dR_j^T).
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) d[j].col(i) = axial(d2R[i][j] * R.transpose() + dR[i] * dR[j].transpose());
  return d;
}

}  // namespace signorini
