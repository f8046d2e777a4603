#include "signorini/solver/petsc_solver.hpp"

#include <unistd.h>

#include <petscksp.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>

#include <fmt/format.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/core/rank_exchange.hpp"
#include "signorini/solver/backend.hpp"
#include "signorini/solver/condensed_solve.hpp"
#include "signorini/solver/multiplier_blocks.hpp"

namespace signorini {

namespace {

static_assert(sizeof(PetscInt) == sizeof(int), "Eigen's int indices are passed to PETSc as they are");

bool g_started_here = false;

void ensure_petsc() {
  PetscBool done = PETSC_FALSE;
  PetscInitialized(&done);
  if (done) return;
  // Signorini handles SIGINT/SIGTERM itself (the run stops cleanly, results kept): PETSc's
  // own signal handlers would abort instead. Unused options are the user's business.
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  PetscOptionsSetValue(nullptr, "-options_left", "0");
  // MUMPS detects null pivots (ICNTL(24) = 1; MUMPS 5.5 users' guide, sec. 5.3) instead of
  // stopping at them (INFOG(1) = -10, and PETSc then reports an error at the solve): a Newton
  // tangent can be singular for one iteration, as when every node of a frictional contact
  // slips and nothing else holds a free rigid body's rolling (examples/rolling_rigid_mesh's
  // hold_back step, one process, linear: mumps: every cutback failed, and the run gave up).
  // The step then leaves the null direction alone and the next iteration's statuses decide;
  // the residual still judges convergence. A raw -mat_mumps_icntl_24 in the deck wins (it is
  // read after this).
  PetscOptionsSetValue(nullptr, "-mat_mumps_icntl_24", "1");
  if (PetscInitializeNoArguments() != 0) throw Error("PETSc could not be initialized");
  // Errors come back as codes (reported by us), without PETSc's traceback on stderr.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  g_started_here = true;
}

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw Error(fmt::format("PETSc: {} failed ({})", what, text ? text : "unknown error"));
}

// PETSc started, the deck's raw options in its database; the ranks and this one.
void start(const LinearSolverSettings& s, int& size, int& rank) {
  ensure_petsc();
  if (!s.options.empty()) check(PetscOptionsInsertString(nullptr, s.options.c_str()), "reading the options");
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
}

// The Krylov method and preconditioner of `s` (symmetric: CG or Cholesky; else GMRES or LU),
// then the user's raw options. Returns the relative tolerance so configured (rtol, or a raw
// -ksp_rtol).
Real configure_ksp(KSP ksp, const LinearSolverSettings& s, bool symmetric) {
  PC pc = nullptr;
  KSPGetPC(ksp, &pc);
  if (s.type == "mumps") {
    check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
    check(PCSetType(pc, symmetric ? PCCHOLESKY : PCLU), "PCSetType");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  } else if (is_amg_solver(s.type)) {
    check(KSPSetType(ksp, symmetric ? KSPCG : KSPGMRES), "KSPSetType");
    // rtol on the true residual |b - A x| / |b| (CG's default is the preconditioned one).
    if (symmetric) KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED);
    if (!symmetric) KSPGMRESSetRestart(ksp, 200);
    if (s.type == "gamg") {
      check(PCSetType(pc, PCGAMG), "PCSetType");
      PCGAMGSetType(pc, PCGAMGAGG);
      PCGAMGSetReuseInterpolation(pc, PETSC_TRUE);
      PCGAMGSetNSmooths(pc, s.amg_smoothing);
      // Connections weaker than 1 % of the diagonal's (|a_ij| < 0.01 sqrt(|a_ii a_jj|)) left out
      // of the graph that GAMG aggregates: on graded tetrahedral meshes they joined nodes across
      // thin cells into aggregates that plain aggregation interpolates badly. Measured on the
      // 3D Hertz model at 394k DOFs (2 ranks, plain aggregation under adaptive forcing): the
      // first solve 52 -> 23 CG iterations, 15-52 -> 16-34 per solve, the same answer
      // (docs/performance.md). A raw -pc_gamg_threshold wins.
      PetscReal threshold[1] = {0.01};
      PCGAMGSetThreshold(pc, threshold, 1);
    } else {
      check(PCSetType(pc, PCHYPRE), "PCSetType (is PETSc built with hypre?)");
      PCHYPRESetType(pc, "boomeramg");
    }
  }
  check(KSPSetTolerances(ksp, s.rtol, 1e-300, PETSC_DEFAULT, 10000), "KSPSetTolerances");
  check(KSPSetFromOptions(ksp), "KSPSetFromOptions");
  PetscReal rtol = s.rtol;
  KSPGetTolerances(ksp, &rtol, nullptr, nullptr, nullptr);
  return rtol;
}

// The Krylov method and preconditioner `ksp` runs, in words (summary.json, issue 15): "cg,
// gamg (plain aggregation, 6 near-nullspace vectors)", "preonly, cholesky (mumps)", "cg, hypre
// (boomeramg)". GAMG's smoothing is the settings' unless raw options set it.
std::string describe_ksp(KSP ksp, const LinearSolverSettings& s) {
  if (!ksp) return s.type;
  KSPType kt = nullptr;
  KSPGetType(ksp, &kt);
  PC pc = nullptr;
  KSPGetPC(ksp, &pc);
  PCType pt = nullptr;
  if (pc) PCGetType(pc, &pt);
  const std::string k = kt ? kt : "?", p = pt ? pt : "?";
  std::string out = k + ", " + p;
  if (p == PCGAMG) {
    PetscInt smooths = s.amg_smoothing;
    PetscBool set = PETSC_FALSE;
    PetscOptionsGetInt(nullptr, nullptr, "-pc_gamg_agg_nsmooths", &smooths, &set);
    PetscInt vectors = 0;
    Mat a = nullptr;
    KSPGetOperators(ksp, &a, nullptr);
    MatNullSpace space = nullptr;
    if (a) MatGetNearNullSpace(a, &space);
    if (space) {
      PetscBool constant = PETSC_FALSE;
      const Vec* vecs = nullptr;
      MatNullSpaceGetVecs(space, &constant, &vectors, &vecs);
      vectors += constant ? 1 : 0;
    }
    out += fmt::format(" ({} aggregation, {})", smooths > 0 ? "smoothed" : "plain",
                       vectors > 0 ? fmt::format("{} near-nullspace vectors", vectors) : "no near-nullspace");
  } else if (p == PCLU || p == PCCHOLESKY) {
    MatSolverType st = nullptr;
    PCFactorGetMatSolverType(pc, &st);
    if (st) out += fmt::format(" ({})", st);
  } else if (p == PCHYPRE) {
    const char* ht = nullptr;
    PCHYPREGetType(pc, &ht);
    if (ht) out += fmt::format(" ({})", ht);
  }
  return out;
}

// CG's breakdown on an indefinite system. A condensed contact system can be indefinite: the
// contact's geometric terms -lambda w hess(g) (measured on the fine tet10 mortar mesh of
// CalculiX's harness, at its fifth Newton iteration with forcing fixed; Cholesky fails there
// too, docs/performance.md). The same preconditioner then goes on with GMRES, preconditioned
// on the right so that rtol stays on the true residual, for the later solves of this matrix
// too (a new pattern configures CG again). Returns whether it switched.
bool cg_to_gmres_if_indefinite(KSP ksp, KSPConvergedReason reason) {
  if (reason != KSP_DIVERGED_INDEFINITE_MAT && reason != KSP_DIVERGED_INDEFINITE_PC) return false;
  KSPType type = nullptr;
  KSPGetType(ksp, &type);
  if (!type || std::string(type) != KSPCG) return false;
  check(KSPSetType(ksp, KSPGMRES), "KSPSetType");
  KSPGMRESSetRestart(ksp, 200);
  check(KSPSetPCSide(ksp, PC_RIGHT), "KSPSetPCSide");
  check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  PetscInt its = 0;
  KSPGetIterationNumber(ksp, &its);
  log::debug("    CG found the system indefinite ({} after {} iterations): GMRES with the same preconditioner",
             KSPConvergedReasons[reason], its);
  return true;
}

// MUMPS's factor behind `ksp`'s preconditioner, or null (another preconditioner, or none yet).
Mat mumps_factor(KSP ksp) {
  PC pc = nullptr;
  Mat F = nullptr;
  MatSolverType type = nullptr;
  if (KSPGetPC(ksp, &pc) != 0 || PCFactorGetMatrix(pc, &F) != 0 || !F) return nullptr;
  if (MatFactorGetSolverType(F, &type) != 0 || !type || std::string(type) != MATSOLVERMUMPS) return nullptr;
  return F;
}

// The MUMPS working-space options this process set itself (after_failed_factor), as against a
// deck's own.
std::set<std::string>& raised_workspace_options() {
  static std::set<std::string> raised;
  return raised;
}

// MUMPS's INFOG(1) for a working space too small: -8, -9, -11, -12, -14, -15, -17, -20 (MUMPS
// 5.5 users' guide, sec. 8, each "increase ICNTL(14)").
bool mumps_short_of_space(PetscInt info) {
  return info == -8 || info == -9 || info == -11 || info == -12 || info == -14 || info == -15 || info == -17 ||
         info == -20;
}

// After `ksp`'s factorization failed. Any failed MUMPS factor is dropped (PCReset), so that the
// next setup analyses and factorizes anew: PETSc's MatFactorNumeric_MUMPS returns at once,
// without factorizing, while INFOG(1) < 0 from the last phase, so a failed factor would fail
// every later solve of its pattern. Measured: examples/brinell with linear: mumps (one process
// as on two ranks) ran short of working space at 75 % of its press step, then every cutback
// failed and the run gave up.
// MUMPS allocates its working space from the analysis' estimate plus ICNTL(14) per cent (MUMPS
// 5.5 users' guide, ICNTL(14)); pivoting on an indefinite matrix (the contact multipliers'
// saddle point) delays pivots beyond that estimate (mumps_short_of_space). Such a failure
// doubles ICNTL(14) (at least 40 %), when `may_raise` (twice per solve) and up to
// kMumpsMostWorkspace, through the options database so that every later factor of this prefix
// gets it too; a deck's own -mat_mumps_icntl_14 stays (no retry then). The bounds matter:
// MUMPS allocates that margin for the rest of the run, and a Newton iterate that has run away
// (a singular tangent) delays pivots past any margin (brinell's press with `auto`: doubled to
// 1280 % in one iteration before UMFPACK found the matrix singular, without the bounds).
// INFOG and ICNTL are the same on every rank, so every rank decides alike (collective).
constexpr PetscInt kMumpsMostWorkspace = 160;  // per cent: 2.6 times the analysis' estimate
struct MumpsFailure {
  PetscInt info = 0;      // MUMPS's INFOG(1) (0: no MUMPS factor)
  bool retry = false;     // the working space was raised: set up again
  bool at_most = false;   // short of working space with ICNTL(14) at kMumpsMostWorkspace already
};
MumpsFailure after_failed_factor(KSP ksp, bool may_raise) {
  MumpsFailure out;
#ifdef PETSC_HAVE_MUMPS
  Mat F = mumps_factor(ksp);
  if (!F) return out;
  PetscInt percent = 0;
  MatMumpsGetInfog(F, 1, &out.info);
  MatMumpsGetIcntl(F, 14, &percent);
  // The factor dropped; PCReset drops the operators too, which go back at once.
  PC pc = nullptr;
  Mat A = nullptr, P = nullptr;
  KSPGetPC(ksp, &pc);
  PCGetOperators(pc, &A, &P);
  PetscObjectReference(reinterpret_cast<PetscObject>(A));
  PetscObjectReference(reinterpret_cast<PetscObject>(P));
  PCReset(pc);
  PCSetFailedReason(pc, PC_NOERROR);
  KSPSetOperators(ksp, A, P);
  MatDestroy(&A);
  MatDestroy(&P);
  if (!mumps_short_of_space(out.info)) return out;
  const char* prefix = nullptr;
  KSPGetOptionsPrefix(ksp, &prefix);
  const std::string key = fmt::format("-{}mat_mumps_icntl_14", prefix ? prefix : "");
  PetscBool given = PETSC_FALSE;
  PetscOptionsHasName(nullptr, nullptr, key.c_str(), &given);
  auto& raised = raised_workspace_options();
  const bool own = given && !raised.count(key);
  out.at_most = !own && percent >= kMumpsMostWorkspace;
  if (own || percent >= kMumpsMostWorkspace || !may_raise) {
    log::info("    MUMPS ran short of working space (INFOG(1) = {}) with ICNTL(14) = {} %{}", out.info, percent,
              own ? " (the deck's own)" : "");
    return out;
  }
  const PetscInt more = std::min<PetscInt>(kMumpsMostWorkspace, std::max<PetscInt>(2 * percent, 40));
  raised.insert(key);
  PetscOptionsSetValue(nullptr, key.c_str(), std::to_string(more).c_str());
  log::info("    MUMPS ran short of working space (INFOG(1) = {}): ICNTL(14) {} -> {} %, factorizing again", out.info,
            percent, more);
  out.retry = true;
#else
  (void)ksp;
  (void)may_raise;
#endif
  return out;
}

// Why a preconditioner failed, for the error message: MUMPS's INFOG(1) when it was MUMPS.
std::string failed_factor_words(const MumpsFailure& f) {
  if (f.info == 0) return "";
  // Pivots delayed past 2.6 times the analysis' estimate: most likely an iterate whose matrix is
  // singular or nearly so (brinell under mpirun with `auto`, at increments that UMFPACK finds
  // singular in one process), which no working space cures.
  if (f.at_most)
    return fmt::format("; MUMPS INFOG(1) = {}, short of working space even at ICNTL(14) = {} %, the most set here: "
                       "the matrix is most likely singular or nearly so",
                       f.info, kMumpsMostWorkspace);
  return fmt::format("; MUMPS INFOG(1) = {}{}", f.info,
                     mumps_short_of_space(f.info) ? ", short of working space (-mat_mumps_icntl_14)"
                     : f.info == -13          ? ", out of memory"
                                              : "");
}

// KSPSolve, and once more after cg_to_gmres_if_indefinite switched or MUMPS's working space was
// raised (after_failed_factor); `reason` the last solve's, `mumps` what MUMPS said when its
// factor failed. Returns PETSc's error code (0: the solve ran, converged or not).
PetscErrorCode solve_krylov(KSP ksp, Vec b, Vec x, KSPConvergedReason& reason, MumpsFailure* mumps = nullptr) {
  bool switched = false;
  for (int attempt = 0;; ++attempt) {
    const PetscErrorCode code = KSPSolve(ksp, b, x);
    if (code != 0) return code;
    KSPGetConvergedReason(ksp, &reason);
    if (reason == KSP_DIVERGED_PC_FAILED) {
      const MumpsFailure f = after_failed_factor(ksp, attempt < 2);
      if (mumps) *mumps = f;
      if (f.retry) continue;
      return 0;
    }
    if (switched || !cg_to_gmres_if_indefinite(ksp, reason)) return 0;
    switched = true;
  }
}

// A Newton iteration's forcing term (rtol > 0) as the Krylov solver's relative tolerance; 0
// puts back the configured one (`configured`: the deck's rtol or a raw -ksp_rtol), which a
// previous solve may have changed. A direct solve has none.
void apply_tolerance(KSP ksp, const LinearSolverSettings& s, Real rtol, Real configured) {
  if (s.type != "mumps") KSPSetTolerances(ksp, rtol > 0 ? rtol : configured, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT);
}

// The rigid-body modes of the layout's displacement unknowns, orthonormalized (modified
// Gram-Schmidt): translations, and rotations about the centroid (one in 2D, three in 3D);
// axisymmetric: the axial translation only (a radial motion strains the hoops). Set as A's
// near-nullspace, this rank's rows [rstart, rend) of a matrix of `padded` rows.
void set_near_nullspace(Mat A, const UnknownLayout& layout, Index padded, Index rstart, Index rend) {
  const Index n = layout.size();
  const int dim = layout.dim;
  Vec3 c = Vec3::Zero();
  Index count = 0;
  for (Index i = 0; i < n; ++i)
    if (layout.comp[i] == 0) c += layout.x[i], ++count;
  if (count) c /= static_cast<Real>(count);
  std::vector<VecX> modes;
  auto translation = [&](int d) {
    VecX v = VecX::Zero(padded);
    for (Index i = 0; i < n; ++i) v(i) = layout.comp[i] == d ? 1.0 : 0.0;
    return v;
  };
  auto rotation = [&](int p, int q) {  // rotation in the (p, q) plane: u_p = -x_q, u_q = x_p
    VecX v = VecX::Zero(padded);
    for (Index i = 0; i < n; ++i) {
      const Vec3 x = layout.x[i] - c;
      if (layout.comp[i] == p) v(i) = -x(q);
      else if (layout.comp[i] == q) v(i) = x(p);
    }
    return v;
  };
  if (layout.axisymmetric) {
    modes.push_back(translation(1));
  } else {
    for (int d = 0; d < dim; ++d) modes.push_back(translation(d));
    if (dim == 2) modes.push_back(rotation(0, 1));
    if (dim == 3) {
      modes.push_back(rotation(0, 1));
      modes.push_back(rotation(1, 2));
      modes.push_back(rotation(2, 0));
    }
  }
  std::vector<VecX> basis;
  for (VecX& v : modes) {
    for (const VecX& e : basis) v -= v.dot(e) * e;
    const Real norm = v.norm();
    if (norm > 1e-12 * std::sqrt(static_cast<Real>(n))) basis.push_back(v / norm);
  }
  if (basis.empty()) return;
  std::vector<Vec> vecs(basis.size());
  for (size_t k = 0; k < basis.size(); ++k) {
    check(MatCreateVecs(A, &vecs[k], nullptr), "MatCreateVecs");
    PetscScalar* p = nullptr;
    VecGetArray(vecs[k], &p);
    std::copy(basis[k].data() + rstart, basis[k].data() + rend, p);
    VecRestoreArray(vecs[k], &p);
  }
  MatNullSpace space = nullptr;
  check(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, static_cast<PetscInt>(vecs.size()), vecs.data(), &space),
        "MatNullSpaceCreate");
  check(MatSetNearNullSpace(A, space), "MatSetNearNullSpace");
  MatNullSpaceDestroy(&space);
  for (Vec& v : vecs) VecDestroy(&v);
}

class PetscKsp final : public LinearSolver {
 public:
  explicit PetscKsp(LinearSolverSettings s) : s_(std::move(s)) {
    start(s_, size_, rank_);
  }
  ~PetscKsp() override {
    if (ksp_) KSPDestroy(&ksp_);
    destroy_system();
  }
  std::string name() const override { return s_.type; }
  void set_symmetric(bool symmetric) override {
    if (symmetric != symmetric_) configured_ = false;
    symmetric_ = symmetric;
  }
  void set_layout(std::shared_ptr<const UnknownLayout> layout) override {
    layout_ = std::move(layout);
    nullspace_stale_ = true;
  }
  bool wants_layout() const override { return is_amg_solver(s_.type); }
  int iterations() const override { return iterations_; }
  std::string method() const override { return describe_ksp(ksp_, s_); }
  std::string failure() const override { return failure_; }
  void set_tolerance(Real rtol) override { tolerance_ = rtol; }

  bool factorize(const SparseMatrix& a) override {
    try {
      copy_matrix(a);
      configure();
      for (int attempt = 0;; ++attempt) {
        check(KSPSetUp(ksp_), "the preconditioner's setup");
        PCFailedReason reason = PC_NOERROR;
        PC pc = nullptr;
        KSPGetPC(ksp_, &pc);
        PCGetFailedReason(pc, &reason);
        if (reason == PC_NOERROR) return true;
        // MUMPS: more working space, or a fresh factor next time.
        const MumpsFailure mumps = after_failed_factor(ksp_, attempt < 2);
        if (mumps.retry) continue;
        failure_ = fmt::format("the preconditioner's setup failed ({}{})", PCFailedReasons[reason],
                               failed_factor_words(mumps));
        return false;
      }
    } catch (const Error& e) {
      failure_ = e.what();
      return false;
    }
  }

  bool solve(const VecX& b, VecX& x) override {
    try {
      const Index n = b.size();
      // This rank's rows of the right-hand side (every rank holds all of it).
      PetscScalar* pb = nullptr;
      check(VecGetArray(b_, &pb), "VecGetArray");
      for (Index i = rstart_; i < rend_; ++i) pb[i - rstart_] = i < n ? b(i) : 0.0;
      VecRestoreArray(b_, &pb);
      apply_tolerance(ksp_, s_, tolerance_, configured_rtol_);
      KSPConvergedReason reason;
      MumpsFailure mumps;
      check(solve_krylov(ksp_, b_, x_, reason, &mumps), "KSPSolve");
      PetscInt its = 0;
      KSPGetIterationNumber(ksp_, &its);
      iterations_ = s_.type == "mumps" ? 0 : static_cast<int>(its);  // a direct solve: no Krylov iterations
      if (reason < 0) {
        failure_ = fmt::format("the Krylov solver did not converge ({} after {} iterations{})",
                               KSPConvergedReasons[reason], its, failed_factor_words(mumps));
        return false;
      }
      // The whole solution on every rank (each goes on with the same Newton iteration).
      Vec whole = x_;
      if (size_ > 1) {
        check(VecScatterBegin(gather_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
        check(VecScatterEnd(gather_, x_, x_all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
        whole = x_all_;
      }
      const PetscScalar* px = nullptr;
      check(VecGetArrayRead(whole, &px), "VecGetArrayRead");
      x = Eigen::Map<const VecX>(px, n);
      VecRestoreArrayRead(whole, &px);
      if (!x.allFinite()) {
        failure_ = "the solution is not finite";
        return false;
      }
      return true;
    } catch (const Error& e) {
      failure_ = e.what();
      return false;
    }
  }

 private:
  // Block size dim when the layout says the unknowns are node-interleaved displacements
  // followed only by other unknowns (padded with identity rows to a multiple of dim).
  int block_size(Index n) const {
    if (!layout_ || layout_->size() != n || layout_->dim < 2) return 1;
    Index lead = 0;
    while (lead < n && layout_->comp[lead] >= 0) {
      if (layout_->comp[lead] != lead % layout_->dim) return 1;
      ++lead;
    }
    if (lead == 0 || lead % layout_->dim) return 1;
    for (Index i = lead; i < n; ++i)
      if (layout_->comp[i] >= 0) return 1;
    return layout_->dim;
  }

  // The system into a sequential AIJ (CSR) matrix, padded with identity rows to a multiple
  // of the block size. A symmetric matrix's CSC arrays are its CSR arrays (no transposed
  // copy); with the pattern of the last call the values are copied straight into PETSc's.
  void copy_matrix(const SparseMatrix& a) {
    using RowMatrix = Eigen::SparseMatrix<Real, Eigen::RowMajor, int>;
    RowMatrix transposed;
    const int* outer = a.outerIndexPtr();
    const int* inner = a.innerIndexPtr();
    const Real* values = a.valuePtr();
    if (!symmetric_ || !a.isCompressed()) {
      transposed = a;  // CSR
      transposed.makeCompressed();
      outer = transposed.outerIndexPtr();
      inner = transposed.innerIndexPtr();
      values = transposed.valuePtr();
    }
    const Index n = a.rows(), nnz = outer[n];
    const int bs = block_size(n);
    const Index np = (n + bs - 1) / bs * bs;
    // outer_ and inner_ hold the padding's identity rows after the system's own.
    const bool same = A_ && np == padded_ && bs == bs_ && outer_.size() == static_cast<size_t>(np + 1) &&
                      inner_.size() == static_cast<size_t>(nnz + np - n) && std::equal(outer, outer + n + 1, outer_.begin()) &&
                      std::equal(inner, inner + nnz, inner_.begin());
    if (!same) {
      // The Krylov solver's reference to the old matrix and the preconditioner built on it go
      // first, so that they never coexist with the new ones (configured again below).
      if (ksp_) KSPDestroy(&ksp_);
      destroy_system();
      // Allocated at their size (a push_back past the capacity would double it).
      std::vector<int>().swap(outer_);
      std::vector<int>().swap(inner_);
      std::vector<PetscScalar>().swap(values_);
      outer_.reserve(static_cast<size_t>(np + 1));
      inner_.reserve(static_cast<size_t>(nnz + np - n));
      outer_.assign(outer, outer + n + 1);
      inner_.assign(inner, inner + nnz);
      sorted_ = true;  // PETSc keeps each row's columns sorted
      for (Index i = 0; i < n && sorted_; ++i)
        sorted_ = std::is_sorted(inner + outer[i], inner + outer[i + 1]);
      for (Index i = n; i < np; ++i) {
        inner_.push_back(static_cast<int>(i));
        outer_.push_back(static_cast<int>(inner_.size()));
      }
      padded_ = np;
      bs_ = bs;
      // This rank's rows: a contiguous range of whole blocks (all of them on one process).
      const Index blocks = np / bs;
      rstart_ = blocks * rank_ / size_ * bs;
      rend_ = blocks * (rank_ + 1) / size_ * bs;
      configured_ = false;
      nullspace_stale_ = true;
      if (size_ > 1) {
        create_distributed(n);
        set_owned_rows(n, outer, inner, values);
      } else {
        create_sequential(n, values);
      }
    } else if (size_ > 1) {
      set_owned_rows(n, outer, inner, values);
    } else if (!sorted_) {
      for (Index i = 0; i < n; ++i) {
        const PetscInt row = static_cast<PetscInt>(i);
        check(MatSetValues(A_, 1, &row, outer[i + 1] - outer[i], inner + outer[i], values + outer[i], INSERT_VALUES),
              "MatSetValues");
      }
      check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "assembly");
      check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "assembly");
    } else {
      // Same pattern: PETSc's value array is in the same CSR order (the padding at its end).
      PetscScalar* v = nullptr;
      check(MatSeqAIJGetArray(A_, &v), "MatSeqAIJGetArray");
      std::copy(values, values + nnz, v);
      check(MatSeqAIJRestoreArray(A_, &v), "MatSeqAIJRestoreArray");
    }
    MatSetOption(A_, MAT_SYMMETRIC, symmetric_ ? PETSC_TRUE : PETSC_FALSE);
    if (nullspace_stale_ && s_.type == "gamg") set_near_nullspace(n);
  }

  // One process: a sequential AIJ matrix on the padded CSR arrays (identity rows after the
  // last), values included. With sorted rows PETSc works on the arrays kept here (outer_,
  // inner_, values_: MatCreateSeqAIJWithArrays, which neither copies nor frees them; A_ is
  // destroyed before they change), so that the system is held once, not twice, and no padded
  // copy is made on the way (the fine tet10 mortar mesh: 21M entries, 0.25 GB each).
  void create_sequential(Index n, const Real* values) {
    const Index nnz = outer_[n];
    values_.reserve(inner_.size());
    values_.assign(values, values + nnz);
    values_.resize(inner_.size(), 1.0);  // the padding's identity
    static_assert(sizeof(PetscInt) == sizeof(int), "PETSc built with 64-bit indices");
    if (sorted_) {
      check(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, static_cast<PetscInt>(padded_), static_cast<PetscInt>(padded_),
                                      outer_.data(), inner_.data(), values_.data(), &A_),
            "MatCreateSeqAIJWithArrays");
      check(MatSetBlockSize(A_, bs_), "MatSetBlockSize");
    } else {
      check(MatCreate(PETSC_COMM_SELF, &A_), "MatCreate");
      check(MatSetSizes(A_, padded_, padded_, padded_, padded_), "MatSetSizes");
      check(MatSetType(A_, MATSEQAIJ), "MatSetType");
      check(MatSetBlockSize(A_, bs_), "MatSetBlockSize");
      check(MatSeqAIJSetPreallocationCSR(A_, outer_.data(), inner_.data(), values_.data()),
            "MatSeqAIJSetPreallocationCSR");
      std::vector<PetscScalar>().swap(values_);  // PETSc holds its own copy
    }
    check(MatCreateVecs(A_, &x_, &b_), "MatCreateVecs");
  }

  void destroy_system() {
    if (A_) MatDestroy(&A_);
    if (b_) VecDestroy(&b_);
    if (x_) VecDestroy(&x_);
    if (x_all_) VecDestroy(&x_all_);
    if (gather_) VecScatterDestroy(&gather_);
  }

  // Several ranks: every rank holds the whole system (assembled redundantly) and gives PETSc
  // its own rows [rstart_, rend_) of a distributed AIJ matrix, preallocated exactly from the
  // pattern (columns inside its range: the diagonal block).
  void create_distributed(Index n) {
    const Index nloc = rend_ - rstart_;
    std::vector<PetscInt> d_nnz(static_cast<size_t>(nloc), 0), o_nnz(static_cast<size_t>(nloc), 0);
    for (Index i = rstart_; i < rend_; ++i) {
      if (i >= n) {
        d_nnz[i - rstart_] = 1;
        continue;
      }
      for (int k = outer_[i]; k < outer_[i + 1]; ++k)
        (inner_[k] >= rstart_ && inner_[k] < rend_ ? d_nnz : o_nnz)[i - rstart_]++;
    }
    check(MatCreate(PETSC_COMM_WORLD, &A_), "MatCreate");
    check(MatSetSizes(A_, nloc, nloc, padded_, padded_), "MatSetSizes");
    check(MatSetType(A_, MATMPIAIJ), "MatSetType");
    check(MatSetBlockSize(A_, bs_), "MatSetBlockSize");
    check(MatMPIAIJSetPreallocation(A_, 0, d_nnz.data(), 0, o_nnz.data()), "MatMPIAIJSetPreallocation");
    check(MatCreateVecs(A_, &x_, &b_), "MatCreateVecs");
    check(VecScatterCreateToAll(x_, &gather_, &x_all_), "VecScatterCreateToAll");
  }

  void set_owned_rows(Index n, const int* outer, const int* inner, const Real* values) {
    for (Index i = rstart_; i < rend_; ++i) {
      const PetscInt row = static_cast<PetscInt>(i);
      if (i >= n) {
        const PetscScalar one = 1.0;
        check(MatSetValues(A_, 1, &row, 1, &row, &one, INSERT_VALUES), "MatSetValues");
        continue;
      }
      check(MatSetValues(A_, 1, &row, outer[i + 1] - outer[i], inner + outer[i], values + outer[i], INSERT_VALUES),
            "MatSetValues");
    }
    check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "assembly");
    check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "assembly");
  }

  void set_near_nullspace(Index n) {
    nullspace_stale_ = false;
    if (layout_ && layout_->size() == n) signorini::set_near_nullspace(A_, *layout_, padded_, rstart_, rend_);
  }

  void configure() {
    if (!ksp_) check(KSPCreate(PETSC_COMM_WORLD, &ksp_), "KSPCreate");
    check(KSPSetOperators(ksp_, A_, A_), "KSPSetOperators");
    if (configured_) return;
    configured_rtol_ = configure_ksp(ksp_, s_, symmetric_);
    configured_ = true;
  }

  LinearSolverSettings s_;
  std::shared_ptr<const UnknownLayout> layout_;
  bool symmetric_ = true, configured_ = false, nullspace_stale_ = true, sorted_ = true;
  Mat A_ = nullptr;
  Vec b_ = nullptr, x_ = nullptr, x_all_ = nullptr;
  VecScatter gather_ = nullptr;
  int size_ = 1, rank_ = 0;
  Index rstart_ = 0, rend_ = 0;  // this rank's rows
  KSP ksp_ = nullptr;
  Index padded_ = 0;
  int bs_ = 1, iterations_ = 0;
  Real tolerance_ = 0, configured_rtol_ = 0;  // set_tolerance; configure_ksp's
  std::vector<int> outer_, inner_;
  std::vector<PetscScalar> values_;  // A_'s values (one process, sorted rows: create_sequential)
  std::string failure_ = "failed";
};


// Several ranks, each assembling its own cells (AlgebraBackend's partitioned assembly): one
// distributed AIJ matrix. The cells are shared out by recursive coordinate bisection of their
// centroids (every rank computes the same partition from the same replicated mesh), and the
// nodes renumbered part after part, so that each rank owns a contiguous range of rows: the
// nodes of its cells not already taken by a lower rank, the multipliers and obstacle unknowns
// coupled mostly with its nodes, and identity rows that pad its rows to a multiple of the node
// block (number()).
// The permutation stays inside this class: the analysis sees its own numbering. Entries added
// into another rank's rows travel to it when the assembly ends (PETSc's stash). No rank holds
// the whole matrix; the vectors stay replicated (every rank runs the same Newton iterations).
class PetscBackend final : public AlgebraBackend, public GlobalMatrix {
 public:
  explicit PetscBackend(LinearSolverSettings s) : s_(std::move(s)) {
    start(s_, size_, rank_);
  }
  ~PetscBackend() override {
    if (ksp_) KSPDestroy(&ksp_);
    destroy();
  }
  std::string name() const override { return fmt::format("distributed over {} ranks", size_); }
  // PETSc's rows (number(): a rank's padding rows among them).
  Index owned_begin() const override { return rstart_; }
  Index owned_end() const override { return rend_; }
  int ranks() const override { return size_; }
  int rank() const override { return rank_; }
  void set_coordinates(const std::vector<Vec3>* X) override { X_ = X; }
  int cell_owner(const ElementBlock* block, Index e) const override {
    const auto it = part_.find(block);
    return it == part_.end() ? 0 : it->second[static_cast<size_t>(e)];
  }
  void keep_cells(const ElementBlock* block, const std::vector<char>& keep) override {
    const auto it = part_.find(block);
    if (it == part_.end() || it->second.size() != keep.size())
      throw Error("keep_cells: a block the partition has not seen, or a mask of the wrong size");
    std::vector<int> kept;
    for (size_t e = 0; e < keep.size(); ++e)
      if (keep[e]) kept.push_back(it->second[e]);
    it->second = std::move(kept);
  }

  // The pattern from this rank's cells, its own rows of the coupling groups and every owned
  // diagonal, gathered by a MATPREALLOCATOR (the cells' off-rank rows sent to their owners), then an AIJ matrix
  // preallocated exactly and filled with zeros on it.
  void build_pattern(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
                     const std::vector<std::vector<Index>>& couplings, Index total) override {
    destroy();
    missed_here_ = false;
    n_ = total;
    nodal_ = dofs.num_dofs();
    const int ndpn = std::max(dofs.dofs_per_node(), 1);
    bs_ = ndpn;
    if (part_.empty()) {
      if (s_.partition == "ptscotch") graph_partition(cells);
      else partition(cells);
    }
    const Index rows_before = rend_ - rstart_;
    number(dofs, cells, couplings);
    rstart_ = starts_[rank_];
    rend_ = starts_[rank_ + 1];
    // A rank's rows change in number when an extra unknown changes owner (a rolling body's
    // angle, coupled with the nodes in contact, as the contact moves across the cut): the
    // Krylov solver, set up on the old sizes, is made anew (PETSc refuses other sizes).
    int resized = ksp_ && rend_ - rstart_ != rows_before ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &resized, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
    if (resized) {
      KSPDestroy(&ksp_);
      configured_ = false;
    }
    Mat pre = preallocator(true);
    std::vector<PetscInt> idx;
    std::vector<PetscScalar> zeros;
    auto insert = [&]() {
      if (idx.empty()) return;
      zeros.assign(idx.size() * idx.size(), 0.0);
      const PetscInt k = static_cast<PetscInt>(idx.size());
      check(MatSetValues(pre, k, idx.data(), k, idx.data(), zeros.data(), INSERT_VALUES), "MatSetValues (pattern)");
    };
    for (const ElementBlock* b : cells) {
      const int npe = b->nodes_per_element();
      for (Index e = 0; e < b->size(); ++e) {
        if (cell_owner(b, e) != rank_) continue;
        idx.clear();
        const Index* c = b->element(e);
        for (int a = 0; a < npe; ++a)
          for (int d = 0; d < ndpn && dofs.has_dofs(c[a]); ++d) idx.push_back(row(dofs.dof(c[a], d)));
        insert();
      }
    }
    // The couplings outside the cells (contact constraints, obstacle and rotation unknowns):
    // every rank knows them all and enters the rows it owns (the assembly adds them alike).
    std::vector<PetscInt> owned_rows;
    for (const auto& group : couplings) {
      idx.clear();
      owned_rows.clear();
      for (Index i : group)
        if (i >= 0) {
          idx.push_back(row(i));
          if (idx.back() >= rstart_ && idx.back() < rend_) owned_rows.push_back(idx.back());
        }
      if (owned_rows.empty()) continue;
      zeros.assign(owned_rows.size() * idx.size(), 0.0);
      check(MatSetValues(pre, static_cast<PetscInt>(owned_rows.size()), owned_rows.data(), static_cast<PetscInt>(idx.size()),
                        idx.data(), zeros.data(), INSERT_VALUES),
            "MatSetValues (pattern)");
    }
    for (Index i = rstart_; i < rend_; ++i) {
      idx.assign(1, static_cast<PetscInt>(i));
      insert();
    }
    A_ = preallocated(pre, true);
    check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "assembly");
    check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "assembly");
    // Element blocks come column-major; an entry outside the pattern is stored (and reported
    // by missed(), so that the analysis rebuilds the pattern) rather than an error.
    MatSetOption(A_, MAT_ROW_ORIENTED, PETSC_FALSE);
    MatSetOption(A_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE);
    pattern_nonzeros_ = global_nonzeros();
    check(MatCreateVecs(A_, &x_, &b_), "MatCreateVecs");
    check(VecDuplicate(x_, &f_), "VecDuplicate");
    check(VecScatterCreateToAll(x_, &gather_, &x_all_), "VecScatterCreateToAll");
    dirty_ = false;
    nullspace_stale_ = true;
  }
  Index rows() const override { return n_; }
  Index nonzeros() const override { return pattern_nonzeros_; }

  void zero() override {
    ensure_assembled();
    check(MatZeroEntries(A_), "MatZeroEntries");
    extra_.clear();
    missed_here_ = false;
    // The padding rows' identity (number()).
    for (Index i = rstart_; i < rend_; ++i) {
      if (unknown_[i] >= 0) continue;
      const PetscInt row = static_cast<PetscInt>(i);
      const PetscScalar one = 1.0;
      check(MatSetValues(A_, 1, &row, 1, &row, &one, ADD_VALUES), "MatSetValues");
    }
    dirty_ = true;
  }
  // This rank's values (the diagonal and off-diagonal blocks of its rows, after assembly).
  void save_values() override {
    ensure_assembled();
    saved_.clear();
    for (Mat block : local_blocks()) {
      const PetscScalar* v = nullptr;
      const PetscInt nz = block_nonzeros(block);
      check(MatSeqAIJGetArrayRead(block, &v), "MatSeqAIJGetArrayRead");
      saved_.emplace_back(v, v + nz);
      MatSeqAIJRestoreArrayRead(block, &v);
    }
    has_saved_ = true;
  }
  bool restore_values() override {
    const std::vector<Mat> blocks = has_saved_ ? local_blocks() : std::vector<Mat>();
    int ok = has_saved_ && blocks.size() == saved_.size() ? 1 : 0;
    for (size_t k = 0; ok && k < blocks.size(); ++k)
      ok = block_nonzeros(blocks[k]) == static_cast<PetscInt>(saved_[k].size());
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
    if (!ok) return false;
    ensure_assembled();
    for (size_t k = 0; k < blocks.size(); ++k) {
      PetscScalar* v = nullptr;
      check(MatSeqAIJGetArrayWrite(blocks[k], &v), "MatSeqAIJGetArrayWrite");
      std::copy(saved_[k].begin(), saved_[k].end(), v);
      MatSeqAIJRestoreArrayWrite(blocks[k], &v);
    }
    dirty_ = true;  // the next assembly marks A changed (a preconditioner built on it is stale)
    extra_.clear();
    missed_here_ = false;
    return true;
  }
  GlobalMatrix& matrix() override { return *this; }
  void add(const Index* dofs, int n, const MatX& k) override {
    dirty_ = true;
    if (!in_cells_ && nodal_ < n_) {
      // Every rank keeps the entries beyond the nodes' DOFs (the contact multipliers' rows and
      // columns, obstacle and rotation unknowns): the condensation reads them.
#pragma omp critical(signorini_petsc_extra)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
          // Stored zeros too: a sticking node's normal and tangential multipliers are coupled in
          // the pattern only (friction's multiplier blocks, solve_condensed_blocks).
          if (dofs[a] >= 0 && dofs[b] >= 0 && (dofs[a] >= nodal_ || dofs[b] >= nodal_))
            extra_[{dofs[a], dofs[b]}] += k(a, b);
    }
    thread_local std::vector<PetscInt> idx, rows;
    idx.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) idx[i] = dofs[i] < 0 ? -1 : row(dofs[i]);  // negative: skipped by PETSc
    const PetscInt* r = idx.data();
    if (!in_cells_) {
      // Outside the cells (contact, loads, the stabilization) every rank runs this code alike:
      // each adds the rows it owns, so that no entry goes through PETSc's stash to another
      // rank (until session 47 rank 0 added them all and sent the others' rows).
      rows.assign(idx.begin(), idx.end());
      bool any = false;
      for (PetscInt& i : rows) {
        if (i < rstart_ || i >= rend_) i = -1;
        any = any || i >= 0;
      }
      if (!any) return;
      r = rows.data();
    }
    PetscErrorCode code = 0;
    // An entry outside the pattern (a contact constraint that met new DOFs) is not stored but
    // reported by missed(), as the serial GlobalSystem does: the analysis rebuilds the pattern
    // and assembles again, so nothing after it is added either. Stored, each new entry would
    // grow its row in place (an off-diagonal block's new column even disassembles the whole
    // matrix): a mortar pair with friction on 186k tet10 DOFs on 2 ranks spent more than 10
    // minutes there at its first line search (docs/performance.md, session 63). The same
    // between begin_cells and end_cells (since session 64; Nitsche's points shared out add
    // there) for the rows this rank owns; a row of another rank's goes through PETSc's stash
    // and is inserted at assembly, beyond this check: stored if new, and reported by missed()'s
    // count of nonzeros. (PETSc's errors come back as codes: ensure_petsc's handler.)
#pragma omp critical(signorini_petsc_add)
    if (!missed_here_) {
      MatSetOption(A_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE);
      code = MatSetValues(A_, n, r, n, idx.data(), k.data(), ADD_VALUES);
      MatSetOption(A_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_FALSE);
      if (code == PETSC_ERR_ARG_OUTOFRANGE) {
        missed_here_ = true;
        code = 0;
      }
    }
    check(code, "MatSetValues");
  }
  bool missed() const override {
    ensure_assembled();
    int here = missed_here_ ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &here, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
    return here > 0 || global_nonzeros() > pattern_nonzeros_;
  }
  void multiply(const VecX& x, VecX& y) const override {
    ensure_assembled();
    set_owned(b_, x);
    check(MatMult(A_, b_, x_), "MatMult");
    gather(x_, y);
  }
  Real mean_abs_diagonal() const override {
    ensure_assembled();
    check(MatGetDiagonal(A_, x_), "MatGetDiagonal");
    const PetscScalar* d = nullptr;
    VecGetArrayRead(x_, &d);
    Real sum = 0;
    for (Index i = rstart_; i < rend_; ++i)
      if (unknown_[i] >= 0) sum += std::abs(d[i - rstart_]);
    VecRestoreArrayRead(x_, &d);
    const_cast<PetscBackend*>(this)->sum_over_ranks(&sum, 1);
    return n_ > 0 ? sum / static_cast<Real>(n_) : 1.0;
  }
  void apply_dirichlet(const std::vector<char>& constrained, Real scale) override {
    ensure_assembled();
    std::vector<PetscInt> rows;
    for (Index i = rstart_; i < rend_; ++i)
      if (unknown_[i] >= 0 && constrained[unknown_[i]]) rows.push_back(static_cast<PetscInt>(i));
    check(MatZeroRowsColumns(A_, static_cast<PetscInt>(rows.size()), rows.data(), scale, nullptr, nullptr),
          "MatZeroRowsColumns");
    for (auto& [ij, v] : extra_)
      if (constrained[ij.first] || constrained[ij.second]) v = ij.first == ij.second ? scale : 0.0;
  }
  bool wants_layout() const override { return is_amg_solver(s_.type); }
  void set_layout(std::shared_ptr<const UnknownLayout> layout) override {
    layout_ = std::move(layout);
    nullspace_stale_ = true;
  }
  int last_iterations() const override { return iterations_; }
  std::string last_method() const override {
    if (direct_last_) return (direct_multipliers_ ? "contact multipliers kept, " : "after GMRES failed, ") + direct_method_;
    return std::string(condensed_last_ ? "condensed multipliers, " : "") +
           (condensed_last_ && refinements_ > 0 ? "gmres on the coupled rows over " : "") + describe_ksp(ksp_, s_);
  }

  std::string solve(const NewtonSolveRequest& q, const VecX& r, VecX& du) override {
    iterations_ = 0;
    tolerance_ = q.rtol;
    condensed_last_ = q.is_multiplier && is_amg_solver(s_.type);
    direct_last_ = false;
    if (q.is_multiplier && is_amg_solver(s_.type)) {
      if (!q.condense_contact)
        throw FatalModelError("linear solver " + s_.type + " on " + std::to_string(size_) +
                              " ranks cannot take the contact multipliers' saddle point (use enforcement: penalty, or "
                              "linear: mumps)");
      // `auto`'s algebraic multigrid (direct_fallback): a system the condensation cannot take
      // (no pivot, or the coupled rows' GMRES stalling), or whose condensed system's Krylov
      // solve fails (friction's blocks go to GMRES over GAMG at any size in 3D), goes whole to
      // MUMPS, as one process's `auto` takes an LU, for that solve and the next 1, 2, 4, ...
      // after each failure in a row. Every rank reaches the same decision (the condensation's
      // data are on every rank, the Krylov solver's verdict is collective).
      if (s_.direct_fallback && direct_skip_ > 0) {
        --direct_skip_;
        return solve_whole_direct(q, r, du);
      }
      // Once the forecast favours a factorization of the whole system (forecast_krylov):
      // MUMPS for the rest of the run.
      if (s_.direct_fallback && forecast_.favours_factorization()) return solve_whole_direct(q, r, du);
      try {
        std::string used = solve_condensed(q, r, du);
        direct_backoff_ = 1;
        forecast_krylov();
        return used;
      } catch (const CannotCondense& e) {
        if (!s_.direct_fallback) throw;
        return direct_after_failure(q, r, du, [&] {
          return fmt::format("    contact multipliers kept in the linear system (MUMPS on {} ranks): {}", size_, e.why);
        });
      } catch (const FatalModelError&) {
        throw;
      } catch (const SolverError& e) {
        if (!s_.direct_fallback) throw;
        return direct_after_failure(q, r, du, [&] {
          return fmt::format("    contact multipliers kept in the linear system (MUMPS on {} ranks for this solve and the "
                             "next {}): the condensed system's solve failed ({})",
                             size_, direct_skip_, e.what());
        });
      }
    }
    ensure_assembled();
    // `auto`'s algebraic multigrid on an unsymmetric displacement system (penalty friction,
    // follower pressure): where GMRES fails, MUMPS's LU for that solve and the next 1, 2, 4, ...
    // after each failure in a row, as one process's `auto` falls back to LU. The Krylov
    // solver's verdict is collective, so every rank takes the same branch.
    const bool fallback = s_.direct_fallback && !q.symmetric && !q.is_multiplier;
    if (fallback && (direct_skip_ > 0 || forecast_.favours_factorization())) {
      if (direct_skip_ > 0) --direct_skip_;
      return solve_whole_direct(q, r, du);
    }
    if (q.symmetric != symmetric_ || !ksp_) configured_ = false;
    symmetric_ = q.symmetric;
    MatSetOption(A_, MAT_SYMMETRIC, symmetric_ ? PETSC_TRUE : PETSC_FALSE);
    if (nullspace_stale_) {
      near_nullspace(A_);
      nullspace_stale_ = false;
    }
    set_owned(b_, r);
    try {
      krylov(A_, b_, x_);
      if (fallback) {
        direct_backoff_ = 1;
        forecast_krylov();
      }
    } catch (const FatalModelError&) {
      throw;
    } catch (const SolverError& e) {
      if (!fallback) throw;
      return direct_after_failure(q, r, du, [&] {
        return fmt::format("    {} failed on {} ranks ({}): MUMPS for this solve and the next {}", s_.type, size_, e.what(),
                           direct_skip_);
      });
    }
    gather(x_, du);
    if (!du.allFinite()) throw SolverError("linear solver " + s_.type + " gave a non-finite solution");
    return s_.type;
  }

  // Coupled rows: a pivot row's coefficients below a fraction of the pivot's are left out of the
  // elimination (solve_condensed): kCoupledDrop at most, less where the product can afford it.
  // Each kept entry k of closed row c's T row spreads J's row and column at c's pivot into row
  // and column k of T^T J T, about len(J_p) entries; the smallest drop of kCoupledDrops whose
  // estimated spread, summed over the closed rows, stays within kCoupledFill of J's nonzeros is
  // taken (the largest otherwise). Measured on 2 ranks with gamg (docs/performance.md, session
  // 68): the plane-strain cylinder on quad9 (mortar, rows of 24-32 entries, J's rows about 50)
  // spreads 0.08-0.24 at 1e-4, and its solves took a GMRES correction each at 1e-2 (3 over the
  // run at 1e-4: 830 -> 484 Krylov iterations, linear solve 9.8 -> 6.1 s); the tet10 quarter (tri6
  // rows of about 190 entries) spreads 0.33-0.36 at 1e-2 and 1.1-1.3 at 1e-4, where the product
  // took 2.7x as long for one correction less.
  static constexpr Real kCoupledDrop = 1e-2;
  static constexpr Real kCoupledDrops[] = {1e-4, 1e-3, kCoupledDrop};
  static constexpr Real kCoupledFill = 0.25;
  // solve_condensed's refusal: a structure it cannot eliminate, or a GMRES that stalled.
  struct CannotCondense : FatalModelError {
    CannotCondense(const std::string& message, std::string reason) : FatalModelError(message), why(std::move(reason)) {}
    std::string why;
  };
  // After a Krylov solve of `auto`'s algebraic multigrid at or below iterative_above (where it
  // goes only for unsymmetric 3D systems, at any size): recorded in the forecast of a
  // factorization (FactorizationForecast, linear_solver.hpp), which may send the next solves
  // whole to MUMPS (logged once; every rank records the same collective Krylov counts).
  void forecast_krylov() {
    if (!s_.direct_fallback || n_ > s_.iterative_above) return;
    if (forecast_.record(iterations_, n_, pattern_nonzeros_))
      log::info("{}", forecast_.describe(n_, pattern_nonzeros_, fmt::format("mumps on {} ranks", size_)));
  }
  // After a failure of `auto`'s algebraic multigrid: MUMPS on the whole system for this solve and
  // the next 1, 2, 4, ... after each failure in a row (direct_skip_, direct_backoff_), logged
  // with `message` (made once the skip is set).
  std::string direct_after_failure(const NewtonSolveRequest& q, const VecX& r, VecX& du,
                                   const std::function<std::string()>& message) {
    direct_skip_ = direct_backoff_;
    direct_backoff_ = std::min(2 * direct_backoff_, 64);
    log::info("{}", message());
    return solve_whole_direct(q, r, du);
  }
  // The whole system, multipliers and all, to MUMPS (LDL^T when symmetric, else LU), its own
  // Krylov object under the options prefix signorini_direct_ (the deck's raw options are for
  // the algebraic multigrid), destroyed after the solve so that its factor does not stay.
  std::string solve_whole_direct(const NewtonSolveRequest& q, const VecX& r, VecX& du) {
    ensure_assembled();
    condensed_last_ = false;
    direct_last_ = true;
    direct_multipliers_ = q.is_multiplier != nullptr;
    LinearSolverSettings direct = s_;
    direct.type = "mumps";
    KSP ksp = nullptr;
    check(KSPCreate(PETSC_COMM_WORLD, &ksp), "KSPCreate");
    KSPSetOptionsPrefix(ksp, "signorini_direct_");
    check(KSPSetOperators(ksp, A_, A_), "KSPSetOperators");
    MatSetOption(A_, MAT_SYMMETRIC, q.symmetric ? PETSC_TRUE : PETSC_FALSE);
    configure_ksp(ksp, direct, q.symmetric);
    set_owned(b_, r);
    direct_method_ = describe_ksp(ksp, direct);
    try {
      solve_or_throw(ksp, b_, x_, "mumps (the whole contact system)", [](PetscInt) {});
    } catch (...) {
      KSPDestroy(&ksp);
      throw;
    }
    KSPDestroy(&ksp);
    gather(x_, du);  // iterations_: a refused condensation's Krylov iterations, MUMPS adding none
    if (!du.allFinite()) throw SolverError("linear solver mumps gave a non-finite solution");
    return "mumps";
  }
  // Contact multipliers for algebraic multigrid: the elimination of condensed_solve.hpp on the
  // distributed matrix. Each closed multiplier row m, a_m . du = r_m, eliminates a pivot DOF p
  // (node-to-segment, node-to-node: the largest |a_mp| of a DOF no other closed row touches and
  // on whose row m acts; coupled rows: below), du = T u~ + z0, and T^T J T u~ = T^T (r - J z0)
  // goes to the Krylov solver (condensed_product: no rank forms more than its rows of J);
  // dl_m = (r_p - (J du)_p) / J_pm. T keeps the pivots' places (their rows and columns of the
  // reduced matrix empty, a decoupled diagonal added), so that the node blocks survive.
  // Throws CannotCondense where it cannot be made, or where the coupled rows' GMRES stalls.
  std::string solve_condensed(const NewtonSolveRequest& q, const VecX& r, VecX& du) {
    log::Timer timer;
    ensure_assembled();
    const std::vector<char>& mult = *q.is_multiplier;
    auto cannot = [&](const std::string& why) { return cannot_condense(why); };
    // SIGNORINI_REFUSE_CONDENSATION (the MPI test of `auto`'s fallback): every condensation refused.
    if (std::getenv("SIGNORINI_REFUSE_CONDENSATION")) throw cannot("refused (SIGNORINI_REFUSE_CONDENSATION)");
    // The multipliers' rows (a_m) and columns (b_m) and diagonals, from the entries kept.
    std::map<Index, std::vector<std::pair<Index, Real>>> row_of, col_of;
    std::map<Index, Real> diag;
    for (const auto& [ij, v] : extra_) {
      if (v == 0) continue;
      const auto [i, j] = ij;
      if (mult[i] && i == j) diag[i] = v;
      else if (mult[i] && mult[j]) return solve_condensed_blocks(q, r, du);  // friction's multiplier blocks
      else if (mult[i]) row_of[i].emplace_back(j, v);
      else if (mult[j]) col_of[j].emplace_back(i, v);
    }
    std::vector<Index> closed, open;
    std::map<Index, int> count;  // closed rows whose support holds the unknown
    for (Index m = nodal_; m < n_; ++m) {
      if (!mult[m]) continue;
      const bool has_u = row_of.count(m) > 0;
      if (has_u && diag.count(m)) return solve_condensed_blocks(q, r, du);  // a released direction's row
      if (!has_u) {
        if (!diag.count(m)) throw SolverError("a contact multiplier's row is empty: the system is singular");
        open.push_back(m);
        continue;
      }
      closed.push_back(m);
      for (const auto& [k, a] : row_of[m]) ++count[k];
    }
    std::map<Index, Real> column;  // sum over closed rows of |a_mk|
    for (Index m : closed)
      for (const auto& [k, a] : row_of[m]) column[k] += std::abs(a);
    std::map<Index, size_t> pivot_of;  // pivot unknown -> its closed row
    std::vector<Index> pivot(closed.size());
    std::vector<Real> ap(closed.size()), bp(closed.size());
    // Exact pivots: in each closed row the largest coefficient on a DOF no other closed row
    // touches, on whose row the multiplier acts and no other closed one does. Coupled rows
    // (mortar, segment_to_segment: no DOF belongs to one closed row only) take as condensed_solve
    // does the DOF where the row dominates its column, |a_mp| / sum over closed rows |a_m'p|,
    // and the couplings at the other rows' pivots are left out of the elimination (P = J - E);
    // flexible GMRES on J, preconditioned by it, then gives J's step (below).
    // Closed row c's pivot by `score` (|a_mk|, k) among the unknowns not yet a pivot, where its
    // coefficient is at least 0.1 of its largest, on whose row its multiplier acts, and that
    // `allowed` admits; the row's pivot at an earlier solve (of this pattern) while it still
    // qualifies, so that T's pattern holds (below). pivot[c], ap[c], bp[c] set; false if none.
    auto pick = [&](size_t c, const std::function<bool(Index)>& allowed, const std::function<Real(Real, Index)>& score) {
      const Index m = closed[c];
      Real amax = 0, best = 0;
      for (const auto& [k, a] : row_of[m]) amax = std::max(amax, std::abs(a));
      std::map<Index, Real> acts;  // J_km over the rows k where m acts
      for (const auto& [k, b] : col_of[m]) acts[k] = b;
      const auto before = last_pivot_.find(m);
      bool kept = false, found = false;
      for (const auto& [k, a] : row_of[m]) {
        if (std::abs(a) < 0.1 * amax || pivot_of.count(k) || !acts.count(k) || !allowed(k)) continue;
        const Real sc = score(std::abs(a), k);
        const bool earlier = before != last_pivot_.end() && before->second == k;
        if (kept || (!earlier && sc <= best)) continue;
        kept = earlier;
        best = sc;
        found = true;
        pivot[c] = k;
        ap[c] = a;
        bp[c] = acts[k];
      }
      return found;
    };
    auto choose_pivots = [&](bool coupled) {
      pivot_of.clear();
      for (size_t c = 0; c < closed.size(); ++c) {
        pivot[c] = -1;
        if (!pick(c, [&](Index k) { return coupled || count[k] == 1; },
                  [&](Real a, Index k) { return coupled ? a / column[k] : a; }))
          return false;
        pivot_of[pivot[c]] = c;
      }
      if (coupled) return true;
      for (const auto& [m, col] : col_of)  // a pivot's row must carry its own multiplier only
        for (const auto& [k, b] : col) {
          const auto it = pivot_of.find(k);
          if (it != pivot_of.end() && closed[it->second] != m && std::binary_search(closed.begin(), closed.end(), m))
            return false;
        }
      return true;
    };
    const bool coupled = !choose_pivots(false);
    if (coupled && !choose_pivots(true))
      throw cannot("a closed constraint has no DOF of its own (two-pass, self-contact, or a slave node that is also a "
                   "master node), nor one where it dominates the other closed constraints");
    // With coupled rows, T's pivot rows leave out the other rows' pivots and the coefficients
    // below kCoupledDrop of the pivot's (E: in closed multiplier rows only, so the elimination
    // stays exact for P and GMRES on J is unchanged; only P^-1's quality is at stake). Each
    // kept entry of a pivot's row fans row p of J T out into one more row of T^T J T: on CalculiX's fine
    // tet10 Hertz mesh (mortar, tri6 slave facets, about 190 entries per row, most of them
    // small: master nodes at the edge of a segment, the normal's variation) the product took
    // 10 s per Newton iteration with every entry and 2.4-3 s with this drop, for the same
    // Krylov iterations (docs/performance.md, session 55).
    // Coupled rows in levels (condensed_solve.hpp, coupled_rows_levels): a row's couplings at
    // the pivots of lower levels' rows are eliminated by substitution (the lowest level first;
    // the multipliers recovered from the highest level down), and the pivots of level 0 are
    // chosen again to dominate the other level-0 rows only, as in one process.
    LevelledRows lr(closed.size());
    std::vector<int>& level = lr.level;
    Real drop = kCoupledDrop;  // the coupled rows' drop (kCoupledDrops), chosen once the pivots are known
    auto acting = [&](Index k, Index m) {  // J(k, m)
      for (const auto& [i, b] : col_of[m])
        if (i == k) return b;
      return 0.0;
    };
    if (coupled) {
      auto levels = [&]() {
        std::vector<std::vector<std::pair<size_t, Real>>> coupling(closed.size());
        for (size_t c = 0; c < closed.size(); ++c)
          for (const auto& [k, a] : row_of[closed[c]]) {
            const auto it = k != pivot[c] && a != 0 ? pivot_of.find(k) : pivot_of.end();
            if (it != pivot_of.end() && acting(k, closed[c]) != 0)
              coupling[c].emplace_back(it->second, std::abs(a / ap[c]));
          }
        return coupled_rows_levels(coupling);
      };
      level = levels();
      std::map<Index, Real> column_parents;
      for (size_t c = 0; c < closed.size(); ++c)
        if (level[c] == 0)
          for (const auto& [k, a] : row_of[closed[c]]) column_parents[k] += std::abs(a);
      for (size_t c = 0; c < closed.size(); ++c)
        if (level[c] == 0) pivot_of.erase(pivot[c]);
      for (size_t c = 0; c < closed.size(); ++c) {
        if (level[c] > 0) continue;
        pick(c, [](Index) { return true; }, [&](Real a, Index k) { return a * a / column_parents[k]; });
        pivot_of[pivot[c]] = c;  // the first choice, free again, if none better
      }
      level = levels();
      drop = coupled_drop(closed, pivot, ap, row_of);
      for (size_t c = 0; c < closed.size(); ++c) {
        if (level[c] == 0) continue;
        for (const auto& [k, a] : row_of[closed[c]]) {
          const auto it = k != pivot[c] ? pivot_of.find(k) : pivot_of.end();
          if (it == pivot_of.end() || level[it->second] >= level[c] || std::abs(a) < drop * std::abs(ap[c]))
            continue;
          const Real b = acting(k, closed[c]);
          if (b == 0) continue;
          lr.substitute(c, it->second, a, b);
        }
      }
    }
    auto dropped = [&](size_t c, Index k, Real a) {
      if (!coupled) return false;
      if (std::abs(a) < drop * std::abs(ap[c])) return true;
      const auto it = pivot_of.find(k);
      return it != pivot_of.end() && it->second != c;  // another row's pivot: a parent's is substituted (elim)
    };
    // T's pivot rows over the unknowns, level by level (a row adds its parents' rows, scaled).
    std::vector<std::map<Index, Real>> elim(closed.size());
    for (size_t c : lr.order()) {
      for (const auto& [k, a] : row_of[closed[c]])
        if (k != pivot[c] && !dropped(c, k, a)) elim[c][k] -= a / ap[c];
      for (const auto& [q, a] : lr.parents_of[c])
        for (const auto& [k, t] : elim[q]) elim[c][k] -= a / ap[c] * t;
    }
    for (size_t c = 0; c < closed.size(); ++c) {
      last_pivot_[closed[c]] = pivot[c];
      auto& columns = pivot_columns_[pivot[c]];
      for (const auto& [k, t] : elim[c]) columns.insert(k);
    }
    // T, this rank's rows: identity, but empty for multipliers and the pivots' elimination.
    // A DOF that was a pivot at an earlier solve of this pattern keeps the columns it had then,
    // as stored zeros (its row is the identity again when its constraint opened): T's pattern
    // only grows while the active set shrinks and grows back, so that T^T J T is updated in
    // place and GAMG keeps its interpolation (on the 1.4M-DOF Hertz model the product anew
    // took 4-28 s per Newton iteration, in place about 1 s).
    const PetscInt nloc = static_cast<PetscInt>(rend_ - rstart_), ng = static_cast<PetscInt>(padded_);
    std::vector<PetscInt> d_nnz(static_cast<size_t>(nloc), 0), o_nnz(static_cast<size_t>(nloc), 0);
    // Row i of T (a PETSc row; every rank can build any of them from what it holds).
    auto t_row = [&](Index i, std::vector<std::pair<PetscInt, PetscScalar>>& rt) {
      rt.clear();
      const Index u = unknown_[i];
      const auto it = u >= 0 ? pivot_of.find(u) : pivot_of.end();
      // A stored zero on the diagonal of the multipliers' and pivots' rows, so that T^T J T
      // has their diagonal in its pattern (the decoupled diagonal below, added in place).
      if ((u >= 0 && mult[u]) || it != pivot_of.end()) rt.emplace_back(static_cast<PetscInt>(i), 0.0);
      if (u >= 0 && mult[u]) {
      } else if (it == pivot_of.end()) {
        rt.emplace_back(static_cast<PetscInt>(i), 1.0);
      } else {
        for (const auto& [k, t] : elim[it->second]) rt.emplace_back(row(k), t);
      }
      if (const auto pc = u >= 0 && !mult[u] ? pivot_columns_.find(u) : pivot_columns_.end(); pc != pivot_columns_.end())
        for (Index k : pc->second) rt.emplace_back(row(k), 0.0);
      // By column, the values before the stored zeros, one entry per column.
      std::stable_sort(rt.begin(), rt.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      rt.erase(std::unique(rt.begin(), rt.end(), [](const auto& x, const auto& y) { return x.first == y.first; }),
               rt.end());
    };
    std::vector<std::vector<std::pair<PetscInt, PetscScalar>>> rows_T(static_cast<size_t>(nloc));
    for (Index i = rstart_; i < rend_; ++i) {
      auto& rt = rows_T[i - rstart_];
      t_row(i, rt);
      for (const auto& [j, v] : rt) (j >= rstart_ && j < rend_ ? d_nnz : o_nnz)[i - rstart_]++;
    }
    // The rows of T that are not the identity's, on every rank (T^T J T reads them at A's
    // columns): multipliers, pivots, and former pivots with their stored zeros.
    TRows special;
    special.at.assign(static_cast<size_t>(padded_), -1);
    auto add_special = [&](Index u) {
      const Index i = row(u);
      if (special.at[i] >= 0) return;
      special.at[i] = static_cast<int>(special.rows.size());
      special.rows.emplace_back();
      t_row(i, special.rows.back());
    };
    for (Index m = nodal_; m < n_; ++m)
      if (mult[m]) add_special(m);
    for (const auto& [u, c] : pivot_of) add_special(u);
    for (const auto& [u, columns] : pivot_columns_) add_special(u);
    // The same T pattern as at the last solve on every rank: T's values and T^T J T updated in
    // place (and GAMG's interpolation reused); else both made anew.
    std::vector<PetscInt> pattern;
    for (const auto& rt : rows_T) {
      pattern.push_back(static_cast<PetscInt>(rt.size()));
      for (const auto& [j, v] : rt) pattern.push_back(j);
    }
    double t_symbolic = 0;  // the product's pattern (a new pattern only)
    int same = T_ && Kr_ && pattern == T_pattern_ ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
    if (!same) {
      // The Krylov solver holds the old product and GAMG's hierarchy built on it (a reference
      // each): released before the new product is formed, so that the two never coexist (on
      // the 1.4M-DOF Hertz model that overlap was about 1.5 GiB per rank). A new pattern gets
      // a new interpolation anyway; the solver is configured again from the settings.
      if (ksp_) KSPDestroy(&ksp_);
      configured_ = false;
      if (T_) MatDestroy(&T_);
      if (Z_) MatDestroy(&Z_);
      if (Kr_) MatDestroy(&Kr_);
      check(MatCreateAIJ(PETSC_COMM_WORLD, nloc, nloc, ng, ng, 0, d_nnz.data(), 0, o_nnz.data(), &T_), "MatCreateAIJ");
      check(MatSetBlockSize(T_, bs_), "MatSetBlockSize");
      T_pattern_ = std::move(pattern);
      // T^T J T's pattern: the product's entries gathered by a MATPREALLOCATOR.
      const double t_start = timer.seconds();
      Mat pre = preallocator(false);
      condensed_product(pre, special);
      Kr_ = preallocated(pre, false);
      // Every row holds its diagonal (J's, or T's stored zero), so the decoupled diagonal
      // below adds in place; an entry outside this pattern would be a mistake, not a malloc.
      MatSetOption(Kr_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE);
      t_symbolic = timer.seconds() - t_start;
    } else {
      check(MatZeroEntries(Kr_), "MatZeroEntries");
    }
    for (Index i = rstart_; i < rend_; ++i) {
      const PetscInt pi = static_cast<PetscInt>(i);
      for (const auto& [j, v] : rows_T[i - rstart_])
        check(MatSetValues(T_, 1, &pi, 1, &j, &v, INSERT_VALUES), "MatSetValues (T)");
    }
    check(MatAssemblyBegin(T_, MAT_FINAL_ASSEMBLY), "assembly (T)");
    check(MatAssemblyEnd(T_, MAT_FINAL_ASSEMBLY), "assembly (T)");
    const double t_plan = timer.seconds() - t_symbolic;
    condensed_product(Kr_, special);
    check(MatAssemblyBegin(Kr_, MAT_FINAL_ASSEMBLY), "assembly (T^T J T)");
    check(MatAssemblyEnd(Kr_, MAT_FINAL_ASSEMBLY), "assembly (T^T J T)");
    if (std::getenv("SIGNORINI_CHECK_CONDENSED_PRODUCT")) check_product(T_, nullptr, "T^T J T");
    const double t_ptap = timer.seconds();
    // The decoupled rows (pivots and multipliers): the mean magnitude of the diagonal.
    add_decoupled_diagonal(mult, [&](Index u) { return pivot_of.count(u) > 0; },
                           static_cast<Index>(closed.size() + open.size()));
    if (q.body_symmetric != symmetric_ || !ksp_) configured_ = false;
    symmetric_ = q.body_symmetric;
    MatSetOption(Kr_, MAT_SYMMETRIC, symmetric_ ? PETSC_TRUE : PETSC_FALSE);
    if (!same) near_nullspace(Kr_);
    // out = P^-1 rhs: z0, T^T (rhs - J z0) to the Krylov solver, out = T u~ + z0, and the closed
    // multipliers from their pivots' rows. (J and P = J - E agree on what is read: E sits in
    // the multipliers' rows, which T^T leaves out, and in closed multipliers' columns, where z0
    // and out are zero.)
    const double t_rhs = timer.seconds();
    double t_krylov = 0;
    refinements_ = 0;
    int inner = 0;  // Krylov iterations over the inner solves
    Vec w = nullptr, rr = nullptr;
    check(VecDuplicate(x_, &w), "VecDuplicate");
    check(VecDuplicate(x_, &rr), "VecDuplicate");
    auto apply = [&](const VecX& rhs, VecX& out) {
      VecX z0 = VecX::Zero(n_);
      for (Index m : open) z0(m) = rhs(m) / diag[m];
      lr.pivot_values(closed, pivot, ap, rhs, z0);
      set_owned(x_, z0);
      check(MatMult(A_, x_, w), "MatMult");  // J z0
      set_owned(b_, rhs);
      check(VecAYPX(w, -1.0, b_), "VecAYPX");  // rhs - J z0
      check(MatMultTranspose(T_, w, rr), "MatMultTranspose");
      const double t0 = timer.seconds();
      krylov(Kr_, rr, w);  // u~
      t_krylov += timer.seconds() - t0;
      inner += iterations_;
      check(MatMult(T_, w, rr), "MatMult");    // T u~
      check(VecAXPY(rr, 1.0, x_), "VecAXPY");  // + z0
      check(MatMult(A_, rr, w), "MatMult");    // J out
      VecX Jout;
      gather(rr, out);
      gather(w, Jout);
      lr.multipliers(closed, pivot, bp, rhs, Jout, out);
    };
    // Coupled rows: loose inner solves, and flexible GMRES on J to the Newton iteration's
    // forcing term (condensed_solve's constants, so that one process and several take the same
    // steps).
    refine_condensed(q, coupled, apply, r, du, "coupled contact rows (segment_to_segment, mortar)", w, rr, inner);
    log::debug("    condensed on {} ranks: {} closed, {} open{}; T {:.2f} s, T^T J T {:.2f} s ({}{}), diagonal {:.2f} s, Krylov {:.2f} s ({} iterations{}); this rank's peak memory {:.0f} MiB",
               size_, closed.size(), open.size(), coupled ? fmt::format(" (coupled rows, drop {:.0e})", drop) : "", t_plan, t_ptap - t_plan,
               same ? "updated in place" : "new pattern", same ? "" : fmt::format(", its pattern {:.2f} s", t_symbolic), t_rhs - t_ptap, t_krylov, inner,
               coupled ? fmt::format(", {} GMRES steps", refinements_) : "", log::peak_memory_mib());
    if (!du.allFinite()) throw SolverError("linear solver " + s_.type + " gave a non-finite solution");
    return "condensed+" + s_.type;
  }

  // Friction's multiplier blocks on the distributed matrix (multiplier_blocks.hpp; in one
  // process CondensedContactSolver::solve_blocks): every rank analyses the blocks alike from the
  // multipliers' rows and columns (extra_, whole on each), T's and Z's pivot rows and Delta's
  // entries follow, Z^T (J + Delta) T is formed by condensed_product (each rank its rows of J)
  // and goes to GMRES over the deck's algebraic multigrid. Throws CannotCondense where the
  // blocks have no pivots, or where GMRES on a barely slipping node's nearby matrix stalls.
  std::string solve_condensed_blocks(const NewtonSolveRequest& q, const VecX& r, VecX& du) {
    log::Timer timer;
    const std::vector<char>& mult = *q.is_multiplier;
    std::vector<Index> mlist;
    for (Index m = nodal_; m < n_; ++m)
      if (mult[m]) mlist.push_back(m);
    auto slot = [&](Index m) { return std::lower_bound(mlist.begin(), mlist.end(), m) - mlist.begin(); };
    std::vector<std::vector<std::pair<Index, Real>>> mrows(mlist.size()), mcols(mlist.size());
    for (const auto& [ij, v] : extra_) {
      const auto [i, j] = ij;
      if (mult[i]) mrows[slot(i)].emplace_back(j, v);
      else if (mult[j]) mcols[slot(j)].emplace_back(i, v);
    }
    const MultiplierBlocks mb = analyse_multiplier_blocks(n_, mult, mlist, mrows, mcols);
    decltype(mrows)().swap(mrows);
    decltype(mcols)().swap(mcols);
    if (!mb.why_not.empty()) throw cannot_condense(mb.why_not);
    const std::vector<Index>& pivot_of = mb.pivot_of;
    // Row i of T (z false) or Z (z true), PETSc's numbering: the identity's, empty with a stored
    // zero on the diagonal for a multiplier, a pivot's T_P or Z_P row over its block's other DOFs.
    auto t_row = [&](Index i, bool z, std::vector<std::pair<PetscInt, PetscScalar>>& rt) {
      rt.clear();
      const Index u = unknown_[i];
      const bool multiplier = u >= 0 && mult[u], pivot = u >= 0 && !multiplier && pivot_of[u] >= 0;
      if (multiplier || pivot) rt.emplace_back(static_cast<PetscInt>(i), 0.0);
      if (!multiplier && !pivot) rt.emplace_back(static_cast<PetscInt>(i), 1.0);
      if (pivot) {
        const MultiplierBlock& b = mb.blocks[static_cast<size_t>(pivot_of[u])];
        const Index a = std::find(b.pivot.begin(), b.pivot.end(), u) - b.pivot.begin();
        const std::vector<Index>& dofs = z ? b.bu : b.cu;
        const MatX& P = z ? b.Zp : b.Tp;
        for (size_t j = 0; j < dofs.size(); ++j)
          if (in_reduced_matrix(mb, b, a, z, j)) rt.emplace_back(row(dofs[j]), P(a, static_cast<Index>(j)));
      }
      std::stable_sort(rt.begin(), rt.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    };
    const PetscInt nloc = static_cast<PetscInt>(rend_ - rstart_), ng = static_cast<PetscInt>(padded_);
    std::vector<std::vector<std::pair<PetscInt, PetscScalar>>> rows_T(static_cast<size_t>(nloc)), rows_Z(rows_T.size()),
        delta(rows_T.size());
    std::vector<PetscInt> t_d(static_cast<size_t>(nloc), 0), t_o(t_d), z_d(t_d), z_o(t_d);
    for (Index i = rstart_; i < rend_; ++i) {
      const size_t l = static_cast<size_t>(i - rstart_);
      t_row(i, false, rows_T[l]);
      t_row(i, true, rows_Z[l]);
      for (const auto& [j, v] : rows_T[l]) (j >= rstart_ && j < rend_ ? t_d : t_o)[l]++;
      for (const auto& [j, v] : rows_Z[l]) (j >= rstart_ && j < rend_ ? z_d : z_o)[l]++;
    }
    // Delta's entries in this rank's rows, those of the reduced matrix (multiplier_blocks.hpp).
    for (size_t e = 0; e < mb.delta.size(); ++e) {
      const auto& [ij, v] = mb.delta[e];
      const PetscInt i = row(ij.first);
      if (i >= rstart_ && i < rend_ && mb.delta_in_reduced[e]) delta[static_cast<size_t>(i - rstart_)].emplace_back(row(ij.second), v);
    }
    // The rows of T and Z that are not the identity's, on every rank.
    TRows special, left;
    special.at.assign(static_cast<size_t>(padded_), -1);
    left.at.assign(static_cast<size_t>(padded_), -1);
    auto add_special = [&](Index u) {
      const Index i = row(u);
      if (special.at[i] >= 0) return;
      special.at[i] = static_cast<int>(special.rows.size());
      special.rows.emplace_back();
      t_row(i, false, special.rows.back());
      left.at[i] = static_cast<int>(left.rows.size());
      left.rows.emplace_back();
      t_row(i, true, left.rows.back());
    };
    for (Index m : mlist) add_special(m);
    for (const MultiplierBlock& b : mb.blocks)
      for (Index p : b.pivot) add_special(p);
    // The same pattern (T's, Z's and Delta's rows) as at the last solve on every rank: the
    // product is updated in place and GAMG keeps its interpolation; else all made anew. The
    // leading -2 tells this pattern from solve_condensed's.
    std::vector<PetscInt> pattern{-2};
    for (const auto* rows : {&rows_T, &rows_Z, &delta})
      for (const auto& rt : *rows) {
        pattern.push_back(static_cast<PetscInt>(rt.size()));
        for (const auto& [j, v] : rt) pattern.push_back(j);
      }
    int same = T_ && Z_ && Kr_ && pattern == T_pattern_ ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &same, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
    if (!same) {
      if (ksp_) KSPDestroy(&ksp_);
      configured_ = false;
      for (Mat* m : {&T_, &Z_, &Kr_})
        if (*m) MatDestroy(m);
      check(MatCreateAIJ(PETSC_COMM_WORLD, nloc, nloc, ng, ng, 0, t_d.data(), 0, t_o.data(), &T_), "MatCreateAIJ");
      check(MatCreateAIJ(PETSC_COMM_WORLD, nloc, nloc, ng, ng, 0, z_d.data(), 0, z_o.data(), &Z_), "MatCreateAIJ");
      check(MatSetBlockSize(T_, bs_), "MatSetBlockSize");
      check(MatSetBlockSize(Z_, bs_), "MatSetBlockSize");
      T_pattern_ = std::move(pattern);
      Mat pre = preallocator(false);
      condensed_product(pre, special, &left, &delta);
      Kr_ = preallocated(pre, false);
      MatSetOption(Kr_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE);
    } else {
      check(MatZeroEntries(Kr_), "MatZeroEntries");
    }
    for (Index i = rstart_; i < rend_; ++i) {
      const PetscInt pi = static_cast<PetscInt>(i);
      for (const auto& [j, v] : rows_T[static_cast<size_t>(i - rstart_)])
        check(MatSetValues(T_, 1, &pi, 1, &j, &v, INSERT_VALUES), "MatSetValues (T)");
      for (const auto& [j, v] : rows_Z[static_cast<size_t>(i - rstart_)])
        check(MatSetValues(Z_, 1, &pi, 1, &j, &v, INSERT_VALUES), "MatSetValues (Z)");
    }
    for (Mat m : {T_, Z_}) {
      check(MatAssemblyBegin(m, MAT_FINAL_ASSEMBLY), "assembly (T, Z)");
      check(MatAssemblyEnd(m, MAT_FINAL_ASSEMBLY), "assembly (T, Z)");
    }
    const double t_plan = timer.seconds();
    condensed_product(Kr_, special, &left, &delta);
    check(MatAssemblyBegin(Kr_, MAT_FINAL_ASSEMBLY), "assembly (Z^T (J + Delta) T)");
    check(MatAssemblyEnd(Kr_, MAT_FINAL_ASSEMBLY), "assembly (Z^T (J + Delta) T)");
    const double t_product = timer.seconds();
    if (std::getenv("SIGNORINI_CHECK_CONDENSED_PRODUCT")) check_product(Z_, &delta, "Z^T (J + Delta) T");
    add_decoupled_diagonal(mult, [&](Index u) { return pivot_of[u] >= 0; }, static_cast<Index>(mlist.size()) +
                           static_cast<Index>(std::count_if(pivot_of.begin(), pivot_of.end(), [](Index b) { return b >= 0; })));
    if (symmetric_ || !ksp_) configured_ = false;
    symmetric_ = false;
    MatSetOption(Kr_, MAT_SYMMETRIC, PETSC_FALSE);
    if (!same) near_nullspace(Kr_);
    // Delta v on the displacement rows, added into y (whole vectors, every rank alike).
    auto add_delta = [&](const VecX& v, VecX& y) {
      for (const auto& [ij, val] : mb.delta) y(ij.first) += val * v(ij.second);
      for (Index m : mlist) y(m) = 0;
    };
    double t_krylov = 0;
    refinements_ = 0;
    int inner = 0;
    Vec w = nullptr, rr = nullptr;
    check(VecDuplicate(x_, &w), "VecDuplicate");
    check(VecDuplicate(x_, &rr), "VecDuplicate");
    // out = P^-1 rhs (P = J but for clamped singular values).
    auto apply = [&](const VecX& rhs, VecX& out) {
      VecX rt, z0, y;
      blocks_reduce_rhs(mb, rhs, rt, z0);
      set_owned(x_, z0);
      check(MatMult(A_, x_, w), "MatMult");  // J z0
      gather(w, y);
      add_delta(z0, y);
      y = rt - y;
      set_owned(b_, y);
      check(MatMultTranspose(Z_, b_, rr), "MatMultTranspose");  // Z^T (r~ - (J + Delta) z0)
      const double t0 = timer.seconds();
      krylov(Kr_, rr, w);  // u~
      t_krylov += timer.seconds() - t0;
      inner += iterations_;
      check(MatMult(T_, w, rr), "MatMult");  // T u~
      gather(rr, out);
      out += z0;
      set_owned(x_, out);
      check(MatMult(A_, x_, w), "MatMult");
      VecX Ku;
      gather(w, Ku);
      add_delta(out, Ku);
      blocks_recover_multipliers(mb, rhs, rt, Ku, out);
    };
    refine_condensed(q, mb.approximate, apply, r, du, "a node barely slipping", w, rr, inner);
    log::debug("    condensed friction blocks on {} ranks: {} blocks{}; T and Z {:.2f} s, Z^T (J + Delta) T {:.2f} s ({}), "
               "Krylov {:.2f} s ({} iterations{}); this rank's peak memory {:.0f} MiB",
               size_, mb.blocks.size(), mb.released ? fmt::format(", {} dependent rows released", mb.released) : "",
               t_plan, t_product - t_plan, same ? "updated in place" : "new pattern", t_krylov, inner,
               refinements_ ? fmt::format(", {} GMRES steps", refinements_) : "", log::peak_memory_mib());
    if (!du.allFinite()) throw SolverError("linear solver " + s_.type + " gave a non-finite solution");
    return "condensed+" + s_.type;
  }
  // apply(r, du) and, when `refine`, flexible GMRES on J right-preconditioned by `apply` (its
  // inner Krylov solves loose) to the Newton iteration's forcing term; throws CannotCondense
  // naming `what` when GMRES stalls. The work vectors w and rr are released either way, and
  // iterations_ set to `inner`, the inner solves' Krylov iterations.
  void refine_condensed(const NewtonSolveRequest& q, bool refine, const std::function<void(const VecX&, VecX&)>& apply,
                        const VecX& r, VecX& du, const std::string& what, Vec& w, Vec& rr, const int& inner) {
    try {
      using C = CondensedContactSolver;
      const Real forcing = q.rtol > 0 ? q.rtol : s_.rtol;
      if (refine) tolerance_ = C::kInnerTolerance;
      apply(r, du);
      if (refine) {
        const Real rnorm = r.norm(), outer = std::max(C::kRefinementTolerance, forcing);
        const FlexibleGmresResult g = flexible_gmres([&](const VecX& v) -> VecX {
          VecX y;
          multiply(v, y);
          return y;
        }, apply, r, du, outer * rnorm, C::kMaxRefinements);
        refinements_ = g.steps;
        if (!(g.residual <= std::max(C::kRefinementAccepted, 2 * outer) * rnorm))
          throw cannot_condense(fmt::format("{}: GMRES on the condensed preconditioner stalls at {:.1e} of the "
                                            "right-hand side after {} steps",
                                            what, g.residual / rnorm, g.steps));
      }
    } catch (...) {
      VecDestroy(&w);
      VecDestroy(&rr);
      iterations_ = inner;
      throw;
    }
    VecDestroy(&w);
    VecDestroy(&rr);
    iterations_ = inner;
  }
  // The coupled rows' drop (kCoupledDrops, kCoupledFill): the same on every rank (each rank
  // counts the lengths of the pivots' rows it owns, summed over the ranks).
  Real coupled_drop(const std::vector<Index>& closed, const std::vector<Index>& pivot, const std::vector<Real>& ap,
                    const std::map<Index, std::vector<std::pair<Index, Real>>>& row_of) const {
    std::vector<double> length(closed.size(), 0.0);  // nonzeros in J's row at the pivot
    for (size_t c = 0; c < closed.size(); ++c) {
      const PetscInt p = row(pivot[c]);
      if (p < rstart_ || p >= rend_) continue;
      PetscInt nc = 0;
      check(MatGetRow(A_, p, &nc, nullptr, nullptr), "MatGetRow");
      length[c] = static_cast<double>(nc);
      check(MatRestoreRow(A_, p, &nc, nullptr, nullptr), "MatRestoreRow");
    }
    MPI_Allreduce(MPI_IN_PLACE, length.data(), static_cast<int>(length.size()), MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    const double budget = kCoupledFill * static_cast<double>(global_nonzeros());
    for (Real d : kCoupledDrops) {
      double spread = 0;
      for (size_t c = 0; c < closed.size(); ++c) {
        int kept = 0;
        for (const auto& [k, a] : row_of.at(closed[c])) kept += k != pivot[c] && a != 0 && std::abs(a) >= d * std::abs(ap[c]);
        spread += kept * length[c];
      }
      if (spread <= budget) return d;
    }
    return kCoupledDrop;
  }
  // SIGNORINI_CHECK_CONDENSED_PRODUCT (the MPI tests): the reduced matrix Kr_ applied to a dense
  // vector, as condensed_product formed it, against its factors applied in turn: L^T (J + Delta) T
  // with L = Z and Delta's entries for friction's blocks, L = T and no Delta for the contact
  // rows (`what` names the product). One dense vector with no zero entry tells the differences
  // an entrywise comparison would (but for cancellations of measure zero); until session 71 T^T J
  // T was compared with PETSc's MatPtAP entry by entry, whose product and MatAXPY on two patterns
  // took 7 of the 22 s of the tet10 mortar test's two ranks.
  // `delta`: Delta's entries in this rank's rows (PETSc's numbering, from rstart_), those the
  // product was formed with (null: none).
  void check_product(Mat left, const std::vector<std::vector<std::pair<PetscInt, PetscScalar>>>* delta,
                     const std::string& what) {
    VecX v(n_), tv, y;
    for (Index i = 0; i < n_; ++i) v(i) = std::sin(0.37 * static_cast<Real>(i) + 0.1);
    Vec w = nullptr;
    check(VecDuplicate(x_, &w), "VecDuplicate");
    VecX direct, steps;
    try {
      set_owned(x_, v);
      check(MatMult(Kr_, x_, w), "MatMult");
      gather(w, direct);
      check(MatMult(T_, x_, w), "MatMult");
      gather(w, tv);
      set_owned(x_, tv);
      check(MatMult(A_, x_, w), "MatMult");
      gather(w, y);
      if (delta)
        for (size_t l = 0; l < delta->size(); ++l)
          for (const auto& [j, val] : (*delta)[l]) y(unknown_[rstart_ + static_cast<Index>(l)]) += val * tv(unknown_[j]);
      set_owned(x_, y);
      check(MatMultTranspose(left, x_, w), "MatMultTranspose");
      gather(w, steps);
    } catch (...) {
      VecDestroy(&w);
      throw;
    }
    VecDestroy(&w);
    const Real diff = (direct - steps).norm(), norm = steps.norm();
    log::info("condensed product {} against its factors: relative difference {:.1e}", what, norm > 0 ? diff / norm : diff);
    if (!(diff <= 1e-12 * norm))
      throw FatalModelError(fmt::format("{} differs from its factors' product by {:.3e} (relative)", what,
                                        norm > 0 ? diff / norm : diff));
  }
  // The decoupled rows of the reduced matrix (multipliers, and pivots for which `pivot` holds):
  // the mean magnitude of the other rows' diagonal. `removed`: how many unknowns they are.
  void add_decoupled_diagonal(const std::vector<char>& mult, const std::function<bool(Index)>& pivot, Index removed) {
    check(MatGetDiagonal(Kr_, x_), "MatGetDiagonal");
    Real sum = 0;
    {
      const PetscScalar* d = nullptr;
      VecGetArrayRead(x_, &d);
      for (Index i = rstart_; i < rend_; ++i)
        if (unknown_[i] >= 0) sum += std::abs(d[i - rstart_]);
      VecRestoreArrayRead(x_, &d);
    }
    sum_over_ranks(&sum, 1);
    const Index kept = n_ - removed;
    const Real mean = kept > 0 && sum > 0 ? sum / static_cast<Real>(kept) : 1.0;
    {
      PetscScalar* d = nullptr;
      VecGetArray(x_, &d);
      for (Index i = rstart_; i < rend_; ++i) {
        const Index u = unknown_[i];
        d[i - rstart_] = u >= 0 && (mult[u] || pivot(u)) ? mean : 0.0;
      }
      VecRestoreArray(x_, &d);
    }
    check(MatDiagonalSet(Kr_, x_, ADD_VALUES), "MatDiagonalSet");
  }
  CannotCondense cannot_condense(const std::string& why) const {
    return CannotCondense("linear solver " + s_.type + " on " + std::to_string(size_) +
                              " ranks cannot condense this contact system: " + why +
                              " (use linear: mumps, or enforcement: penalty)",
                          why);
  }

  // A MATPREALLOCATOR of this rank's rows (entries added to it in any rows make the pattern),
  // and the AIJ matrix preallocated from it, zeros on its pattern (not yet assembled), of the
  // node block's block size. PETSc's preallocator keeps its pattern by blocks of its block size
  // and fills whole blocks: `exact` gives it block size 1 and the matrix its block size after
  // the preallocation, so that the pattern holds the entries added and no others. J's pattern is
  // exact (until session 69 the multipliers' rows and columns were filled by 3x3 blocks: 381 483
  // entries on 2 ranks against 359 721 in one process on the Hertz sphere at hc 0.015); the
  // condensed products keep node blocks (their updates in place add within them).
  Mat preallocator(bool exact) const {
    const PetscInt nloc = static_cast<PetscInt>(rend_ - rstart_), ng = static_cast<PetscInt>(padded_);
    Mat pre = nullptr;
    check(MatCreate(PETSC_COMM_WORLD, &pre), "MatCreate");
    check(MatSetType(pre, MATPREALLOCATOR), "MatSetType");
    check(MatSetSizes(pre, nloc, nloc, ng, ng), "MatSetSizes");
    check(MatSetBlockSize(pre, exact ? 1 : bs_), "MatSetBlockSize");
    check(MatSetUp(pre), "MatSetUp");
    return pre;
  }
  Mat preallocated(Mat& pre, bool exact) const {
    const PetscInt nloc = static_cast<PetscInt>(rend_ - rstart_), ng = static_cast<PetscInt>(padded_);
    check(MatAssemblyBegin(pre, MAT_FINAL_ASSEMBLY), "assembly (pattern)");
    check(MatAssemblyEnd(pre, MAT_FINAL_ASSEMBLY), "assembly (pattern)");
    Mat M = nullptr;
    check(MatCreate(PETSC_COMM_WORLD, &M), "MatCreate");
    check(MatSetSizes(M, nloc, nloc, ng, ng), "MatSetSizes");
    check(MatSetType(M, MATAIJ), "MatSetType");
    if (!exact) check(MatSetBlockSize(M, bs_), "MatSetBlockSize");
    check(MatPreallocatorPreallocate(pre, PETSC_TRUE, M), "MatPreallocatorPreallocate");
    if (exact) check(MatSetBlockSize(M, bs_), "MatSetBlockSize");
    MatDestroy(&pre);
    return M;
  }

  // The rows of T other than the identity's: at[i] indexes rows (-1: row i is e_i).
  struct TRows {
    std::vector<int> at;
    std::vector<std::vector<std::pair<PetscInt, PetscScalar>>> rows;
  };
  // Adds T^T J T into `target` (a MATPREALLOCATOR for the pattern, or the product itself):
  // (T^T J T)_ab = sum over i, k of T_ia J_ik T_kb, over this rank's rows i of J. T is the
  // identity but for a few thousand rows (`special`), so each row of J goes, times T, into
  // row i (most rows) or into the rows a of its T row; no rank forms more than J's rows it
  // owns, and no intermediate product is kept. Before session 37, PETSc's MatPtAP formed it
  // and kept its symbolic data for the update in place: about twice the product's own size
  // (94 MB against 48 MB per rank on the 148k-DOF Hertz model), and 4-9 s per new pattern
  // on the 1.4M one.
  // With friction's multiplier blocks (solve_condensed_blocks) the product is Z^T (J + Delta) T:
  // `left` holds Z's rows other than the identity's, `delta` Delta's entries in this rank's rows
  // (indexed from rstart_).
  void condensed_product(Mat target, const TRows& special, const TRows* left = nullptr,
                         const std::vector<std::vector<std::pair<PetscInt, PetscScalar>>>* delta = nullptr) {
    std::vector<std::pair<PetscInt, PetscScalar>> y;
    std::vector<PetscInt> cols_out;
    std::vector<PetscScalar> vals_out;
    for (PetscInt i = static_cast<PetscInt>(rstart_); i < static_cast<PetscInt>(rend_); ++i) {
      // T's row i is never empty: a multiplier's and a pivot's hold a stored zero on the
      // diagonal, so that their rows of the product keep it (the decoupled diagonal, below).
      const int si = special.at[static_cast<size_t>(i)];
      PetscInt nc = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* vals = nullptr;
      check(MatGetRow(A_, i, &nc, &cols, &vals), "MatGetRow");
      // y = (J T)_i., by column (J's pattern holds every diagonal, so y holds column i).
      y.clear();
      bool plain = true;
      for (PetscInt c = 0; c < nc; ++c) {
        const int sk = special.at[static_cast<size_t>(cols[c])];
        if (sk < 0) {
          y.emplace_back(cols[c], vals[c]);
        } else {
          plain = false;
          for (const auto& [b, t] : special.rows[static_cast<size_t>(sk)]) y.emplace_back(b, vals[c] * t);
        }
      }
      check(MatRestoreRow(A_, i, &nc, &cols, &vals), "MatRestoreRow");
      if (delta)
        for (const auto& [k, v] : (*delta)[static_cast<size_t>(i - rstart_)]) {
          plain = false;
          const int sk = special.at[static_cast<size_t>(k)];
          if (sk < 0) y.emplace_back(k, v);
          else
            for (const auto& [b, t] : special.rows[static_cast<size_t>(sk)]) y.emplace_back(b, v * t);
        }
      if (!plain) {  // by column, one entry per column
        std::sort(y.begin(), y.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
        size_t w = 0;
        for (size_t r = 0; r < y.size(); ++r) {
          if (w > 0 && y[w - 1].first == y[r].first) y[w - 1].second += y[r].second;
          else y[w++] = y[r];
        }
        y.resize(w);
      }
      cols_out.resize(y.size());
      vals_out.resize(y.size());
      auto add_row = [&](PetscInt a, PetscScalar t) {
        for (size_t r = 0; r < y.size(); ++r) {
          cols_out[r] = y[r].first;
          vals_out[r] = t * y[r].second;
        }
        check(MatSetValues(target, 1, &a, static_cast<PetscInt>(y.size()), cols_out.data(), vals_out.data(), ADD_VALUES),
              "MatSetValues (T^T J T)");
      };
      const TRows& l = left ? *left : special;
      const int li = left ? l.at[static_cast<size_t>(i)] : si;
      if (li < 0) add_row(i, 1.0);
      else
        for (const auto& [a, t] : l.rows[static_cast<size_t>(li)]) add_row(a, t);
    }
  }
  // GAMG's near-nullspace on `M` (the layout in PETSc's row order).
  void near_nullspace(Mat M) {
    if (s_.type != "gamg" || !layout_ || layout_->size() != n_) return;
    UnknownLayout permuted;
    permuted.dim = layout_->dim;
    permuted.axisymmetric = layout_->axisymmetric;
    permuted.x.assign(static_cast<size_t>(padded_), Vec3::Zero());
    permuted.comp.assign(static_cast<size_t>(padded_), -1);
    for (Index i = 0; i < n_; ++i) {
      permuted.x[row(i)] = layout_->x[i];
      permuted.comp[row(i)] = layout_->comp[i];
    }
    set_near_nullspace(M, permuted, padded_, rstart_, rend_);
  }

  // M x = b by the deck's KSP; throws SolverError when it fails.
  void krylov(Mat M, Vec b, Vec x) {
    if (!ksp_) check(KSPCreate(PETSC_COMM_WORLD, &ksp_), "KSPCreate");
    check(KSPSetOperators(ksp_, M, M), "KSPSetOperators");
    if (!configured_) {
      configured_rtol_ = configure_ksp(ksp_, s_, symmetric_);
      configured_ = true;
    }
    apply_tolerance(ksp_, s_, tolerance_, configured_rtol_);
    solve_or_throw(ksp_, b, x, s_.type, [&](PetscInt its) { iterations_ = s_.type == "mumps" ? 0 : static_cast<int>(its); });
  }
  // KSPSolve with `ksp`; `counted` gets its iterations, then a PETSc error or a diverged solve
  // throws SolverError naming `name`.
  static void solve_or_throw(KSP ksp, Vec b, Vec x, const std::string& name,
                             const std::function<void(PetscInt)>& counted) {
    KSPConvergedReason reason;
    MumpsFailure mumps;
    const PetscErrorCode code = solve_krylov(ksp, b, x, reason, &mumps);
    if (code != 0) {
      const char* text = nullptr;
      PetscErrorMessage(code, &text, nullptr);
      throw SolverError(fmt::format("linear solver {} failed ({})", name, text ? text : "unknown error"));
    }
    PetscInt its = 0;
    KSPGetIterationNumber(ksp, &its);
    counted(its);
    if (reason < 0)
      throw SolverError(fmt::format("linear solver {}: the Krylov solver did not converge ({} after {} iterations{})",
                                    name, KSPConvergedReasons[reason], its, failed_factor_words(mumps)));
  }

  void begin_cells() override {
    in_cells_ = true;
    dirty_ = true;
  }
  void end_cells() override { in_cells_ = false; }
  // Reduced on rank 0 in one fixed order, then broadcast: the same bits everywhere, which the
  // ranks' identical Newton decisions rely on.
  void sum_over_ranks(Real* v, Index n) override {
    const int count = static_cast<int>(n);
    if (rank_ == 0) MPI_Reduce(MPI_IN_PLACE, v, count, MPI_DOUBLE, MPI_SUM, 0, PETSC_COMM_WORLD);
    else MPI_Reduce(v, nullptr, count, MPI_DOUBLE, MPI_SUM, 0, PETSC_COMM_WORLD);
    MPI_Bcast(v, count, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
  }
  // The owners' sums: each rank sends its ghost rows' entries to their owners (point to
  // point, neighbours only), each owner adds them to its own in rank order (the same bits from
  // run to run), and the owned rows go to every rank through the solution's scatter. Until
  // session 50 the whole vector was reduced on rank 0 and broadcast (sum_over_ranks): 2 x n
  // values through rank 0 at every residual, against the cut's rows and one gather now.
  void sum_cell_forces(VecX& f) override {
    if (!f_ || f.size() != n_) {
      sum_over_ranks(f.data(), f.size());
      return;
    }
    // Entries outside the rows this rank's cells touch would be lost: a programming error,
    // reported by every rank alike (any_failed is collective: no rank left waiting below).
    std::string stray;
    for (Index i = 0; i < n_ && stray.empty(); ++i)
      if (!touched_[i] && f(i) != 0.0)
        stray = fmt::format("internal error: an internal force was added into unknown {}, outside the rows of the "
                            "rank's own cells", i);
    if (any_failed(stray)) throw FatalModelError(stray);
    // SIGNORINI_CHECK_CELL_SUMS (the MPI tests): the owners' sums against the whole vector's
    // reduction, at every call.
    VecX reduced;
    if (std::getenv("SIGNORINI_CHECK_CELL_SUMS")) {
      reduced = f;
      sum_over_ranks(reduced.data(), reduced.size());
    }
    std::vector<std::vector<PetscScalar>> out(static_cast<size_t>(size_)), in(static_cast<size_t>(size_));
    std::vector<MPI_Request> requests;
    requests.reserve(2 * static_cast<size_t>(size_));
    const int tag = 5150;
    for (int r = 0; r < size_; ++r) {
      if (mirror_of_[r].empty()) continue;
      in[r].resize(mirror_of_[r].size());
      requests.emplace_back();
      MPI_Irecv(in[r].data(), static_cast<int>(in[r].size()), MPIU_SCALAR, r, tag, PETSC_COMM_WORLD, &requests.back());
    }
    for (int r = 0; r < size_; ++r) {
      if (ghost_of_[r].empty()) continue;
      for (Index i : ghost_of_[r]) out[r].push_back(f(i));
      requests.emplace_back();
      MPI_Isend(out[r].data(), static_cast<int>(out[r].size()), MPIU_SCALAR, r, tag, PETSC_COMM_WORLD, &requests.back());
    }
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    for (int r = 0; r < size_; ++r)
      for (size_t k = 0; k < in[r].size(); ++k) f(mirror_of_[r][k]) += in[r][k];
    set_owned(f_, f);
    gather(f_, f);
    if (reduced.size()) {
      const Real scale = reduced.cwiseAbs().maxCoeff(), diff = (f - reduced).cwiseAbs().maxCoeff();
      log::debug("internal forces, owners' sums against the reduction: {:.1e} (relative)", scale > 0 ? diff / scale : diff);
      if (!(diff <= 1e-12 * scale))
        throw FatalModelError(fmt::format("the owners' sums of the internal forces differ from their reduction by {:.3e} "
                                          "(relative)", scale > 0 ? diff / scale : diff));
    }
  }
  bool any_failed(std::string& message) override {
    int first = message.empty() ? size_ : rank_;
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
    if (first == size_) return false;
    int length = static_cast<int>(message.size());
    MPI_Bcast(&length, 1, MPI_INT, first, PETSC_COMM_WORLD);
    message.resize(static_cast<size_t>(length));
    MPI_Bcast(message.data(), length, MPI_CHAR, first, PETSC_COMM_WORLD);
    if (rank_ != first) message += fmt::format(" (on rank {})", first);
    return true;
  }

 private:
  void destroy() {
    if (A_) MatDestroy(&A_);
    if (T_) MatDestroy(&T_);
    if (Z_) MatDestroy(&Z_);
    if (Kr_) MatDestroy(&Kr_);
    T_pattern_.clear();
    last_pivot_.clear();
    pivot_columns_.clear();
    saved_.clear();
    has_saved_ = false;
    if (b_) VecDestroy(&b_);
    if (x_) VecDestroy(&x_);
    if (x_all_) VecDestroy(&x_all_);
    if (f_) VecDestroy(&f_);
    if (gather_) VecScatterDestroy(&gather_);
  }
  // Collective: every rank calls it at the same point of the same code.
  void ensure_assembled() const {
    if (!dirty_) return;
    check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "assembly");
    check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "assembly");
    dirty_ = false;
  }
  Index global_nonzeros() const {
    MatInfo info;
    check(MatGetInfo(A_, MAT_GLOBAL_SUM, &info), "MatGetInfo");
    return static_cast<Index>(info.nz_used);
  }
  PetscInt row(Index unknown) const { return static_cast<PetscInt>(row_[unknown]); }
  // A's sequential blocks on this rank: its diagonal and off-diagonal parts (MPIAIJ), or A.
  std::vector<Mat> local_blocks() const {
    PetscBool mpi = PETSC_FALSE;
    PetscObjectTypeCompare(reinterpret_cast<PetscObject>(A_), MATMPIAIJ, &mpi);
    if (!mpi) return {A_};
    Mat d = nullptr, o = nullptr;
    check(MatMPIAIJGetSeqAIJ(A_, &d, &o, nullptr), "MatMPIAIJGetSeqAIJ");
    return {d, o};
  }
  static PetscInt block_nonzeros(Mat block) {
    MatInfo info;
    check(MatGetInfo(block, MAT_LOCAL, &info), "MatGetInfo");
    return static_cast<PetscInt>(info.nz_used);
  }
  void set_owned(Vec v, const VecX& full) const {
    PetscScalar* p = nullptr;
    check(VecGetArray(v, &p), "VecGetArray");
    for (Index i = rstart_; i < rend_; ++i) p[i - rstart_] = unknown_[i] >= 0 ? full(unknown_[i]) : 0.0;
    VecRestoreArray(v, &p);
  }
  void gather(Vec v, VecX& full) const {
    check(VecScatterBegin(gather_, v, x_all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
    check(VecScatterEnd(gather_, v, x_all_, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
    const PetscScalar* p = nullptr;
    check(VecGetArrayRead(x_all_, &p), "VecGetArrayRead");
    full.resize(n_);
    for (Index i = 0; i < n_; ++i) full(i) = p[row_[i]];
    VecRestoreArrayRead(x_all_, &p);
  }

  // Recursive coordinate bisection of the cells' centroids (Berger & Bokhari 1987): the
  // longest side of the parts' bounding box is cut where the ranks on either side get cells
  // in proportion to their number. Ties are broken by the cells' order, so that every rank
  // finds the same parts.
  void partition(const std::vector<const ElementBlock*>& cells) {
    struct Item {
      Vec3 c;
      Index order;
    };
    std::vector<Item> items;
    std::vector<std::pair<const ElementBlock*, Index>> where;
    for (const ElementBlock* b : cells) {
      part_[b].assign(static_cast<size_t>(b->size()), 0);
      const int npe = b->nodes_per_element();
      for (Index e = 0; e < b->size(); ++e) {
        Vec3 c = Vec3::Zero();
        if (X_) {
          for (int a = 0; a < npe; ++a) c += (*X_)[b->element(e)[a]];
          c /= npe;
        } else {
          c(0) = static_cast<Real>(items.size());  // no coordinates: the cells' order
        }
        items.push_back({c, static_cast<Index>(items.size())});
        where.emplace_back(b, e);
      }
    }
    std::function<void(size_t, size_t, int, int)> bisect = [&](size_t lo, size_t hi, int r0, int r1) {
      if (r1 - r0 == 1 || hi - lo < 2) {
        for (size_t k = lo; k < hi; ++k) part_[where[items[k].order].first][where[items[k].order].second] = r0;
        return;
      }
      Vec3 low = Vec3::Constant(std::numeric_limits<Real>::max()), high = -low;
      for (size_t k = lo; k < hi; ++k) {
        low = low.cwiseMin(items[k].c);
        high = high.cwiseMax(items[k].c);
      }
      int axis = 0;
      (high - low).maxCoeff(&axis);
      const int rm = (r0 + r1) / 2;
      const size_t mid = lo + (hi - lo) * static_cast<size_t>(rm - r0) / static_cast<size_t>(r1 - r0);
      std::nth_element(items.begin() + static_cast<std::ptrdiff_t>(lo), items.begin() + static_cast<std::ptrdiff_t>(mid),
                       items.begin() + static_cast<std::ptrdiff_t>(hi), [axis](const Item& a, const Item& b) {
                         return a.c(axis) < b.c(axis) || (a.c(axis) == b.c(axis) && a.order < b.order);
                       });
      bisect(lo, mid, r0, rm);
      bisect(mid, hi, rm, r1);
    };
    bisect(0, items.size(), 0, size_);
  }

  // Graph partition (PETSc's MatPartitioning with PT-Scotch, Pellegrini & Chevalier 2008):
  // the cells' dual graph, two cells adjacent when they share as many corner nodes as their
  // dimension (a facet of simplices, and of most hexahedra and quadrilaterals), cut into one
  // part per rank with the fewest cut edges. Each rank gives PETSc a contiguous block of the
  // graph's rows; the parts are gathered on every rank.
  void graph_partition(const std::vector<const ElementBlock*>& cells) {
    std::vector<std::pair<const ElementBlock*, Index>> where;
    for (const ElementBlock* b : cells) {
      part_[b].assign(static_cast<size_t>(b->size()), 0);
      for (Index e = 0; e < b->size(); ++e) where.emplace_back(b, e);
    }
    const Index n = static_cast<Index>(where.size());
    // The cells of each corner node (CSR).
    Index nodes = 0;
    for (const ElementBlock* b : cells)
      for (Index v : b->conn) nodes = std::max(nodes, v + 1);
    std::vector<Index> start(static_cast<size_t>(nodes) + 1, 0), list;
    for (int pass = 0; pass < 2; ++pass) {
      std::vector<Index> fill(start.begin(), start.end() - 1);
      if (pass == 1) list.resize(static_cast<size_t>(start.back()));
      for (Index c = 0; c < n; ++c) {
        const auto [b, e] = where[c];
        const int corners = element_info(b->type).num_corners;
        for (int a = 0; a < corners; ++a) {
          const Index v = b->element(e)[a];
          if (pass == 0) ++start[v + 1];
          else list[fill[v]++] = c;
        }
      }
      if (pass == 0)
        for (Index v = 0; v < nodes; ++v) start[v + 1] += start[v];
    }
    const Index lo = n * rank_ / size_, hi = n * (rank_ + 1) / size_;
    PetscInt *ia = nullptr, *ja = nullptr;
    std::vector<PetscInt> adjacency;
    std::vector<PetscInt> offsets{0};
    std::unordered_map<Index, int> shared;
    for (Index c = lo; c < hi; ++c) {
      const auto [b, e] = where[c];
      const ElementInfo& info = element_info(b->type);
      shared.clear();
      for (int a = 0; a < info.num_corners; ++a) {
        const Index v = b->element(e)[a];
        for (Index k = start[v]; k < start[v + 1]; ++k)
          if (list[k] != c) ++shared[list[k]];
      }
      const size_t first = adjacency.size();
      for (auto [d, count] : shared)
        if (count >= info.dim) adjacency.push_back(static_cast<PetscInt>(d));
      std::sort(adjacency.begin() + static_cast<std::ptrdiff_t>(first), adjacency.end());
      offsets.push_back(static_cast<PetscInt>(adjacency.size()));
    }
    // MatCreateMPIAdj takes arrays from PetscMalloc and frees them with the matrix.
    check(PetscMalloc1(offsets.size(), &ia), "PetscMalloc");
    check(PetscMalloc1(std::max<size_t>(adjacency.size(), 1), &ja), "PetscMalloc");
    std::copy(offsets.begin(), offsets.end(), ia);
    std::copy(adjacency.begin(), adjacency.end(), ja);
    Mat graph = nullptr;
    check(MatCreateMPIAdj(PETSC_COMM_WORLD, static_cast<PetscInt>(hi - lo), static_cast<PetscInt>(n), ia, ja, nullptr,
                          &graph),
          "MatCreateMPIAdj");
    MatPartitioning mp = nullptr;
    IS mine = nullptr, all = nullptr;
    check(MatPartitioningCreate(PETSC_COMM_WORLD, &mp), "MatPartitioningCreate");
    check(MatPartitioningSetAdjacency(mp, graph), "MatPartitioningSetAdjacency");
    check(MatPartitioningSetNParts(mp, size_), "MatPartitioningSetNParts");
    check(MatPartitioningSetType(mp, MATPARTITIONINGPTSCOTCH), "MatPartitioningSetType");
    check(MatPartitioningApply(mp, &mine), "MatPartitioningApply (PT-Scotch)");
    check(ISAllGather(mine, &all), "ISAllGather");
    const PetscInt* p = nullptr;
    check(ISGetIndices(all, &p), "ISGetIndices");
    for (Index c = 0; c < n; ++c) part_[where[c].first][where[c].second] = static_cast<int>(p[c]);
    ISRestoreIndices(all, &p);
    ISDestroy(&all);
    ISDestroy(&mine);
    MatPartitioningDestroy(&mp);
    MatDestroy(&graph);
  }

  // PETSc's numbering: a node block belongs to the lowest rank among its cells' (nodes in no
  // cell: the last rank); an unknown after the nodes' (a contact multiplier, an obstacle's or a
  // turning body's unknown) to the rank owning most of the node DOFs it is coupled with (the
  // coupling groups holding it; ties: the lower rank; none: the last rank), so that a
  // multiplier's row lies with its slave node's and its master's (until session 69 all of them
  // were the last rank's). Each rank's rows: its node blocks in the analysis' order, then its
  // extra unknowns in the analysis' order, then identity rows up to a multiple of the node
  // block (PETSc's block size divides each rank's rows).
  void number(const DofMap& dofs, const std::vector<const ElementBlock*>& cells,
              const std::vector<std::vector<Index>>& couplings) {
    const int ndpn = bs_;
    const Index slots = dofs.num_dofs() / ndpn;
    // The owners come from the whole mesh's cells, at the first pattern: later patterns may
    // see a rank's own cells only (keep_cells), and the rows keep their owners.
    if (static_cast<Index>(slot_owner_.size()) != slots) {
      std::vector<int> owner(static_cast<size_t>(slots), size_ - 1), last(static_cast<size_t>(slots), -1);
      for (const ElementBlock* b : cells)
        for (Index e = 0; e < b->size(); ++e) {
          const int r = cell_owner(b, e);
          const Index* c = b->element(e);
          for (int a = 0; a < b->nodes_per_element(); ++a)
            if (dofs.has_dofs(c[a])) {
              const Index k = dofs.dof(c[a], 0) / ndpn;
              owner[k] = std::min(owner[k], r);
              last[k] = std::max(last[k], r);
            }
        }
      // The nodes on a cut (in the cells of two ranks or more): the rows whose entries travel.
      Index cut = 0;
      for (Index k = 0; k < slots; ++k) cut += last[k] > owner[k];
      log::debug("cells shared out by {}: {} of {} nodes on a cut", s_.partition, cut, slots);
      slot_owner_ = std::move(owner);
    }
    const std::vector<int>& owner = slot_owner_;
    const Index first_extra = slots * ndpn;
    std::vector<int> extra_owner(static_cast<size_t>(n_ - first_extra), size_ - 1);
    {
      std::vector<std::map<int, Index>> votes(extra_owner.size());
      std::map<int, Index> group_votes;
      for (const auto& group : couplings) {
        group_votes.clear();
        for (Index i : group)
          if (i >= 0 && i < first_extra) ++group_votes[owner[i / ndpn]];
        for (Index i : group)
          if (i >= first_extra && i < n_)
            for (const auto& [r, count] : group_votes) votes[i - first_extra][r] += count;
      }
      for (size_t x = 0; x < votes.size(); ++x) {
        Index most = 0;
        for (const auto& [r, count] : votes[x])  // by rank, ascending: ties keep the lower
          if (count > most) most = count, extra_owner[x] = r;
      }
    }
    std::vector<Index> slot(static_cast<size_t>(slots), -1);
    row_.assign(static_cast<size_t>(n_), -1);
    Index next = 0;
    starts_.assign(static_cast<size_t>(size_) + 1, 0);
    for (int r = 0; r < size_; ++r) {
      starts_[r] = next;
      for (Index k = 0; k < slots; ++k)
        if (owner[k] == r) slot[k] = next / ndpn, next += ndpn;
      for (size_t x = 0; x < extra_owner.size(); ++x)
        if (extra_owner[x] == r) row_[first_extra + static_cast<Index>(x)] = next++;
      next = (next + ndpn - 1) / ndpn * ndpn;
    }
    starts_[size_] = next;
    padded_ = next;
    unknown_.assign(static_cast<size_t>(padded_), -1);
    for (Index i = 0; i < n_; ++i) {
      if (i < first_extra) row_[i] = slot[i / ndpn] * ndpn + i % ndpn;
      unknown_[row_[i]] = i;
    }
    if (first_extra < n_) {
      std::vector<Index> held(static_cast<size_t>(size_), 0);
      for (int r : extra_owner) ++held[r];
      log::debug("the {} unknowns after the nodes' held by the ranks: {}", n_ - first_extra, fmt::join(held, ", "));
    }
    find_ghosts(dofs, cells);
  }
  // The rows this rank's cells add into (touched_), those of them another rank owns (its
  // ghosts, ghost_of_[owner]), and this rank's rows that each other rank's cells add into
  // (mirror_of_[rank], told by that rank): sum_cell_forces()' lists, in the analysis' unknowns,
  // ascending. Collective.
  void find_ghosts(const DofMap& dofs, const std::vector<const ElementBlock*>& cells) {
    touched_.assign(static_cast<size_t>(n_), 0);
    for (const ElementBlock* b : cells)
      for (Index e = 0; e < b->size(); ++e) {
        if (cell_owner(b, e) != rank_) continue;
        const Index* c = b->element(e);
        for (int a = 0; a < b->nodes_per_element(); ++a)
          for (int d = 0; d < bs_ && dofs.has_dofs(c[a]); ++d) touched_[dofs.dof(c[a], d)] = 1;
      }
    ghost_of_.assign(static_cast<size_t>(size_), {});
    for (Index i = 0; i < n_; ++i) {
      if (!touched_[i]) continue;
      const int owner = static_cast<int>(std::upper_bound(starts_.begin(), starts_.end(), row_[i]) - starts_.begin()) - 1;
      if (owner != rank_) ghost_of_[owner].push_back(i);
    }
    std::vector<int> send(static_cast<size_t>(size_)), recv(static_cast<size_t>(size_)), sdispl(send), rdispl(recv);
    for (int r = 0; r < size_; ++r) send[r] = static_cast<int>(ghost_of_[r].size());
    MPI_Alltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, PETSC_COMM_WORLD);
    std::vector<Index> out, in;
    for (int r = 0; r < size_; ++r) {
      sdispl[r] = static_cast<int>(out.size());
      out.insert(out.end(), ghost_of_[r].begin(), ghost_of_[r].end());
      rdispl[r] = r ? rdispl[r - 1] + recv[r - 1] : 0;
    }
    in.resize(static_cast<size_t>(rdispl[size_ - 1] + recv[size_ - 1]));
    MPI_Alltoallv(out.data(), send.data(), sdispl.data(), MPI_INT64_T, in.data(), recv.data(), rdispl.data(), MPI_INT64_T,
                  PETSC_COMM_WORLD);
    mirror_of_.assign(static_cast<size_t>(size_), {});
    Index ghosts = 0;
    for (int r = 0; r < size_; ++r) {
      mirror_of_[r].assign(in.begin() + rdispl[r], in.begin() + rdispl[r] + recv[r]);
      ghosts += static_cast<Index>(ghost_of_[r].size());
    }
    log::debug("rank {}: {} ghost rows of its cells, owned by other ranks", rank_, ghosts);
  }

  LinearSolverSettings s_;
  std::shared_ptr<const UnknownLayout> layout_;
  int size_ = 1, rank_ = 0, bs_ = 1, iterations_ = 0;
  bool condensed_last_ = false;  // the last solve condensed the contact multipliers
  int refinements_ = 0;          // its flexible GMRES steps (coupled rows; 0 when the elimination is exact)
  bool direct_last_ = false;     // the last solve took the whole system to MUMPS (solve_whole_direct)
  bool direct_multipliers_ = false;  // ... with contact multipliers (else after GMRES failed)
  std::string direct_method_;
  int direct_skip_ = 0, direct_backoff_ = 1;  // solves left whole after a failed condensation, and the next run's length
  FactorizationForecast forecast_;  // forecast_krylov()
  Real tolerance_ = 0;  // the Newton iteration's forcing term (NewtonSolveRequest::rtol)
  Real configured_rtol_ = 0;  // configure_ksp's
  Index n_ = 0, padded_ = 0, rstart_ = 0, rend_ = 0, pattern_nonzeros_ = 0;
  std::vector<Index> starts_;               // first PETSc row of each rank (and the size)
  std::vector<Index> row_, unknown_;         // the analysis' unknown -> PETSc row, and back
  std::vector<char> touched_;                // find_ghosts(): the rows this rank's cells add into
  std::vector<std::vector<Index>> ghost_of_, mirror_of_;  // ... and those another rank owns, or it adds into
  const std::vector<Vec3>* X_ = nullptr;     // the nodes' reference coordinates
  std::unordered_map<const ElementBlock*, std::vector<int>> part_;  // each cell's rank
  Index nodal_ = 0;                          // the nodes' DOFs (the unknowns before the extras)
  std::map<std::pair<Index, Index>, Real> extra_;  // entries in an extra unknown's row or column
  std::vector<std::vector<PetscScalar>> saved_;  // save_values(): local_blocks()' values
  std::vector<int> slot_owner_;                  // number(): each node block's rank
  bool has_saved_ = false;
  std::map<Index, Index> last_pivot_;               // closed multiplier row -> its pivot at the last solve
  std::map<Index, std::set<Index>> pivot_columns_;  // pivot DOF -> the other DOFs of its T row, so far
  std::vector<PetscInt> T_pattern_;          // T's pattern, this rank's rows (count, columns)
  Mat A_ = nullptr, T_ = nullptr, Kr_ = nullptr;  // J; the condensation's T and T^T J T
  Mat Z_ = nullptr;  // friction's multiplier blocks: the left factor, Z^T (J + Delta) T
  Vec b_ = nullptr, x_ = nullptr, x_all_ = nullptr;
  Vec f_ = nullptr;  // sum_cell_forces(): the owned rows
  VecScatter gather_ = nullptr;
  KSP ksp_ = nullptr;
  bool symmetric_ = true, configured_ = false, nullspace_stale_ = true, in_cells_ = false;
  bool missed_here_ = false;  // an entry outside the pattern, dropped since the last zero() (add)
  mutable bool dirty_ = false;
};
}  // namespace

int petsc_world_size() {
  PetscBool done = PETSC_FALSE;
  PetscInitialized(&done);
  if (!done) return 1;
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}

MpiInfo start_petsc_if_launched_by_mpi() {
  MpiInfo info;
  info.size = launched_ranks();
  if (info.size <= 1) return info;  // PETSc starts later, on first use
  ensure_petsc();
  MPI_Comm_size(PETSC_COMM_WORLD, &info.size);
  MPI_Comm_rank(PETSC_COMM_WORLD, &info.rank);
  return info;
}

std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings& settings) {
  return std::make_unique<PetscKsp>(settings);
}

std::unique_ptr<AlgebraBackend> make_petsc_backend(const LinearSolverSettings& settings) {
  return std::make_unique<PetscBackend>(settings);
}

namespace {
class MpiRankExchange final : public RankExchange {
  // Tests the request, sleeping in between (50 us at first, doubling up to 20 ms).
  static void wait_asleep(MPI_Request& request) {
    int done = 0;
    for (useconds_t pause = 50;; pause = std::min<useconds_t>(2 * pause, 20000)) {
      MPI_Test(&request, &done, MPI_STATUS_IGNORE);
      if (done) return;
      ::usleep(pause);
    }
  }

 public:
  MpiRankExchange() {
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
    MPI_Comm_size(PETSC_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> allgather(const std::string& mine) const override {
    // The counts first, then the bytes (int counts: a rank's share stays far below 2 GB).
    if (mine.size() > static_cast<size_t>(std::numeric_limits<int>::max()))
      throw SolverError(fmt::format("rank {}: {} bytes to share with the other ranks, more than MPI's counts take",
                                    rank_, mine.size()));
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(size_), offsets(size_ + 1, 0);
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, PETSC_COMM_WORLD);
    for (int r = 0; r < size_; ++r) {
      if (offsets[r] > std::numeric_limits<int>::max() - counts[r])
        throw SolverError("the ranks' shares together exceed MPI's counts (2 GB)");
      offsets[r + 1] = offsets[r] + counts[r];
    }
    std::string all(static_cast<size_t>(offsets[size_]), '\0');
    MPI_Allgatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), offsets.data(), MPI_CHAR,
                   PETSC_COMM_WORLD);
    std::vector<std::string> out(size_);
    for (int r = 0; r < size_; ++r) out[r] = all.substr(offsets[r], counts[r]);
    return out;
  }
  void broadcast(std::string& bytes, int root) const override {
    // The size first, then the bytes in pieces that MPI's int counts take. The ranks wait
    // asleep (a blocking MPI_Bcast spins: while rank 0 meshes for minutes the others would take
    // the cores its gmsh runs on, when the ranks outnumber them).
    unsigned long long size = bytes.size();
    MPI_Request request;
    MPI_Ibcast(&size, 1, MPI_UNSIGNED_LONG_LONG, root, PETSC_COMM_WORLD, &request);
    wait_asleep(request);
    bytes.resize(static_cast<size_t>(size));
    constexpr size_t piece = size_t{1} << 30;
    for (size_t at = 0; at < bytes.size(); at += piece) {
      MPI_Ibcast(bytes.data() + at, static_cast<int>(std::min(piece, bytes.size() - at)), MPI_CHAR, root,
                 PETSC_COMM_WORLD, &request);
      wait_asleep(request);
    }
  }

 private:
  int rank_ = 0, size_ = 1;
};
}  // namespace

std::unique_ptr<RankExchange> make_rank_exchange() {
  if (petsc_world_size() <= 1) return nullptr;
  return std::make_unique<MpiRankExchange>();
}

int petsc_max_over_ranks(int value) {
  if (petsc_world_size() > 1) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  return value;
}

void abort_all_ranks(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);  // not reached
}

void start_petsc() { ensure_petsc(); }

void finalize_petsc() {
  if (!g_started_here) return;
  PetscFinalize();
  g_started_here = false;
}

}  // namespace signorini
