// Sparse solvers behind one interface: CHOLMOD (symmetric positive definite), UMFPACK
// (general), Eigen's own LDLT and LU that always build, and Eigen's conjugate gradients with
// an incomplete Cholesky preconditioner. `auto` picks CHOLMOD for a symmetric matrix (CG for
// a symmetric 3D system above `iterative_threshold` DOFs, where a direct factor would not fit
// in memory) and UMFPACK otherwise, and falls back to UMFPACK when Cholesky or CG fails (for
// the next 1, 2, 4, ... solves, then Cholesky again).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/fem/global_system.hpp"

namespace signorini {

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  // Factorizes; returns false if the factorization failed (not positive definite, singular).
  virtual bool factorize(const SparseMatrix& a) = 0;
  virtual bool solve(const VecX& b, VecX& x) = 0;
};

std::unique_ptr<LinearSolver> make_linear_solver(const std::string& name);
const std::vector<std::string>& linear_solver_names();  // for the registry and the deck

// Chooses per factorization: holds the selected solver and falls back as documented.
class AutoLinearSolver {
 public:
  explicit AutoLinearSolver(std::string choice, bool three_d = false)
      : choice_(std::move(choice)), three_d_(three_d) {}
  static constexpr Index iterative_threshold = 200000;
  // Factorizes and solves; throws SolverError when no solver succeeds.
  void solve(const SparseMatrix& a, bool symmetric, const VecX& b, VecX& x);
  std::string last_used() const { return solver_ ? solver_->name() : last_name_; }
  // Forget the factorization and its symbolic analysis (after a change of sparse pattern).
  void reset() {
    if (solver_) last_name_ = solver_->name();
    solver_.reset();
  }

 private:
  std::string choice_;
  bool three_d_;
  // After Cholesky or CG fails (the tangent is not positive definite), LU for the next spd_skip_
  // solves; the skip doubles with each failure in a row (spd_backoff_) and resets on success.
  int spd_skip_ = 0, spd_backoff_ = 1;
  std::unique_ptr<LinearSolver> solver_;
  std::string last_name_ = "none";
};

}  // namespace signorini
