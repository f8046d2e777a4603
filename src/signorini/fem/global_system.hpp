// The global tangent matrix and residual behind a small interface, so element and contact
// code never see the storage (a PETSc backend can implement the same interface later).
// The sparse pattern is built once from the cells; assembly is thread safe.
#pragma once
#include <Eigen/SparseCore>
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/fem/dof_map.hpp"

namespace signorini {

using SparseMatrix = Eigen::SparseMatrix<Real, Eigen::ColMajor, int>;

class GlobalMatrix {
 public:
  virtual ~GlobalMatrix() = default;
  // Adds the dense block `k` (n x n) at rows and columns `dofs` (entries < 0 are skipped).
  // Called concurrently from the assembly threads: implementations must be thread safe.
  virtual void add(const Index* dofs, int n, const MatX& k) = 0;
};

class SparseSystem final : public GlobalMatrix {
 public:
  // Pattern: all DOF pairs that share a cell (full storage, both triangles).
  void build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells);
  void zero() { matrix_.coeffs().setZero(); }
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
};

}  // namespace signorini
