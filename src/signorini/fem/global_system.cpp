#include "signorini/fem/global_system.hpp"

#include <algorithm>
#include <cmath>

namespace signorini {

void SparseSystem::build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
                                 const std::vector<std::vector<Index>>& couplings, Index total_dofs) {
  const Index nn = dofs.num_nodes();
  const int ndpn = dofs.dofs_per_node();
  const Index n = std::max(total_dofs, dofs.num_dofs());
  // Nodes that share DOFs (a rigid body's) are one node here: its first one, which comes
  // first in the DOF numbering, so columns are emitted in order.
  std::vector<Index> rep(nn);
  {
    std::vector<Index> owner(dofs.num_dofs() / std::max(ndpn, 1) + 1, -1);
    for (Index node = 0; node < nn; ++node) {
      rep[node] = node;
      if (!dofs.shared(node) || !dofs.has_dofs(node)) continue;
      Index& o = owner[dofs.dof(node, 0) / ndpn];
      if (o < 0) o = node;
      rep[node] = o;
    }
  }
  // Node adjacency through cells.
  std::vector<std::vector<Index>> adj(nn);
  for (auto* b : cells) {
    const int npe = b->nodes_per_element();
    for (Index e = 0; e < b->size(); ++e) {
      const Index* c = b->element(e);
      for (int i = 0; i < npe; ++i)
        for (int j = 0; j < npe; ++j) adj[rep[c[i]]].push_back(rep[c[j]]);
    }
  }
  // Extra DOF-level couplings, by column.
  std::vector<std::vector<int>> extra(couplings.empty() ? 0 : n);
  for (const auto& group : couplings)
    for (Index c : group)
      if (c >= 0)
        for (Index r : group)
          if (r >= 0) extra[c].push_back(static_cast<int>(r));
  std::vector<int> outer(n + 1, 0);
  std::vector<int> inner;
  inner.reserve(static_cast<size_t>(nn) * 27 * ndpn * ndpn);
  std::vector<int> column;
  // A column's extra rows come from every coupling group that holds it, and neighbouring
  // slave nodes' contact groups overlap, so most rows come many times: those already in the
  // column or already seen are marked off, and only the new ones are sorted and merged in
  // (sorting the column with all the repeats was 5 % of a 3D mortar run, whose pattern is
  // rebuilt as its active set grows).
  std::vector<Index> seen(extra.empty() ? 0 : n, -1);
  auto emit = [&](Index col) {
    if (!extra.empty() && !extra[col].empty()) {
      if (!std::is_sorted(column.begin(), column.end())) std::sort(column.begin(), column.end());
      for (int r : column) seen[r] = col;
      const auto mid = static_cast<std::ptrdiff_t>(column.size());
      for (int r : extra[col])
        if (seen[r] != col) seen[r] = col, column.push_back(r);
      std::sort(column.begin() + mid, column.end());
      std::inplace_merge(column.begin(), column.begin() + mid, column.end());
      column.erase(std::unique(column.begin(), column.end()), column.end());
    }
    inner.insert(inner.end(), column.begin(), column.end());
    outer[col + 1] = static_cast<int>(inner.size());
  };
  Index col = 0;
  for (Index node = 0; node < nn; ++node) {
    if (!dofs.has_dofs(node) || rep[node] != node) continue;
    auto& a = adj[node];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    for (int c = 0; c < ndpn; ++c) {
      col = dofs.dof(node, c);
      column.clear();
      for (Index m : a)
        for (int r = 0; r < ndpn; ++r) column.push_back(static_cast<int>(dofs.dof(m, r)));
      emit(col);
    }
    std::vector<Index>().swap(a);
  }
  for (Index c = dofs.num_dofs(); c < n; ++c) {
    column.clear();
    emit(c);
  }
  matrix_ = SparseMatrix(n, n);
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
      if (p == end || *p != dofs[i]) {
        missed_.store(true, std::memory_order_relaxed);  // outside the pattern: dropped, the caller rebuilds
        continue;
      }
      values[p - inner] += v;  // no atomic: concurrent callers write disjoint entries (fem/coloring.hpp)
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
