#include "signorini/solver/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCholesky>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseLU>
#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <cstdlib>
#include <type_traits>

#include <fmt/format.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#ifdef SIGNORINI_HAVE_PETSC
#include "signorini/solver/petsc_solver.hpp"
#endif

namespace signorini {

namespace {

// The pattern does not change between Newton iterations: analyse once, refactorize after.
template <typename EigenSolver>
class EigenDirect final : public LinearSolver {
 public:
  explicit EigenDirect(std::string name) : name_(std::move(name)) {
    // CHOLMOD prints its own warnings (e.g. "not positive definite"); we report failures.
    if constexpr (requires(EigenSolver& s) { s.cholmod(); }) solver_.cholmod().print = 0;
    // Finite element patterns are structurally symmetric (contact multipliers included):
    // UMFPACK's symmetric strategy orders A + A^T (AMD) and is much faster on 3D meshes than
    // its default column ordering.
    if constexpr (requires(EigenSolver& s) { s.umfpackControl(); })
      solver_.umfpackControl()(UMFPACK_STRATEGY) = UMFPACK_STRATEGY_SYMMETRIC;
  }
  std::string name() const override { return name_; }
  bool factorize(const SparseMatrix& a) override {
    if constexpr (std::is_same_v<typename EigenSolver::MatrixType, SparseMatrix>) {
      factorize_matrix(a);
    } else {
      // UMFPACK on 32-bit indices runs out of its integers on the LU of a 3D system of about
      // 100k unknowns (the CalculiX fine tet10 Hertz mesh): its 64-bit version on a copy.
      wide_ = typename EigenSolver::MatrixType(a);
      factorize_matrix(wide_);
    }
    failure_.clear();
    resources_ = false;
    if (solver_.info() == Eigen::Success) return true;
    failure_ = factorization_failure();
    return false;
  }
  bool ran_out_of_resources() const override { return resources_; }
  bool solve(const VecX& b, VecX& x) override {
    x = solver_.solve(b);
    return solver_.info() == Eigen::Success && x.allFinite();
  }
  std::string failure() const override { return failure_.empty() ? "failed" : failure_; }

 private:
  // What the library says of a failed factorization: out of memory or an index overflow is
  // not a singular matrix, and the user should not be sent looking for missing supports.
  std::string factorization_failure() {
    if constexpr (requires(EigenSolver& s) { s.cholmod(); }) {
      resources_ = solver_.cholmod().status == CHOLMOD_OUT_OF_MEMORY || solver_.cholmod().status == CHOLMOD_TOO_LARGE;
      switch (solver_.cholmod().status) {
        case CHOLMOD_NOT_POSDEF: return "the matrix is not positive definite";
        case CHOLMOD_OUT_OF_MEMORY: return "CHOLMOD ran out of memory";
        case CHOLMOD_TOO_LARGE: return "the factor is too large for CHOLMOD's integers";
        default: return fmt::format("CHOLMOD status {}", solver_.cholmod().status);
      }
    } else if constexpr (requires(EigenSolver& s) { s.umfpackFactorizeReturncode(); }) {
      resources_ = solver_.umfpackFactorizeReturncode() == UMFPACK_ERROR_out_of_memory;
      switch (solver_.umfpackFactorizeReturncode()) {
        case UMFPACK_WARNING_singular_matrix: return "the matrix is singular";
        case UMFPACK_ERROR_out_of_memory: return "UMFPACK ran out of memory";
        default: return fmt::format("UMFPACK status {}", solver_.umfpackFactorizeReturncode());
      }
    } else {
      return "";
    }
  }
  template <typename M>
  void factorize_matrix(const M& a) {
    if (!analysed_ || a.rows() != rows_ || a.nonZeros() != nnz_) {
      solver_.analyzePattern(a);
      if constexpr (requires(EigenSolver& s) { s.cholmod(); }) {
        static const char* const names[] = {"natural", "given", "AMD", "METIS", "NESDIS", "COLAMD", "postordered"};
        const auto& c = solver_.cholmod();
        const int o = c.method[c.selected].ordering;
        log::debug("    cholmod analysis: {} ordering, nnz(L) {:.3g}, {:.3g} flops", o >= 0 && o <= 6 ? names[o] : "?",
                   c.lnz, c.fl);
      }
      analysed_ = true;
      rows_ = a.rows();
      nnz_ = a.nonZeros();
    }
    solver_.factorize(a);
  }
  std::string failure_;
  bool resources_ = false;
  std::string name_;
  EigenSolver solver_;
  typename EigenSolver::MatrixType wide_;  // the copy a solver on other indices factorizes
  bool analysed_ = false;
  Index rows_ = 0, nnz_ = 0;
};

// Conjugate gradients preconditioned by an incomplete Cholesky factorization (Lin & More),
// for large symmetric positive definite systems where a direct factor does not fit in memory.
class EigenCg final : public LinearSolver {
 public:
  std::string name() const override { return "eigen_cg"; }
  bool factorize(const SparseMatrix& a) override {
    solver_.setTolerance(1e-10);
    solver_.setMaxIterations(std::max<Index>(1000, a.rows() / 10));
    solver_.compute(a);
    return solver_.info() == Eigen::Success;
  }
  void set_tolerance(Real rtol) override { tolerance_ = rtol; }
  int iterations() const override { return static_cast<int>(iterations_); }
  bool solve(const VecX& b, VecX& x) override {
    solver_.setTolerance(tolerance_ > 0 ? tolerance_ : 1e-10);
    x = solver_.solve(b);
    iterations_ = solver_.iterations();
    return solver_.info() == Eigen::Success && x.allFinite();
  }
  Index iterations_ = 0;

 private:
  Real tolerance_ = 0;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<Real, Eigen::Lower, Eigen::AMDOrdering<int>>> solver_;
};

}  // namespace

const std::vector<std::string>& linear_solver_names() {
  static const std::vector<std::string> n{"auto",     "cholmod", "umfpack", "eigen_ldlt", "eigen_lu",
                                          "eigen_cg", "gamg",    "hypre",   "mumps",      "petsc"};
  return n;
}

bool petsc_available() {
#ifdef SIGNORINI_HAVE_PETSC
  return true;
#else
  return false;
#endif
}

int launched_ranks() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* v = std::getenv(var)) return std::max(1, std::atoi(v));
  return 1;
}

int launched_rank() {
  for (const char* var : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* v = std::getenv(var)) return std::max(0, std::atoi(v));
  return 0;
}

int parallel_ranks() {
#ifdef SIGNORINI_HAVE_PETSC
  return petsc_world_size();
#else
  return 1;
#endif
}

int max_over_ranks(int value) {
#ifdef SIGNORINI_HAVE_PETSC
  return petsc_max_over_ranks(value);
#else
  return value;
#endif
}

double cholesky_factor_entries(const SparseMatrix& a) {
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> chol;
  chol.cholmod().print = 0;
  chol.analyzePattern(a);
  return chol.cholmod().lnz;
}

void AutoLinearSolver::assess_factor(const SparseMatrix& pattern) {
  if (choice_.type != "auto" || !three_d_ || !petsc_available() || choice_.direct_factor_limit <= 0 ||
      iterative(pattern.rows()))
    return;
  // No factor of n unknowns holds more than n (n + 1) / 2 entries: small systems need no analysis.
  const double n = static_cast<double>(pattern.rows());
  if (n * (n + 1) / 2 <= choice_.direct_factor_limit) return;
  const double entries = cholesky_factor_entries(pattern);
  if (entries > choice_.direct_factor_limit) {
    factor_too_large_ = true;
    announced_ = true;
    log::info("    linear solver auto: Cholesky's factor of {} unknowns would hold {:.3g} entries ({:.2g} GB; "
              "direct_factor_limit {:.3g}): gamg, on one core in one process (mpirun -np N shares it out)",
              pattern.rows(), entries, entries * 8e-9, choice_.direct_factor_limit);
  } else {
    log::debug("    linear solver auto: Cholesky's factor of {} unknowns would hold {:.3g} entries: cholmod",
               pattern.rows(), entries);
  }
}

bool is_petsc_solver(const std::string& name) {
  return is_amg_solver(name) || name == "mumps" || name == "petsc";
}

std::string LinearSolver::method() const {
  const std::string n = name();
  if (n == "cholmod") return "supernodal Cholesky (CHOLMOD)";
  if (n == "umfpack") return "multifrontal LU (UMFPACK)";
  if (n == "eigen_ldlt") return "simplicial LDLT (Eigen)";
  if (n == "eigen_lu") return "sparse LU (Eigen)";
  if (n == "eigen_cg") return "cg, incomplete Cholesky (Eigen)";
  return n;
}

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings) {
  const std::string& name = settings.type;
  if (is_petsc_solver(name)) {
#ifdef SIGNORINI_HAVE_PETSC
    return make_petsc_solver(settings);
#else
    throw Error("linear solver '" + name + "' needs PETSc, and this build has none (configure with "
                "-DSIGNORINI_WITH_PETSC=ON after installing petsc-dev; scripts/install-deps.sh does)");
#endif
  }
  if (name == "cholmod")
    return std::make_unique<EigenDirect<Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>>>(name);
  if (name == "umfpack")
    return std::make_unique<EigenDirect<Eigen::UmfPackLU<Eigen::SparseMatrix<Real, Eigen::ColMajor, SuiteSparse_long>>>>(
        name);
  if (name == "eigen_ldlt")
    return std::make_unique<EigenDirect<Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>>>(name);
  if (name == "eigen_lu")
    return std::make_unique<EigenDirect<Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>>>>(name);
  if (name == "eigen_cg") return std::make_unique<EigenCg>();
  throw Error("unknown linear solver '" + name + "'");
}

std::string AutoLinearSolver::indefinite_solver(Index rows, bool symmetric) {
  // A symmetric matrix that Cholesky cannot take: LDL^T with pivoting (MUMPS through PETSc, in
  // one process), whose factor is about Cholesky's size, where LU's is several times it (the
  // reduced contact system of the fine tet10 Hertz mesh, 118k unknowns: peak memory 8.5 GB
  // with UMFPACK against 3.2 GB with CHOLMOD). An unsymmetric one: LU, MUMPS's above
  // kMumpsLuAbove unknowns (its nested dissection fills less), else UMFPACK's.
  const bool mumps = petsc_available() && launched_ranks() == 1 && (symmetric || rows > kMumpsLuAbove);
  return mumps ? "mumps" : "umfpack";
}

void AutoLinearSolver::solve(const SparseMatrix& a, bool symmetric, const VecX& b, VecX& x) {
  std::string want = choice_.type;
  // A solver for symmetric systems would solve an unsymmetric one's symmetric part (one
  // triangle read): refused (the Analysis refuses such a deck before the first solve, naming
  // why its tangent is unsymmetric; this guards the other callers).
  if (!symmetric && is_symmetric_only_solver(want))
    throw SolverError("linear solver " + want + " takes symmetric systems only, and this one is unsymmetric (use auto, "
                      "umfpack or mumps)");
  const bool skipping = spd_skip_ > 0;  // after a failed Cholesky or Krylov solve: LU
  const bool spd_wanted = symmetric && !skipping;
  if (skipping) --spd_skip_;
  const std::string indefinite = indefinite_solver(a.rows(), symmetric);
  if (want == "auto") {
    // An unsymmetric displacement system (set_unsymmetric_amg) that unsymmetric_iterative sends
    // to algebraic multigrid (large, or in 3D at any size while set_unsymmetric_amg_any_size
    // holds): GMRES over GAMG, falling back to LU as a symmetric one falls back from Cholesky.
    if (!symmetric && unsymmetric_amg_ && !skipping && unsymmetric_iterative(a.rows())) want = "gamg";
    else want = !spd_wanted ? indefinite : auto_spd_solver(a.rows());
  }
  if (choice_.type == "auto" && want == "gamg" && !announced_) {
    // PETSc is not threaded: in one process its solve runs on one core (measured on the 3D Hertz
    // model at 394k DOFs: as fast as CG with incomplete Cholesky on two threads; under mpirun -np 2
    // twice as fast, docs/performance.md).
    announced_ = true;
    const std::string why = a.rows() > choice_.iterative_above
                                ? fmt::format("above iterative_above, {}", choice_.iterative_above)
                            : !symmetric ? std::string("3D, unsymmetric: GMRES over it at any size")
                                         : std::string("its Cholesky factor too large");
    log::info("    linear solver auto: {} unknowns ({}): gamg, on one core in one process (mpirun -np N shares it out)",
              a.rows(), why);
  }
  if (!solver_ || solver_->name() != want) {
    LinearSolverSettings s = choice_;
    s.type = want;
    solver_ = make_linear_solver(s);
    solver_->set_layout(layout_);
  }
  solver_->set_symmetric(symmetric);
  solver_->set_tolerance(tolerance_);
  const bool spd = want == "cholmod" || want == "eigen_cg" || (choice_.type == "auto" && want == "gamg");
  if (solver_->factorize(a) && solver_->solve(b, x)) {
    if (spd) spd_backoff_ = 1;
    return;
  }
  if (choice_.type == "auto" && spd) {
    // Not positive definite (an instability, or contact's geometric term -p w hess g while the
    // penetration is large): the indefinite factorization above instead (MUMPS's LDL^T or
    // UMFPACK's LU; also when CHOLMOD ran out of its integers, where 64-bit UMFPACK may not), for
    // the next 1, 2, 4, ... solves after each failure in
    // a row, rather than paying for a failed factorization at every iteration; Cholesky comes
    // back once the tangent is definite again (measured on the 2D Hertz mesh of CalculiX with
    // penalty: it fails in the first 7 of 19 iterations, then succeeds).
    spd_skip_ = spd_backoff_;
    spd_backoff_ = std::min(2 * spd_backoff_, 64);
    log::debug("    {} failed ({}): {} for this solve and the next {}", solver_->name(), solver_->failure(), indefinite,
               spd_skip_);
    solver_ = make_linear_solver(indefinite);
    solver_->set_symmetric(symmetric);
    if (solver_->factorize(a) && solver_->solve(b, x)) return;
  }
  if (choice_.type == "auto" && solver_->name() == "mumps") {
    // MUMPS failed too (singular, or out of its workspace): LU, the last resort.
    log::debug("    mumps failed ({}): LU (UMFPACK)", solver_->failure());
    solver_ = make_linear_solver("umfpack");
    if (solver_->factorize(a) && solver_->solve(b, x)) return;
  }
  if (is_petsc_solver(solver_->name()))
    throw SolverError("linear solver " + solver_->name() + " failed: " + solver_->failure() +
                      (solver_->name() == "mumps" ? std::string(" (a singular system, or MUMPS out of its workspace: try umfpack)")
                                                  : std::string(" (a singular or indefinite system, or a preconditioner unfit "
                                                                "for it: try mumps or umfpack)")));
  const std::string why = solver_->failure();
  if (solver_->ran_out_of_resources())
    throw SolverResourceError("linear solver " + solver_->name() + " failed: " + why + " (" +
                              std::to_string(a.rows()) + " unknowns, " + std::to_string(a.nonZeros()) + " nonzeros)");
  throw SolverError("linear solver " + solver_->name() + " failed: the system is singular (missing supports or a "
                    "mechanism?) or not positive definite" + (why == "failed" ? "" : " (" + why + ")"));
}

bool FactorizationForecast::record(long krylov_iterations, Index rows, Index nonzeros) {
  if (favours_ || rows <= 0) return favours_;
  iterations_ += krylov_iterations;
  ++solves_;
  const Real n = static_cast<Real>(rows);
  ratio_ = kConstant * mean_iterations() * static_cast<Real>(nonzeros) / (n * n);
  favours_ = ratio_ > 1;
  return favours_;
}

std::string FactorizationForecast::describe(Index rows, Index nonzeros, const std::string& factorization) const {
  return fmt::format("    linear solver auto: GMRES over GAMG took {:.0f} Krylov iterations per solve on {} unknowns ({} "
                     "nonzeros): a factorization forecast {:.1f}x faster (t_Krylov / t_LU = {} K nnz / n^2, "
                     "docs/performance.md); the whole system to {} from the next solve on",
                     mean_iterations(), rows, nonzeros, ratio_, kConstant, factorization);
}

}  // namespace signorini
