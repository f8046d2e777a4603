// Segment-based dual mortar in 3D: slave and master facets of every type (tri3, tri6, quad4,
// quad8, quad9), mortar.hpp.
//
// Per slave facet e and master facet m (Puso and Laursen 2004, "A mortar segment-to-segment
// contact method for large deformation solid mechanics", CMAME 193; Popp, Gee and Wall 2009,
// "A finite deformation mortar contact formulation using a primal-dual active set strategy",
// IJNME 79, sec. 3.3, for the auxiliary plane and the integration cells):
//  - the projection direction is n0, the slave facet's unit normal at its centre (the normal of
//    the auxiliary plane): the master's corners are projected along n0 onto the slave facet,
//    (x_s(xi) - x_m) . a_alpha = 0 with a_1, a_2 the slave's tangents at its centre, which span
//    the plane normal to n0; on a tri3 slave the slave facet is that plane and the map is the
//    auxiliary-plane projection exactly;
//  - the projected master polygon is clipped against the slave's reference element in the
//    slave's parameter plane (Sutherland-Hodgman: the reference element is convex);
//  - the clipped polygon is cut into a fan of triangles from its first vertex (the integration
//    cells), each
//    integrated with a triangle Gauss rule in the slave parameter; at each point the master
//    point is x_s + t n0 on the master facet, and the gap g = (x_m - x_s) . n0 (a tri3 slave on
//    a tri3 master: the gap is affine, and the integrals come exactly from the clipped
//    polygon's moments);
//  - G_k = int N_k g dA, M_ik = int N_i N_k dA with dA = |a_1 x a_2| dxi, summed over the
//    master facets, give the weighted gaps through the dual basis on the covered part
//    (mortar_dual.hpp), as in 2D; on quadratic slave facets the dual basis is built on a
//    transformed basis N~ of non-negative functions (Popp, Wohlmuth, Gee and Wall 2012;
//    mortar_dual.hpp, basis_transform), whose weights int_c N~_j dA are positive on any
//    covered part c (a tri6 corner's int N_j dA is zero).
// The cells of neighbouring master facets share the projected images of the master's common
// edge, so they tile the covered part of the slave's parameter plane without gap or overlap
// (on a quad4 slave the image of a master edge is approximated by its chord in the parameter
// plane, on both sides alike). Everything, from the projections to the clipped vertices and the
// rule's points, is written on T = Real or HyperDual over the pair's
// coordinates, so the gradient and Hessian of the integrals include the variation of the
// segmentation. The gap is measured along the facet's own normal n0, not along the averaged
// nodal normals of the 2D mortar (those would make the integrals depend on the neighbouring
// facets' nodes too); on a flat interface the two agree.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <type_traits>

#include "signorini/contact/discretization/mortar.hpp"
#include "signorini/contact/discretization/mortar_dual.hpp"
#include "signorini/contact/geometry/dual.hpp"
#include "signorini/contact/geometry/hyper_dual.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/quadrature.hpp"

namespace signorini {

namespace {

using namespace mortar_detail;

inline Real sqrt(Real a) { return std::sqrt(a); }

template <class T>
struct V3 {
  T x{}, y{}, z{};
};
template <class T>
V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T, class S>
V3<T> operator*(const S& s, const V3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
T dot(const V3<T>& a, const V3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
V3<T> cross(const V3<T>& a, const V3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
V3<Real> val(const V3<T>& a) {
  return {value(a.x), value(a.y), value(a.z)};
}

// Points of a facet's parameter plane.
template <class T>
struct V2 {
  T a{}, b{};
};
template <class T>
V2<T> operator+(const V2<T>& p, const V2<T>& q) {
  return {p.a + q.a, p.b + q.b};
}
template <class T>
V2<T> operator-(const V2<T>& p, const V2<T>& q) {
  return {p.a - q.a, p.b - q.b};
}
template <class T, class S>
V2<T> operator*(const S& s, const V2<T>& p) {
  return {s * p.a, s * p.b};
}
template <class T>
T cross2(const V2<T>& p, const V2<T>& q) {
  return p.a * q.b - p.b * q.a;
}

// The shape functions of a facet with nn nodes and their derivatives, the element library's
// node order: tri3 (nodes at (0,0), (1,0), (0,1)), tri6 (then the mid-sides of 0-1, 1-2, 2-0),
// quad4 (nodes at (-1,-1), (1,-1), (1,1), (-1,1)), quad8 (then the mid-sides of 0-1, 1-2, 2-3,
// 3-0), quad9 (then the centre).
constexpr int kMaxFacetNodes = 9;
template <class T>
void shape(int nn, const T& a, const T& b, T* N, T* Na, T* Nb) {
  if (nn == 3) {
    N[0] = 1 - a - b, N[1] = a, N[2] = b;
    Na[0] = T(-1), Na[1] = T(1), Na[2] = T(0);
    Nb[0] = T(-1), Nb[1] = T(0), Nb[2] = T(1);
    return;
  }
  if (nn == 6) {
    const T l0 = 1 - a - b;
    N[0] = l0 * (2 * l0 - 1), N[1] = a * (2 * a - 1), N[2] = b * (2 * b - 1);
    N[3] = 4 * l0 * a, N[4] = 4 * a * b, N[5] = 4 * b * l0;
    Na[0] = 1 - 4 * l0, Na[1] = 4 * a - 1, Na[2] = T(0), Na[3] = 4 * (l0 - a), Na[4] = 4 * b, Na[5] = -4 * b;
    Nb[0] = 1 - 4 * l0, Nb[1] = T(0), Nb[2] = 4 * b - 1, Nb[3] = -4 * a, Nb[4] = 4 * a, Nb[5] = 4 * (l0 - b);
    return;
  }
  static constexpr Real c[4] = {-1, 1, 1, -1}, d[4] = {-1, -1, 1, 1};
  if (nn == 4) {
    for (int i = 0; i < 4; ++i) {
      const T fa = 1 + c[i] * a, fb = 1 + d[i] * b;
      N[i] = 0.25 * fa * fb;
      Na[i] = (0.25 * c[i]) * fb;
      Nb[i] = (0.25 * d[i]) * fa;
    }
    return;
  }
  if (nn == 8) {
    // Serendipity: corners (1 + c a)(1 + d b)(c a + d b - 1) / 4; mid-sides of the edges
    // b = -1, 1 (a = 0 there): (1 - a^2)(1 + d b) / 2; of a = 1, -1: (1 + c a)(1 - b^2) / 2.
    for (int i = 0; i < 4; ++i) {
      const T fa = 1 + c[i] * a, fb = 1 + d[i] * b, s = c[i] * a + d[i] * b - 1;
      N[i] = 0.25 * fa * fb * s;
      Na[i] = (0.25 * c[i]) * fb * (s + fa);
      Nb[i] = (0.25 * d[i]) * fa * (s + fb);
    }
    const T qa = 1 - a * a, qb = 1 - b * b;
    N[4] = 0.5 * qa * (1 - b), Na[4] = -(a * (1 - b)), Nb[4] = -0.5 * qa;
    N[5] = 0.5 * (1 + a) * qb, Na[5] = 0.5 * qb, Nb[5] = -((1 + a) * b);
    N[6] = 0.5 * qa * (1 + b), Na[6] = -(a * (1 + b)), Nb[6] = 0.5 * qa;
    N[7] = 0.5 * (1 - a) * qb, Na[7] = -0.5 * qb, Nb[7] = -((1 - a) * b);
    return;
  }
  // Quad9: products of the line3 functions L_-1 = s (s - 1) / 2, L_0 = 1 - s^2, L_1 = s (s + 1) / 2.
  const T La[3] = {0.5 * a * (a - 1), 1 - a * a, 0.5 * a * (a + 1)}, Lb[3] = {0.5 * b * (b - 1), 1 - b * b, 0.5 * b * (b + 1)};
  const T dLa[3] = {a - 0.5, -2 * a, a + 0.5}, dLb[3] = {b - 0.5, -2 * b, b + 0.5};
  static constexpr int ia[9] = {0, 2, 2, 0, 1, 2, 1, 0, 1}, ib[9] = {0, 0, 2, 2, 0, 1, 2, 1, 1};
  for (int i = 0; i < 9; ++i) {
    N[i] = La[ia[i]] * Lb[ib[i]];
    Na[i] = dLa[ia[i]] * Lb[ib[i]];
    Nb[i] = La[ia[i]] * dLb[ib[i]];
  }
}
// Scratch arrays of numbers that are all assigned before they are read (shape functions): a
// hyper-dual number is not zeroed first (a 36-input one is 5.6 kB, 10 kB until session 62, and
// the shape functions' arrays at every rule point were zeroed 80 times over: a fifth of the
// tri6 mortar's time).
template <class T>
struct IsHyperDual : std::false_type {};
template <int N>
struct IsHyperDual<HyperDual<N>> : std::true_type {};
// A hyper-dual number's value and gradient, and a first-order number as a hyper-dual one whose
// Hessian is zero.
template <int N>
Dual<N> to_dual(const HyperDual<N>& a) {
  Dual<N> r(a.v);
  r.g = a.g;
  return r;
}
template <class T, int N>
T from_dual(const Dual<N>& a) {
  T r{typename T::Uninitialized{}};
  r.v = a.v;
  r.g = a.g;
  r.h.setZero();
  return r;
}
template <class T>
T scratch_number() {
  if constexpr (IsHyperDual<T>::value) return T(typename T::Uninitialized{});
  else return T();
}
template <class T, size_t... I>
std::array<T, sizeof...(I)> scratch_array(std::index_sequence<I...>) {
  return {{(static_cast<void>(I), scratch_number<T>())...}};
}
template <class T>
std::array<T, kMaxFacetNodes> scratch_shape() {
  return scratch_array<T>(std::make_index_sequence<kMaxFacetNodes>());
}

// acc += a b on any number type (hyper-dual numbers without the product's temporary).
template <class T>
void accumulate(T& acc, const T& a, const T& b) {
  if constexpr (IsHyperDual<T>::value) add_product(acc, a, b);
  else acc += a * b;
}
template <class T>
V3<T> interpolate(int nn, const T* N, const V3<T>* x) {
  V3<T> p{T(0), T(0), T(0)};
  for (int i = 0; i < nn; ++i) {
    accumulate(p.x, N[i], x[i].x);
    accumulate(p.y, N[i], x[i].y);
    accumulate(p.z, N[i], x[i].z);
  }
  return p;
}
// A facet's point and tangents at parameters xi, x = sum N_i X_i, a_1 = sum N_i,a X_i and
// a_2 = sum N_i,b X_i (a1 and a2 null: not wanted), and its shape functions there (N on T and
// Nv their values, each null when not wanted).
template <class T>
void facet_map(int nn, const V2<T>& xi, const V3<T>* X, std::type_identity_t<T>* N, Real* Nv, V3<T>& x,
               std::type_identity_t<V3<T>>* a1, std::type_identity_t<V3<T>>* a2) {
  std::array<T, kMaxFacetNodes> Ns = scratch_shape<T>(), Na = scratch_shape<T>(), Nb = scratch_shape<T>();
  shape(nn, xi.a, xi.b, Ns.data(), Na.data(), Nb.data());
  x = interpolate(nn, Ns.data(), X);
  if (a1) *a1 = interpolate(nn, Na.data(), X);
  if (a2) *a2 = interpolate(nn, Nb.data(), X);
  for (int i = 0; i < nn; ++i) {
    if (N) N[i] = Ns[i];
    if (Nv) Nv[i] = value(Ns[i]);
  }
}
// On hyper-dual numbers, through the chain rule: every quantity here is F(xi, X) = sum F_i(xi)
// X_i with F_i = N_i, N_i,a or N_i,b, a function of the two parameters (evaluated on
// HyperDual<2>: its first and second derivatives in xi), and X_i the pair's inputs or constants
// (the nodes' coordinates, cell_derivatives: a unit gradient, no Hessian). With
// c(xi) = sum F_i(xi) X_i at the nodes' values and u_alpha = sum F_i,alpha grad X_i,
//   F'  = c_alpha xi_alpha' + sum F_i grad X_i,
//   F'' = c_alpha xi_alpha'' + c_alpha,beta xi_alpha' xi_beta'^T + sum_alpha (xi_alpha' u_alpha^T + u_alpha xi_alpha'^T):
// one pass over the Hessian and two symmetric products per quantity, where the shape functions
// on HyperDual<NV> and their interpolation (the general path above, taken when a node is not
// an input) take some 3 nn products.
template <int NV>
void facet_map(int nn, const V2<HyperDual<NV>>& xi, const V3<HyperDual<NV>>* X, std::type_identity_t<HyperDual<NV>>* N,
               Real* Nv, V3<HyperDual<NV>>& x, std::type_identity_t<V3<HyperDual<NV>>>* a1,
               std::type_identity_t<V3<HyperDual<NV>>>* a2) {
  using HD = HyperDual<NV>;
  using L = HyperDual<2>;
  // Each node coordinate's input (its unit gradient's index), -1 for a constant.
  int input[kMaxFacetNodes][3];
  for (int i = 0; i < nn; ++i)
    for (int c = 0; c < 3; ++c) {
      const HD& xc = c == 0 ? X[i].x : c == 1 ? X[i].y : X[i].z;
      int k = -1;
      for (int j = 0; j < NV; ++j)
        if (xc.g(j) != 0) {
          if (k != -1 || xc.g(j) != 1) {
            facet_map<HD>(nn, xi, X, N, Nv, x, a1, a2);  // not an input: the general path
            return;
          }
          k = j;
        }
      input[i][c] = k;
    }
  const HD& xa = xi.a;
  const HD& xb = xi.b;
  L Ls[kMaxFacetNodes], La[kMaxFacetNodes], Lb[kMaxFacetNodes];
  shape(nn, L::input(xa.v, 0), L::input(xb.v, 1), Ls, La, Lb);
  // F from its derivatives in xi, with u_a and u_b.
  auto lift = [&](const L& f, const typename HD::Vec& ua, const typename HD::Vec& ub) {
    HD r{typename HD::Uninitialized{}};
    r.v = f.v;
    r.g = f.g(0) * xa.g + f.g(1) * xb.g;
    r.h = f.g(0) * xa.h + f.g(1) * xb.h;
    r.add_symmetric_product(xa.g, (0.5 * f.hess(0, 0)) * xa.g + f.hess(0, 1) * xb.g + ua);
    r.add_symmetric_product(xb.g, (0.5 * f.hess(1, 1)) * xb.g + ub);
    return r;
  };
  auto sum = [&](const L* F, int c) {
    L f(0.0);
    typename HD::Vec ua = HD::Vec::Zero(), ub = HD::Vec::Zero(), g = HD::Vec::Zero();
    for (int i = 0; i < nn; ++i) {
      const HD& xc = c == 0 ? X[i].x : c == 1 ? X[i].y : X[i].z;
      f += F[i] * xc.v;
      if (const int k = input[i][c]; k >= 0) {
        g(k) += F[i].v;
        ua(k) += F[i].g(0);
        ub(k) += F[i].g(1);
      }
    }
    HD r = lift(f, ua, ub);
    r.g += g;
    return r;
  };
  auto point = [&](const L* F) { return V3<HD>{sum(F, 0), sum(F, 1), sum(F, 2)}; };
  x = point(Ls);
  if (a1) *a1 = point(La);
  if (a2) *a2 = point(Lb);
  const typename HD::Vec zero = HD::Vec::Zero();
  for (int i = 0; i < nn; ++i) {
    if (N) N[i] = lift(Ls[i], zero, zero);
    if (Nv) Nv[i] = Ls[i].v;
  }
}

// The reference element as a counter-clockwise polygon, its area and its centre.
struct Reference {
  int n;
  V2<Real> corner[4];
  Real area;
  V2<Real> centre;
};
const Reference& reference(int nn) {
  static const Reference tri{3, {{0, 0}, {1, 0}, {0, 1}, {0, 0}}, 0.5, {1.0 / 3, 1.0 / 3}};
  static const Reference quad{4, {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, 4.0, {0, 0}};
  return nn == 3 || nn == 6 ? tri : quad;
}
// Whether the facet's map is affine (tri3) and its corner count.
inline bool affine_facet(int nn) { return nn == 3; }
inline int corners(int nn) { return nn == 3 || nn == 6 ? 3 : 4; }

// The parameters of facet xf (nn nodes) at which x(xi) - p is normal to t1 and t2 (parallel to
// n0 = t1 x t2): Newton in plain numbers from the centre, then two Newton steps from the
// converged parameters (the first makes the gradient exact, the second the Hessian; the map is
// stationary at its fixed point; on hyper-dual numbers the first runs on first-order ones; on
// tri3 facets one step is exact). False if Newton fails (the facet is edge-on to n0).
// One Newton step for those parameters from xi: the step d (xi - d is the next iterate) and the
// determinant of the Jacobian [a_beta . t_alpha].
template <class T>
V2<T> projection_step(int nn, const V3<T>* xf, const V3<T>& p, const V3<T>& t1, const V3<T>& t2, const V2<T>& xi,
                      T& det) {
  V3<T> x, a1, a2;
  facet_map(nn, xi, xf, nullptr, nullptr, x, &a1, &a2);
  const V3<T> r = x - p;
  const T F1 = dot(r, t1), F2 = dot(r, t2);
  const T J11 = dot(a1, t1), J12 = dot(a2, t1), J21 = dot(a1, t2), J22 = dot(a2, t2);
  det = J11 * J22 - J12 * J21;
  return {(J22 * F1 - J12 * F2) / det, (J11 * F2 - J21 * F1) / det};
}
template <class T>
bool project_along(int nn, const V3<T>* xf, const V3<T>& p, const V3<T>& t1, const V3<T>& t2, V2<T>& out) {
  V3<Real> xv[kMaxFacetNodes];
  for (int i = 0; i < nn; ++i) xv[i] = val(xf[i]);
  const V3<Real> pv = val(p), t1v = val(t1), t2v = val(t2);
  V2<Real> xi = reference(nn).centre;
  const Real scale = std::sqrt(dot(t1v, t1v) * dot(t2v, t2v));
  bool ok = false;
  for (int it = 0; it < 30; ++it) {
    Real det = 0;
    const V2<Real> d = projection_step(nn, xv, pv, t1v, t2v, xi, det);
    if (!(std::abs(det) > 1e-12 * scale) || !std::isfinite(d.a + d.b)) return false;
    xi = xi - d;
    if (!(std::abs(xi.a) < 1e3 && std::abs(xi.b) < 1e3)) return false;
    if (std::abs(d.a) + std::abs(d.b) < 1e-13) {
      ok = true;
      break;
    }
  }
  if (!ok) return false;
  V2<T> t{T(xi.a), T(xi.b)};
  if constexpr (IsHyperDual<T>::value) {
    if (!affine_facet(nn)) {
      // The first step on gradients only: Newton's map is stationary at its fixed point for
      // every X (the coordinates), so a start exact to first order in X gives a step exact to
      // second order, the Hessian included, whatever the start's own Hessian (zero here); the
      // first step, from the converged parameters as constants, is exact to first order. On
      // first-order numbers it costs O(N) where a hyper-dual step costs O(N^2): it was half of
      // the projections' work, and the master's projection at each rule point is about half
      // of the 3D mortar's.
      using D = Dual<T::Vec::RowsAtCompileTime>;
      auto first = [](const V3<T>& a) { return V3<D>{to_dual(a.x), to_dual(a.y), to_dual(a.z)}; };
      V3<D> xd[kMaxFacetNodes];
      for (int i = 0; i < nn; ++i) xd[i] = first(xf[i]);
      V2<D> td{D(xi.a), D(xi.b)};
      D det;
      td = td - projection_step(nn, xd, first(p), first(t1), first(t2), td, det);
      t = {from_dual<T>(td.a), from_dual<T>(td.b)};
    }
  }
  // The steps on T: one on a tri3 facet (its equations are linear: one step is exact,
  // derivatives included) or after the first-order step above; otherwise two (on first-order
  // numbers one step from the constants is exact to first order only up to the converged
  // residual, of order 1e-13: the second squares it).
  const int steps = affine_facet(nn) || IsHyperDual<T>::value ? 1 : 2;
  for (int step = 0; step < steps; ++step) {
    T det;
    t = t - projection_step(nn, xf, p, t1, t2, t, det);
  }
  out = t;
  return true;
}

// Sutherland-Hodgman: the part of polygon `subject` (counter-clockwise) inside the convex
// reference element. A vertex within kOnEdge of an edge's line counts as on it (inside), and no
// intersection is computed for it: the intersection of a master edge nearly collinear with a
// slave edge (coincident boundaries up to round-off, as in the patch test) is ill-conditioned,
// s = s_P / (s_P - s_Q) with both of order 1e-16, and its derivatives, of order 1 / 1e-16, would
// reach every integration point through the cells' vertices. Counted inside, such a vertex lies at most
// kOnEdge outside the facet; the integrals change by that much, smoothly.
constexpr Real kOnEdge = 1e-10;
template <class T>
std::vector<V2<T>> clip(const std::vector<V2<T>>& subject, const Reference& ref) {
  std::vector<V2<T>> out = subject, in;
  for (int e = 0; e < ref.n && out.size() >= 3; ++e) {
    const V2<Real> A = ref.corner[e], B = ref.corner[(e + 1) % ref.n];
    const V2<Real> AB = B - A;
    const Real len = std::sqrt(AB.a * AB.a + AB.b * AB.b);
    auto side = [&](const V2<T>& q) { return (1 / len) * (AB.a * (q.b - A.b) - AB.b * (q.a - A.a)); };
    in.swap(out);
    out.clear();
    for (size_t i = 0; i < in.size(); ++i) {
      const V2<T>& P = in[i];
      const V2<T>& Q = in[(i + 1) % in.size()];
      const T sp = side(P), sq = side(Q);
      const bool pin = value(sp) >= -kOnEdge, qin = value(sq) >= -kOnEdge;
      if (pin) out.push_back(P);
      // An intersection where the edge crosses the line from inside to strictly outside or
      // back; an end on the line is the intersection itself (and is pushed as inside).
      if (pin != qin && value(pin ? sp : sq) > kOnEdge) {
        const T s = sp / (sp - sq);
        out.push_back(P + s * (Q - P));
      }
    }
  }
  // Merge vertices closer than round-off (a master corner on a slave edge gives one twice).
  std::vector<V2<T>> merged;
  for (const V2<T>& p : out) {
    if (!merged.empty()) {
      const V2<Real> d = {value(p.a) - value(merged.back().a), value(p.b) - value(merged.back().b)};
      if (std::abs(d.a) + std::abs(d.b) < 1e-13) continue;  // duplicates of one vertex
    }
    merged.push_back(p);
  }
  while (merged.size() >= 2) {
    const V2<Real> d = {value(merged.front().a) - value(merged.back().a), value(merged.front().b) - value(merged.back().b)};
    if (std::abs(d.a) + std::abs(d.b) >= 1e-13) break;
    merged.pop_back();
  }
  return merged;
}

// Twice the signed area of a polygon of the parameter plane (shoelace), on its values.
template <class T>
Real twice_signed_area(const std::vector<V2<T>>& poly) {
  Real a = 0;
  for (size_t l = 0; l < poly.size(); ++l) {
    const V2<T>& p = poly[l];
    const V2<T>& q = poly[(l + 1) % poly.size()];
    a += value(p.a) * value(q.b) - value(q.a) * value(p.b);
  }
  return a;
}

// The rule on a triangular cell (reference triangle (0,0), (1,0), (0,1); weights sum to 1/2) for
// a slave facet of ns nodes: of the degree of the mass integrands N_i N_k in the slave parameter.
// The rule's error is what changes when the cells change (the clipped polygon gains or loses a
// vertex as a master corner crosses a slave edge, and its fan other triangles): below that
// degree, on curved quad8 and quad9 facets, the weighted gaps moved by 1e-5 of their size
// between two cuttings of one master surface (Mortar3d.WeightedGapsDoNotDependOnTheMastersCells;
// 2e-8 and 3e-9 with these rules), and M_55 of a quad9 facet on the 3D tube slice's fold by 1 %
// from one Newton iterate to the next, which cycled across the jump:
//  - tri3, quad4, tri6 (degree 2, 4, 4): degree 4, 6 points (Dunavant 1985, "High degree
//    efficient symmetrical Gaussian quadrature rules for the triangle", IJNME 21; monomials to
//    degree 4 exact to 5e-16 with these digits), exact for M_ik and G_k of a flat tri6 slave on
//    a tri6 master and of a parallelogram quad4 slave (biquadratic), and otherwise close;
//  - quad8 (N up to xi^2 eta: degree 6) and quad9 (xi^2 eta^2: degree 8): the collapsed Gauss
//    rule of that degree (fem/quadrature, quadrature_rule), 16 and 25 points.
// A tri3 slave on a tri3 master needs no rule (the polygon's moments, below).
struct CellPoint {
  Real r, s, weight;
};
const std::vector<CellPoint>& cell_rule(int ns) {
  static const std::vector<CellPoint> four = [] {
    const Real a = 0.445948490915965, b = 0.091576213509771;
    const Real wa = 0.223381589678011 / 2, wb = 0.109951743655322 / 2;
    return std::vector<CellPoint>{{a, a, wa}, {1 - 2 * a, a, wa}, {a, 1 - 2 * a, wa},
                                  {b, b, wb}, {1 - 2 * b, b, wb}, {b, 1 - 2 * b, wb}};
  }();
  auto of_degree = [](int degree) {
    std::vector<CellPoint> out;
    for (const QuadraturePoint& q : quadrature_rule(ElementType::tri3, degree)) out.push_back({q.xi(0), q.xi(1), q.weight});
    return out;
  };
  static const std::vector<CellPoint> six = of_degree(6), eight = of_degree(8);
  return ns == 9 ? eight : ns == 8 ? six : four;
}

// One integration point of the cells, for friction's slip (plain numbers): the slave and master
// shape functions there and the point's weight (rule weight times current dA); for Nitsche on
// mortar integration (mortar_cell_points) its slave parameters and the rule weight times the
// cell's parameter area (twice it: the rule's weights sum to 1/2).
struct CellSample {
  Real N[kMaxFacetNodes], M[kMaxFacetNodes], w, xi[2], pw;
};

// The integrals u (mortar_dual.hpp) of slave facet xs (ns nodes) against master facet xm (nm
// nodes), `cover` its share of the slave's reference area and `area` the covered current area.
// False when they do not face each other or do not overlap. With `points`, the cells' rule
// points too (tri3 on tri3 as well, whose integrals need no rule: the slip integrands N_k N_i are
// quadratic, which the rule integrates exactly).
template <class T>
bool cell_integrals(int ns, int nm, const V3<T>* xs, const V3<T>* xm, T* u, Real& area, Real& cover,
                    std::vector<CellSample>* points = nullptr) {
  const Reference& ref = reference(ns);
  std::array<T, kMaxFacetNodes> Nv = scratch_shape<T>();
  T* N = Nv.data();  // the slave's shape functions at a rule point
  V3<T> t1, t2;
  {
    V3<T> centre;
    facet_map(ns, V2<T>{T(ref.centre.a), T(ref.centre.b)}, xs, nullptr, nullptr, centre, &t1, &t2);
  }
  const V3<T> m0 = cross(t1, t2);
  const T m0_length = sqrt(dot(m0, m0));
  const V3<T> n0 = (1 / m0_length) * m0;
  {  // facing: the master's normal at its centre points against n0
    const Reference& mr = reference(nm);
    Real M[kMaxFacetNodes], Ma[kMaxFacetNodes], Mb[kMaxFacetNodes];
    shape(nm, mr.centre.a, mr.centre.b, M, Ma, Mb);
    V3<Real> xmv[kMaxFacetNodes];
    for (int i = 0; i < nm; ++i) xmv[i] = val(xm[i]);
    if (dot(cross(interpolate(nm, Ma, xmv), interpolate(nm, Mb, xmv)), val(n0)) >= 0) return false;
  }
  // The master's corners in the slave's parameter plane, counter-clockwise (a quadratic
  // master's edges are taken as their chords there, on both sides of an edge alike, so that
  // neighbouring master facets still tile the plane).
  const int nmc = corners(nm);
  std::vector<V2<T>> poly(nmc);
  const bool flat = ns == 3, affine = ns == 3 && affine_facet(nm);
  if (flat) {
    // A tri3 slave is its own auxiliary plane: the projection along n0 is the orthogonal one,
    // xi = G^-1 [t_1 . (y - x_0), t_2 . (y - x_0)] with the metric G_ab = t_a . t_b.
    const T g11 = dot(t1, t1), g12 = dot(t1, t2), g22 = dot(t2, t2);
    const T inv = 1 / (g11 * g22 - g12 * g12);
    const T i11 = g22 * inv, i12 = -(g12 * inv), i22 = g11 * inv;
    for (int l = 0; l < nmc; ++l) {
      const V3<T> d = xm[l] - xs[0];
      const T r1 = dot(t1, d), r2 = dot(t2, d);
      poly[l] = {i11 * r1 + i12 * r2, i12 * r1 + i22 * r2};
    }
  } else {
    for (int l = 0; l < nmc; ++l)
      if (!project_along(ns, xs, xm[l], t1, t2, poly[l])) return false;
  }
  // A tri3 slave is flat, its Jacobian |a_1 x a_2| = |m0| constant; on a tri3 master as well,
  // the gap along n0 is affine in the slave parameter: g = g0 + ga xi_a + gb xi_b, the
  // interpolation of the master corners' heights h_l = (y_l - x_0) . n0 over their projections
  // xi_l (barycentric coordinates of the projected master triangle). Both evaluated once per pair.
  const T jac_flat = flat ? m0_length : T(0);
  T g0(0), ga(0), gb(0);
  if (affine) {
    const V2<T> e1 = poly[1] - poly[0], e2 = poly[2] - poly[0];
    const T h0 = dot(xm[0] - xs[0], n0);
    const T dh1 = dot(xm[1] - xs[0], n0) - h0, dh2 = dot(xm[2] - xs[0], n0) - h0;
    const T inv = 1 / cross2(e1, e2);
    ga = (e2.b * dh1 - e1.b * dh2) * inv;
    gb = (e1.a * dh2 - e2.a * dh1) * inv;
    g0 = h0 - ga * poly[0].a - gb * poly[0].b;
  }
  const Real signed_area = 0.5 * twice_signed_area(poly);
  if (!(std::abs(signed_area) > 1e-12 * ref.area)) return false;
  if (signed_area < 0) std::reverse(poly.begin(), poly.end());
  const std::vector<V2<T>> cell = clip(poly, ref);
  if (cell.size() < 3) return false;
  const int nc = static_cast<int>(cell.size());
  const Real covered = 0.5 * twice_signed_area(cell);
  if (!(covered > 1e-12 * ref.area)) return false;

  for (int i = 0; i < num_u(ns); ++i) u[i] = T(0);
  Real current = 0;
  if (affine) {
    // Everything is polynomial in the slave parameter (N_k linear, g affine, the Jacobian
    // constant): the integrals are combinations of the clipped polygon's moments
    // [int 1, int a, int b, int a^2, int ab, int b^2], exact by the divergence theorem over its
    // edges (p, q), with c = p_a q_b - q_a p_b: int 1 = sum c / 2, int a = sum (p_a + q_a) c / 6,
    // int a^2 = sum (p_a^2 + p_a q_a + q_a^2) c / 12, int ab = sum (p_a q_b + 2 p_a p_b +
    // 2 q_a q_b + q_a p_b) c / 24 (and b alike).
    T m1(0), ma(0), mb(0), maa(0), mab(0), mbb(0);
    for (int i = 0; i < nc; ++i) {
      const V2<T>& p = cell[i];
      const V2<T>& q = cell[(i + 1) % nc];
      const T pq = p.a * q.b, qp = q.a * p.b, cr = pq - qp;
      m1 += cr;
      ma += (p.a + q.a) * cr;
      mb += (p.b + q.b) * cr;
      maa += (p.a * p.a + p.a * q.a + q.a * q.a) * cr;
      mbb += (p.b * p.b + p.b * q.b + q.b * q.b) * cr;
      mab += (pq + qp + 2.0 * (p.a * p.b + q.a * q.b)) * cr;
    }
    m1 *= 0.5;
    ma *= 1.0 / 6, mb *= 1.0 / 6, maa *= 1.0 / 12, mbb *= 1.0 / 12, mab *= 1.0 / 24;
    // N_k = alpha_k + beta_k a + gamma_k b; int N_j N_k and int N_k g from the moments, int g,
    // int a g and int b g first; all times the constant Jacobian.
    static constexpr Real al[3] = {1, 0, 0}, be[3] = {-1, 1, 0}, gm[3] = {-1, 0, 1};
    const T I0 = g0 * m1 + ga * ma + gb * mb, Ia = g0 * ma + ga * maa + gb * mab, Ib = g0 * mb + ga * mab + gb * mbb;
    for (int k = 0; k < 3; ++k) {
      u[k] = jac_flat * (al[k] * I0 + be[k] * Ia + gm[k] * Ib);
      for (int j = 0; j <= k; ++j)
        u[m_index(3, j, k)] =
            jac_flat * ((al[j] * al[k]) * m1 + (al[j] * be[k] + al[k] * be[j]) * ma +
                        (al[j] * gm[k] + al[k] * gm[j]) * mb + (be[j] * be[k]) * maa +
                        (be[j] * gm[k] + be[k] * gm[j]) * mab + (gm[j] * gm[k]) * mbb);
    }
    current = value(jac_flat) * value(m1);
  }
  if (!affine || points) {
    // The integration cells: the fan of triangles from the clipped polygon's first vertex (nc - 2
    // of them; a fan from the centroid has nc, and took twice the points: the rule's points are
    // most of the work). The polygon is convex (the clipping of a convex projected master facet
    // by the reference element); were it not, its fan's triangles count with their signed areas,
    // which still sum to its integrals.
    const V2<T>& c = cell[0];
    const std::vector<CellPoint>& rule = cell_rule(ns);
    for (int i = 1; i + 1 < nc; ++i) {
      const V2<T> e1 = cell[i] - c, e2 = cell[i + 1] - c;
      const T det = cross2(e1, e2);
      if (value(det) == 0) continue;
      for (const CellPoint& q : rule) {
        const V2<T> xi = c + q.r * e1 + q.s * e2;
        V3<T> x, sa1, sa2;  // the slave's point and (curved facets) its tangents
        facet_map(ns, xi, xs, N, nullptr, x, flat ? nullptr : &sa1, flat ? nullptr : &sa2);
        V2<T> eta;
        if (!project_along(nm, xm, x, t1, t2, eta)) {
          if (affine) continue;  // only the slip's points (the integrals came from the moments)
          return false;
        }
        Real M[kMaxFacetNodes];
        V3<T> y;  // the master's point
        facet_map(nm, eta, xm, nullptr, M, y, nullptr, nullptr);
        T jac;
        if (flat) {
          jac = jac_flat;
        } else {
          const V3<T> m = cross(sa1, sa2);
          jac = sqrt(dot(m, m));
        }
        const T w = (q.weight * det) * jac;
        if (points) {
          CellSample p{};
          for (int k = 0; k < ns; ++k) p.N[k] = value(N[k]);
          for (int k = 0; k < nm; ++k) p.M[k] = M[k];
          p.w = value(w);
          p.xi[0] = value(xi.a), p.xi[1] = value(xi.b);
          p.pw = q.weight * value(det);
          points->push_back(p);
        }
        if (affine) continue;
        const T g = dot(y - x, n0);
        current += value(w);
        const T gw = g * w;
        for (int k = 0; k < ns; ++k) {
          accumulate(u[k], N[k], gw);
          const T nw = N[k] * w;
          for (int j = 0; j <= k; ++j) accumulate(u[m_index(ns, j, k)], N[j], nw);
        }
      }
    }
  }
  area += current;
  cover = covered / ref.area;
  return true;
}

// The integrals and their derivatives over the pair's coordinates xl (slave facet's nodes, then
// the master's). They depend on the nodes' differences only (a common translation changes
// nothing), so the hyper-dual inputs are the other nodes' coordinates relative to the first
// (3 (ns + nm - 1) of them: every product costs NV^2, 15^2 against 18^2 for tri3 on tri3), and the
// first node's derivatives follow: d/dx_0 = -sum_i d/dx_i, i.e. grad = P g and hess = P H P^T.
// HD = HyperDual<NV> (gradients and Hessians) or Dual<NV> (gradients only: s.hess stays empty).
template <class HD>
bool cell_derivatives(int ns, int nm, const std::vector<Vec3>& xl, SegmentIntegrals& s, Real& area, Real& cover) {
  V3<HD> xs[kMaxFacetNodes], xm[kMaxFacetNodes];
  auto input = [&](int i) {
    if (i == 0) return V3<HD>{HD(xl[0](0)), HD(xl[0](1)), HD(xl[0](2))};
    const int k = 3 * (i - 1);
    return V3<HD>{HD::input(xl[i](0), k), HD::input(xl[i](1), k + 1), HD::input(xl[i](2), k + 2)};
  };
  for (int k = 0; k < ns; ++k) xs[k] = input(k);
  for (int k = 0; k < nm; ++k) xm[k] = input(ns + k);
  std::vector<HD> u(num_u(ns));  // on the heap: up to 54 numbers of 11 kB (quad9 on quad9)
  if (!cell_integrals(ns, nm, xs, xm, u.data(), area, cover)) return false;
  const int nu = num_u(ns), nd = 3 * (ns + nm), nr = nd - 3;
  // P g and P H P^T for P = [-I -I ... -I; identity], written out (O(nr^2), where the two
  // matrix products were O(nr^3) per integral): the first node's rows are minus the sums of
  // the others' over each coordinate.
  s.grad.resize(nu);
  for (int k = 0; k < nu; ++k) {
    s.u[k] = u[k].v;
    VecX& g = s.grad[k];
    g.resize(nd);
    g.tail(nr) = u[k].g.head(nr);
    g.head(3).setZero();
    for (int i = 0; i < nr; ++i) g(i % 3) -= u[k].g(i);
  }
  if constexpr (!std::is_same_v<HD, Dual<HD::Vec::RowsAtCompileTime>>) {
    s.hess.resize(nu);
    for (int k = 0; k < nu; ++k) {
      MatX& F = s.hess[k];
      F.resize(nd, nd);
      for (int i = 0; i < nr; ++i)
        for (int j = i; j < nr; ++j) F(3 + i, 3 + j) = F(3 + j, 3 + i) = u[k].h(HD::row(i) + j - i);
      F.topRows(3).setZero();
      for (int j = 0; j < nr; ++j)
        for (int i = 0; i < nr; ++i) F(i % 3, 3 + j) -= F(3 + i, 3 + j);
      for (int j = 0; j < nr; ++j) F.block(0, j % 3, 3, 1) -= F.block(0, 3 + j, 3, 1);
      F.block(3, 0, nr, 3) = F.block(0, 3, 3, nr).transpose();
    }
  }
  return true;
}

// cell_derivatives on AD<NV>, NV the 3 (ns + nm - 1) inputs padded to a multiple of 4 (Eigen
// vectorizes those sizes: 13 % faster on the tet4 Hertz sphere than 15 for tri3 on tri3).
template <template <int> class AD>
bool derivatives_for(int ns, int nm, const std::vector<Vec3>& xl, SegmentIntegrals& s, Real& area, Real& cover) {
  switch ((3 * (ns + nm - 1) + 3) / 4) {
    case 4: return cell_derivatives<AD<16>>(ns, nm, xl, s, area, cover);  // tri3 on tri3
    case 5: return cell_derivatives<AD<20>>(ns, nm, xl, s, area, cover);
    case 6: return cell_derivatives<AD<24>>(ns, nm, xl, s, area, cover);
    case 7: return cell_derivatives<AD<28>>(ns, nm, xl, s, area, cover);
    case 8: return cell_derivatives<AD<32>>(ns, nm, xl, s, area, cover);
    case 9: return cell_derivatives<AD<36>>(ns, nm, xl, s, area, cover);  // quad4 on quad9, tri6 on tri6
    case 10: return cell_derivatives<AD<40>>(ns, nm, xl, s, area, cover);
    case 11: return cell_derivatives<AD<44>>(ns, nm, xl, s, area, cover);  // tri6 on quad9
    case 12: return cell_derivatives<AD<48>>(ns, nm, xl, s, area, cover);
    case 13: return cell_derivatives<AD<52>>(ns, nm, xl, s, area, cover);  // quad9 on quad9
    default: throw Error("mortar (3D): a facet pair has more nodes than expected (" + std::to_string(ns + nm) + ")");
  }
}

}  // namespace

void mortar_cell_points_3d(const MasterSurface& slave, Index e, const MasterSurface& master,
                           const std::vector<Index>& masters, const std::vector<Vec3>& x,
                           std::vector<MortarCellPoint>& out) {
  out.clear();
  const std::vector<Index>& sf = slave.facets[e];
  const int ns = static_cast<int>(sf.size());
  V3<Real> xs[kMaxFacetNodes], xm[kMaxFacetNodes];
  for (int k = 0; k < ns; ++k) xs[k] = {x[sf[k]](0), x[sf[k]](1), x[sf[k]](2)};
  std::vector<CellSample> points;
  for (Index m : masters) {
    const std::vector<Index>& mf = master.facets[m];
    const int nm = static_cast<int>(mf.size());
    for (int k = 0; k < nm; ++k) xm[k] = {x[mf[k]](0), x[mf[k]](1), x[mf[k]](2)};
    Real u[kMaxU], area = 0, cover = 0;
    points.clear();
    if (!cell_integrals(ns, nm, xs, xm, u, area, cover, &points)) continue;
    for (const CellSample& q : points) {
      MortarCellPoint p;
      p.master = m;
      p.xi[0] = q.xi[0], p.xi[1] = q.xi[1];
      p.weight = q.pw;
      out.push_back(p);
    }
  }
}

MortarFacetResult mortar_element_3d(const MasterSurface& slave, Index e, const MasterSurface& master,
                                    const std::vector<Index>& masters, const std::vector<Vec3>& x, bool derivatives,
                                    bool hessian) {
  MortarFacetResult r;
  const std::vector<Index>& sf = slave.facets[e];
  const int ns = static_cast<int>(sf.size());
  if (ns != 3 && ns != 4 && ns != 6 && ns != 8 && ns != 9)
    throw Error("mortar (3D): slave facets must be tri3, tri6, quad4, quad8 or quad9 (a facet has " +
                std::to_string(ns) + " nodes)");
  const BasisTransform tr = basis_transform(3, ns, false);
  const int nu = num_u(ns);
  Real u[kMaxU] = {};
  Real cover = 0, best = 0;
  std::vector<SegmentIntegrals> cells;
  V3<Real> xs[kMaxFacetNodes], xm[kMaxFacetNodes];
  for (int k = 0; k < ns; ++k) xs[k] = {x[sf[k]](0), x[sf[k]](1), x[sf[k]](2)};
  r.nodes.assign(sf.begin(), sf.end());
  std::vector<CellSample> points;
  std::vector<VecX> relative(ns, VecX::Zero(ns));
  std::vector<Real> slip_weight(ns, 0.0);
  for (Index m : masters) {
    const std::vector<Index>& mf = master.facets[m];
    const int nm = static_cast<int>(mf.size());
    if (nm != 3 && nm != 4 && nm != 6 && nm != 8 && nm != 9)
      throw Error("mortar (3D): master facets must be tri3, tri6, quad4, quad8 or quad9 (a facet has " +
                  std::to_string(nm) + " nodes)");
    for (int k = 0; k < nm; ++k) xm[k] = {x[mf[k]](0), x[mf[k]](1), x[mf[k]](2)};
    // Plain numbers first: most candidates do not overlap (88 candidates per slave facet, 5 of
    // them overlapping, on the tet4 Hertz sphere). With derivatives the integrals are then those
    // of the hyper-dual evaluation (whose branch decisions, on values, may differ from the plain
    // one's by round-off at a degenerate overlap), so that values and derivatives belong together.
    Real us[kMaxU], c = 0, area = 0;
    points.clear();
    if (!cell_integrals(ns, nm, xs, xm, us, area, c, &points)) continue;
    SegmentIntegrals s;
    if (derivatives) {
      s.nodes.assign(sf.begin(), sf.end());
      s.nodes.insert(s.nodes.end(), mf.begin(), mf.end());
      std::vector<Vec3> xl;
      for (Index n : s.nodes) xl.push_back(x[n]);
      bool ok = false;
      area = c = 0;
      ok = hessian ? derivatives_for<HyperDual>(ns, nm, xl, s, area, c) : derivatives_for<Dual>(ns, nm, xl, s, area, c);
      if (!ok) continue;
      std::copy(s.u, s.u + nu, us);
    }
    r.segment_length += area;
    if (r.masters.empty() || c > best) r.facet = m, best = c;  // the master of the largest cover
    r.masters.push_back(m);
    cover += c;
    for (int i = 0; i < nu; ++i) u[i] += us[i];
    int at[2 * kMaxFacetNodes];
    for (int k = 0; k < ns + nm; ++k) {
      const Index n = k < ns ? sf[k] : mf[k - ns];
      auto it = std::find(r.nodes.begin(), r.nodes.end(), n);
      at[k] = static_cast<int>(it - r.nodes.begin());
      if (it == r.nodes.end()) {
        r.nodes.push_back(n);
        for (VecX& v : relative) v.conservativeResize(static_cast<Index>(r.nodes.size())), v.tail(1).setZero();
      }
    }
    // Friction's relative positions: per slave facet node k, sum_q N~_k(xi_q) w_q (x_s(xi_q) -
    // x_m(eta_q)) as coefficients of the nodes, and its weight sum_q N~_k w_q (N~: N itself on
    // tri3 and quad4, basis_transform's on quadratic facets), turned into the dual basis's once
    // the facet's integrals are summed (dual_slip_weights), as in 2D.
    for (const CellSample& q : points)
      for (int k = 0; k < ns; ++k) {
        Real nt = q.N[k];
        if (!tr.identity) {
          nt = 0;
          for (int i = 0; i < ns; ++i) nt += tr.t[k][i] * q.N[i];
        }
        const Real wk = nt * q.w;
        slip_weight[k] += wk;
        for (int i = 0; i < ns; ++i) relative[k](at[i]) += wk * q.N[i];
        for (int l = 0; l < nm; ++l) relative[k](at[ns + l]) -= wk * q.M[l];
      }
    if (derivatives) cells.push_back(std::move(s));
  }
  // A sliver of cover: the dual basis on it is ill-conditioned (M nearly singular) while its
  // weighted gaps are of the order of the cover times the gap; it is left out.
  if (!(cover >= kMinCover)) {
    r.masters.clear();
    r.nodes.clear();
    r.segment_length = 0;
    return r;
  }
  r.overlap = true;
  Real gap[kMaxNs];
  dual_weighted_gaps(ns, u, tr, gap);
  r.gap.assign(gap, gap + ns);
  dual_slip_weights(ns, u, tr, relative, slip_weight);
  r.relative = std::move(relative);
  r.slip_weight = std::move(slip_weight);
  if (derivatives) weighted_gap_derivatives(3, ns, u, tr, cells, r);
  return r;
}

}  // namespace signorini
