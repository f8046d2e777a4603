// The algebra behind the analysis: the global tangent that element and contact code add
// into (through GlobalMatrix), its sparse pattern, the Dirichlet rows, and the solve of the
// Newton system. The Analysis talks to this interface only, so a distributed backend (PETSc
// Mat/Vec with MPI, issue 15) plugs in without touching element or contact code: each rank
// then owns the rows [owned_begin, owned_end) and adds into ghost rows too, which the backend
// sends to their owners at assembly's end. The serial backend (Eigen storage, SuiteSparse
// and Eigen solvers) owns every row.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/fem/global_system.hpp"
#include "signorini/solver/linear_solver.hpp"

namespace signorini {

struct NewtonSolveRequest {
  bool symmetric = true;            // the whole system (bodies and contact) is symmetric
  bool body_symmetric = true;       // symmetric apart from the contact multipliers' rows and columns
  const std::vector<char>* is_multiplier = nullptr;  // per unknown (null: none)
  bool condense_contact = true;     // eliminate the multipliers when the structure allows
  Real rtol = 0;                    // Krylov solvers' relative tolerance for this solve (0: the deck's)
};

class AlgebraBackend {
 public:
  virtual ~AlgebraBackend() = default;
  virtual std::string name() const = 0;
  // The rows this process owns (serial: all of them).
  virtual Index owned_begin() const = 0;
  virtual Index owned_end() const = 0;
  // Pattern: DOF pairs sharing a cell plus every pair within each coupling group; `total`
  // unknowns (displacements, then multipliers and obstacle unknowns). Forgets factorizations.
  virtual void build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
                             const std::vector<std::vector<Index>>& couplings, Index total) = 0;
  virtual Index rows() const = 0;
  virtual Index nonzeros() const = 0;
  // Assembly: zero, add (thread safe) through matrix(), then missed() tells whether an add
  // fell outside the pattern.
  virtual void zero() = 0;
  virtual GlobalMatrix& matrix() = 0;
  virtual bool missed() const = 0;
  // The matrix's values kept (save_values, collective; a backend may decline to keep them)
  // and put back (restore_values; false, on every rank alike, when none are kept since the
  // last build_pattern): the tangent of the bodies whose internal force is linear in u,
  // assembled once per pattern (Analysis::evaluate). restore_values() stands for zero()
  // followed by that assembly.
  virtual void save_values() {}
  virtual bool restore_values() { return false; }
  // y = K x over all unknowns.
  virtual void multiply(const VecX& x, VecX& y) const = 0;
  virtual Real mean_abs_diagonal() const = 0;
  // Zeroes the rows and columns of constrained unknowns, `scale` on their diagonal.
  virtual void apply_dirichlet(const std::vector<char>& constrained, Real scale) = 0;
  // Solves K du = r; returns the solver used (for the log and summary.json). Throws
  // SolverError when no solver succeeds.
  virtual std::string solve(const NewtonSolveRequest& request, const VecX& r, VecX& du) = 0;
  // Krylov iterations of the last solve (0 for a direct solver).
  virtual int last_iterations() const { return 0; }
  // The last solve's method and preconditioner in words (LinearSolver::method).
  virtual std::string last_method() const { return ""; }
  // `auto` in one process: the Analysis calls this once, after the first pattern, when its
  // systems are ones Cholesky would take (symmetric, or multipliers the condensation removes
  // from a symmetric bodies' tangent); a factor above direct_factor_limit sends them to GAMG
  // (AutoLinearSolver::assess_factor).
  virtual void assess_factor() {}
  // Algebraic multigrid wants to know where the unknowns sit (its near-nullspace).
  virtual bool wants_layout() const { return false; }
  virtual void set_layout(std::shared_ptr<const UnknownLayout>) {}

  // Partitioned assembly (the distributed backend; the serial one has one rank). Every rank
  // runs the same analysis on the same (replicated) vectors, but the bodies' cells are shared
  // out: between begin_cells() and end_cells() each rank adds the entries of its own cells
  // (cell_owner()); outside, the code that every rank runs alike (loads, contact,
  // stabilization) is added by every rank for the rows it owns. The internal forces, summed
  // per rank, are then summed by the owners of their rows and made whole on every rank
  // (sum_cell_forces()).
  virtual int ranks() const { return 1; }
  virtual int rank() const { return 0; }
  // The nodes' reference coordinates, for sharing out the cells (before build_pattern).
  virtual void set_coordinates(const std::vector<Vec3>* X) {}
  // The rank that assembles cell e of `block` (one of build_pattern's cells).
  virtual int cell_owner(const ElementBlock* block, Index e) const { return 0; }
  // After the first build_pattern: `block` keeps only the cells marked (Body::keep_cells, in
  // their order), which the next patterns pass; the cells' owners and the rows' owners stay
  // those of the whole mesh.
  virtual void keep_cells(const ElementBlock* block, const std::vector<char>& keep) {}
  virtual void begin_cells() {}
  virtual void end_cells() {}
  // v[0..n) summed over the ranks, the same bits on every rank.
  virtual void sum_over_ranks(Real* v, Index n) {}
  // f over all unknowns, in which each rank has added its own cells' entries (between
  // begin_cells and end_cells, after a build_pattern): each row summed by the rank that owns
  // it, from its own entries and the ghost entries the other ranks' cells added there, then
  // the owned rows sent to every rank, so that f is whole, the same bits on every rank.
  virtual void sum_cell_forces(VecX& f) { sum_over_ranks(f.data(), f.size()); }
  // Collective: whether any rank has a failure to report (its `message` not empty); the
  // lowest such rank's message is then in `message` on every rank.
  virtual bool any_failed(std::string& message) { return !message.empty(); }
};

// The serial backend: SparseSystem storage, the automatic linear solver (CHOLMOD, UMFPACK,
// CG), the condensed solve of contact multipliers. `linear`: the deck's solver.linear.
std::unique_ptr<AlgebraBackend> make_serial_backend(const LinearSolverSettings& linear, bool three_d);

}  // namespace signorini
