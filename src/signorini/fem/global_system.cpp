#include "signorini/fem/global_system.hpp"

#include <algorithm>
#include <cmath>

namespace signorini {

void SparseSystem::build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells) {
  const Index nn = dofs.num_nodes();
  const int ndpn = dofs.dofs_per_node();
  // Node adjacency through cells.
  std::vector<std::vector<Index>> adj(nn);
  for (auto* b : cells) {
    const int npe = b->nodes_per_element();
    for (Index e = 0; e < b->size(); ++e) {
      const Index* c = b->element(e);
      for (int i = 0; i < npe; ++i)
        for (int j = 0; j < npe; ++j) adj[c[i]].push_back(c[j]);
    }
  }
  std::vector<int> outer(dofs.num_dofs() + 1, 0);
  std::vector<int> inner;
  Index nnz = 0;
  for (Index n = 0; n < nn; ++n) {
    auto& a = adj[n];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    if (dofs.has_dofs(n)) nnz += static_cast<Index>(a.size()) * ndpn * ndpn;
  }
  inner.reserve(nnz);
  for (Index n = 0; n < nn; ++n) {
    if (!dofs.has_dofs(n)) continue;
    for (int c = 0; c < ndpn; ++c) {
      const Index col = dofs.dof(n, c);
      for (Index m : adj[n])
        for (int r = 0; r < ndpn; ++r) inner.push_back(static_cast<int>(dofs.dof(m, r)));
      outer[col + 1] = static_cast<int>(inner.size());
    }
    std::vector<Index>().swap(adj[n]);
  }
  matrix_ = SparseMatrix(dofs.num_dofs(), dofs.num_dofs());
  matrix_.resizeNonZeros(static_cast<Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), matrix_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), matrix_.innerIndexPtr());
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + inner.size(), 0.0);
}

void SparseSystem::add(const Index* dofs, int n, const MatX& k) {
  const int* outer = matrix_.outerIndexPtr();
  const int* inner = matrix_.innerIndexPtr();
  Real* values = matrix_.valuePtr();
  for (int j = 0; j < n; ++j) {
    const Index col = dofs[j];
    if (col < 0) continue;
    const int* begin = inner + outer[col];
    const int* end = inner + outer[col + 1];
    for (int i = 0; i < n; ++i) {
      if (dofs[i] < 0) continue;
      const Real v = k(i, j);
      if (v == 0) continue;
      const int* p = std::lower_bound(begin, end, static_cast<int>(dofs[i]));
      Real& target = values[p - inner];
#pragma omp atomic
      target += v;
    }
  }
}

void SparseSystem::apply_dirichlet(const std::vector<char>& constrained, Real scale) {
  for (int col = 0; col < matrix_.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(matrix_, col); it; ++it)
      if (constrained[it.row()] || constrained[col]) it.valueRef() = it.row() == col ? scale : 0.0;
}

bool SparseSystem::is_symmetric(Real tol) const {
  Real maxv = 0;
  for (Index i = 0; i < matrix_.nonZeros(); ++i) maxv = std::max(maxv, std::abs(matrix_.valuePtr()[i]));
  const SparseMatrix t = matrix_.transpose();
  const SparseMatrix d = matrix_ - t;
  for (Index i = 0; i < d.nonZeros(); ++i)
    if (std::abs(d.valuePtr()[i]) > tol * maxv) return false;
  return true;
}

Real SparseSystem::mean_abs_diagonal() const {
  Real s = 0;
  for (int i = 0; i < matrix_.rows(); ++i) s += std::abs(matrix_.coeff(i, i));
  return matrix_.rows() > 0 ? s / matrix_.rows() : 1.0;
}

}  // namespace signorini
