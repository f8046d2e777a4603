// The global tangent matrix and residual behind a small interface, so element and contact
// code never see the storage (a PETSc backend can implement the same interface later).
// The sparse pattern is built once from the cells; concurrent assembly of disjoint entries.
#pragma once
#include <Eigen/SparseCore>
#include <atomic>
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/fem/dof_map.hpp"

namespace signorini {

using SparseMatrix = Eigen::SparseMatrix<Real, Eigen::ColMajor, int>;

class GlobalMatrix {
 public:
  virtual ~GlobalMatrix() = default;
  // Adds the dense block `k` (n x n) at rows and columns `dofs` (entries < 0 are skipped).
  // Called concurrently from the assembly threads, which never write the same entry at the
  // same time (they colour their cells and constraints, fem/coloring.hpp): no locking needed.
  virtual void add(const Index* dofs, int n, const MatX& k) = 0;
};

class SparseSystem final : public GlobalMatrix {
 public:
  // Pattern: all DOF pairs that share a cell (full storage, both triangles), plus every pair
  // within each of the `couplings` (contact constraints, multipliers). `total_dofs` may exceed
  // dofs.num_dofs() (extra unknowns such as Lagrange multipliers, numbered after the nodes').
  void build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
                     const std::vector<std::vector<Index>>& couplings = {}, Index total_dofs = -1);
  // True if an add() since the last zero() hit an entry outside the pattern (it was dropped):
  // the caller must rebuild the pattern with the couplings it now needs.
  bool missed() const { return missed_.load(); }
  void zero() {
    matrix_.coeffs().setZero();
    missed_ = false;
  }
  void add(const Index* dofs, int n, const MatX& k) override;
  // Zeroes the rows and columns of constrained DOFs and puts `scale` on their diagonal.
  void apply_dirichlet(const std::vector<char>& constrained, Real scale);
  // Largest relative asymmetry max|K - K^T| / max|K|, for choosing a solver.
  bool is_symmetric(Real tol = 1e-10) const;
  Real mean_abs_diagonal() const;
  const SparseMatrix& matrix() const { return matrix_; }
  SparseMatrix& matrix() { return matrix_; }
  Index nonzeros() const { return matrix_.nonZeros(); }

 private:
  SparseMatrix matrix_;
  std::atomic<bool> missed_{false};
};

}  // namespace signorini
