// The semi-smooth Newton system of contact multipliers solved without its multipliers: each
// closed constraint's row a . du = r eliminates one DOF of its slave node (master-slave
// elimination of a linear multi-point constraint), each open one fixes its multiplier, and
// what remains is the displacement system T^T J T, symmetric when the bodies' tangent is, so
// Cholesky or CG can solve it. The multipliers are recovered from the eliminated DOFs' rows.
#pragma once
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "signorini/fem/global_system.hpp"
#include "signorini/solver/linear_solver.hpp"

namespace signorini {

class CondensedContactSolver {
 public:
  explicit CondensedContactSolver(bool three_d) : solver_("auto", three_d) { solver_.set_unsymmetric_amg(true); }
  // With algebraic multigrid (gamg, hypre) the eliminated DOFs keep their place in the
  // reduced system as decoupled rows (so that its unknowns stay node-interleaved blocks).
  CondensedContactSolver(const LinearSolverSettings& linear, bool three_d)
      : solver_(linear, three_d), rtol_(linear.rtol) {
    solver_.set_unsymmetric_amg(true);
  }
  // Friction's multiplier blocks (Lagrange friction) are condensed only when the reduced
  // system goes to algebraic multigrid (AutoLinearSolver::unsymmetric_iterative: in 3D with
  // `auto` and PETSc at any size, in 2D above iterative_above): with a factorization the whole
  // system, whose pattern stays while the nodes stick and slip, was twice as fast in 2D
  // (docs/performance.md). `always`: condensed with a factorization too (tests).
  void set_condense_blocks_always(bool always) { blocks_always_ = always; }
  // Whether friction's blocks may go to algebraic multigrid in this 3D model whatever its size
  // (`auto` with PETSc): the caller then provides the unknowns' layout.
  bool wants_layout_for_blocks() const { return solver_.unsymmetric_amg_in_3d(); }
  // The Newton iteration's forcing term (0: the configured rtol). Uncoupled rows: the Krylov
  // inner solver's relative tolerance. Coupled rows: GMRES's, when the inner solver is
  // iterative (kInnerTolerance); with a factorization GMRES goes to kRefinementTolerance.
  void set_tolerance(Real rtol) { tolerance_ = rtol; }
  void set_layout(std::shared_ptr<const UnknownLayout> layout) {
    layout_ = std::move(layout);
    pattern_rows_ = -1;
  }
  // `auto`'s decision that a Cholesky factor of this model is too large (assess_factor).
  void set_factor_too_large(bool v) { solver_.set_factor_too_large(v); }
  // Krylov iterations of the last solve (with coupled rows: of all its inner solves).
  int last_iterations() const { return iterations_; }
  // J dz = r with `is_multiplier` flagging the multiplier unknowns; `symmetric`: whether J
  // is symmetric apart from its multiplier rows and columns. Returns false (dz untouched)
  // when the structure does not allow the elimination: a closed constraint with no DOF of
  // its own (two-pass, a slave node that is also a master node); the caller then solves the
  // whole system. Throws SolverError when the reduced system is singular.
  bool solve(const SparseMatrix& J, const std::vector<char>& is_multiplier, bool symmetric, const VecX& r, VecX& dz);
  std::string last_used() const { return solver_.last_used(); }
  // The reduced system's method, after GMRES when the last solve refined coupled rows.
  std::string last_method() const {
    return (refinements_ > 0 ? "gmres on the coupled rows over " : "") + solver_.last_method();
  }
  std::string why_not() const { return why_not_; }
  // How many times friction's multiplier blocks were analysed (solve_blocks; skipped after a
  // refusal, see blocks_backoff_).
  int block_analyses() const { return block_analyses_; }
  // Symbolic analyses of the reduced system so far (one per distinct pattern in a row).
  int analyses() const { return analyses_; }
  // Frees the reduced system's factorization (its caller solves the whole system from now on);
  // the next solve, if any, analyses its pattern anew.
  void release() {
    solver_.reset();
    pattern_rows_ = -1;
  }
  // Refinement steps of the last solve (coupled rows; 0 when the elimination is exact).
  int refinements() const { return refinements_; }
  // GMRES stops at kRefinementTolerance |r| or after kMaxRefinements steps, and its step is
  // taken if |r - J dz| <= kRefinementAccepted |r| (a Newton step to 1e-9 of its residual
  // leaves the Newton iterations as they are; tolerance 1e-8).
  static constexpr int kMaxRefinements = 40;
  static constexpr Real kRefinementTolerance = 1e-13;
  static constexpr Real kRefinementAccepted = 1e-9;
  // With an iterative inner solver (algebraic multigrid, CG) each GMRES step is a Krylov solve,
  // not two triangular solves: the inner solves stop at kInnerTolerance (GMRES is the flexible
  // one, Saad 2003 alg. 9.6, which takes a preconditioner that changes from step to step), and
  // GMRES at the Newton iteration's forcing term (set_tolerance; the deck's rtol without one),
  // never below kRefinementTolerance.
  static constexpr Real kInnerTolerance = 1e-2;

 private:
  // Multiplier rows that couple multipliers (Lagrange friction): solve() hands them here.
  bool solve_blocks(const SparseMatrix& J, const std::vector<char>& is_multiplier, const VecX& r, VecX& dz);
  // Keeps the reduced pattern, or notes a new one (a new symbolic analysis, and with algebraic
  // multigrid the reduced unknowns' layout).
  void follow_pattern(const SparseMatrix& Kr, bool keep_places, const std::vector<Index>& ridx);
  VecX inner_solve(const SparseMatrix& Kr, bool symmetric, const VecX& rr, bool& factorized);
  AutoLinearSolver solver_;
  std::shared_ptr<const UnknownLayout> layout_;
  std::string why_not_;
  // The reduced system's pattern at the last solve (its symbolic factorization is reused).
  Index pattern_rows_ = -1;
  std::vector<int> pattern_outer_, pattern_inner_;
  int analyses_ = 0;
  Real tolerance_ = 0;
  Real rtol_ = 1e-8;  // the deck's rtol (the inner Krylov solver's)
  int refinements_ = 0;
  int iterations_ = 0;
  // The whole system for the next 1, 2, 4, ... (at most 64) solves after each failure in a row
  // (as AutoLinearSolver's after a failed Cholesky); a success resets the count.
  struct Backoff {
    int skip = 0, next = 1;
    bool skipping() { return skip > 0 ? (--skip, true) : false; }
    void failed() {
      skip = next;
      next = std::min(2 * next, 64);
    }
    void succeeded() { next = 1; }
  };
  Backoff coupled_backoff_;  // after a failed refinement of coupled rows
  Backoff blocks_backoff_;   // after friction's blocks were refused or their refinement stalled (solve_blocks)
  std::string blocks_why_not_;
  int block_analyses_ = 0;
  bool blocks_always_ = false;
};

// Coupled contact rows (segment_to_segment, mortar) in two levels. coupling[c] lists (c', w):
// closed row c's coefficient at row c''s pivot relative to its own pivot's,
// w = |a_{c,p(c')}| / |a_{c,p(c)}|, for the pairs where row c's multiplier also acts on row
// p(c') (J(p(c'), c) stored). A row is a child when its couplings to the other pivots outweigh
// the other rows' couplings to its own pivot. A child's couplings at its parents' pivots are
// then eliminated exactly by substitution (the parents first), the other couplings at pivots
// left to GMRES. On tri6/quad8 slave facets (mortar's transformed dual basis, mortar_dual.hpp)
// a mid-side node's weighted gap sees its edge's corners through D = D_diag T^-1 (about
// -kTransform of its own coefficient each): the mid-side rows become children of the corners,
// whose rows see the mid-side pivots through the geometry's variation only.
std::vector<char> coupled_rows_children(const std::vector<std::vector<std::pair<size_t, Real>>>& coupling);
// Levels 0 .. kCoupledLevels - 1: the children split again by coupled_rows_children over their
// couplings among themselves, and so on; a row's couplings at the pivots of rows on lower
// levels are substituted. On quad9 slave facets (the transformed basis a tensor product) the
// centre node's gap sees the mid-side nodes, whose gaps see the corners: three levels in the
// ideal structure (CondensedSolve.CoupledRowsInThreeLevelsAreEliminatedExactly). Measured on a
// hex27 block pressed on a hex27 block (docs/performance.md, session 67): 20 GMRES steps a
// solve with one level, 10 with two or three; what is left couples rows of one level.
constexpr int kCoupledLevels = 3;
std::vector<int> coupled_rows_levels(const std::vector<std::vector<std::pair<size_t, Real>>>& coupling);

// The closed rows' levels and the couplings substituted between them, for both backends'
// elimination (indices into their list of closed rows `closed`, with pivot[c], the pivot's
// coefficient ap[c] in row c and the multiplier's bp[c] on the pivot's row).
struct LevelledRows {
  std::vector<int> level;                                          // per closed row (0: none coupled)
  std::vector<std::vector<std::pair<size_t, Real>>> parents_of;   // (parent c', a_{c,p(c')})
  std::vector<std::vector<std::pair<size_t, Real>>> children_of;  // (child c, J(p(c'), c's multiplier))
  explicit LevelledRows(size_t rows = 0) : level(rows, 0), parents_of(rows), children_of(rows) {}
  void substitute(size_t child, size_t parent, Real a, Real b) {
    parents_of[child].emplace_back(parent, a);
    children_of[parent].emplace_back(child, b);
  }
  bool substitutes(size_t child, size_t parent) const;
  // The closed rows, lowest level first (T's pivot rows are built in this order, each adding
  // its parents' rows).
  std::vector<size_t> order() const;
  // z0 on the pivots: each closed row's equation a_c . z0 = rhs(closed[c]), its parents' pivots
  // substituted, the lowest level first.
  void pivot_values(const std::vector<Index>& closed, const std::vector<Index>& pivot, const std::vector<Real>& ap,
                    const VecX& rhs, VecX& z0) const;
  // The closed multipliers from their pivots' rows, the highest level first: out(closed[c]) =
  // (rhs(p) - Jout(p) - sum over children J(p, child) out(child)) / bp[c], with Jout = J out
  // computed while out held 0 on the closed multipliers.
  void multipliers(const std::vector<Index>& closed, const std::vector<Index>& pivot, const std::vector<Real>& bp,
                   const VecX& rhs, const VecX& Jout, VecX& out) const;
};

// Flexible GMRES (Saad 2003, "Iterative Methods for Sparse Linear Systems", alg. 9.6) on
// A x = r, right-preconditioned, from the first guess x (updated in place): the preconditioned
// vectors are kept, so the preconditioner may change from step to step (an inner Krylov solve
// to a loose tolerance). Stops once the estimated residual is at most `tolerance` (absolute)
// or after max_steps. Returns the steps taken and the true residual |r - A x| at the end.
// Every operation is on whole vectors in a fixed order: under MPI each rank runs it alike on
// its replicated vectors (times_A and precondition being the collective calls).
struct FlexibleGmresResult {
  int steps = 0;
  Real residual = 0;
};
FlexibleGmresResult flexible_gmres(const std::function<VecX(const VecX&)>& times_A,
                                   const std::function<void(const VecX&, VecX&)>& precondition, const VecX& r, VecX& x,
                                   Real tolerance, int max_steps);

}  // namespace signorini
