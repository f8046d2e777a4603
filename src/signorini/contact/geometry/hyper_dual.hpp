// A scalar that carries its gradient and Hessian with respect to N inputs (forward-mode
// automatic differentiation to second order): every operation applies the chain rule,
//   (a b)'' = a'' b + a b'' + a' b'^T + b' a'^T,  f(a)'' = f'(a) a'' + f''(a) a' a'^T.
// The mortar kinematics (segmentation, dual basis, averaged normals, projections) are written
// once on this type, so their first and second variations are exact to round-off without a
// hand-derived linearization (the linearization Popp et al. 2010 derive by hand is what it
// computes). Include it only where it is used: the fixed-size Hessian makes every operation
// O(N^2) (N (N + 1) / 2 entries: the upper triangle).
#pragma once
#include <Eigen/Core>
#include <cmath>

#include "signorini/core/types.hpp"

namespace signorini {

template <int N>
struct HyperDual {
  using Vec = Eigen::Matrix<Real, N, 1>;
  using Mat = Eigen::Matrix<Real, N, N>;
  // The Hessian is symmetric: its upper triangle is stored, row after row, (i, j >= i) at
  // row(i) + j - i. Half the storage and half the work of the full matrix (every operation
  // updates it; since session 62: the 3D tri6 mortar's contact evaluation took 0.6 of a tet10
  // Hertz run, most of it in full 36 x 36 Hessians and their copies).
  static constexpr int kPacked = N * (N + 1) / 2;
  using Packed = Eigen::Matrix<Real, kPacked, 1>;
  static constexpr int row(int i) { return i * N - i * (i - 1) / 2; }
  Real v = 0;
  Vec g = Vec::Zero();
  Packed h = Packed::Zero();

  HyperDual() = default;
  HyperDual(Real value) : v(value) {}  // NOLINT: a constant
  // A result whose value, gradient and Hessian are all assigned next: no zeroing (a 36-input
  // number is 5.6 kB, and zeroing results took a tenth of the 3D mortar's time).
  struct Uninitialized {};
  explicit HyperDual(Uninitialized) : g(), h() {}
  // The i-th input with value `value`.
  static HyperDual input(Real value, int i) {
    HyperDual r(value);
    r.g(i) = 1;
    return r;
  }
  // Entry (i, j) of the Hessian, and the whole matrix.
  Real hess(int i, int j) const { return i <= j ? h(row(i) + j - i) : h(row(j) + i - j); }
  Mat hessian() const {
    Mat m;
    for (int i = 0; i < N; ++i)
      for (int j = i; j < N; ++j) m(i, j) = m(j, i) = h(row(i) + j - i);
    return m;
  }
  // H += a b^T + b a^T, on the upper triangle; the rows where both a and b are zero (the inputs
  // a number does not depend on) are skipped.
  void add_symmetric_product(const Vec& a, const Vec& b) {
    for (int i = 0; i < N; ++i) {
      if (a(i) == 0 && b(i) == 0) continue;
      h.segment(row(i), N - i) += a(i) * b.tail(N - i) + b(i) * a.tail(N - i);
    }
  }
  // H += s a a^T, on the upper triangle.
  void add_square(Real s, const Vec& a) {
    for (int i = 0; i < N; ++i) {
      const Real ai = s * a(i);
      if (ai == 0) continue;
      h.segment(row(i), N - i) += ai * a.tail(N - i);
    }
  }
  // f(this) from f, f' and f'' at v.
  HyperDual apply(Real f, Real df, Real d2f) const {
    HyperDual r{Uninitialized{}};
    r.v = f;
    r.g = df * g;
    r.h = df * h;
    if (d2f != 0) r.add_square(d2f, g);
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
  r.h = a.v * b.h + b.v * a.h;
  r.add_symmetric_product(a.g, b.g);
  return r;
}
// acc += a b, without the product's temporary: one pass over the Hessian fewer than
// `acc += a * b` and no 5.6 kB number written and read back (a 36-input one). Sums of products
// (the 3D mortar's mass integrals, sum over the rule's points of N_j N_k w) are most of its work.
template <int N>
void add_product(HyperDual<N>& acc, const HyperDual<N>& a, const HyperDual<N>& b) {
  acc.v += a.v * b.v;
  acc.g += a.v * b.g + b.v * a.g;
  acc.h += a.v * b.h + b.v * a.h;
  acc.add_symmetric_product(a.g, b.g);
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
