// A scalar that carries its gradient with respect to N inputs (forward-mode automatic
// differentiation to first order): HyperDual (hyper_dual.hpp) without the Hessian, for code
// written once on a number type T when only the first variation is wanted (the 3D mortar's
// weighted gaps in a residual without its Newton matrix: a line search's trial point, a finite
// difference). Every operation is O(N) where HyperDual's is O(N^2).
#pragma once
#include <Eigen/Core>
#include <cmath>

#include "signorini/core/types.hpp"

namespace signorini {

template <int N>
struct Dual {
  using Vec = Eigen::Matrix<Real, N, 1>;
  Real v = 0;
  Vec g = Vec::Zero();

  Dual() = default;
  Dual(Real value) : v(value) {}  // NOLINT: a constant
  static Dual input(Real value, int i) {
    Dual r(value);
    r.g(i) = 1;
    return r;
  }
  // f(this) from f and f' at v (f'' is not needed to first order).
  Dual apply(Real f, Real df) const {
    Dual r;
    r.v = f;
    r.g = df * g;
    return r;
  }
  Dual operator-() const {
    Dual r;
    r.v = -v;
    r.g = -g;
    return r;
  }
  Dual& operator+=(const Dual& b) {
    v += b.v;
    g += b.g;
    return *this;
  }
  Dual& operator-=(const Dual& b) {
    v -= b.v;
    g -= b.g;
    return *this;
  }
  Dual& operator*=(Real s) {
    v *= s;
    g *= s;
    return *this;
  }
};

template <int N>
Dual<N> operator+(Dual<N> a, const Dual<N>& b) {
  return a += b;
}
template <int N>
Dual<N> operator-(Dual<N> a, const Dual<N>& b) {
  return a -= b;
}
template <int N>
Dual<N> operator+(Dual<N> a, Real s) {
  a.v += s;
  return a;
}
template <int N>
Dual<N> operator+(Real s, Dual<N> a) {
  a.v += s;
  return a;
}
template <int N>
Dual<N> operator-(Dual<N> a, Real s) {
  a.v -= s;
  return a;
}
template <int N>
Dual<N> operator-(Real s, const Dual<N>& a) {
  Dual<N> r = -a;
  r.v += s;
  return r;
}
template <int N>
Dual<N> operator*(Dual<N> a, Real s) {
  return a *= s;
}
template <int N>
Dual<N> operator*(Real s, Dual<N> a) {
  return a *= s;
}
template <int N>
Dual<N> operator*(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  return r;
}
template <int N>
Dual<N> inverse(const Dual<N>& a) {
  const Real i = 1 / a.v;
  return a.apply(i, -i * i);
}
template <int N>
Dual<N> operator/(const Dual<N>& a, const Dual<N>& b) {
  return a * inverse(b);
}
template <int N>
Dual<N> operator/(Dual<N> a, Real s) {
  return a *= 1 / s;
}
template <int N>
Dual<N> operator/(Real s, const Dual<N>& a) {
  return inverse(a) * s;
}
template <int N>
Dual<N> sqrt(const Dual<N>& a) {
  const Real r = std::sqrt(a.v);
  return a.apply(r, 0.5 / r);
}
template <int N>
Real value(const Dual<N>& a) {
  return a.v;
}

}  // namespace signorini
