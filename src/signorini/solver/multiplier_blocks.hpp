// Lagrange friction's multiplier blocks, for the condensed contact solve (condensed_solve.hpp,
// and the partitioned backend's in petsc_solver.cpp): a closed node's normal and tangential
// multipliers are one block whose rows couple them. Notation per block of multipliers l: its
// rows C du + M dl = r_l, its columns B in the displacement rows. With M = U S V^T, the range
// of M is eliminated locally (a Schur complement of at most 4 x 4):
//   mu = V1^T dl = S^-1 U1^T (r_l - C du),
// which adds Delta = -W C, W = B V1 S^-1 U1^T, to the displacement block (inside the
// constraint's own DOFs, within J's pattern) and -W r_l to the displacement rows. What remains
// are k = dim null(M) closed rows C~ = U0^T C on the displacements alone (the normal gap, and
// a sticking node's tangential slips) with their multipliers nu = V0^T dl acting through the
// columns B~ = B V0 (not parallel to C~: the friction bound follows the normal multiplier).
// Each block's k closed rows eliminate k DOFs together (block pivots P) among those no other
// block's closed rows touch and on whose rows only its multipliers act (its slave node's, as a
// rule; a master node's that no other closed node touches can serve too):
//   du = T u~ + z0,  T_P = -C~_P^-1 C~_K,  z0_P = C~_P^-1 U0^T r_l,
// and the displacement rows are combined by Z, Z_P = -B~_P^-T B~_K^T (Z^T B~ = 0), so that
//   Z^T (K + Delta) T u~ = Z^T (r~ - (K + Delta) z0)
// no longer sees the multipliers: the null-space method for a saddle point whose constraint
// rows and multiplier columns differ (Benzi, Golub & Liesen 2005, Acta Numerica, sec. 6). The
// pivots' rows then give nu = B~_P^-1 (r~_P - ((K + Delta) du)_P), and mu follows from du.
// A block whose closed rows or multiplier columns are dependent (the whole system singular but for
// round-off) has the dependent combinations released: no equation, a zero multiplier step, and no
// GMRES correction (J has no step to correct towards there).
// Singular values of M below kNullSingular of the block's largest are taken as zero (round-off:
// a sticking node's D_TT = w n n^T); those below kClampedSingular (a node barely past the slip
// limit, 1 - F/|q| tiny across its slip) are raised to it, and the elimination is then that
// of a nearby matrix: `approximate`, for flexible GMRES on J to correct.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "signorini/core/types.hpp"

namespace signorini {

struct MultiplierBlock {
  std::vector<Index> l, cu, bu;  // its multipliers; the DOFs of its rows, and of its columns (sorted)
  MatX C;                        // rows on the DOFs (s x cu)
  MatX W;                        // B V1 S^-1 U1^T (bu x s)
  MatX SU1t, V0, V1, U0t;        // S^-1 U1^T (r x s), V0 (s x k), V1 (s x r), U0^T (k x s)
  MatX Ct, Bt;                   // closed rows U0^T C (k x cu), columns B V0 (bu x k)
  std::vector<Index> pivot;      // its k pivot DOFs
  MatX Tp, Zp;                   // T's and Z's pivot rows: -C~_P^-1 C~ (k x cu), -B~_P^-T B~^T (k x bu)
  Eigen::PartialPivLU<MatX> CtP, BtP;  // C~_P and B~_P
  int closed() const { return static_cast<int>(pivot.size()); }
};

struct MultiplierBlocks {
  std::vector<MultiplierBlock> blocks;
  std::vector<Index> pivot_of;  // per unknown: its block when it is a pivot, else -1
  // Delta's entries (row, column, value), stored zeros included (the pattern follows J's).
  std::vector<std::pair<std::pair<Index, Index>, Real>> delta;
  // Whether delta[e] enters the reduced matrix Z^T (J + Delta) T (all but the small entries of
  // blocks on shared DOFs, kSharedDofsDrop); the elimination's own products use every entry.
  std::vector<char> delta_in_reduced;
  bool approximate = false;  // a clamped singular value: the elimination is a nearby matrix's
  bool coupled = false;      // pivots shared with other blocks' rows (approximate too)
  int released = 0;          // closed rows released as dependent on their node's DOFs
  std::string why_not;       // empty when the blocks could be set up
};

constexpr Real kNullSingular = 1e-10;
constexpr Real kClampedSingular = 1e-6;
// A pivot block is taken when the least singular values of C~_P and B~_P are at least this share
// of C~'s and B~'s largest entries.
constexpr Real kPivotQuality = 1e-3;
// A block's closed rows (or its multipliers' columns) whose singular values fall below this
// share of the largest are dependent: released.
constexpr Real kDependentRows = 1e-8;
// The pivot blocks are sought among this many of a block's candidate DOFs (the best ranked).
constexpr int kPivotCandidates = 8;

// Blocks on shared DOFs (`coupled`, mortar's friction): the reduced matrix, a preconditioner
// there (flexible GMRES on J takes the step), leaves out T's and Z's pivot-row coefficients below
// kSharedDofsDrop and Delta's entries below kSharedDofsDrop of their row's largest, as the
// partitioned backend does for coupled rows (petsc_solver.cpp, kCoupledDrop). A tet10 mortar
// row spans about 190 DOFs, and Delta = -W C is dense over a block's DOFs (about 105 x 105 per
// closed node there, every closed node's block having a coupled direction: 1.3M entries on the
// tet10 Hertz quarter with friction, 107k kept). Measured there (docs/performance.md, session
// 62): the same Newton, Krylov and GMRES counts; on 2 ranks T, Z and the product 2.9-5.5 s per
// Newton iteration with every entry, 0.4-0.8 s without these; in one process the linear solve
// 9.9 s -> 8.1 s (the reduced matrix 3.6M -> 3.1M nonzeros).
constexpr Real kSharedDofsDrop = 1e-2;
// Whether entry j of pivot row a of block b enters T (z false: over b.cu) or Z (z true: over b.bu):
// the block's other DOFs that are not pivots, but for the small coefficients above.
bool in_reduced_matrix(const MultiplierBlocks& mb, const MultiplierBlock& b, Index a, bool z, size_t j);

// The blocks of the multipliers `mult` (ascending) of a system of n unknowns: rows[i] holds
// multiplier mult[i]'s row (column, value) with its stored zeros, cols[i] its column's entries
// in the displacement rows (row, value). Throws SolverError when a multiplier's row is empty.
MultiplierBlocks analyse_multiplier_blocks(Index n, const std::vector<char>& is_multiplier, const std::vector<Index>& mult,
                                           const std::vector<std::vector<std::pair<Index, Real>>>& rows,
                                           const std::vector<std::vector<std::pair<Index, Real>>>& cols);

// The elimination's right-hand side pieces of one vector `rhs` (whole, every unknown): r~ on
// the displacement rows (rhs less each block's W r_l, zero on the multipliers) and z0.
void blocks_reduce_rhs(const MultiplierBlocks& mb, const VecX& rhs, VecX& rt, VecX& z0);
// The multipliers of the step `out` (displacements set): nu from the pivots' rows of r~ - Ku
// (Ku = (K + Delta) du on the displacement rows), mu from du.
void blocks_recover_multipliers(const MultiplierBlocks& mb, const VecX& rhs, const VecX& rt, const VecX& Ku, VecX& out);

}  // namespace signorini
