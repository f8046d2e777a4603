#include "signorini/fem/boundary_traction.hpp"

#include <algorithm>
#include <map>

#include "signorini/core/error.hpp"
#include "signorini/fem/body.hpp"
#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

BoundaryTraction::BoundaryTraction(std::vector<Cells> cells, const std::vector<Vec3>& X, AnalysisSettings settings)
    : cells_(std::move(cells)), X_(&X), settings_(settings) {
  for (const Cells& c : cells_)
    if (c.material->history_size() > 0)
      throw Error("the bodies' boundary traction (Nitsche's method) needs materials without history (elastic): '" +
                  c.material->model() + "' has " + std::to_string(c.material->history_size()) + " history values");
}

std::vector<Index> BoundaryTraction::locate(const std::vector<std::vector<Index>>& facets) {
  // Facets by their sorted node lists (which identify a facet of a conforming mesh), then
  // every cell facet looked up.
  std::map<std::vector<Index>, std::vector<size_t>> by_nodes;
  for (size_t f = 0; f < facets.size(); ++f) {
    std::vector<Index> k = facets[f];
    std::sort(k.begin(), k.end());
    by_nodes[k].push_back(f);
  }
  std::vector<Index> handle(facets.size(), -1);
  for (size_t ci = 0; ci < cells_.size(); ++ci) {
    const ElementBlock& b = *cells_[ci].block;
    const ElementInfo& info = element_info(b.type);
    for (Index e = 0; e < b.size(); ++e) {
      const Index* c = b.element(e);
      for (const Facet& ft : info.facets) {
        std::vector<Index> k;
        for (int l : ft.nodes) k.push_back(c[l]);
        std::sort(k.begin(), k.end());
        auto it = by_nodes.find(k);
        if (it == by_nodes.end()) continue;
        for (size_t f : it->second)
          if (handle[f] < 0) {
            handle[f] = static_cast<Index>(owners_.size());
            owners_.push_back({ci, e});
          }
      }
    }
  }
  return handle;
}

void BoundaryTraction::mark_needed(const ElementBlock* block, std::vector<char>& keep) const {
  for (const Owner& o : owners_)
    if (cells_[o.cells].block == block) keep.at(static_cast<size_t>(o.element)) = 1;
}

void BoundaryTraction::renumber(const ElementBlock* block, const std::vector<Index>& index) {
  for (Owner& o : owners_) {
    if (cells_[o.cells].block != block) continue;
    const Index k = index.at(static_cast<size_t>(o.element));
    if (k < 0) throw Error("the boundary traction's cell " + std::to_string(o.element) + " was dropped");
    o.element = k;
  }
}

std::vector<Index> BoundaryTraction::cell_nodes(Index handle) const {
  const Owner& o = owners_.at(handle);
  const ElementBlock& b = *cells_[o.cells].block;
  return std::vector<Index>(b.element(o.element), b.element(o.element) + b.nodes_per_element());
}

Real BoundaryTraction::stiffness(Index handle) const { return cells_[owners_.at(handle).cells].material->stiffness_scale(); }

Real BoundaryTraction::height(Index handle, const std::vector<Index>& facet, ElementType facet_type) const {
  const Owner& o = owners_.at(handle);
  const ElementBlock& b = *cells_[o.cells].block;
  const Index* c = b.element(o.element);
  const int nn = b.nodes_per_element();
  const int dim = settings_.spatial_dim();
  const std::vector<Vec3>& X = *X_;
  Real volume = 0, area = 0;
  VecX N;
  MatX dN;
  for (const QuadraturePoint& q : quadrature_rule(b.type, 2 * element_info(b.type).order)) {
    shape_functions(b.type, q.xi, N, dN);
    Mat3 J = Mat3::Identity();
    J.topLeftCorner(dim, dim).setZero();
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i)
        for (int d = 0; d < dim; ++d) J(i, d) += X[c[a]](i) * dN(a, d);
    volume += std::abs(J.determinant()) * q.weight;
  }
  for (const QuadraturePoint& q : quadrature_rule(facet_type, 2 * element_info(facet_type).order)) {
    shape_functions(facet_type, q.xi, N, dN);
    Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero();
    for (size_t i = 0; i < facet.size(); ++i) {
      a1 += dN(static_cast<Index>(i), 0) * X[facet[i]];
      if (dim == 3) a2 += dN(static_cast<Index>(i), 1) * X[facet[i]];
    }
    area += (dim == 2 ? a1.norm() : a1.cross(a2).norm()) * q.weight;
  }
  return area > 0 ? volume / area : 0;
}

void BoundaryTraction::normal_pressure(Index handle, const std::vector<Index>& facet, const VecX& Nf, const Vec3& n,
                                       const std::vector<Vec3>& x, Real& p, VecX& grad) const {
  Vec3 t;
  MatX dt;
  traction(handle, facet, Nf, n, x, t, dt);
  const int dim = settings_.spatial_dim();
  p = -n.head(dim).dot(t.head(dim));
  grad = -(dt.transpose() * n.head(dim));
}

void BoundaryTraction::traction(Index handle, const std::vector<Index>& facet, const VecX& Nf, const Vec3& n,
                                const std::vector<Vec3>& x, Vec3& t, MatX& grad) const {
  const Owner& o = owners_.at(handle);
  const ElementBlock& b = *cells_[o.cells].block;
  const Material& mat = *cells_[o.cells].material;
  const ElementInfo& info = element_info(b.type);
  const Index* c = b.element(o.element);
  const int nn = info.num_nodes;
  const int dim = settings_.spatial_dim();
  const std::vector<Vec3>& X = *X_;
  // The point in the cell's reference element: the facet's nodes are cell nodes, and a
  // facet of the reference element is affine in the reference coordinates (mid-side nodes
  // at mid-edges), so xi = sum_i N_i(facet) xi_i.
  Vec3 xi = Vec3::Zero();
  for (size_t i = 0; i < facet.size(); ++i) {
    const Index* at = std::find(c, c + nn, facet[i]);
    if (at == c + nn) throw Error("boundary traction: a facet node is not a node of its cell");
    xi += Nf(static_cast<Index>(i)) * info.ref_coords[at - c];
  }
  VecX N;
  MatX dN;
  shape_functions(b.type, xi, N, dN);
  Mat3 J = Mat3::Identity();
  J.topLeftCorner(dim, dim).setZero();
  for (int a = 0; a < nn; ++a)
    for (int i = 0; i < dim; ++i)
      for (int d = 0; d < dim; ++d) J(i, d) += X[c[a]](i) * dN(a, d);
  const Mat3 Jinv = J.inverse();
  MatX G = MatX::Zero(nn, 3);
  for (int a = 0; a < nn; ++a)
    for (int d = 0; d < dim; ++d)
      for (int i = 0; i < dim; ++i) G(a, d) += dN(a, i) * Jinv(i, d);
  const bool axi = settings_.dimension == Dimension::axisymmetric;
  Real R = 0;
  if (axi)
    for (int a = 0; a < nn; ++a) R += N(a) * X[c[a]](0);
  Mat3 H = Mat3::Zero();
  for (int a = 0; a < nn; ++a) {
    const Vec3 ua = x[c[a]] - X[c[a]];
    for (int i = 0; i < dim; ++i)
      for (int d = 0; d < dim; ++d) H(i, d) += ua(i) * G(a, d);
    if (axi && R > 0) H(2, 2) += N(a) * ua(0) / R;
  }
  const bool finite = settings_.finite_strain;
  MaterialInput in;
  in.finite = finite;
  Vec6 S;
  Mat6 D;
  Mat3 F = Mat3::Identity() + H;
  auto evaluate = [&]() {
    if (finite) {
      in.F = F;
      in.strain = to_voigt_strain(0.5 * (F.transpose() * F - Mat3::Identity()));
    } else {
      in.strain = to_voigt_strain(0.5 * (H + H.transpose()));
    }
    mat.compute(in, S, D);
  };
  evaluate();
  if (settings_.dimension == Dimension::plane_stress) {
    // sigma_zz = 0 (S_zz at finite strain): the out-of-plane strain or stretch from the local
    // Newton iteration of Body::element, and the tangent condensed.
    for (int it = 0; it < 25 && std::abs(S(2)) > 1e-12 * (S.norm() + mat.stiffness_scale() * 1e-12); ++it) {
      if (finite) F(2, 2) -= S(2) / (D(2, 2) * F(2, 2));
      else H(2, 2) -= S(2) / D(2, 2);
      evaluate();
    }
    const Real d22 = D(2, 2);
    const Vec6 col = D.col(2), row = D.row(2).transpose();
    for (int i = 0; i < 6; ++i)
      for (int k = 0; k < 6; ++k) D(i, k) -= col(i) * row(k) / d22;
    S(2) = 0;
  }
  // B: the strain's variation per nodal DOF (engineering shears), delta E = sym(F^T delta F) at
  // finite strain (F = I at small strain), as Body::element.
  const Mat3 Fb = finite ? F : Mat3::Identity();
  Eigen::Matrix<Real, 6, Eigen::Dynamic> B = Eigen::Matrix<Real, 6, Eigen::Dynamic>::Zero(6, nn * dim);
  for (int a = 0; a < nn; ++a) {
    const Real g0 = G(a, 0), g1 = G(a, 1), g2 = G(a, 2);
    for (int i = 0; i < dim; ++i) {
      const int col = a * dim + i;
      strain_column(B.col(col), Fb(i, 0), Fb(i, 1), Fb(i, 2), g0, g1, g2);
    }
    if (axi && R > 0) B(2, a * dim) += Fb(2, 2) * N(a) / R;
  }
  if (finite) {
    // The nominal traction t = P n = F S n (P the first Piola-Kirchhoff stress, n the reference
    // normal: force per reference area) and its variation dt = dF S n + F dS n, dF = e_i (x)
    // grad N_a for DOF (a, i) (and the hoop term N_a / R in F_zz in axisymmetry), dS = D dE.
    const Mat3 Sm = from_voigt_stress(S);
    const Vec3 Sn = Sm * n;
    t.setZero();
    t.head(dim) = (F * Sn).head(dim);
    grad.setZero(dim, nn * dim);
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i) {
        const int col = a * dim + i;
        const Vec6 dS = D * B.col(col);
        Vec3 dt = F * (from_voigt_stress(dS) * n);
        Real gn = 0;
        for (int d = 0; d < dim; ++d) gn += G(a, d) * Sn(d);
        dt(i) += gn;
        if (axi && R > 0 && i == 0) dt(2) += N(a) / R * Sn(2);
        grad.col(col) = dt.head(dim);
      }
    return;
  }
  // t = sigma n = T S, T the Voigt form of the map sigma -> sigma n (S: xx yy zz yz xz xy).
  Eigen::Matrix<Real, 3, 6> T = Eigen::Matrix<Real, 3, 6>::Zero();
  T(0, 0) = n(0), T(0, 4) = n(2), T(0, 5) = n(1);
  T(1, 1) = n(1), T(1, 3) = n(2), T(1, 5) = n(0);
  T(2, 2) = n(2), T(2, 3) = n(1), T(2, 4) = n(0);
  t.setZero();
  t.head(dim) = (T * S).head(dim);
  grad = (T * D * B).topRows(dim);
}

}  // namespace signorini
