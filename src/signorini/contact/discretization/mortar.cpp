#include "signorini/contact/discretization/mortar.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "signorini/contact/geometry/hyper_dual.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/quadrature.hpp"

namespace signorini {

namespace {

inline Real sqrt(Real a) { return std::sqrt(a); }

// Points of the plane with coordinates of type T (Real or HyperDual).
template <class T>
struct P2 {
  T x{}, y{};
};
template <class T>
P2<T> operator+(const P2<T>& a, const P2<T>& b) {
  return {a.x + b.x, a.y + b.y};
}
template <class T>
P2<T> operator-(const P2<T>& a, const P2<T>& b) {
  return {a.x - b.x, a.y - b.y};
}
template <class T, class S>
P2<T> operator*(const S& s, const P2<T>& a) {
  return {s * a.x, s * a.y};
}
template <class T>
T dot(const P2<T>& a, const P2<T>& b) {
  return a.x * b.x + a.y * b.y;
}
template <class T>
T cross(const P2<T>& a, const P2<T>& b) {
  return a.x * b.y - a.y * b.x;
}
template <class T>
P2<Real> val(const P2<T>& a) {
  return {value(a.x), value(a.y)};
}

// Line2 (nn = 2) or line3 (nn = 3; nodes at xi = -1, 1, 0) shape functions and derivatives.
template <class T>
void line_shape(int nn, const T& xi, T* N, T* dN) {
  if (nn == 2) {
    N[0] = (1 - xi) * 0.5;
    N[1] = (1 + xi) * 0.5;
    dN[0] = T(-0.5);
    dN[1] = T(0.5);
  } else {
    N[0] = xi * (xi - 1) * 0.5;
    N[1] = xi * (xi + 1) * 0.5;
    N[2] = 1 - xi * xi;
    dN[0] = xi - 0.5;
    dN[1] = xi + 0.5;
    dN[2] = -2 * xi;
  }
}
Real node_parameter(int k) { return k == 0 ? -1.0 : k == 1 ? 1.0 : 0.0; }

template <class T>
P2<T> interpolate(int nn, const T* N, const P2<T>* x) {
  P2<T> p{T(0), T(0)};
  for (int i = 0; i < nn; ++i) p = p + N[i] * x[i];
  return p;
}

// Outward unit normal of a line facet at xi (facets are oriented so that (t_y, -t_x) points out
// of their body, as facet_normal does).
template <class T>
P2<T> facet_normal_at(int nn, const P2<T>* x, const T& xi) {
  T N[3], dN[3];
  line_shape(nn, xi, N, dN);
  const P2<T> t = interpolate(nn, dN, x);
  const T len = sqrt(dot(t, t));
  return {t.y / len, -t.x / len};
}
// The local layout of one slave facet against one master facet: local node indices.
struct Layout {
  int ns = 2, nm = 2;  // nodes of the slave and master facets
  int slave[3] = {0, 1, 2};
  int master[3] = {0, 0, 0};
  // Per slave facet node: the slave facets around it (node count, local indices, the node's
  // place in that facet), for its averaged normal.
  struct Around {
    int nn;
    int nodes[3];
    int at;
  };
  std::vector<Around> around[3];
};

template <class T>
P2<T> nodal_normal(const Layout::Around* around, size_t count, const std::vector<P2<T>>& X) {
  P2<T> n{T(0), T(0)};
  for (size_t a = 0; a < count; ++a) {
    const Layout::Around& f = around[a];
    P2<T> xf[3];
    for (int i = 0; i < f.nn; ++i) xf[i] = X[f.nodes[i]];
    n = n + facet_normal_at(f.nn, xf, T(node_parameter(f.at)));
  }
  const T len = sqrt(dot(n, n));
  return {n.x / len, n.y / len};
}

// Newton in plain numbers from xi0, then two steps on T from the converged parameter: one step
// makes the first derivatives exact (the Newton map is stationary at its fixed point), the
// second the second derivatives. F(xi) and F'(xi) come from `residual`.
template <class T, class FR, class FT>
bool solve_parameter(Real xi0, const FR& residual_real, const FT& residual, T& xi_out) {
  // Converged when the step is at round-off (1e-12 in the parameter, whose range is [-1, 1]);
  // a step that stops shrinking above it (round-off in F) is accepted below 1e-9, since the two
  // polishing steps follow.
  Real xi = xi0, last = 1e300;
  bool ok = false;
  for (int it = 0; it < 50; ++it) {
    Real F = 0, dF = 0;
    residual_real(xi, F, dF);
    if (!(std::abs(dF) > 0) || !std::isfinite(F)) return false;
    const Real d = F / dF;
    xi -= d;
    if (!(std::abs(xi) < 1e3)) return false;
    if (std::abs(d) < 1e-12 * (1 + std::abs(xi))) {
      ok = true;
      break;
    }
    if (it >= 8 && std::abs(d) >= 0.5 * last && std::abs(d) < 1e-9) {
      ok = true;
      break;
    }
    last = std::abs(d);
  }
  if (!ok) return false;
  T t = T(xi);
  for (int step = 0; step < 2; ++step) {
    T F, dF;
    residual(t, F, dF);
    t = t - F / dF;
  }
  xi_out = t;
  return true;
}

// The weighted gaps of the slave facet's nodes (gap[k] += ...) over its overlap with the master
// facet; false when they do not overlap (or do not face each other).
template <class T>
bool evaluate(const Layout& L, const std::vector<P2<T>>& X, const MortarMeasure& ms, T* gap, Real& seglen) {
  const int ns = L.ns, nm = L.nm;
  P2<T> xs[3], xm[3], nk[3];
  for (int k = 0; k < ns; ++k) xs[k] = X[L.slave[k]];
  for (int k = 0; k < nm; ++k) xm[k] = X[L.master[k]];
  // Facing: the slave and master normals at the facet centres point against each other.
  {
    P2<Real> xsv[3], xmv[3];
    for (int k = 0; k < ns; ++k) xsv[k] = val(xs[k]);
    for (int k = 0; k < nm; ++k) xmv[k] = val(xm[k]);
    if (dot(facet_normal_at(ns, xsv, 0.0), facet_normal_at(nm, xmv, 0.0)) >= 0) return false;
  }
  for (int k = 0; k < ns; ++k) nk[k] = nodal_normal(L.around[k].data(), L.around[k].size(), X);

  // Segmentation: the master's end nodes projected onto the slave facet along the
  // interpolated slave normal n(xi): (x_s(xi) - x_m) x n(xi) = 0.
  T ends[2];
  for (int c = 0; c < 2; ++c) {
    const P2<T> p = xm[c];
    P2<Real> xsv[3], nkv[3];
    for (int k = 0; k < ns; ++k) xsv[k] = val(xs[k]), nkv[k] = val(nk[k]);
    const P2<Real> pv = val(p);
    auto fr = [&](Real xi, Real& F, Real& dF) {
      Real N[3], dN[3];
      line_shape(ns, xi, N, dN);
      const P2<Real> x = interpolate(ns, N, xsv), dx = interpolate(ns, dN, xsv);
      const P2<Real> n = interpolate(ns, N, nkv), dn = interpolate(ns, dN, nkv);
      F = cross(x - pv, n);
      dF = cross(dx, n) + cross(x - pv, dn);
    };
    auto ft = [&](const T& xi, T& F, T& dF) {
      T N[3], dN[3];
      line_shape(ns, xi, N, dN);
      const P2<T> x = interpolate(ns, N, xs), dx = interpolate(ns, dN, xs);
      const P2<T> n = interpolate(ns, N, nk), dn = interpolate(ns, dN, nk);
      F = cross(x - p, n);
      dF = cross(dx, n) + cross(x - p, dn);
    };
    if (!solve_parameter(0.0, fr, ft, ends[c])) return false;
  }
  const T& lo = value(ends[0]) < value(ends[1]) ? ends[0] : ends[1];
  const T& hi = value(ends[0]) < value(ends[1]) ? ends[1] : ends[0];
  const T a = value(lo) > -1 ? lo : T(-1);
  const T b = value(hi) < 1 ? hi : T(1);
  if (!(value(b) - value(a) > 1e-12)) return false;

  auto measure = [&](const P2<T>& x) { return ms.axisymmetric ? T(2 * std::numbers::pi) * x.x : T(ms.thickness); };

  // Dual basis on the whole slave facet: A = D M^-1.
  std::vector<Real> gx, gw;
  gauss_legendre(ns == 2 ? 3 : 6, gx, gw);
  T M[3][3], D[3];
  for (int i = 0; i < ns; ++i) {
    D[i] = T(0);
    for (int k = 0; k < ns; ++k) M[i][k] = T(0);
  }
  for (size_t q = 0; q < gx.size(); ++q) {
    T N[3], dN[3];
    line_shape(ns, T(gx[q]), N, dN);
    const P2<T> dx = interpolate(ns, dN, xs);
    const T da = sqrt(dot(dx, dx)) * measure(interpolate(ns, N, xs)) * gw[q];
    for (int i = 0; i < ns; ++i) {
      D[i] += N[i] * da;
      for (int k = 0; k < ns; ++k) M[i][k] += N[i] * N[k] * da;
    }
  }
  // A = D M^-1 by Gauss-Jordan on [M | I] (M is a mass matrix: symmetric positive definite).
  T inv[3][3];
  for (int i = 0; i < ns; ++i)
    for (int k = 0; k < ns; ++k) inv[i][k] = T(i == k ? 1.0 : 0.0);
  for (int p = 0; p < ns; ++p) {
    const T piv = 1 / M[p][p];
    for (int k = 0; k < ns; ++k) {
      M[p][k] = M[p][k] * piv;
      inv[p][k] = inv[p][k] * piv;
    }
    for (int r = 0; r < ns; ++r) {
      if (r == p) continue;
      const T f = M[r][p];
      for (int k = 0; k < ns; ++k) {
        M[r][k] -= f * M[p][k];
        inv[r][k] -= f * inv[p][k];
      }
    }
  }
  T A[3][3];
  for (int i = 0; i < ns; ++i)
    for (int k = 0; k < ns; ++k) A[i][k] = D[i] * inv[i][k];

  // The segment's Gauss points in the slave parameter.
  gauss_legendre(ns == 2 && nm == 2 ? 5 : 8, gx, gw);
  const T mid = 0.5 * (a + b), half = 0.5 * (b - a);
  for (size_t q = 0; q < gx.size(); ++q) {
    const T xi = mid + half * gx[q];
    T N[3], dN[3];
    line_shape(ns, xi, N, dN);
    const P2<T> x = interpolate(ns, N, xs), dx = interpolate(ns, dN, xs);
    const P2<T> n = interpolate(ns, N, nk);
    // The master point along n: (x_m(eta) - x) x n = 0.
    P2<Real> xmv[3];
    for (int k = 0; k < nm; ++k) xmv[k] = val(xm[k]);
    const P2<Real> xv = val(x), nv = val(n);
    auto fr = [&](Real eta, Real& F, Real& dF) {
      Real M2[3], dM2[3];
      line_shape(nm, eta, M2, dM2);
      F = cross(interpolate(nm, M2, xmv) - xv, nv);
      dF = cross(interpolate(nm, dM2, xmv), nv);
    };
    auto ft = [&](const T& eta, T& F, T& dF) {
      T M2[3], dM2[3];
      line_shape(nm, eta, M2, dM2);
      F = cross(interpolate(nm, M2, xm) - x, n);
      dF = cross(interpolate(nm, dM2, xm), n);
    };
    T eta;
    if (!solve_parameter(0.0, fr, ft, eta)) return false;
    T M2[3], dM2[3];
    line_shape(nm, eta, M2, dM2);
    const P2<T> y = interpolate(nm, M2, xm);
    const T g = dot(y - x, n) / sqrt(dot(n, n));
    const T jac = sqrt(dot(dx, dx));
    const T w = half * gw[q] * jac * measure(x);
    seglen += value(half) * gw[q] * value(jac);
    const T gw_ = g * w;
    for (int j = 0; j < ns; ++j) {
      T phi = T(0);
      for (int k = 0; k < ns; ++k) phi += A[j][k] * N[k];
      gap[j] += phi * gw_;
    }
  }
  return true;
}

template <int N>
void evaluate_derivatives(const Layout& L, const std::vector<Vec3>& xl, const MortarMeasure& ms,
                          MortarFacetResult& r) {
  using HD = HyperDual<N>;
  const int nl = static_cast<int>(xl.size());
  std::vector<P2<HD>> X(nl);
  for (int i = 0; i < nl; ++i) X[i] = {HD::input(xl[i](0), 2 * i), HD::input(xl[i](1), 2 * i + 1)};
  HD gap[3];
  Real seglen = 0;
  if (!evaluate(L, X, ms, gap, seglen)) {
    r.overlap = false;
    return;
  }
  for (int k = 0; k < L.ns; ++k) {
    r.gap[k] = gap[k].v;
    r.grad[k] = gap[k].g.head(2 * nl);
    r.hess[k] = gap[k].h.topLeftCorner(2 * nl, 2 * nl);
  }
}

}  // namespace

MortarFacetResult mortar_facet_2d(const MasterSurface& slave, Index e, const MasterSurface& master, Index m,
                                  const std::vector<Vec3>& x, const MortarMeasure& measure, bool derivatives) {
  MortarFacetResult r;
  Layout L;
  auto local = [&](Index node) {
    auto it = std::find(r.nodes.begin(), r.nodes.end(), node);
    if (it != r.nodes.end()) return static_cast<int>(it - r.nodes.begin());
    r.nodes.push_back(node);
    return static_cast<int>(r.nodes.size() - 1);
  };
  const auto& sf = slave.facets[e];
  L.ns = static_cast<int>(sf.size());
  for (int k = 0; k < L.ns; ++k) L.slave[k] = local(sf[k]);
  for (int k = 0; k < L.ns; ++k) {
    // The corner nodes' normals average the facets around them; a mid-side node has its facet's.
    const std::vector<Index> around = k < 2 ? slave.node_facets[sf[k]] : std::vector<Index>{e};
    for (Index f : around) {
      Layout::Around a;
      a.nn = static_cast<int>(slave.facets[f].size());
      a.at = 0;
      for (int i = 0; i < a.nn; ++i) {
        a.nodes[i] = local(slave.facets[f][i]);
        if (slave.facets[f][i] == sf[k]) a.at = i;
      }
      L.around[k].push_back(a);
    }
  }
  const auto& mf = master.facets[m];
  L.nm = static_cast<int>(mf.size());
  for (int k = 0; k < L.nm; ++k) L.master[k] = local(mf[k]);

  std::vector<Vec3> xl(r.nodes.size());
  for (size_t i = 0; i < xl.size(); ++i) xl[i] = x[r.nodes[i]];
  std::vector<P2<Real>> X(xl.size());
  for (size_t i = 0; i < xl.size(); ++i) X[i] = {xl[i](0), xl[i](1)};
  Real gap[3] = {0, 0, 0};
  r.overlap = evaluate(L, X, measure, gap, r.segment_length);
  if (!r.overlap) return r;
  r.gap.assign(gap, gap + L.ns);
  if (!derivatives) return r;
  r.grad.resize(L.ns);
  r.hess.resize(L.ns);
  const size_t n2 = 2 * r.nodes.size();
  if (n2 <= 12) evaluate_derivatives<12>(L, xl, measure, r);
  else if (n2 <= 16) evaluate_derivatives<16>(L, xl, measure, r);
  else if (n2 <= 20) evaluate_derivatives<20>(L, xl, measure, r);
  else if (n2 <= 24) evaluate_derivatives<24>(L, xl, measure, r);
  else throw Error("mortar: a slave facet depends on more nodes than expected (" + std::to_string(r.nodes.size()) + ")");
  return r;
}

void mortar_nodal_normal_2d(const MasterSurface& slave, Index node, const std::vector<Vec3>& x, Vec3& normal,
                            std::vector<Index>& nodes, MatX& jacobian) {
  using HD = HyperDual<12>;
  nodes.clear();
  std::vector<Layout::Around> around;
  auto local = [&](Index n) {
    auto it = std::find(nodes.begin(), nodes.end(), n);
    if (it != nodes.end()) return static_cast<int>(it - nodes.begin());
    nodes.push_back(n);
    return static_cast<int>(nodes.size() - 1);
  };
  for (Index f : slave.node_facets[node]) {
    Layout::Around a;
    a.nn = static_cast<int>(slave.facets[f].size());
    a.at = 0;
    for (int i = 0; i < a.nn; ++i) {
      a.nodes[i] = local(slave.facets[f][i]);
      if (slave.facets[f][i] == node) a.at = i;
    }
    around.push_back(a);
  }
  if (2 * nodes.size() > 12) throw Error("mortar: a slave node with more than 6 neighbouring nodes");
  std::vector<P2<HD>> X(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    X[i] = {HD::input(x[nodes[i]](0), 2 * static_cast<int>(i)), HD::input(x[nodes[i]](1), 2 * static_cast<int>(i) + 1)};
  const P2<HD> n = nodal_normal(around.data(), around.size(), X);
  normal = Vec3(n.x.v, n.y.v, 0);
  const Index cols = 2 * static_cast<Index>(nodes.size());
  jacobian.resize(2, cols);
  jacobian.row(0) = n.x.g.head(cols).transpose();
  jacobian.row(1) = n.y.g.head(cols).transpose();
}

}  // namespace signorini
