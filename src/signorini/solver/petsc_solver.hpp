// PETSc's linear solvers behind LinearSolver (built with SIGNORINI_WITH_PETSC): one
// process's system copied into a sequential AIJ matrix and solved by a KSP.
//   gamg   conjugate gradients (GMRES when unsymmetric) preconditioned by PETSc's smoothed
//          aggregation multigrid, with the rigid-body modes as near-nullspace and the
//          interpolation reused while the pattern holds (Adams et al. 2004; PETSc manual, PCGAMG);
//   hypre  the same Krylov method with hypre's BoomerAMG (nodal systems of block size dim);
//   mumps  MUMPS's direct LU, or LDL^T when symmetric (any nonsingular system);
//   petsc  PETSc's defaults (GMRES, ILU(0)), to be set by the raw options.
// The deck's `options` string is inserted into PETSc's options database before the KSP
// reads it, so "-ksp_monitor" or "-pc_gamg_threshold 0.02" override the choices above.
#pragma once
#include <memory>

#include "signorini/solver/linear_solver.hpp"

namespace signorini {

std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings& settings);

// The distributed backend (several ranks): each rank assembles its own cells into the rows it
// owns of one PETSc matrix, solved by the KSP of `settings` (gamg, hypre, mumps, petsc).
class AlgebraBackend;
std::unique_ptr<AlgebraBackend> make_petsc_backend(const LinearSolverSettings& settings);

// PETSc (and MPI) are initialized on first use; finalize_petsc() ends them at the end of
// main when they were started (a no-op otherwise).
void finalize_petsc();
// Initializes PETSc now if it has not started (e.g. before timing a solve that would start it).
void start_petsc();

// Several MPI ranks (mpirun -np N): every rank reads the deck and runs the same Newton
// iterations on replicated vectors; the assembly is partitioned (make_petsc_backend: each rank
// its own cells into its rows of one PETSc matrix, contact multipliers condensed there for
// algebraic multigrid). Only rank 0 writes files and prints. Started at the
// beginning of main when the process was launched by mpirun (launched_ranks() > 1).
struct MpiInfo {
  int rank = 0, size = 1;
};
MpiInfo start_petsc_if_launched_by_mpi();
// Ends every rank's process with `code` (an error on some ranks only: MPI_Abort).
[[noreturn]] void abort_all_ranks(int code);
// Collective over PETSC_COMM_WORLD: the largest of the ranks' values (the value itself with
// one rank, or before PETSc starts).
int petsc_max_over_ranks(int value);
// Ranks of PETSC_COMM_WORLD (1 before PETSc starts).
int petsc_world_size();
// The ranks' exchange of shared-out work over PETSC_COMM_WORLD (core/rank_exchange.hpp); null
// with one rank.
class RankExchange;
std::unique_ptr<RankExchange> make_rank_exchange();

}  // namespace signorini
