#include "signorini/fem/body.hpp"

#include <cmath>
#include <numbers>

#include "signorini/core/error.hpp"
#include "signorini/fem/coloring.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

Body::Body(std::string name, std::vector<ElementBlock> blocks, std::shared_ptr<const Material> material,
           AnalysisSettings settings)
    : name_(std::move(name)), blocks_(std::move(blocks)), material_(std::move(material)), settings_(settings) {
  for (auto& b : blocks_) {
    BlockCache c;
    c.rule = quadrature_rule(b.type, default_quadrature_degree(b.type));
    for (auto& q : c.rule) {
      VecX N;
      MatX dN;
      shape_functions(b.type, q.xi, N, dN);
      c.N.push_back(N);
      c.dN.push_back(dN);
    }
    caches_.push_back(std::move(c));
  }
}

Index Body::num_cells() const {
  Index n = 0;
  for (auto& b : blocks_) n += b.size();
  return n;
}

void Body::keep_cells(const std::vector<std::vector<char>>& keep) {
  if (keep.size() != blocks_.size()) throw Error("body " + name_ + ": one mask of kept cells per block expected");
  const bool first = whole_index_.empty();
  if (first) {
    whole_cells_.resize(blocks_.size());
    whole_index_.resize(blocks_.size());
  }
  for (size_t bi = 0; bi < blocks_.size(); ++bi) {
    ElementBlock& b = blocks_[bi];
    if (static_cast<Index>(keep[bi].size()) != b.size()) throw Error("body " + name_ + ": a mask of the wrong size");
    const int nn = b.nodes_per_element();
    Index kept = 0;
    for (char k : keep[bi]) kept += k ? 1 : 0;
    // New vectors of the kept size: the dropped cells' memory is given back.
    std::vector<Index> conn, ids, where;
    conn.reserve(static_cast<size_t>(kept * nn));
    ids.reserve(static_cast<size_t>(kept));
    where.reserve(static_cast<size_t>(kept));
    for (Index e = 0; e < b.size(); ++e) {
      if (!keep[bi][static_cast<size_t>(e)]) continue;
      conn.insert(conn.end(), b.element(e), b.element(e) + nn);
      ids.push_back(b.ids[static_cast<size_t>(e)]);
      where.push_back(first ? e : whole_index_[bi][static_cast<size_t>(e)]);
    }
    if (first) whole_cells_[bi] = b.size();
    b.conn = std::move(conn);
    b.ids = std::move(ids);
    whole_index_[bi] = std::move(where);
  }
}

const Body::BlockCache& Body::cache(ElementType t) const {
  for (size_t i = 0; i < blocks_.size(); ++i)
    if (blocks_[i].type == t) return caches_[i];
  throw Error("body " + name_ + " has no block of type " + element_info(t).name);
}

void Body::element(ElementType type, const std::vector<Vec3>& Xe, const VecX& ue, const Real* hist_old,
                   Real* hist_new, VecX& fe, MatX* ke, Vec6* mean_stress, Vec6* mean_strain, Real dt) const {
  const BlockCache& c = cache(type);
  const int nn = static_cast<int>(Xe.size());
  const int dim = settings_.spatial_dim();
  const int ndof = nn * dim;
  const bool finite = settings_.finite_strain;
  const bool axi = settings_.dimension == Dimension::axisymmetric;
  const bool pstress = settings_.dimension == Dimension::plane_stress;
  const int hs = material_->history_size();
  fe.setZero(ndof);
  if (ke) ke->setZero(ndof, ndof);
  if (mean_stress) mean_stress->setZero();
  if (mean_strain) mean_strain->setZero();
  Eigen::Matrix<Real, 6, Eigen::Dynamic> B(6, ndof);
  MatX G(nn, 3);
  Real total_weight = 0;
  for (size_t q = 0; q < c.rule.size(); ++q) {
    const VecX& N = c.N[q];
    const MatX& dN = c.dN[q];
    // Reference Jacobian dX/dxi and gradients dN/dX.
    Mat3 J = Mat3::Identity();
    J.topLeftCorner(dim, dim).setZero();
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i)
        for (int d = 0; d < dim; ++d) J(i, d) += Xe[a](i) * dN(a, d);
    const Real detJ = J.determinant();
    if (!(detJ > 0)) throw SolverError("body " + name_ + ": element with non-positive Jacobian");
    const Mat3 Jinv = J.inverse();
    G.setZero();
    for (int a = 0; a < nn; ++a)
      for (int d = 0; d < dim; ++d)
        for (int i = 0; i < dim; ++i) G(a, d) += dN(a, i) * Jinv(i, d);
    Real R = 0;
    if (axi) {
      for (int a = 0; a < nn; ++a) R += N(a) * Xe[a](0);
      if (!(R > 0)) throw SolverError("body " + name_ + ": axisymmetric cell at r <= 0 (r = x must be positive)");
    }
    // Displacement gradient H = du/dX (3x3, zero padded; hoop strain u_r / R in axisymmetry).
    Mat3 H = Mat3::Zero();
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i)
        for (int d = 0; d < dim; ++d) H(i, d) += ue(a * dim + i) * G(a, d);
    if (axi) {
      Real ur = 0;
      for (int a = 0; a < nn; ++a) ur += N(a) * ue(a * dim);
      H(2, 2) = ur / R;
    }
    MaterialInput in;
    in.finite = finite;
    in.dt = dt;
    const Index qoff = static_cast<Index>(q) * hs;
    in.history_old = hist_old ? hist_old + qoff : nullptr;
    in.history_new = hist_new ? hist_new + qoff : nullptr;
    Mat3 F = Mat3::Identity() + H;
    Vec6 S;
    Mat6 D;
    auto evaluate = [&]() {
      if (finite) {
        in.F = F;
        in.strain = to_voigt_strain(0.5 * (F.transpose() * F - Mat3::Identity()));
      } else {
        in.strain = to_voigt_strain(0.5 * (H + H.transpose()));
      }
      material_->compute(in, S, D);
    };
    evaluate();
    if (pstress) {
      // Plane stress: find the out-of-plane stretch (or strain) with S33 = 0 by a local
      // Newton iteration, then condense the tangent (S33 stays zero to first order).
      for (int it = 0; it < 25 && std::abs(S(2)) > 1e-12 * (S.norm() + material_->stiffness_scale() * 1e-12); ++it) {
        if (finite) {
          F(2, 2) -= S(2) / (D(2, 2) * F(2, 2));
          H(2, 2) = F(2, 2) - 1;
        } else {
          H(2, 2) -= S(2) / D(2, 2);
        }
        evaluate();
      }
      const Real d22 = D(2, 2);
      const Vec6 col = D.col(2), row = D.row(2).transpose();
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b) D(a, b) -= col(a) * row(b) / d22;
      D.row(2).setZero();
      D.col(2).setZero();
      S(2) = 0;
    }
    const Mat3 Fb = finite ? F : Mat3::Identity();
    // B: variation of the strain (Voigt, engineering) per nodal DOF, delta E = sym(F^T delta H).
    for (int a = 0; a < nn; ++a) {
      const Real g0 = G(a, 0), g1 = G(a, 1), g2 = dim == 3 ? G(a, 2) : 0.0;
      for (int i = 0; i < dim; ++i) {
        const int col = a * dim + i;
        strain_column(B.col(col), Fb(i, 0), Fb(i, 1), Fb(i, 2), g0, g1, g2);
      }
      if (axi) B(2, a * dim) += Fb(2, 2) * N(a) / R;
    }
    Real dV = detJ * c.rule[q].weight;
    if (axi) dV *= 2 * std::numbers::pi * R;
    else if (dim == 2) dV *= settings_.thickness;
    fe.noalias() += B.transpose() * (S * dV);
    if (ke) {
      ke->noalias() += B.transpose() * (D * dV) * B;
      if (finite) {
        const Mat3 Sm = from_voigt_stress(S);
        for (int a = 0; a < nn; ++a)
          for (int b = 0; b < nn; ++b) {
            Real gsg = 0;
            for (int I = 0; I < dim; ++I)
              for (int K = 0; K < dim; ++K) gsg += G(a, I) * Sm(I, K) * G(b, K);
            gsg *= dV;
            for (int i = 0; i < dim; ++i) (*ke)(a * dim + i, b * dim + i) += gsg;
            if (axi) (*ke)(a * dim, b * dim) += Sm(2, 2) * N(a) * N(b) / (R * R) * dV;
          }
      }
    }
    if (mean_stress || mean_strain) {
      const Real w = dV;
      total_weight += w;
      if (mean_stress) {
        Vec6 sigma = S;
        if (finite) {
          const Mat3 Sm = from_voigt_stress(S);
          sigma = to_voigt_stress(F * Sm * F.transpose() / F.determinant());
        }
        *mean_stress += w * sigma;
      }
      if (mean_strain) {
        Vec6 e = finite ? to_voigt_strain(0.5 * (F.transpose() * F - Mat3::Identity()))
                        : to_voigt_strain(0.5 * (H + H.transpose()));
        e.tail<3>() *= 0.5;  // tensor components for output
        *mean_strain += w * e;
      }
    }
  }
  if (total_weight > 0) {
    if (mean_stress) *mean_stress /= total_weight;
    if (mean_strain) *mean_strain /= total_weight;
  }
}

namespace {
// Gathers the nodal coordinates, displacements and DOFs of one cell.
void gather(const ElementBlock& b, Index e, const std::vector<Vec3>& X, const VecX& u, const DofMap& dofs,
            std::vector<Vec3>& Xe, VecX& ue, std::vector<Index>& edofs) {
  const int nn = b.nodes_per_element(), dim = dofs.dofs_per_node();
  const Index* c = b.element(e);
  Xe.resize(nn);
  ue.resize(nn * dim);
  edofs.resize(nn * dim);
  for (int a = 0; a < nn; ++a) {
    Xe[a] = X[c[a]];
    for (int i = 0; i < dim; ++i) {
      edofs[a * dim + i] = dofs.dof(c[a], i);
      ue(a * dim + i) = u(edofs[a * dim + i]);
    }
  }
}
}  // namespace

void Body::assemble(const std::vector<Vec3>& X, const VecX& u, const DofMap& dofs, VecX& fint, GlobalMatrix* matrix,
                    QuadratureHistory* history, Real dt, const std::vector<std::vector<char>>* owned) const {
  if (rigid()) return;  // no strain energy; its nodes move with the reference node
  const int hs = material_->history_size();
  if (hs && (!history || history->per_point() != hs))
    throw Error("body " + name_ + ": its material has history variables and needs their storage");
  const int ndpn = dofs.dofs_per_node();
  for (size_t bi = 0; bi < blocks_.size(); ++bi) {
    const ElementBlock& b = blocks_[bi];
    const int npe = b.nodes_per_element();
    // Cells that share a node's DOFs (a slot) never run at the same time (fem/coloring.hpp).
    const Coloring coloring = color_items(b.size(), dofs.num_dofs() / std::max(ndpn, 1), [&](Index e, std::vector<Index>& s) {
      const Index* c = b.element(e);
      for (int a = 0; a < npe; ++a) s.push_back(dofs.has_dofs(c[a]) ? dofs.dof(c[a], 0) / ndpn : -1);
    });
    Index failed = -1;  // the first failing cell in cell order, whatever the threads
    std::string failure;
#pragma omp parallel
    {
      std::vector<Vec3> Xe;
      VecX ue, fe;
      MatX ke;
      std::vector<Index> edofs;
      for (int color = 0; color < coloring.colors(); ++color) {
#pragma omp for schedule(static)
        for (Index k = coloring.begin(color); k < coloring.end(color); ++k) {
          const Index e = coloring.items[k];
          if (owned && !(*owned)[bi][e]) continue;
          try {
            gather(b, e, X, u, dofs, Xe, ue, edofs);
            element(b.type, Xe, ue, hs ? history->committed(bi, e) : nullptr, hs ? history->trial(bi, e) : nullptr, fe,
                    matrix ? &ke : nullptr, nullptr, nullptr, dt);
            for (size_t i = 0; i < edofs.size(); ++i)
              if (edofs[i] >= 0) fint(edofs[i]) += fe(i);
            if (matrix) matrix->add(edofs.data(), static_cast<int>(edofs.size()), ke);
          } catch (const std::exception& ex) {
#pragma omp critical(signorini_body_failure)
            if (failed < 0 || e < failed) {
              failed = e;
              failure = std::string(ex.what()) + " (element " + std::to_string(b.ids[e]) + " of body " + name_ + ")";
            }
          }
        }
      }
    }
    if (!failure.empty()) throw SolverError(failure);
  }
}

void Body::add_body_force(const std::vector<Vec3>& X, const DofMap& dofs, const Vec3& bf, Real scale, VecX& fext,
                          const std::vector<std::vector<char>>* owned) const {
  add_body_force(X, dofs, [&](const Vec3&) { return bf; }, scale, fext, owned);
}

void Body::add_body_force(const std::vector<Vec3>& X, const DofMap& dofs, const std::function<Vec3(const Vec3&)>& bfun,
                          Real scale, VecX& fext, const std::vector<std::vector<char>>* owned) const {
  if (owned && owned->size() != blocks_.size()) throw Error("body " + name_ + ": the body force's cell mask has the wrong size");
  const int dim = dofs.dofs_per_node();
  const bool axi = settings_.dimension == Dimension::axisymmetric;
  for (size_t bi = 0; bi < blocks_.size(); ++bi) {
    const ElementBlock& b = blocks_[bi];
    const BlockCache& c = caches_[bi];
    const int nn = b.nodes_per_element();
    for (Index e = 0; e < b.size(); ++e) {
      if (owned && !(*owned)[bi].at(static_cast<size_t>(e))) continue;
      const Index* cn = b.element(e);
      for (size_t q = 0; q < c.rule.size(); ++q) {
        Mat3 J = Mat3::Identity();
        J.topLeftCorner(dim, dim).setZero();
        Vec3 xq = Vec3::Zero();
        for (int a = 0; a < nn; ++a) {
          xq += c.N[q](a) * X[cn[a]];
          for (int i = 0; i < dim; ++i)
            for (int d = 0; d < dim; ++d) J(i, d) += X[cn[a]](i) * c.dN[q](a, d);
        }
        const Real R = xq(0);
        Real dV = J.determinant() * c.rule[q].weight;
        if (axi) dV *= 2 * std::numbers::pi * R;
        else if (dim == 2) dV *= settings_.thickness;
        const Vec3 bf = bfun(xq);
        for (int a = 0; a < nn; ++a)
          for (int i = 0; i < dim; ++i) fext(dofs.dof(cn[a], i)) += scale * c.N[q](a) * bf(i) * dV;
      }
    }
  }
}

Real Body::volume(const std::vector<Vec3>& X) const {
  DofMap dofs(static_cast<Index>(X.size()), settings_.spatial_dim(),
              [&] {
                std::vector<const ElementBlock*> v;
                for (auto& b : blocks_) v.push_back(&b);
                return v;
              }());
  VecX f = VecX::Zero(dofs.num_dofs());
  add_body_force(X, dofs, Vec3(1, 0, 0), 1.0, f);
  Real s = 0;
  for (Index i = 0; i < f.size(); i += dofs.dofs_per_node()) s += f(i);
  return s;
}

CellResults Body::results(const std::vector<Vec3>& X, const VecX& u, const DofMap& dofs,
                          const QuadratureHistory* history, const std::vector<std::vector<char>>* owned) const {
  CellResults r;
  if (owned && owned->size() != blocks_.size()) throw Error("body " + name_ + ": the output's cell mask has the wrong size");
  // The cells evaluated, block by block: all, or the rank's own (their results held in this
  // order, not in a whole body's arrays: 104 bytes per cell of the body on every rank).
  std::vector<std::vector<Index>> cells(blocks_.size());
  for (size_t bi = 0; bi < blocks_.size(); ++bi)
    for (Index e = 0; e < blocks_[bi].size(); ++e)
      if (!owned || (*owned)[bi].at(static_cast<size_t>(e))) cells[bi].push_back(e);
  if (rigid()) {
    // Rigid cells: no strain, and their stress is not defined by a constitutive law (zero).
    size_t n = 0;
    for (const auto& c : cells) n += c.size();
    r.stress.assign(n, Vec6::Zero());
    r.strain.assign(n, Vec6::Zero());
    r.von_mises.assign(n, 0.0);
    return r;
  }
  const int hs = material_->history_size();
  if (hs && (!history || history->per_point() != hs))
    throw Error("body " + name_ + ": its material has history variables and needs their storage");
  for (size_t bi = 0; bi < blocks_.size(); ++bi) {
    const ElementBlock& b = blocks_[bi];
    const BlockCache& c = caches_[bi];
    const Index nq = static_cast<Index>(c.rule.size());
    const Index start = static_cast<Index>(r.stress.size());
    const std::vector<Index>& list = cells[bi];
    const Index count = static_cast<Index>(list.size());
    r.stress.resize(start + count, Vec6::Zero());
    r.strain.resize(start + count, Vec6::Zero());
    r.von_mises.resize(start + count, 0.0);
#pragma omp parallel
    {
      std::vector<Vec3> Xe;
      VecX ue, fe;
      std::vector<Index> edofs;
      std::vector<Real> hnew(nq * hs);
#pragma omp for schedule(static)
      for (Index k = 0; k < count; ++k) {
        const Index e = list[k];
        gather(b, e, X, u, dofs, Xe, ue, edofs);
        Vec6 s, eps;
        element(b.type, Xe, ue, hs ? history->committed(bi, e) : nullptr, hs ? hnew.data() : nullptr, fe, nullptr, &s,
                &eps);
        r.stress[start + k] = s;
        r.strain[start + k] = eps;
        r.von_mises[start + k] =
            std::sqrt(0.5 * ((s(0) - s(1)) * (s(0) - s(1)) + (s(1) - s(2)) * (s(1) - s(2)) +
                             (s(2) - s(0)) * (s(2) - s(0))) +
                      3 * (s(3) * s(3) + s(4) * s(4) + s(5) * s(5)));
      }
    }
  }
  return r;
}

}  // namespace signorini
