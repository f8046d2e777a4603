#include "signorini/solver/backend.hpp"

#include <cstdlib>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/solver/condensed_solve.hpp"
#include "signorini/solver/linear_solver.hpp"
#ifdef SIGNORINI_HAVE_PETSC
#include "signorini/solver/petsc_solver.hpp"
#endif

namespace signorini {

namespace {

class SerialBackend final : public AlgebraBackend {
 public:
  SerialBackend(const LinearSolverSettings& linear, bool three_d)
      : linear_name_(linear.type),
        iterative_above_(linear.iterative_above),
        linear_(linear, three_d),
        condensed_(condenses(linear.type) ? linear : LinearSolverSettings("auto"), three_d) {}
  std::string name() const override { return "serial"; }
  Index owned_begin() const override { return 0; }
  Index owned_end() const override { return rows(); }
  void build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
                     const std::vector<std::vector<Index>>& couplings, Index total) override {
    system_.build_pattern(dofs, cells, couplings, total);
    linear_.reset();  // a new pattern needs a new symbolic analysis
    saved_.clear();
    saved_.shrink_to_fit();
  }
  // Kept only for an iterative solver (or `auto` on a 3D system it solves iteratively), where the
  // assembly is a large share of a Newton iteration. A factorization dwarfs the assembly, and
  // the copy would only add to the memory: on the medium tet10 mortar Hertz mesh (CHOLMOD,
  // 7.0M nonzeros) keeping it saves 1 s of 42 s and costs 56 MB, where the memory is the
  // target (issue 14: at most CalculiX's).
  // Also kept once a solve went to an iterative solver below that size (`auto`'s GMRES over
  // GAMG on an unsymmetric 3D system, friction's multiplier blocks): the cattaneo_sphere_3d
  // example (11.8k unknowns, penalty friction) assembled its linear bodies at each of its 63
  // tangents, and now 10 times (docs/performance.md, session 59).
  void save_values() override {
    if (!linear_.iterative(rows()) && !iterative_last_) return;
    const SparseMatrix& m = system_.matrix();
    saved_.assign(m.valuePtr(), m.valuePtr() + m.nonZeros());
  }
  bool restore_values() override {
    SparseMatrix& m = system_.matrix();
    if (saved_.empty() || static_cast<Index>(saved_.size()) != m.nonZeros()) return false;
    system_.zero();  // (the missed-entry flag)
    std::copy(saved_.begin(), saved_.end(), m.valuePtr());
    return true;
  }
  Index rows() const override { return system_.matrix().rows(); }
  Index nonzeros() const override { return system_.nonzeros(); }
  void zero() override { system_.zero(); }
  GlobalMatrix& matrix() override { return system_; }
  bool missed() const override { return system_.missed(); }
  void multiply(const VecX& x, VecX& y) const override { y = system_.matrix() * x; }
  Real mean_abs_diagonal() const override { return system_.mean_abs_diagonal(); }
  void apply_dirichlet(const std::vector<char>& constrained, Real scale) override {
    system_.apply_dirichlet(constrained, scale);
  }
  // A factor too large for `auto` sends the bodies' and the condensed contact systems to GAMG.
  void assess_factor() override {
    if (linear_name_ != "auto") return;
    linear_.assess_factor(system_.matrix());
    condensed_.set_factor_too_large(linear_.factor_too_large());
  }
  // In 3D with `auto` and PETSc, Lagrange friction's condensed system may go to GAMG at any size.
  // So may an unsymmetric system without multipliers (set per solve, so asked here directly).
  bool wants_layout() const override {
    return linear_.wants_layout(rows()) || condensed_.wants_layout_for_blocks() || linear_.unsymmetric_amg_in_3d();
  }
  void set_layout(std::shared_ptr<const UnknownLayout> layout) override {
    linear_.set_layout(layout);
    condensed_.set_layout(layout);
  }
  int last_iterations() const override { return last_iterations_; }
  std::string last_method() const override { return last_method_; }
  std::string solve(const NewtonSolveRequest& q, const VecX& r, VecX& du) override {
    // Multiplier contact with the automatic solver, algebraic multigrid or a symmetric solver
    // without pivoting (none of which can take a saddle-point system): the condensed system
    // when its structure allows (condensed_solve.hpp), solved by that solver; another solver
    // chosen in the deck (an LU, MUMPS) gets the whole system.
    last_iterations_ = 0;
    linear_.set_tolerance(q.rtol);
    condensed_.set_tolerance(q.rtol);
    if (q.is_multiplier && !q.condense_contact && is_amg_solver(linear_name_))
      throw FatalModelError("linear solver " + linear_name_ + " with condense_contact: false: algebraic multigrid "
                            "cannot take the contact multipliers' saddle point (condense them, or use enforcement: "
                            "penalty, or linear: mumps or umfpack)");
    // `auto`, once its forecast favours a factorization of the whole system over the Krylov
    // solves it sent to GAMG at any size in 3D (FactorizationForecast, recorded below): the
    // whole system to LU, multipliers and all, for the rest of the run.
    const bool factorize = forecast_.favours_factorization();
    const log::Timer timer;
    if (q.is_multiplier && q.condense_contact && condenses(linear_name_) && !factorize && !whole_trial_ &&
        !whole_faster_) {
      if (condensed_.solve(system_.matrix(), *q.is_multiplier, q.body_symmetric, r, du)) {
        last_iterations_ = condensed_.last_iterations();
        last_method_ = "condensed multipliers, " + condensed_.last_method();
        iterative_last_ = is_iterative(condensed_.last_used());
        if (condensed_.refinements() > 0) log::debug("    condensed solve: {} refinement steps", condensed_.refinements());
        forecast(condensed_.last_used());
        time_coupled_rows(timer.seconds());
        return "condensed+" + condensed_.last_used();
      }
      if (linear_name_ != "auto")
        throw FatalModelError("linear solver " + linear_name_ + " cannot solve this contact system: " +
                              condensed_.why_not() + ", and " +
                              (is_amg_solver(linear_name_) ? "algebraic multigrid" : "a symmetric solver without pivoting") +
                              " cannot take the contact multipliers' saddle point (use enforcement: penalty, or linear: "
                              "auto, mumps or umfpack)");
      if (!condense_reported_) {
        log::info("    contact multipliers kept in the linear system ({}): {}",
                  AutoLinearSolver::indefinite_solver(rows(), q.symmetric),
                  condensed_.why_not());
        condense_reported_ = true;
      }
    }
    // A system without multipliers is a displacement system, which algebraic multigrid takes
    // unsymmetric too (friction by the penalty or the augmented Lagrangian, follower pressure):
    // `auto` sends it in 3D to GMRES over GAMG at any size, as friction's multiplier blocks,
    // falling back to LU where GMRES fails (measured on the 3D Hertz sphere with penalty
    // friction: 3.5x faster than MUMPS's LU at 15k unknowns, 5-6x at 35k; docs/performance.md).
    linear_.set_unsymmetric_amg(!q.is_multiplier && !factorize);
    linear_.set_unsymmetric_amg_any_size(!q.is_multiplier && !factorize);
    // The trial: the condensed system's factor freed first (not held beside the whole system's;
    // if the condensation stays, its next solve analyses its pattern anew).
    if (whole_trial_) condensed_.release();
#ifdef SIGNORINI_HAVE_PETSC
    if (whole_trial_ && petsc_available()) start_petsc();  // not a cost of the trial's solve
#endif
    const log::Timer whole_timer;
    linear_.solve(system_.matrix(), q.symmetric, r, du);
    last_iterations_ = linear_.last_iterations();
    last_method_ = linear_.last_method();
    iterative_last_ = is_iterative(linear_.last_used());
    forecast(linear_.last_used());
    if (whole_trial_) {
      whole_trial_ = false;
      const double whole = whole_timer.seconds();
      // SIGNORINI_WHOLE_TRIAL=whole|condensed (tests): the trial's verdict, whatever the times.
      const char* verdict = std::getenv("SIGNORINI_WHOLE_TRIAL");
      whole_faster_ = verdict ? std::string(verdict) == "whole" : whole < condensed_seconds_;
      if (!whole_faster_) linear_.reset();  // the whole system's factor is not needed again
      log::info("    linear solver auto: the whole system's factorization ({}) took {:.2f} s against {:.2f} s for the "
                "condensed solve of the coupled contact rows with its GMRES corrections: {} for the rest of the run",
                linear_.last_used(), whole, condensed_seconds_, whole_faster_ ? "the whole system" : "condensed");
    }
    return linear_.last_used();
  }

 private:
  std::string linear_name_;
  Index iterative_above_;
  int last_iterations_ = 0;
  std::string last_method_;
  SparseSystem system_;
  std::vector<Real> saved_;  // save_values()
  AutoLinearSolver linear_;
  CondensedContactSolver condensed_;
  bool condense_reported_ = false;
  bool iterative_last_ = false;  // the last solve was a Krylov solver's (save_values)
  FactorizationForecast forecast_;
  // `auto` on coupled contact rows (mortar, segment_to_segment) condensed for a factorization:
  // the condensed solve is exact (GMRES corrects the left-out couplings to round-off), and so is
  // a factorization of the whole system, so the two give the same Newton steps and the faster
  // may be kept. At the second condensed solve with corrections (the first of a run may have
  // few or many: its closed rows are the touching ones), if it took kTrialCorrections or more,
  // the next solve is the whole system's, timed (whole_trial_), and the faster of the two takes
  // the rest of the run (whole_faster_); with fewer the condensation stays without a trial (a
  // trial costs a factorization of the whole system and its memory: on the tet4 mortar quarter
  // at hc 0.01, before the trial freed the condensed factor, 573 MiB against 334 MiB). Measured: linear mortar facets 2-3 corrections a solve after the first
  // (the condensation faster, 0.87 s against MUMPS's 1.51 s), quadratic ones 23-28 (the whole
  // system faster, 1.57 s against 3.53 s; docs/performance.md, session 66). Since session 67
  // (coupled rows in two levels, condensed_solve.hpp) quadratic facets take 2-3 corrections after
  // the first Newton iterations too, and the count no longer tells the two apart: the tet10
  // quarter's trial comes at its second solve (12 corrections, the gaps still open), and a
  // model whose second solve takes fewer stays condensed (on the tet10 quarter the condensed
  // path took 7.1 s of linear solve, the whole system 3.6 s).
  static constexpr int kTrialCorrections = 10;
  int coupled_solves_ = 0;  // condensed solves with corrections, counted up to the second (decided once)
  double condensed_seconds_ = 0;
  bool whole_trial_ = false, whole_faster_ = false;
  void time_coupled_rows(double seconds) {
    if (linear_name_ != "auto" || coupled_solves_ >= 2 || condensed_.refinements() == 0 ||
        is_iterative(condensed_.last_used()))
      return;
    if (++coupled_solves_ < 2) return;
    condensed_seconds_ = seconds;
    // SIGNORINI_WHOLE_TRIAL (tests): a trial whatever the count (and its verdict, below).
    whole_trial_ = condensed_.refinements() >= kTrialCorrections || std::getenv("SIGNORINI_WHOLE_TRIAL");
  }
  // After a solve by `used`: `auto`'s GAMG at or below iterative_above (where it goes only for
  // unsymmetric 3D systems, at any size; not after a Cholesky factor was found too large) is
  // recorded in the forecast, which may send the next solves whole to LU (logged once).
  void forecast(const std::string& used) {
    if (linear_name_ != "auto" || !is_amg_solver(used) || rows() > iterative_above_ || linear_.factor_too_large()) return;
    if (forecast_.record(last_iterations_, rows(), nonzeros()))
      log::info("{}", forecast_.describe(rows(), nonzeros(), AutoLinearSolver::indefinite_solver(rows(), false)));
  }
  static bool is_iterative(const std::string& used) { return is_amg_solver(used) || used == "eigen_cg"; }
  // Whether the deck's solver takes the contact multipliers condensed (it cannot take their
  // saddle point, or it is `auto`, which condenses when it can).
  static bool condenses(const std::string& type) {
    return type == "auto" || is_amg_solver(type) || is_symmetric_only_solver(type);
  }
};

}  // namespace

std::unique_ptr<AlgebraBackend> make_serial_backend(const LinearSolverSettings& linear, bool three_d) {
  return std::make_unique<SerialBackend>(linear, three_d);
}

}  // namespace signorini
