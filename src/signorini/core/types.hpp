// Small shared types: scalar and index types and the fixed-size Eigen aliases used in the
// hot loops over quadrature points. Everything numerical in Signorini speaks these types.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cstdint>
#include <vector>

namespace signorini {

using Real = double;
using Index = std::int64_t;

using Vec2 = Eigen::Matrix<Real, 2, 1>;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Vec6 = Eigen::Matrix<Real, 6, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using Mat6 = Eigen::Matrix<Real, 6, 6>;
using VecX = Eigen::Matrix<Real, Eigen::Dynamic, 1>;
using MatX = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;

// [v]x, the matrix of the cross product with v: cross_matrix(v) w = v x w.
inline Mat3 cross_matrix(const Vec3& v) {
  Mat3 m;
  m << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return m;
}

// Voigt order used throughout: [11, 22, 33, 23, 13, 12]; strains carry engineering shears.
inline Vec6 to_voigt_stress(const Mat3& s) {
  Vec6 v;
  v << s(0, 0), s(1, 1), s(2, 2), s(1, 2), s(0, 2), s(0, 1);
  return v;
}
inline Vec6 to_voigt_strain(const Mat3& e) {
  Vec6 v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(0, 2), 2 * e(0, 1);
  return v;
}
inline Mat3 from_voigt_stress(const Vec6& v) {
  Mat3 s;
  s << v(0), v(5), v(4), v(5), v(1), v(3), v(4), v(3), v(2);
  return s;
}
inline Mat3 from_voigt_strain(const Vec6& v) {
  Mat3 e;
  e << v(0), v(5) / 2, v(4) / 2, v(5) / 2, v(1), v(3) / 2, v(4) / 2, v(3) / 2, v(2);
  return e;
}
// Index pairs of the Voigt components, in Voigt order.
inline constexpr int kVoigtI[6] = {0, 1, 2, 1, 0, 0};
inline constexpr int kVoigtJ[6] = {0, 1, 2, 2, 2, 1};

}  // namespace signorini
