#include "signorini/contact/discretization/mortar.hpp"

#include "signorini/contact/discretization/mortar_dual.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "signorini/contact/geometry/hyper_dual.hpp"
#include "signorini/core/binary_io.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/quadrature.hpp"

namespace signorini {

namespace {

using namespace mortar_detail;

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

// The integrals u of one segment (mortar_dual.hpp) and `cover`, the segment's share of the slave
// facet's parameter range. False when the facets do not overlap, do not face each other, or the
// slave-to-master map folds over (a point of the segment projects off the master facet: beyond
// the focus of a concave slave wall's normals).

// One integration point of a segment, for friction's slip (plain numbers): the slave and master
// shape functions there and the point's weight (current dA times the Gauss weight); for Nitsche
// on mortar integration (mortar_cell_points) its slave parameter and the Gauss weight times the
// segment's half length in that parameter.
struct SegmentPoint {
  Real N[3], M[3], w, xi, pw;
};

template <class T>
bool segment_integrals(const Layout& L, const std::vector<P2<T>>& X, const MortarMeasure& ms, T* u, Real& seglen,
                       Real& cover, std::vector<SegmentPoint>* points = nullptr) {
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
  const int nu = num_u(ns);
  for (int i = 0; i < nu; ++i) u[i] = T(0);
  Real length = 0;

  // The segment's Gauss points in the slave parameter (exact for M_ik).
  std::vector<Real> gx, gw;
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
    // Inside the segment the map is monotone and eta stays in [-1, 1] (its ends map to the
    // master's ends); a point beyond means the map folded over.
    if (std::abs(value(eta)) > 1 + 1e-6) return false;
    T M2[3], dM2[3];
    line_shape(nm, eta, M2, dM2);
    const P2<T> y = interpolate(nm, M2, xm);
    const T g = dot(y - x, n) / sqrt(dot(n, n));
    const T jac = sqrt(dot(dx, dx));
    const T w = half * gw[q] * jac * measure(x);
    length += value(half) * gw[q] * value(jac);
    const T gw_ = g * w;
    if (points) {
      SegmentPoint sp;
      for (int k = 0; k < 3; ++k) sp.N[k] = k < ns ? value(N[k]) : 0, sp.M[k] = k < nm ? value(M2[k]) : 0;
      sp.w = value(w);
      sp.xi = value(xi);
      sp.pw = value(half) * gw[q];
      points->push_back(sp);
    }
    for (int k = 0; k < ns; ++k) {
      u[k] += N[k] * gw_;
      const T nw = N[k] * w;
      for (int i = 0; i <= k; ++i) u[m_index(ns, i, k)] += N[i] * nw;
    }
  }
  seglen += length;
  cover = 0.5 * (value(b) - value(a));
  return true;
}

template <int N>
bool segment_derivatives(const Layout& L, const std::vector<Vec3>& xl, const MortarMeasure& ms, SegmentIntegrals& r) {
  using HD = HyperDual<N>;
  const int nl = static_cast<int>(xl.size());
  std::vector<P2<HD>> X(nl);
  for (int i = 0; i < nl; ++i) X[i] = {HD::input(xl[i](0), 2 * i), HD::input(xl[i](1), 2 * i + 1)};
  HD u[kMaxU2d];
  Real seglen = 0, cover = 0;
  if (!segment_integrals(L, X, ms, u, seglen, cover)) return false;
  const int nu = num_u(L.ns);
  r.grad.resize(nu);
  r.hess.resize(nu);
  for (int k = 0; k < nu; ++k) {
    r.u[k] = u[k].v;
    r.grad[k] = u[k].g.head(2 * nl);
    r.hess[k] = u[k].hessian().topLeftCorner(2 * nl, 2 * nl);
  }
  return true;
}

// The layout of slave facet e against master facet m; `nodes` (mesh indices) is the local
// numbering: the slave facet's nodes, the other nodes of its neighbouring facets, the master's.
Layout make_layout(const MasterSurface& slave, Index e, const MasterSurface& master, Index m, std::vector<Index>& nodes) {
  Layout L;
  nodes.clear();
  auto local = [&](Index node) {
    auto it = std::find(nodes.begin(), nodes.end(), node);
    if (it != nodes.end()) return static_cast<int>(it - nodes.begin());
    nodes.push_back(node);
    return static_cast<int>(nodes.size() - 1);
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
  return L;
}

}  // namespace

BasisTransform mortar_detail::basis_transform(int dim, int ns, bool positive) {
  BasisTransform tr;
  const bool line3 = dim == 2 && ns == 3 && positive, tri6 = dim == 3 && ns == 6, quad8 = dim == 3 && ns == 8;
  if (!(line3 || tri6 || quad8 || (dim == 3 && ns == 9))) return tr;
  tr.identity = false;
  if (dim == 3 && ns == 9) {
    // Tensor product of line3's transform over the 1D node positions (-1, 0, 1) of each node.
    const Real t1[3][3] = {{1, kTransform, 0}, {0, 1 - 2 * kTransform, 0}, {0, kTransform, 1}};
    static constexpr int ia[9] = {0, 2, 2, 0, 1, 2, 1, 0, 1}, ib[9] = {0, 0, 2, 2, 0, 1, 2, 1, 1};
    for (int i = 0; i < 9; ++i)
      for (int k = 0; k < 9; ++k) tr.t[i][k] = t1[ia[i]][ia[k]] * t1[ib[i]][ib[k]];
    return tr;
  }
  // Corners 0..nc-1, then the mid-side node of edge (k, k+1) at nc + k (line3: its one mid-side).
  const int nc = line3 ? 2 : tri6 ? 3 : 4;
  const Real alpha = quad8 ? 0.375 : kTransform;
  for (int k = 0; k < ns; ++k) tr.t[k][k] = k < nc ? 1 : 1 - 2 * alpha;
  for (int k = 0; k < (line3 ? 1 : nc); ++k) {
    tr.t[k][nc + k] = alpha;
    tr.t[(k + 1) % nc][nc + k] = alpha;
  }
  return tr;
}

void mortar_positive_basis(const VecX& N, VecX& Nt) {
  const int ns = static_cast<int>(N.size());
  const BasisTransform tr = basis_transform(3, ns, false);
  Nt = N;
  if (tr.identity) return;
  for (int i = 0; i < ns; ++i) {
    Nt(i) = 0;
    for (int k = 0; k < ns; ++k) Nt(i) += tr.t[i][k] * N(k);
  }
}

namespace {
template <int NU>
void weighted_gap_derivatives_on(int dim, int ns, const Real* u, const BasisTransform& tr,
                                 const std::vector<SegmentIntegrals>& segments, MortarFacetResult& r) {
  const int nu = num_u(ns);
  using HU = HyperDual<NU>;
  // On the heap: a quad9's 54 inputs make each number 12 kB.
  std::vector<HU> uh(nu), gh(ns);
  for (int i = 0; i < nu; ++i) uh[i] = HU::input(u[i], i);
  dual_weighted_gaps(ns, uh.data(), tr, gh.data());
  const Index nd = dim * static_cast<Index>(r.nodes.size());
  // Without the segments' Hessians (3D, a residual only): gradients only, r.hess empty.
  const bool hessian = std::all_of(segments.begin(), segments.end(), [](const SegmentIntegrals& s) { return !s.hess.empty(); });
  r.grad.assign(ns, VecX::Zero(nd));
  if (hessian) r.hess.assign(ns, MatX::Zero(nd, nd));
  // The segments' nodes in the element's numbering, and the gradients of the summed u there.
  std::vector<std::vector<Index>> at(segments.size());
  MatX Gsum = MatX::Zero(nd, nu);
  for (size_t p = 0; p < segments.size(); ++p) {
    const SegmentIntegrals& s = segments[p];
    for (size_t a = 0; a < s.nodes.size(); ++a) {
      at[p].push_back(std::find(r.nodes.begin(), r.nodes.end(), s.nodes[a]) - r.nodes.begin());
      for (int i = 0; i < nu; ++i)
        Gsum.block(dim * at[p][a], i, dim, 1) += s.grad[i].segment(dim * static_cast<Index>(a), dim);
    }
  }
  MatX sum;
  for (int j = 0; j < ns; ++j) {
    const VecX fa = gh[j].g;
    const MatX fab = gh[j].hessian();
    r.grad[j] = Gsum * fa.head(nu);
    if (!hessian) continue;
    r.hess[j] = Gsum * fab.topLeftCorner(nu, nu) * Gsum.transpose();
    for (size_t p = 0; p < segments.size(); ++p) {
      const SegmentIntegrals& s = segments[p];
      const std::vector<Index>& A = at[p];
      // sum_i fa_i H_i on the segment's nodes, then added into the element's numbering once.
      sum.setZero(s.hess[0].rows(), s.hess[0].cols());
      for (int i = 0; i < nu; ++i)
        if (fa(i) != 0) sum += fa(i) * s.hess[i];
      for (size_t a = 0; a < A.size(); ++a)
        for (size_t b = 0; b < A.size(); ++b)
          r.hess[j].block(dim * A[a], dim * A[b], dim, dim) +=
              sum.block(dim * static_cast<Index>(a), dim * static_cast<Index>(b), dim, dim);
    }
  }
}
}  // namespace

void mortar_detail::weighted_gap_derivatives(int dim, int ns, const Real* u, const BasisTransform& tr,
                                             const std::vector<SegmentIntegrals>& segments, MortarFacetResult& r) {
  // Sized by the integrals' count: 5 and 9 (line2, line3; tri3), 14 (quad4), 27 (tri6), 44 (quad8), 54 (quad9).
  const int nu = num_u(ns);
  if (nu <= 9) weighted_gap_derivatives_on<9>(dim, ns, u, tr, segments, r);
  else if (nu <= 14) weighted_gap_derivatives_on<14>(dim, ns, u, tr, segments, r);
  else if (nu <= 27) weighted_gap_derivatives_on<27>(dim, ns, u, tr, segments, r);
  else if (nu <= 44) weighted_gap_derivatives_on<44>(dim, ns, u, tr, segments, r);
  else weighted_gap_derivatives_on<kMaxU>(dim, ns, u, tr, segments, r);
}

void mortar_cell_points(const MasterSurface& slave, Index e, const MasterSurface& master,
                        const std::vector<Index>& masters, const std::vector<Vec3>& x, int dim,
                        std::vector<MortarCellPoint>& out) {
  if (dim == 3) return mortar_cell_points_3d(slave, e, master, masters, x, out);
  out.clear();
  std::vector<Index> nodes;
  std::vector<SegmentPoint> points;
  for (Index m : masters) {
    const Layout L = make_layout(slave, e, master, m, nodes);
    std::vector<P2<Real>> X(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) X[i] = {x[nodes[i]](0), x[nodes[i]](1)};
    Real u[kMaxU], length = 0, cover = 0;
    points.clear();
    if (!segment_integrals(L, X, MortarMeasure{}, u, length, cover, &points)) continue;
    for (const SegmentPoint& q : points) {
      MortarCellPoint p;
      p.master = m;
      p.xi[0] = q.xi;
      p.weight = q.pw;
      out.push_back(p);
    }
  }
}

MortarFacetResult mortar_element_2d(const MasterSurface& slave, Index e, const MasterSurface& master,
                                    const std::vector<Index>& masters, const std::vector<Vec3>& x,
                                    const MortarMeasure& measure, bool derivatives, bool positive_basis) {
  MortarFacetResult r;
  const int ns = static_cast<int>(slave.facets[e].size());
  const int nu = num_u(ns);
  Real u[kMaxU] = {};
  Real cover = 0;
  std::vector<SegmentIntegrals> segments;
  std::vector<Index> nodes;
  std::vector<SegmentPoint> points;
  std::vector<VecX> relative(ns);
  std::vector<Real> slip_weight(ns, 0.0);
  const BasisTransform tr = basis_transform(2, ns, positive_basis);
  for (Index m : masters) {
    const Layout L = make_layout(slave, e, master, m, nodes);
    std::vector<Vec3> xl(nodes.size());
    for (size_t i = 0; i < xl.size(); ++i) xl[i] = x[nodes[i]];
    std::vector<P2<Real>> X(xl.size());
    for (size_t i = 0; i < xl.size(); ++i) X[i] = {xl[i](0), xl[i](1)};
    Real us[kMaxU], c = 0;
    points.clear();
    if (!segment_integrals(L, X, measure, us, r.segment_length, c, &points)) continue;
    if (r.masters.empty() || c > cover) r.facet = m;  // the master of the longest segment
    r.masters.push_back(m);
    cover += c;
    for (int i = 0; i < nu; ++i) u[i] += us[i];
    // Friction's relative positions: per slave facet node k, sum_q N~_k(xi_q) w_q (x_s(xi_q) -
    // x_m(eta_q)) as coefficients of the nodes, and its weight sum_q N~_k w_q (N~ >= 0: the
    // transformed basis on line3), turned into the weights of N~'s dual basis once the facet's
    // integrals are summed (dual_slip_weights; its weights int N~_j dA stay positive, where those
    // of N's dual basis, the normal's on line3 but in self-contact, may not on a partly covered
    // facet).
    std::vector<int> at(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
      auto it = std::find(r.nodes.begin(), r.nodes.end(), nodes[i]);
      at[i] = static_cast<int>(it - r.nodes.begin());
      if (it == r.nodes.end()) {
        r.nodes.push_back(nodes[i]);
        for (VecX& v : relative) v.conservativeResize(static_cast<Index>(r.nodes.size())), v.tail(1).setZero();
      }
    }
    for (const SegmentPoint& q : points) {
      Real Nt[3];
      transformed_basis(ns, q.N, Nt);
      for (int k = 0; k < ns; ++k) {
        const Real wk = Nt[k] * q.w;
        slip_weight[k] += wk;
        for (int i = 0; i < ns; ++i) relative[k](at[L.slave[i]]) += wk * q.N[i];
        for (int l = 0; l < L.nm; ++l) relative[k](at[L.master[l]]) -= wk * q.M[l];
      }
    }
    if (!derivatives) continue;
    SegmentIntegrals s;
    s.nodes = nodes;
    const size_t n2 = 2 * nodes.size();
    bool ok = false;
    if (n2 <= 12) ok = segment_derivatives<12>(L, xl, measure, s);
    else if (n2 <= 16) ok = segment_derivatives<16>(L, xl, measure, s);
    else if (n2 <= 20) ok = segment_derivatives<20>(L, xl, measure, s);
    else if (n2 <= 24) ok = segment_derivatives<24>(L, xl, measure, s);
    else throw Error("mortar: a slave facet depends on more nodes than expected (" + std::to_string(nodes.size()) + ")");
    // The overlap at the clipping's round-off threshold (an iterate that moved the bodies far,
    // e.g. a line search's trial): a SolverError, so that Newton shortens its step or the
    // increment is cut back, instead of ending the analysis.
    if (!ok) throw SolverError("mortar: a segment found in plain numbers was not found again with derivatives");
    segments.push_back(std::move(s));
  }
  // A sliver of cover: the dual basis on it is ill-conditioned (M nearly singular) while its
  // weighted gaps are of the order of the cover times the gap; it is left out.
  if (!(cover >= kMinCover)) {
    r.masters.clear();
    r.segment_length = 0;
    return r;
  }
  r.overlap = true;
  Real gap[3];
  dual_weighted_gaps(ns, u, tr, gap);
  r.gap.assign(gap, gap + ns);
  dual_slip_weights(ns, u, basis_transform(2, ns, true), relative, slip_weight);
  r.relative = std::move(relative);
  r.slip_weight = std::move(slip_weight);
  if (!derivatives) return r;

  mortar_detail::weighted_gap_derivatives(2, ns, u, tr, segments, r);
  return r;
}

void mortar_slave_weights(const MasterSurface& slave, const std::vector<Vec3>& X, const MortarMeasure& measure,
                          bool positive_basis, std::vector<Real>& weight) {
  weight.assign(X.size(), 0);
  std::vector<Real> gx, gw;
  gauss_legendre(4, gx, gw);
  for (Index e = 0; e < slave.size(); ++e) {
    const auto& f = slave.facets[e];
    const int nn = static_cast<int>(f.size());
    P2<Real> xf[3];
    for (int k = 0; k < nn; ++k) xf[k] = {X[f[k]](0), X[f[k]](1)};
    Real w[3] = {0, 0, 0};
    for (size_t q = 0; q < gx.size(); ++q) {
      Real N[3], dN[3];
      line_shape(nn, gx[q], N, dN);
      const P2<Real> x = interpolate(nn, N, xf), dx = interpolate(nn, dN, xf);
      const Real da = std::sqrt(dot(dx, dx)) * gw[q] * (measure.axisymmetric ? 2 * std::numbers::pi * x.x : measure.thickness);
      for (int k = 0; k < nn; ++k) w[k] += N[k] * da;
    }
    if (positive_basis && nn == 3) {
      w[0] += kTransform * w[2];
      w[1] += kTransform * w[2];
      w[2] *= 1 - 2 * kTransform;
    }
    for (int k = 0; k < nn; ++k) weight[f[k]] += w[k];
  }
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

namespace {
template <class M>
void put_mat(std::ostream& os, const M& m) {
  binary::put<std::int64_t>(os, m.rows());
  binary::put<std::int64_t>(os, m.cols());
  if (m.size() > 0) os.write(reinterpret_cast<const char*>(m.data()), static_cast<std::streamsize>(m.size() * sizeof(Real)));
}
MatX get_mat(std::istream& is) {
  const auto rows = binary::get<std::int64_t>(is), cols = binary::get<std::int64_t>(is);
  if (rows < 0 || cols < 0 || rows > 100000 || cols > 100000) throw Error("mortar facet result: corrupt matrix size");
  MatX m(rows, cols);
  if (m.size() > 0 && !is.read(reinterpret_cast<char*>(m.data()), static_cast<std::streamsize>(m.size() * sizeof(Real))))
    throw Error("mortar facet result: the bytes end early");
  return m;
}
template <class V>
void put_vecs(std::ostream& os, const std::vector<V>& v) {
  binary::put<std::int64_t>(os, static_cast<std::int64_t>(v.size()));
  for (const V& x : v) put_mat(os, x);
}
template <class V>
std::vector<V> get_vecs(std::istream& is) {
  const auto n = binary::get<std::int64_t>(is);
  if (n < 0 || n > 100000) throw Error("mortar facet result: corrupt count");
  std::vector<V> v(static_cast<size_t>(n));
  for (V& x : v) {
    MatX m = get_mat(is);
    if constexpr (std::is_same_v<V, VecX>) {
      if (m.cols() != 1 && m.size() > 0) throw Error("mortar facet result: a vector with several columns");
      x = Eigen::Map<const VecX>(m.data(), m.size());
    } else {
      x = std::move(m);
    }
  }
  return v;
}
}  // namespace

void write_facet_result(std::ostream& os, const MortarFacetResult& r) {
  binary::put<char>(os, r.overlap ? 1 : 0);
  binary::put_vector(os, r.masters);
  binary::put<std::int64_t>(os, r.facet);
  binary::put<Real>(os, r.segment_length);
  binary::put_vector(os, r.nodes);
  binary::put_vector(os, r.gap);
  put_vecs(os, r.grad);
  put_vecs(os, r.hess);
  put_vecs(os, r.relative);
  binary::put_vector(os, r.slip_weight);
}

MortarFacetResult read_facet_result(std::istream& is) {
  try {
    MortarFacetResult r;
    r.overlap = binary::get<char>(is) != 0;
    r.masters = binary::get_vector<Index>(is, -1, "mortar facet result");
    r.facet = static_cast<Index>(binary::get<std::int64_t>(is));
    r.segment_length = binary::get<Real>(is);
    r.nodes = binary::get_vector<Index>(is, -1, "mortar facet result");
    r.gap = binary::get_vector<Real>(is, -1, "mortar facet result");
    r.grad = get_vecs<VecX>(is);
    r.hess = get_vecs<MatX>(is);
    r.relative = get_vecs<VecX>(is);
    r.slip_weight = binary::get_vector<Real>(is, -1, "mortar facet result");
    return r;
  } catch (const Error& e) {
    throw Error(std::string("mortar facet result from another rank: ") + e.what());
  }
}

}  // namespace signorini
