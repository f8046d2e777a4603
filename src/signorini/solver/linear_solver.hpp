// Sparse solvers behind one interface: CHOLMOD (symmetric positive definite), UMFPACK
// (general), Eigen's own LDLT and LU that always build, and Eigen's conjugate gradients with
// an incomplete Cholesky preconditioner. `auto` picks CHOLMOD for a symmetric matrix (for a
// symmetric 3D system above `iterative_above` DOFs, where a direct factor would not fit in
// memory, PETSc's GAMG, or CG with incomplete Cholesky in a build without PETSc) and, for an
// unsymmetric one, MUMPS's LU above AutoLinearSolver::kMumpsLuAbove unknowns with PETSc, else
// UMFPACK; it falls back to MUMPS's LDL^T or UMFPACK when Cholesky or the iterative solver
// fails (for the next 1, 2, 4, ... solves, then again). With PETSc (SIGNORINI_WITH_PETSC),
// `gamg`, `hypre`, `mumps` and `petsc` solve through a KSP (petsc_solver.hpp).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/fem/global_system.hpp"

namespace signorini {

// The deck's solver.linear: a type and, for the iterative (PETSc) solvers, the relative
// tolerance and raw PETSc options ("-ksp_monitor -pc_gamg_threshold 0.05").
struct LinearSolverSettings {
  std::string type = "auto";
  Real rtol = 1e-8;
  // Krylov solvers inside Newton's method: "adaptive" asks each solve for no more than the
  // Newton iteration can use (Eisenstat & Walker 1996, Analysis::forcing_term), rtol being the
  // tightest; "fixed" asks rtol of every solve; "auto" is adaptive on nonlinear models.
  std::string forcing = "auto";
  // GAMG's prolongator smoothing steps (PCGAMGSetNSmooths; a raw -pc_gamg_agg_nsmooths in
  // `options` wins). Not a deck key: the Analysis sets 0 under adaptive forcing
  // (solver_settings, analysis.hpp), 1 (smoothed aggregation) otherwise.
  int amg_smoothing = 1;
  std::string options;
  // Under mpirun: how the cells are shared out between the ranks (rcb, ptscotch).
  std::string partition = "rcb";
  // `auto`: a symmetric 3D system with more unknowns than this goes to an iterative solver
  // (GAMG with PETSc, else eigen_cg) instead of a factorization, whose fill grows like N^4/3.
  Index iterative_above = 200000;
  // `auto`, in a build with PETSc: a symmetric 3D system at or below iterative_above whose
  // Cholesky factor would hold more entries than this (CHOLMOD's symbolic analysis of the first
  // pattern) goes to GAMG too. Quadratic elements fill a factor faster than their unknowns
  // grow: CalculiX's fine tet10 Hertz mesh, 118k unknowns, 1.25e8 entries (3.0 GB of peak
  // memory against GAMG's 1.5 GB; the tet4 Hertz example at 148k DOFs, 1.58e8 entries, 2.3 GB
  // and 180 s against 0.6 GB and 29 s: docs/performance.md). 0: no limit.
  Real direct_factor_limit = 5e7;
  // Under mpirun, when `auto` took algebraic multigrid (not a deck key): contact multipliers
  // the partitioned backend cannot condense, or whose coupled rows' GMRES stalls, go whole to
  // MUMPS instead of stopping the run (as one process's `auto` takes UMFPACK).
  bool direct_fallback = false;
  LinearSolverSettings() = default;
  LinearSolverSettings(const char* t) : type(t) {}  // NOLINT: a bare name is a type
  LinearSolverSettings(std::string t) : type(std::move(t)) {}  // NOLINT
};

// Where each unknown of a system sits, for algebraic multigrid's near-nullspace (the
// rigid-body modes): the reference position of its node and its displacement component
// (-1: not a displacement, e.g. a contact multiplier). `dim` is the spatial dimension.
struct UnknownLayout {
  int dim = 0;
  bool axisymmetric = false;  // (r, z): the only rigid motion is the axial translation
  std::vector<Vec3> x;
  std::vector<signed char> comp;
  Index size() const { return static_cast<Index>(comp.size()); }
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  // Factorizes; returns false if the factorization failed (not positive definite, singular).
  virtual bool factorize(const SparseMatrix& a) = 0;
  virtual bool solve(const VecX& b, VecX& x) = 0;
  // Iterative solvers: whether the system is symmetric (CG) or not (GMRES), set before
  // factorize; and the layout of the unknowns of the next systems (null: unknown).
  virtual void set_symmetric(bool) {}
  // The relative residual the next solves stop at (Krylov solvers; 0: their configured one).
  virtual void set_tolerance(Real) {}
  virtual void set_layout(std::shared_ptr<const UnknownLayout>) {}
  // Krylov iterations of the last solve (0 for a direct solver).
  virtual int iterations() const { return 0; }
  // The method and preconditioner in words, for summary.json: "supernodal Cholesky (CHOLMOD)",
  // "cg, gamg (plain aggregation, 6 near-nullspace vectors)".
  virtual std::string method() const;
  // Why the last factorize or solve failed, when the solver knows.
  virtual std::string failure() const { return "failed"; }
  // Whether the last factorization failed for want of memory or of the library's integers.
  virtual bool ran_out_of_resources() const { return false; }
  // Whether the solver wants the unknown layout (algebraic multigrid).
  virtual bool wants_layout() const { return false; }
};

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings);
// Whether a solver name is a PETSc solver; and an algebraic-multigrid one (gamg, hypre),
// which needs the unknowns' layout and cannot take the multipliers' saddle point.
bool is_petsc_solver(const std::string& name);
inline bool is_amg_solver(const std::string& name) { return name == "gamg" || name == "hypre"; }
// Whether a solver takes symmetric matrices only (Cholesky, LDL^T without pivoting, CG): it
// reads one triangle, so an unsymmetric tangent would be solved as its symmetric part, and it
// cannot take the contact multipliers' saddle point (the Analysis refuses the first and
// condenses the second).
inline bool is_symmetric_only_solver(const std::string& name) {
  return name == "cholmod" || name == "eigen_ldlt" || name == "eigen_cg";
}
// Whether this build has PETSc (SIGNORINI_WITH_PETSC).
bool petsc_available();
// The entries of the Cholesky factor of a symmetric matrix's pattern (its lower triangle), from
// CHOLMOD's symbolic analysis (the ordering CHOLMOD would choose: AMD, or METIS when AMD fills
// much); no numerical factorization.
double cholesky_factor_entries(const SparseMatrix& a);
// The number of processes mpirun (OpenMPI or MPICH) launched this one among (1 otherwise),
// from the environment; and the MPI ranks the linear solve runs on (1 without PETSc).
int launched_ranks();
// This process's rank as the MPI launcher gives it (0 when not launched by one), read
// without starting MPI.
int launched_rank();
int parallel_ranks();
// Under mpirun (collective: every rank calls it at the same point): the largest of the ranks'
// values; otherwise the value.
int max_over_ranks(int value);
const std::vector<std::string>& linear_solver_names();  // for the registry and the deck

// Chooses per factorization: holds the selected solver and falls back as documented.
class AutoLinearSolver {
 public:
  explicit AutoLinearSolver(LinearSolverSettings choice, bool three_d = false)
      : choice_(std::move(choice)), three_d_(three_d) {}
  // Whether a symmetric positive definite system of `rows` unknowns goes to an iterative
  // solver (CG, algebraic multigrid, a PETSc KSP) rather than a factorization.
  bool iterative(Index rows) const {
    if (choice_.type == "auto") return three_d_ && (rows > choice_.iterative_above || factor_too_large_);
    return choice_.type == "eigen_cg" || choice_.type == "petsc" || is_amg_solver(choice_.type);
  }
  // Whether an unsymmetric system of `rows` unknowns that algebraic multigrid can take goes to
  // GMRES over it (set_unsymmetric_amg) rather than to an LU factorization: with `auto`, in a
  // build with PETSc, a 3D system above iterative_above (or whose Cholesky factor was found too
  // large), or any 3D system while set_unsymmetric_amg_any_size holds; with gamg or hypre, always.
  bool unsymmetric_iterative(Index rows) const {
    if (choice_.type == "auto") return petsc_available() && (iterative(rows) || (three_d_ && any_size_3d_));
    return is_amg_solver(choice_.type);
  }
  // With `auto` in a build with PETSc, 3D: the unsymmetric systems of set_unsymmetric_amg go to
  // GMRES over GAMG at any size (Lagrange friction's condensed system, and since session 59 any
  // system without multipliers, e.g. penalty friction's, whose LU fills badly in 3D:
  // docs/performance.md, sessions 58-59). Set per solve.
  void set_unsymmetric_amg_any_size(bool v) { any_size_3d_ = v; }
  // Whether `auto` would send such systems of a 3D model to GAMG at any size (its caller then
  // wants the unknowns' layout for the rigid-body modes).
  bool unsymmetric_amg_in_3d() const { return choice_.type == "auto" && three_d_ && petsc_available(); }
  // The systems this solver gets are displacement systems that algebraic multigrid can take
  // even when unsymmetric (the condensed contact system with friction's multipliers, or a
  // system without multipliers); not a saddle point. Off by default; set per solve.
  void set_unsymmetric_amg(bool v) { unsymmetric_amg_ = v; }
  // The solver `auto` gives such a system: CHOLMOD, or when iterative() GAMG (eigen_cg in a
  // build without PETSc).
  std::string auto_spd_solver(Index rows) const {
    return !iterative(rows) ? "cholmod" : petsc_available() ? "gamg" : "eigen_cg";
  }
  // The factorization `auto` gives a system Cholesky cannot take (solve): MUMPS, in one
  // process of a build with PETSc, for a symmetric (indefinite) system (LDL^T) and for an
  // unsymmetric one above kMumpsLuAbove unknowns (LU); UMFPACK's LU otherwise.
  static std::string indefinite_solver(Index rows, bool symmetric);
  // Unsymmetric systems (Lagrange friction's whole contact system; in 2D, or without PETSc's
  // algebraic multigrid in 3D, follower pressure and penalty friction) above this many unknowns
  // go to MUMPS's LU rather than UMFPACK's: MUMPS orders by nested
  // dissection, UMFPACK by AMD on A + A^T. Measured on this 2-core machine (docs/performance.md,
  // session 57), the 3D Hertz sphere with Coulomb friction: 4.3k unknowns 0.58 s against MUMPS's
  // 0.90 s (PETSc's set-up); 15k 6.2 s against 4.0 s; 35k 64 s and 2 631 MiB against 24 s and
  // 750 MiB; 148k: UMFPACK's first factorization had not ended after 4 minutes at 13 438 MiB,
  // MUMPS solved the 8 Newton iterations in 206 s at 4 134 MiB. In 2D the gain is 1.2-1.4x (54k
  // and 206k unknowns).
  static constexpr Index kMumpsLuAbove = 10000;
  // `auto` in a build with PETSc, for a symmetric 3D system it would factorize: predicts the
  // Cholesky factor of this pattern and, above direct_factor_limit entries, solves this
  // analysis's systems with GAMG (logged).
  void assess_factor(const SparseMatrix& pattern);
  // The same decision, made by another solver of the same model (the condensed contact system's).
  void set_factor_too_large(bool v) {
    factor_too_large_ = v;
    announced_ = announced_ || v;  // the other solver logged it
  }
  bool factor_too_large() const { return factor_too_large_; }
  // Factorizes and solves; throws SolverError when no solver succeeds.
  void solve(const SparseMatrix& a, bool symmetric, const VecX& b, VecX& x);
  // Solves again with the last factorization (false if there is none or the solve fails).
  bool solve_again(const VecX& b, VecX& x) {
    if (!solver_) return false;
    solver_->set_tolerance(tolerance_);
    return solver_->solve(b, x);
  }
  std::string last_used() const { return solver_ ? solver_->name() : last_name_; }
  // Why the last solve failed, when the solver knows.
  std::string failure() const { return solver_ ? solver_->failure() : "no solver"; }
  int last_iterations() const { return solver_ ? solver_->iterations() : 0; }
  std::string last_method() const { return solver_ ? solver_->method() : last_name_; }
  // The layout of the next systems' unknowns (for algebraic multigrid).
  void set_layout(std::shared_ptr<const UnknownLayout> layout) {
    layout_ = std::move(layout);
    if (solver_) solver_->set_layout(layout_);
  }
  // The relative residual the next Krylov solves stop at (0: the configured rtol).
  void set_tolerance(Real rtol) { tolerance_ = rtol; }
  // Whether the solver of a system of `rows` unknowns wants their layout (algebraic multigrid).
  bool wants_layout(Index rows) const {
    return is_petsc_solver(choice_.type) || (choice_.type == "auto" && auto_spd_solver(rows) == "gamg") ||
           (unsymmetric_amg_ && any_size_3d_ && unsymmetric_amg_in_3d());
  }
  const std::string& choice() const { return choice_.type; }
  // Forget the factorization and its symbolic analysis (after a change of sparse pattern).
  void reset() {
    if (solver_) last_name_ = solver_->name();
    solver_.reset();
  }

 private:
  LinearSolverSettings choice_;
  bool three_d_;
  std::shared_ptr<const UnknownLayout> layout_;
  // After Cholesky or CG fails (the tangent is not positive definite), LU for the next spd_skip_
  // solves; the skip doubles with each failure in a row (spd_backoff_) and resets on success.
  int spd_skip_ = 0, spd_backoff_ = 1;
  Real tolerance_ = 0;
  bool announced_ = false;  // the first choice of gamg by `auto` is logged
  bool factor_too_large_ = false;  // assess_factor()
  bool unsymmetric_amg_ = false;   // set_unsymmetric_amg()
  bool any_size_3d_ = false;       // set_unsymmetric_amg_any_size()
  std::unique_ptr<LinearSolver> solver_;
  std::string last_name_ = "none";
};

// `auto`'s forecast for the systems it sends to GMRES over GAMG at any size in 3D (Lagrange
// friction's condensed blocks, on their own DOFs or shared ones; penalty friction's and follower
// pressure's displacement systems): whether a factorization of the whole system (MUMPS's LU)
// would take less time. The work of a sparse factorization of a 3D mesh grows like n^2
// (nested dissection's separators; George 1973, Lipton, Rose & Tarjan 1979), a Krylov solve's
// like K nnz (K iterations, each a product with the matrix and a multigrid cycle over it).
// Their time ratio t_Krylov / t_LU = C K nnz / n^2, with the whole system's n unknowns and nnz
// entries and K the Krylov iterations per solve (the mean over the run's Krylov solves so far),
// was measured on this 2-core machine (docs/performance.md, session 66) at C = 7-22 over the
// frictional 3D Hertz sphere (tet4 and tet10, mortar, segment_to_segment and node_to_segment,
// 11k to 86k unknowns) and session 61's and 63's runs at 148k and 186k unknowns: kConstant = 10
// puts each of them on the side that was faster. Only asked at or below iterative_above (the
// factorization's memory).
class FactorizationForecast {
 public:
  static constexpr Real kConstant = 10;
  // Records a Krylov solve of `krylov_iterations` on a system of `rows` unknowns and `nonzeros`
  // entries. True when the forecast favours the factorization: from then on (kept for the run).
  bool record(long krylov_iterations, Index rows, Index nonzeros);
  bool favours_factorization() const { return favours_; }
  Real ratio() const { return ratio_; }  // the last forecast of t_Krylov / t_LU
  Real mean_iterations() const { return solves_ > 0 ? static_cast<Real>(iterations_) / solves_ : 0.0; }
  // The log line of the decision, for a system of `rows` unknowns going to `factorization`.
  std::string describe(Index rows, Index nonzeros, const std::string& factorization) const;

 private:
  long iterations_ = 0;
  int solves_ = 0;
  Real ratio_ = 0;
  bool favours_ = false;
};

}  // namespace signorini
