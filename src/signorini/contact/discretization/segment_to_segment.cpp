#include "signorini/contact/discretization/segment_to_segment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "signorini/contact/geometry/facet_projection.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

namespace {
constexpr Real kModifiedAlpha = 0.2;   // Popp et al. 2012
constexpr Real kEdgeTolerance = 1e-2;  // in facet parameters, as node-to-segment
}  // namespace

void modified_shape_functions(ElementType type, const VecX& N, VecX& Nt) {
  Nt = N;
  if (type != ElementType::tri6 && type != ElementType::quad8) return;
  const int nc = type == ElementType::tri6 ? 3 : 4;
  // Mid-side node nc + k lies between corners k and k + 1.
  for (int k = 0; k < nc; ++k) {
    const Real m = N(nc + k);
    Nt(k) += kModifiedAlpha * m;
    Nt((k + 1) % nc) += kModifiedAlpha * m;
    Nt(nc + k) = (1 - 2 * kModifiedAlpha) * m;
  }
}

namespace {
// One point of facet f at parameters xi with rule weight `weight`: N, N~, the weight times the
// reference area element (thickness, 2 pi r) and the unit reference normal.
void add_point(IntegrationFacet& f, const std::vector<Vec3>& X, int dim, bool axisymmetric, Real thickness,
               const Vec3& xi, Real weight) {
  const int n = element_info(f.type).num_nodes;
  VecX N, Ntq;
  MatX dN;
  shape_functions(f.type, xi, N, dN);
  Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero(), x = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    x += N(i) * X[f.nodes[i]];
    a1 += dN(i, 0) * X[f.nodes[i]];
    if (dim == 3) a2 += dN(i, 1) * X[f.nodes[i]];
  }
  Real da = (dim == 2 ? a1.norm() : a1.cross(a2).norm()) * weight;
  if (axisymmetric) da *= 2 * std::numbers::pi * x(0);
  else if (dim == 2) da *= thickness;
  Vec3 nq = dim == 2 ? Vec3(a1(1), -a1(0), 0) : a1.cross(a2);
  f.normal.push_back(nq.norm() > 0 ? Vec3(nq / nq.norm()) : nq);
  modified_shape_functions(f.type, N, Ntq);
  f.N.push_back(N);
  f.dN.push_back(dN);
  f.Nt.push_back(Ntq);
  f.weight.push_back(da);
}
}  // namespace

IntegrationFacet make_integration_facet(ElementType type, const std::vector<Index>& nodes,
                                        const std::vector<Vec3>& X, int dim, bool axisymmetric, Real thickness) {
  IntegrationFacet f;
  f.type = type;
  f.nodes = nodes;
  const ElementInfo& info = element_info(type);
  const int n = info.num_nodes;
  // Degree 2 p + 3: the gap is smooth on each master facet but has kinks across master edges
  // inside a slave facet; more points than the polynomial degree calls for spread them.
  const QuadratureRule rule = quadrature_rule(type, 2 * info.order + 3);
  MatX M = MatX::Zero(n, n);
  VecX D = VecX::Zero(n);
  for (const QuadraturePoint& q : rule) {
    add_point(f, X, dim, axisymmetric, thickness, q.xi, q.weight);
    const VecX& Ntq = f.Nt.back();
    M += Ntq * Ntq.transpose() * f.weight.back();
    D += Ntq * f.weight.back();
  }
  // Dual basis Phi = A N~, A = D M^-1 (biorthogonal: int Phi_j N~_k = delta_jk D_j).
  f.dual = D.asDiagonal() * M.inverse();
  for (const VecX& ntq : f.Nt) f.phi.push_back(f.dual * ntq);
  f.area = D;
  return f;
}

IntegrationFacet integration_facet_at(const IntegrationFacet& f, const std::vector<Vec3>& X, int dim,
                                      bool axisymmetric, Real thickness, const std::vector<Vec2>& xi,
                                      const std::vector<Real>& weight) {
  IntegrationFacet g;
  g.type = f.type;
  g.nodes = f.nodes;
  g.dual = f.dual;
  g.area = f.area;
  // The facet's parameters (2D: xi[q](1) is 0), as the Vec3 the shape functions take.
  for (size_t q = 0; q < xi.size(); ++q) {
    add_point(g, X, dim, axisymmetric, thickness, Vec3(xi[q](0), xi[q](1), 0), weight[q]);
    g.phi.push_back(g.dual * g.Nt.back());
  }
  return g;
}

void integration_point_gaps(const IntegrationFacet& f, const MasterSurface& master, const std::vector<Index>& candidates,
                            const std::vector<Vec3>& x, int dim, IntegrationResult& out,
                            std::vector<IntegrationPointGap>* points, std::vector<Index>* held) {
  if (points) points->clear();
  if (held) held->resize(f.N.size(), -1);
  const int ns = static_cast<int>(f.nodes.size());
  out = IntegrationResult{};
  out.nodes = f.nodes;
  out.gap.assign(ns, 0.0);
  out.grad.assign(ns, VecX());
  out.hess.assign(ns, MatX());
  out.relative.assign(ns, VecX());
  auto column = [&](Index node) {
    auto it = std::find(out.nodes.begin(), out.nodes.end(), node);
    if (it != out.nodes.end()) return static_cast<Index>(it - out.nodes.begin());
    out.nodes.push_back(node);
    return static_cast<Index>(out.nodes.size() - 1);
  };
  // First the projections (which master nodes are involved), then the sums.
  struct PointHit {
    Index facet = -1;
    FacetProjection fp;
    std::vector<Vec3> xf;
  };
  std::vector<PointHit> hits(f.N.size());
  // The candidates' nodal positions and bounding boxes, once: a point's projection inside a
  // facet is at least as far as the facet's box, so candidates are tried nearest box first and
  // the search stops once a strict projection is nearer than the next box.
  const size_t nc = candidates.size();
  std::vector<std::vector<Vec3>> cx(nc);
  std::vector<Vec3> lo(nc), hi(nc);
  for (size_t k = 0; k < nc; ++k) {
    for (Index nd : master.basis_nodes(candidates[k])) cx[k].push_back(x[nd]);
    lo[k] = hi[k] = cx[k][0];
    for (const Vec3& y : cx[k]) lo[k] = lo[k].cwiseMin(y), hi[k] = hi[k].cwiseMax(y);
  }
  std::vector<std::pair<Real, size_t>> order(nc);
  for (size_t q = 0; q < f.N.size(); ++q) {
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < ns; ++i) p += f.N[q](i) * x[f.nodes[i]];
    // The facet the point was held on, while its projection stays inside it (edge tolerance).
    if (held && (*held)[q] >= 0) {
      const auto it = std::find(candidates.begin(), candidates.end(), (*held)[q]);
      if (it != candidates.end()) {
        const size_t k = static_cast<size_t>(it - candidates.begin());
        FacetProjection fp = project_on_facet(master.basis(*it), cx[k], p, dim, kEdgeTolerance);
        if (fp.inside) {
          hits[q] = {*it, fp, cx[k]};
        }
      }
    }
    if (hits[q].facet < 0) {
      order.resize(nc);
      for (size_t k = 0; k < nc; ++k) {
        const Vec3 d = (lo[k] - p).cwiseMax(p - hi[k]).cwiseMax(Vec3::Zero());
        order[k] = {d.norm(), k};
      }
      std::sort(order.begin(), order.end());
    } else {
      order.clear();
    }
    Real best = std::numeric_limits<Real>::infinity();
    bool best_strict = false;
    for (auto [box_distance, k] : order) {
      if (best_strict && box_distance > best) break;
      const Index m = candidates[k];
      const FacetBasis basis = master.basis(m);
      FacetProjection fp = project_on_facet(basis, cx[k], p, dim, kEdgeTolerance);
      if (!fp.inside) continue;
      const bool strict = inside_reference(basis, fp.xi, 1e-9);
      if ((strict && !best_strict) || (strict == best_strict && std::abs(fp.gap) < best)) {
        best = std::abs(fp.gap);
        best_strict = strict;
        hits[q].facet = m;
        hits[q].fp = fp;
        hits[q].xf = cx[k];
      }
    }
    if (held) (*held)[q] = hits[q].facet;
    if (hits[q].facet >= 0) {
      if (std::find(out.hit.begin(), out.hit.end(), hits[q].facet) == out.hit.end()) out.hit.push_back(hits[q].facet);
      for (Index nd : master.basis_nodes(hits[q].facet)) column(nd);
      if (out.first_facet < 0) out.first_facet = hits[q].facet;
      ++out.points;
    }
  }
  std::sort(out.hit.begin(), out.hit.end());
  const Index nn = static_cast<Index>(out.nodes.size()) * dim;
  for (int j = 0; j < ns; ++j) {
    out.grad[j].setZero(nn);
    out.hess[j].setZero(nn, nn);
    out.relative[j].setZero(static_cast<Index>(out.nodes.size()));
  }
  if (out.points == 0) return;
  VecX g, Nm;
  MatX H, dNm;
  std::vector<Index> at;
  for (size_t q = 0; q < hits.size(); ++q) {
    const PointHit& h = hits[q];
    if (h.facet < 0) continue;
    gap_variations(master.basis(h.facet), h.xf, h.fp, dim, g, H);
    // Local DOFs of gap_variations: [x_p, master nodes]; x_p = sum_i N_i x_i.
    at.clear();
    for (Index nd : master.basis_nodes(h.facet)) at.push_back(column(nd));
    const int nm = static_cast<int>(at.size());
    // The point's gradient and Hessian over `out.nodes`, then weighted per slave node.
    VecX gq = VecX::Zero(nn);
    MatX Hq = MatX::Zero(nn, nn);
    const VecX& N = f.N[q];
    for (int i = 0; i < ns; ++i) gq.segment(i * dim, dim) += N(i) * g.head(dim);
    for (int a = 0; a < nm; ++a) gq.segment(at[a] * dim, dim) += g.segment((a + 1) * dim, dim);
    const MatX Hpp = H.topLeftCorner(dim, dim);
    for (int i = 0; i < ns; ++i) {
      for (int k = 0; k < ns; ++k) Hq.block(i * dim, k * dim, dim, dim) += N(i) * N(k) * Hpp;
      for (int a = 0; a < nm; ++a) {
        const MatX Hpm = H.block(0, (a + 1) * dim, dim, dim);
        Hq.block(i * dim, at[a] * dim, dim, dim) += N(i) * Hpm;
        Hq.block(at[a] * dim, i * dim, dim, dim) += N(i) * Hpm.transpose();
      }
    }
    for (int a = 0; a < nm; ++a)
      for (int b = 0; b < nm; ++b)
        Hq.block(at[a] * dim, at[b] * dim, dim, dim) += H.block((a + 1) * dim, (b + 1) * dim, dim, dim);
    master.basis(h.facet).eval(h.fp.xi, Nm, dNm);
    if (points) {
      std::vector<std::pair<Index, Real>> mp;
      const std::vector<Index>& mn = master.basis_nodes(h.facet);
      for (int a = 0; a < nm; ++a) mp.emplace_back(mn[a], Nm(a));
      points->push_back({static_cast<int>(q), h.fp.gap, gq, Hq, std::move(mp)});
    }
    for (int j = 0; j < ns; ++j) {
      const Real wr = f.Nt[q](j) * f.weight[q];
      const Real w = f.phi[q](j) * f.weight[q];
      out.gap[j] += w * h.fp.gap;
      out.grad[j] += w * gq;
      out.hess[j] += w * Hq;
      for (int i = 0; i < ns; ++i) out.relative[j](i) += wr * N(i);
      for (int a = 0; a < nm; ++a) out.relative[j](at[a]) -= wr * Nm(a);
    }
  }
}

}  // namespace signorini
