// A scalar that carries its gradient and Hessian with respect to N inputs (forward-mode
// automatic differentiation to second order): every operation applies the chain rule,
//   (a b)'' = a'' b + a b'' + a' b'^T + b' a'^T,  f(a)'' = f'(a) a'' + f''(a) a' a'^T.
// The mortar kinematics (segmentation, dual basis, averaged normals, projections) are written
// once on this type, so their first and second variations are exact to round-off without a
// hand-derived linearization (the linearization Popp et al. 2010 derive by hand is what it
// computes). Include it only where it is used: the fixed-size Hessian makes every operation
// O(N^2).
#pragma once
#include <Eigen/Core>
#include <cmath>

#include "signorini/core/types.hpp"

namespace signorini {

template <int N>
struct HyperDual {
  using Vec = Eigen::Matrix<Real, N, 1>;
  using Mat = Eigen::Matrix<Real, N, N>;
  Real v = 0;
  Vec g = Vec::Zero();
  Mat h = Mat::Zero();

  HyperDual() = default;
  HyperDual(Real value) : v(value) {}  // NOLINT: a constant
  // A result whose value, gradient and Hessian are all assigned next: no zeroing (a 36-input
  // number is 10 kB, and zeroing results took a tenth of the 3D mortar's time).
  struct Uninitialized {};
  explicit HyperDual(Uninitialized) : g(), h() {}
  // The i-th input with value `value`.
  static HyperDual input(Real value, int i) {
    HyperDual r(value);
    r.g(i) = 1;
    return r;
  }
  // f(this) from f, f' and f'' at v.
  HyperDual apply(Real f, Real df, Real d2f) const {
    HyperDual r{Uninitialized{}};
    r.v = f;
    r.g = df * g;
    r.h.noalias() = df * h;
    r.h.noalias() += (d2f * g) * g.transpose();
    return r;
  }

  HyperDual operator-() const {
    HyperDual r{Uninitialized{}};
    r.v = -v;
    r.g = -g;
    r.h = -h;
    return r;
  }
  HyperDual& operator+=(const HyperDual& b) {
    v += b.v;
    g += b.g;
    h += b.h;
    return *this;
  }
  HyperDual& operator-=(const HyperDual& b) {
    v -= b.v;
    g -= b.g;
    h -= b.h;
    return *this;
  }
  HyperDual& operator*=(Real s) {
    v *= s;
    g *= s;
    h *= s;
    return *this;
  }
};

template <int N>
HyperDual<N> operator+(HyperDual<N> a, const HyperDual<N>& b) {
  return a += b;
}
template <int N>
HyperDual<N> operator-(HyperDual<N> a, const HyperDual<N>& b) {
  return a -= b;
}
template <int N>
HyperDual<N> operator+(HyperDual<N> a, Real s) {
  a.v += s;
  return a;
}
template <int N>
HyperDual<N> operator+(Real s, HyperDual<N> a) {
  a.v += s;
  return a;
}
template <int N>
HyperDual<N> operator-(HyperDual<N> a, Real s) {
  a.v -= s;
  return a;
}
template <int N>
HyperDual<N> operator-(Real s, const HyperDual<N>& a) {
  HyperDual<N> r = -a;
  r.v += s;
  return r;
}
template <int N>
HyperDual<N> operator*(HyperDual<N> a, Real s) {
  return a *= s;
}
template <int N>
HyperDual<N> operator*(Real s, HyperDual<N> a) {
  return a *= s;
}
template <int N>
HyperDual<N> operator*(const HyperDual<N>& a, const HyperDual<N>& b) {
  HyperDual<N> r{typename HyperDual<N>::Uninitialized{}};
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  r.h.noalias() = a.v * b.h + b.v * a.h;
  r.h.noalias() += a.g * b.g.transpose();
  r.h.noalias() += b.g * a.g.transpose();
  return r;
}
template <int N>
HyperDual<N> inverse(const HyperDual<N>& a) {
  const Real i = 1 / a.v;
  return a.apply(i, -i * i, 2 * i * i * i);
}
template <int N>
HyperDual<N> operator/(const HyperDual<N>& a, const HyperDual<N>& b) {
  return a * inverse(b);
}
template <int N>
HyperDual<N> operator/(HyperDual<N> a, Real s) {
  return a *= 1 / s;
}
template <int N>
HyperDual<N> operator/(Real s, const HyperDual<N>& a) {
  return inverse(a) * s;
}
template <int N>
HyperDual<N> sqrt(const HyperDual<N>& a) {
  const Real r = std::sqrt(a.v);
  return a.apply(r, 0.5 / r, -0.25 / (r * a.v));
}

// The value of a plain number or of a hyper-dual one (code written for both).
inline Real value(Real a) { return a; }
template <int N>
Real value(const HyperDual<N>& a) {
  return a.v;
}

}  // namespace signorini
