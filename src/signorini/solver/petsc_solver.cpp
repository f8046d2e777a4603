#include "signorini/solver/petsc_solver.hpp"

#include <petscksp.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "signorini/core/error.hpp"

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

class PetscKsp final : public LinearSolver {
 public:
  explicit PetscKsp(LinearSolverSettings s) : s_(std::move(s)) {
    ensure_petsc();
    if (!s_.options.empty()) check(PetscOptionsInsertString(nullptr, s_.options.c_str()), "reading the options");
    MPI_Comm_size(PETSC_COMM_WORLD, &size_);
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
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
  std::string failure() const override { return failure_; }

  bool factorize(const SparseMatrix& a) override {
    try {
      copy_matrix(a);
      configure();
      check(KSPSetUp(ksp_), "the preconditioner's setup");
      PCFailedReason reason = PC_NOERROR;
      PC pc = nullptr;
      KSPGetPC(ksp_, &pc);
      PCGetFailedReason(pc, &reason);
      if (reason != PC_NOERROR) {
        failure_ = fmt::format("the preconditioner's setup failed ({})", PCFailedReasons[reason]);
        return false;
      }
      return true;
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
      check(KSPSolve(ksp_, b_, x_), "KSPSolve");
      KSPConvergedReason reason;
      KSPGetConvergedReason(ksp_, &reason);
      PetscInt its = 0;
      KSPGetIterationNumber(ksp_, &its);
      iterations_ = s_.type == "mumps" ? 0 : static_cast<int>(its);  // a direct solve: no Krylov iterations
      if (reason < 0) {
        failure_ = fmt::format("the Krylov solver did not converge ({} after {} iterations)",
                               KSPConvergedReasons[reason], its);
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
      return x.allFinite();
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
    const bool same = A_ && np == padded_ && bs == bs_ && std::equal(outer, outer + n + 1, outer_.begin(), outer_.end()) &&
                      std::equal(inner, inner + nnz, inner_.begin(), inner_.end());
    if (!same) {
      destroy_system();
      outer_.assign(outer, outer + n + 1);
      inner_.assign(inner, inner + nnz);
      sorted_ = true;  // PETSc keeps each row's columns sorted
      for (Index i = 0; i < n && sorted_; ++i)
        sorted_ = std::is_sorted(inner + outer[i], inner + outer[i + 1]);
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

  // One process: a sequential AIJ matrix from the padded CSR arrays (identity rows after the
  // last), values included.
  void create_sequential(Index n, const Real* values) {
    const Index nnz = outer_[n];
    std::vector<PetscInt> i_pad(outer_.begin(), outer_.end()), j_pad(inner_.begin(), inner_.end());
    std::vector<PetscScalar> v_pad(values, values + nnz);
    for (Index i = n; i < padded_; ++i) {
      j_pad.push_back(static_cast<PetscInt>(i));
      v_pad.push_back(1.0);
      i_pad.push_back(static_cast<PetscInt>(j_pad.size()));
    }
    check(MatCreate(PETSC_COMM_SELF, &A_), "MatCreate");
    check(MatSetSizes(A_, padded_, padded_, padded_, padded_), "MatSetSizes");
    check(MatSetType(A_, MATSEQAIJ), "MatSetType");
    check(MatSetBlockSize(A_, bs_), "MatSetBlockSize");
    check(MatSeqAIJSetPreallocationCSR(A_, i_pad.data(), j_pad.data(), v_pad.data()), "MatSeqAIJSetPreallocationCSR");
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

  // The rigid-body modes of the layout's displacement unknowns, orthonormalized (modified
  // Gram-Schmidt): translations, and rotations about the centroid (one in 2D, three in 3D);
  // axisymmetric: the axial translation only (a radial motion strains the hoops).
  void set_near_nullspace(Index n) {
    nullspace_stale_ = false;
    if (!layout_ || layout_->size() != n) return;
    const int dim = layout_->dim;
    Vec3 c = Vec3::Zero();
    Index count = 0;
    for (Index i = 0; i < n; ++i)
      if (layout_->comp[i] == 0) c += layout_->x[i], ++count;
    if (count) c /= static_cast<Real>(count);
    std::vector<VecX> modes;
    auto translation = [&](int d) {
      VecX v = VecX::Zero(padded_);
      for (Index i = 0; i < n; ++i) v(i) = layout_->comp[i] == d ? 1.0 : 0.0;
      return v;
    };
    auto rotation = [&](int p, int q) {  // rotation in the (p, q) plane: u_p = -x_q, u_q = x_p
      VecX v = VecX::Zero(padded_);
      for (Index i = 0; i < n; ++i) {
        const Vec3 x = layout_->x[i] - c;
        if (layout_->comp[i] == p) v(i) = -x(q);
        else if (layout_->comp[i] == q) v(i) = x(p);
      }
      return v;
    };
    if (layout_->axisymmetric) {
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
      check(MatCreateVecs(A_, &vecs[k], nullptr), "MatCreateVecs");
      PetscScalar* p = nullptr;
      VecGetArray(vecs[k], &p);
      std::copy(basis[k].data() + rstart_, basis[k].data() + rend_, p);
      VecRestoreArray(vecs[k], &p);
    }
    MatNullSpace space = nullptr;
    check(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, static_cast<PetscInt>(vecs.size()), vecs.data(), &space),
          "MatNullSpaceCreate");
    check(MatSetNearNullSpace(A_, space), "MatSetNearNullSpace");
    MatNullSpaceDestroy(&space);
    for (Vec& v : vecs) VecDestroy(&v);
  }

  void configure() {
    if (!ksp_) check(KSPCreate(PETSC_COMM_WORLD, &ksp_), "KSPCreate");
    check(KSPSetOperators(ksp_, A_, A_), "KSPSetOperators");
    if (configured_) return;
    PC pc = nullptr;
    KSPGetPC(ksp_, &pc);
    if (s_.type == "mumps") {
      check(KSPSetType(ksp_, KSPPREONLY), "KSPSetType");
      check(PCSetType(pc, symmetric_ ? PCCHOLESKY : PCLU), "PCSetType");
      check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    } else if (is_amg_solver(s_.type)) {
      check(KSPSetType(ksp_, symmetric_ ? KSPCG : KSPGMRES), "KSPSetType");
      // rtol on the true residual |b - A x| / |b| (CG's default is the preconditioned one).
      if (symmetric_) KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED);
      if (!symmetric_) KSPGMRESSetRestart(ksp_, 200);
      if (s_.type == "gamg") {
        check(PCSetType(pc, PCGAMG), "PCSetType");
        PCGAMGSetType(pc, PCGAMGAGG);
        PCGAMGSetReuseInterpolation(pc, PETSC_TRUE);
      } else {
        check(PCSetType(pc, PCHYPRE), "PCSetType (is PETSc built with hypre?)");
        PCHYPRESetType(pc, "boomeramg");
      }
    }
    check(KSPSetTolerances(ksp_, s_.rtol, 1e-300, PETSC_DEFAULT, 10000), "KSPSetTolerances");
    check(KSPSetFromOptions(ksp_), "KSPSetFromOptions");
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
  std::vector<int> outer_, inner_;
  std::string failure_ = "failed";
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

void finalize_petsc() {
  if (!g_started_here) return;
  PetscFinalize();
  g_started_here = false;
}

}  // namespace signorini
