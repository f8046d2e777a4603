#include "signorini/solver/condensed_solve.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"

namespace signorini {

namespace {

// Kr = L^T (J + Delta) T over the kept unknowns (ridx >= 0), column by column straight into
// its arrays: a counting pass, then the values. Column j of (J + Delta) T is the sum of
// (J + Delta)(:, a) T(a, j) over T's column j (the kept unknown's own 1, and the pivots whose
// row holds it); L^T y keeps y on the kept unknowns and spreads each pivot's y_p over left[p]
// (L's pivot rows; L = T when the multipliers' columns are parallel to their rows). The
// multipliers' rows are skipped (T's and L's are empty). Eigen's product of two square sparse
// matrices made three copies of the result (unsorted, transposed to sort it, assigned) next
// to J T, a copy of J (docs/performance.md). Structural zeros are kept, so the pattern
// follows the structure alone. Pivots that keep their places (algebraic multigrid) get an
// empty column and row but for a decoupled diagonal of the mean magnitude of Kr's diagonal.
SparseMatrix reduced_product(const SparseMatrix& J, const SparseMatrix* delta, const SparseMatrix& T,
                             const std::vector<Index>& ridx, const std::vector<Index>& pivot_of,
                             const std::vector<std::vector<std::pair<Index, Real>>>& left,
                             const std::vector<char>& is_multiplier) {
  const Index n = J.rows(), nr = T.cols();
  SparseMatrix Kr(nr, nr);
  VecX y = VecX::Zero(n), col = VecX::Zero(nr);
  std::vector<char> in_y(static_cast<size_t>(n), 0), in_col(static_cast<size_t>(nr), 0);
  std::vector<Index> rows_y, rows_col;
  auto add_y = [&](Index a, Real v) {
    if (!in_y[a]) in_y[a] = 1, rows_y.push_back(a);
    y(a) += v;
  };
  auto add_col = [&](Index i, Real v) {
    if (!in_col[i]) in_col[i] = 1, rows_col.push_back(i);
    col(i) += v;
  };
  auto add_column = [&](Index k, Real w) {
    for (SparseMatrix::InnerIterator it(J, k); it; ++it) add_y(it.row(), w * it.value());
    if (delta)
      for (SparseMatrix::InnerIterator it(*delta, k); it; ++it) add_y(it.row(), w * it.value());
  };
  // Kr's column of kept unknown k into rows_col (sorted) and col.
  auto column = [&](Index k) {
    for (SparseMatrix::InnerIterator t(T, ridx[k]); t; ++t) add_column(t.row(), t.value());
    for (Index a : rows_y) {
      const Real v = y(a);
      y(a) = 0;
      in_y[a] = 0;
      if (is_multiplier[a]) continue;
      if (pivot_of[a] >= 0) {
        for (const auto& [i, w] : left[a]) add_col(i, w * v);
      } else {
        add_col(ridx[a], v);
      }
    }
    rows_y.clear();
    std::sort(rows_col.begin(), rows_col.end());
  };
  auto clear_column = [&]() {
    for (Index i : rows_col) col(i) = 0, in_col[i] = 0;
    rows_col.clear();
  };
  int* outer = Kr.outerIndexPtr();
  for (Index k = 0; k < n; ++k) {
    if (ridx[k] < 0) continue;
    Index count = 1;  // a pivot's place: its decoupled diagonal
    if (pivot_of[k] < 0) {
      column(k);
      count = static_cast<Index>(rows_col.size());
      clear_column();
    }
    outer[ridx[k] + 1] = static_cast<int>(count);
  }
  for (Index j = 0; j < nr; ++j) outer[j + 1] += outer[j];
  Kr.resizeNonZeros(outer[nr]);
  int* inner = Kr.innerIndexPtr();
  Real* value = Kr.valuePtr();
  Real diagonal = 0;
  for (Index k = 0; k < n; ++k) {
    if (ridx[k] < 0) continue;
    const Index j = ridx[k];
    Index at = outer[j];
    if (pivot_of[k] >= 0) {
      inner[at] = static_cast<int>(j);
      value[at] = 0;  // set below, once the mean is known
      continue;
    }
    column(k);
    for (Index i : rows_col) {
      inner[at] = static_cast<int>(i);
      value[at++] = col(i);
      if (i == j) diagonal += std::abs(col(i));
    }
    clear_column();
  }
  const Real mean = nr ? diagonal / static_cast<Real>(nr) : 1.0;
  for (Index k = 0; k < n; ++k)
    if (ridx[k] >= 0 && pivot_of[k] >= 0) value[outer[ridx[k]]] = mean > 0 ? mean : 1.0;
  return Kr;
}

}  // namespace

void CondensedContactSolver::follow_pattern(const SparseMatrix& Kr, bool keep_places, const std::vector<Index>& ridx) {
  // The reduced pattern follows the active set and the pivots: the symbolic factorization is
  // kept while the pattern is the same as at the last solve (most Newton iterations once the
  // active set has settled) and redone when it changed.
  const bool same_pattern =
      Kr.rows() == pattern_rows_ &&
      std::equal(Kr.outerIndexPtr(), Kr.outerIndexPtr() + Kr.outerSize() + 1, pattern_outer_.begin(),
                 pattern_outer_.end()) &&
      std::equal(Kr.innerIndexPtr(), Kr.innerIndexPtr() + Kr.nonZeros(), pattern_inner_.begin(), pattern_inner_.end());
  if (same_pattern) return;
  solver_.reset();
  pattern_rows_ = Kr.rows();
  pattern_outer_.assign(Kr.outerIndexPtr(), Kr.outerIndexPtr() + Kr.outerSize() + 1);
  pattern_inner_.assign(Kr.innerIndexPtr(), Kr.innerIndexPtr() + Kr.nonZeros());
  ++analyses_;
  const Index n = static_cast<Index>(ridx.size());
  if (keep_places && layout_ && layout_->size() == n) {
    auto reduced = std::make_shared<UnknownLayout>();
    reduced->dim = layout_->dim;
    reduced->axisymmetric = layout_->axisymmetric;
    for (Index k = 0; k < n; ++k)
      if (ridx[k] >= 0) {
        reduced->x.push_back(layout_->x[k]);
        reduced->comp.push_back(layout_->comp[k]);
      }
    solver_.set_layout(reduced);
  }
}

bool CondensedContactSolver::solve(const SparseMatrix& J, const std::vector<char>& is_multiplier, bool symmetric,
                                   const VecX& r, VecX& dz) {
  // Notation: a multiplier row m of J is either closed, a_m . du = r_m over displacement
  // unknowns (its own diagonal zero), or open, J_mm dl_m = r_m. The displacement rows hold
  // the multipliers' columns b_m (parallel to a_m). Eliminating the pivot DOF p of each
  // closed row, du_p = (r_m - sum_{k != p} a_mk du_k) / a_mp, gives du = T u~ + z0 with
  // a_m^T T = 0, so T^T J T u~ = T^T (r - J z0) no longer sees the multipliers. Row p of J
  // then gives dl_m = (r_p - (J dz)_p) / J_pm (Wriggers 2006, sec. 6.3, for the elimination of
  // linear constraints; here applied to the active set of each Newton iteration).
  //
  // Coupled rows (segment_to_segment and mortar: a slave node's weighted gap also sees the
  // other nodes of its facets, through the dual basis against a normal that varies between
  // points and, on tri6/quad8, the modified basis): no unknown belongs to one closed row only.
  // Each row then takes as pivot the unknown where it dominates its column (the largest
  // |a_mp| / sum over closed rows of |a_m'p|); the couplings at the pivots (other rows' a_m'p,
  // and the pivot rows' other multipliers) are left out of a matrix P that the elimination
  // above solves exactly, and GMRES on J, right-preconditioned by P^-1 (P's factorization
  // reused), gives J's step. If GMRES does not get there, the whole system is solved instead
  // (plain refinement, dz += P^-1 (r - J dz), diverged on tri6).
  const Index n = J.rows();
  why_not_.clear();
  refinements_ = 0;
  iterations_ = 0;
  // The multiplier rows of J, gathered from its columns in column order (J is column-major;
  // a transpose of the whole matrix would take as much memory again as J).
  std::vector<Index> slot(n, -1);
  Index nm = 0;
  for (Index m = 0; m < n; ++m)
    if (is_multiplier[m]) slot[m] = nm++;
  std::vector<std::vector<std::pair<Index, Real>>> mrow(static_cast<size_t>(nm));
  for (Index col = 0; col < J.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(J, col); it; ++it)
      if (slot[it.row()] >= 0) mrow[slot[it.row()]].emplace_back(col, it.value());
  auto row_of = [&](Index m) -> const std::vector<std::pair<Index, Real>>& { return mrow[slot[m]]; };
  std::vector<Index> closed, open;
  std::vector<int> count(n, 0);      // closed rows whose support holds the unknown
  std::vector<Real> column(n, 0.0);  // sum over closed rows of |a_mk|
  for (Index m = 0; m < n; ++m) {
    if (!is_multiplier[m]) continue;
    bool has_u = false;
    Real diag = 0;
    for (const auto& [k, v] : row_of(m)) {
      if (v == 0) continue;
      if (k == m) diag = v;
      else if (is_multiplier[k]) return solve_blocks(J, is_multiplier, r, dz);
      else has_u = true;
    }
    if (has_u && diag != 0) return solve_blocks(J, is_multiplier, r, dz);  // a released direction's row
    if (!has_u) {
      if (diag == 0) throw SolverError("a contact multiplier's row is empty: the system is singular");
      open.push_back(m);
      continue;
    }
    closed.push_back(m);
    for (const auto& [k, v] : row_of(m))
      if (v != 0 && k != m) {
        ++count[k];
        column[k] += std::abs(v);
      }
  }
  std::vector<char> is_closed(n, 0);
  for (Index m : closed) is_closed[m] = 1;
  // For each unknown, how many closed multipliers act on its row (column m of J holds b_m).
  std::vector<int> acting(n, 0);
  for (Index m : closed)
    for (SparseMatrix::InnerIterator it(J, m); it; ++it)
      if (it.value() != 0) ++acting[it.row()];
  // Exact pivots: in each closed row, the largest coefficient on an unknown no other closed
  // row touches, whose own row carries no other closed multiplier.
  std::vector<Index> pivot_of(n, -1);  // unknown -> its closed row
  std::vector<Index> pivot(closed.size(), -1);
  auto choose_pivots = [&](bool coupled) {
    std::fill(pivot_of.begin(), pivot_of.end(), -1);
    std::fill(pivot.begin(), pivot.end(), -1);
    for (size_t c = 0; c < closed.size(); ++c) {
      const Index m = closed[c];
      Real amax = 0, best = 0;
      for (const auto& [k, v] : row_of(m))
        if (k != m) amax = std::max(amax, std::abs(v));
      for (const auto& [k, v] : row_of(m)) {
        const Real a = std::abs(v);
        if (k == m || a < 0.1 * amax || pivot_of[k] >= 0) continue;
        if (J.coeff(k, m) == 0) continue;  // the multiplier must act on its pivot's row
        const Real score = coupled ? a / column[k] : (count[k] == 1 ? a : 0.0);
        if (score <= best) continue;
        best = score;
        pivot[c] = k;
      }
      if (pivot[c] < 0) return false;
      pivot_of[pivot[c]] = static_cast<Index>(c);
    }
    if (coupled) return true;
    // The pivot's row must hold no other closed multiplier (else dl_m is not recovered alone);
    // its own acts on it (J(p, m) != 0 above).
    for (size_t c = 0; c < closed.size(); ++c)
      if (acting[pivot[c]] != 1) return false;
    return true;
  };
  bool coupled = false;
  if (!choose_pivots(false)) {
    coupled = true;
    if (coupled_skip_ > 0) {
      --coupled_skip_;
      why_not_ = "coupled contact rows (segment_to_segment, mortar), whose refined solve failed lately";
      return false;
    }
    if (!choose_pivots(true)) {
      why_not_ =
          "a closed constraint has no DOF of its own (two-pass, or a slave node that is also a master node), nor one "
          "where it dominates the other closed constraints";
      return false;
    }
  }
  // Coupled rows with an iterative inner solver: loose inner solves, GMRES to the forcing term
  // (kInnerTolerance). With a factorization the inner solve is exact and GMRES goes on to
  // kRefinementTolerance.
  const bool inexact = coupled && solver_.iterative(n);
  const Real outer = inexact ? std::max(kRefinementTolerance, tolerance_ > 0 ? tolerance_ : rtol_) : kRefinementTolerance;
  solver_.set_tolerance(coupled ? (inexact ? kInnerTolerance : 0.0) : tolerance_);
  // P = J - E: J without the couplings at the pivots (coupled rows only; else P = J). E holds
  // the left-out entries, which sit in closed rows and columns only, so P is never formed.
  auto dropped = [&](Index row, Index col) {
    return (is_closed[row] && pivot_of[col] >= 0 && closed[pivot_of[col]] != row) ||
           (is_closed[col] && pivot_of[row] >= 0 && closed[pivot_of[row]] != col);
  };
  SparseMatrix E(n, n);
  if (coupled) {
    std::vector<Eigen::Triplet<Real, int>> left;
    for (Index m : closed)
      for (const auto& [k, v] : row_of(m))
        if (dropped(m, k)) left.emplace_back(static_cast<int>(m), static_cast<int>(k), v);
    for (Index m : closed)
      for (SparseMatrix::InnerIterator it(J, m); it; ++it)
        if (!is_closed[it.row()] && dropped(it.row(), m))
          left.emplace_back(static_cast<int>(it.row()), static_cast<int>(m), it.value());
    E.setFromTriplets(left.begin(), left.end());
  }
  auto times_P = [&](const VecX& v) -> VecX {
    VecX out = J * v;
    if (coupled) out -= E * v;
    return out;
  };
  // Reduced numbering and T. Algebraic multigrid keeps the pivots' places (their columns of
  // T empty, a decoupled diagonal added below), so that the unknowns stay in node blocks.
  const bool keep_places = solver_.wants_layout(n);
  std::vector<Index> ridx(n, -1);
  Index nr = 0;
  for (Index k = 0; k < n; ++k)
    if (!is_multiplier[k] && (keep_places || pivot_of[k] < 0)) ridx[k] = nr++;
  std::vector<Eigen::Triplet<Real, int>> trip;
  trip.reserve(static_cast<size_t>(nr) + 16 * closed.size());
  for (Index k = 0; k < n; ++k)
    if (ridx[k] >= 0 && pivot_of[k] < 0) trip.emplace_back(static_cast<int>(k), static_cast<int>(ridx[k]), 1.0);
  std::vector<Real> ap(closed.size()), bp(closed.size());
  // T's pivot rows, row by row (T is stored by columns): spread[p] = (reduced column, T(p, .)).
  std::vector<std::vector<std::pair<Index, Real>>> spread(static_cast<size_t>(n));
  for (size_t c = 0; c < closed.size(); ++c) {
    const Index m = closed[c], p = pivot[c];
    bp[c] = J.coeff(p, m);  // never left out: m is p's own row
    for (const auto& [k, v] : row_of(m))
      if (k == p) ap[c] = v;
    for (const auto& [k, v] : row_of(m)) {
      if (k == m || k == p || v == 0 || (coupled && dropped(m, k))) continue;
      trip.emplace_back(static_cast<int>(p), static_cast<int>(ridx[k]), -v / ap[c]);
      spread[p].emplace_back(ridx[k], -v / ap[c]);
    }
  }
  SparseMatrix T(n, nr);
  T.setFromTriplets(trip.begin(), trip.end());
  decltype(trip)().swap(trip);
  // Kr = T^T P T (P = J, or J - E with coupled rows: the same Kr; E's entries sit in the
  // multipliers' rows and columns, which T leaves out).
  const SparseMatrix Kr = reduced_product(J, nullptr, T, ridx, pivot_of, spread, is_multiplier);
  follow_pattern(Kr, keep_places, ridx);
  // out = A^-1 rhs through the elimination; the first call factorizes Kr.
  bool factorized = false;
  auto apply = [&](const VecX& rhs, VecX& out) {
    VecX z0 = VecX::Zero(n);
    for (Index m : open) z0(m) = rhs(m) / J.coeff(m, m);
    for (size_t c = 0; c < closed.size(); ++c) z0(pivot[c]) = rhs(closed[c]) / ap[c];
    const VecX rr = T.transpose() * (rhs - times_P(z0));
    VecX ur;
    if (!factorized) {
      solver_.solve(Kr, symmetric, rr, ur);
      factorized = true;
    } else if (!solver_.solve_again(rr, ur)) {
      throw SolverError("linear solver " + solver_.last_used() + " failed in the refinement of a condensed solve: " +
                        solver_.failure());
    }
    iterations_ += solver_.last_iterations();
    out = T * ur + z0;
    // Closed multipliers from their pivots' rows (out holds 0 for them so far).
    const VecX Aout = times_P(out);
    for (size_t c = 0; c < closed.size(); ++c) out(closed[c]) = (rhs(pivot[c]) - Aout(pivot[c])) / bp[c];
  };
  apply(r, dz);
  log::debug("    condensed solve: {} unknowns, {} nonzeros ({}); resident memory {:.0f} MiB", Kr.rows(), Kr.nonZeros(),
             solver_.last_used(), log::memory_mib());
  if (!coupled) return true;
  // GMRES on J x = r, right-preconditioned by P^-1, from x0 = P^-1 r.
  const Real rnorm = r.norm();
  const FlexibleGmresResult g = flexible_gmres([&](const VecX& v) -> VecX { return J * v; }, apply, r, dz,
                                               outer * rnorm, kMaxRefinements);
  refinements_ = g.steps;
  const Real final_norm = g.residual;
  if (final_norm <= std::max(kRefinementAccepted, 2 * outer) * rnorm) {
    coupled_backoff_ = 1;
    return true;
  }
  // The whole system for the next 1, 2, 4, ... solves after each failure in a row.
  coupled_skip_ = coupled_backoff_;
  coupled_backoff_ = std::min(2 * coupled_backoff_, 64);
  why_not_ = fmt::format(
      "coupled contact rows (segment_to_segment, mortar): GMRES on the condensed preconditioner stalls at {:.1e} of "
      "the right-hand side after {} steps",
      final_norm / rnorm, g.steps);
  return false;
}

// Multiplier blocks (Lagrange friction: a closed node's normal and tangential multipliers, whose
// complementarity rows couple them; docs/contact.md). Notation per block of multipliers l (the
// connected multipliers of one node): its rows C du + M dl = r_l, and its columns B in the
// displacement rows. With M = U S V^T (singular values), the range of M is eliminated locally
// (a Schur complement of a block of at most 4 x 4): mu = V1^T dl = S^-1 U1^T (r_l - C du), which
// adds -B V1 S^-1 U1^T C to the displacement block (inside the constraint's own DOFs) and
// -B V1 S^-1 U1^T r_l to its rows. What remains are k = dim null(M) closed rows C~ = U0^T C on
// the displacements alone (the normal gap, and a sticking node's tangential slips) with their
// multipliers nu = V0^T dl acting through the columns B~ = B V0 (no longer parallel to C~: the
// friction's bound follows the normal multiplier). Each block's k closed rows eliminate k DOFs
// of its own together (block pivots, one k x k solve): du = T u~ + z0 with C~ T = 0, and the
// displacement rows are taken in combinations Z with Z^T B~ = 0, so that
//   Z^T K~ T u~ = Z^T (r~ - K~ z0)
// no longer sees the multipliers (the null-space method for a saddle point with B != C^T,
// Benzi, Golub & Liesen 2005, sec. 6). The pivots' rows then give nu, and mu follows from u.
// The reduced matrix is unsymmetric. Singular values below kClampedSingular of the block's
// largest (a node barely slipping across its slip direction) are raised to it: the elimination
// is then that of a nearby matrix P, and flexible GMRES on J, preconditioned by it, gives J's
// step, as for coupled rows.
bool CondensedContactSolver::solve_blocks(const SparseMatrix& J, const std::vector<char>& is_multiplier, const VecX& r,
                                          VecX& dz) {
  constexpr Real kNullSingular = 1e-10;     // below this share of the block's largest: null
  constexpr Real kClampedSingular = 1e-6;   // between the two: raised to this share (P != J)
  constexpr Real kPivotQuality = 1e-3;      // the least singular value of a pivot block, relative
  const Index n = J.rows();
  std::vector<Index> slot(n, -1), mult;
  for (Index m = 0; m < n; ++m)
    if (is_multiplier[m]) slot[m] = static_cast<Index>(mult.size()), mult.push_back(m);
  const Index nm = static_cast<Index>(mult.size());
  // The multipliers' rows; entries between multipliers are kept where they are stored zeros
  // (a sticking node's normal and tangential multipliers are coupled in the pattern only).
  std::vector<std::vector<std::pair<Index, Real>>> mrow(static_cast<size_t>(nm));
  for (Index col = 0; col < J.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(J, col); it; ++it)
      if (slot[it.row()] >= 0 && (it.value() != 0 || is_multiplier[col])) mrow[slot[it.row()]].emplace_back(col, it.value());
  // The blocks: multipliers connected through their rows' pattern (union-find on the slots): a
  // node's normal and tangential multipliers, whose closed rows share the node's DOFs.
  std::vector<Index> parent(static_cast<size_t>(nm));
  for (Index i = 0; i < nm; ++i) parent[i] = i;
  auto find = [&](Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (Index i = 0; i < nm; ++i)
    for (const auto& [k, v] : mrow[i])
      if (is_multiplier[k]) {
        const Index a = find(i), b = find(slot[k]);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
  struct Block {
    std::vector<Index> l, cu, bu;  // its multipliers; the DOFs of its rows, and of its columns
    MatX C;                        // rows on the DOFs (s x cu)
    MatX W;                        // B V1 S^-1 U1^T (bu x s)
    MatX SU1t, V0, V1, U0t;        // S^-1 U1^T (r x s), V0 (s x k), V1 (s x r), U0^T (k x s)
    MatX Ct, Bt;                   // closed rows U0^T C (k x cu), columns B V0 (bu x k)
    std::vector<Index> pivot;      // k DOFs, their places in cu and bu
    std::vector<int> pc, pb;
    Eigen::PartialPivLU<MatX> CtP, BtP;
    MatX BtPm;                     // B~_P (k x k)
  };
  std::vector<Index> block_of(static_cast<size_t>(nm), -1);
  std::vector<Block> blocks;
  for (Index i = 0; i < nm; ++i) {
    const Index root = find(i);
    if (block_of[root] < 0) block_of[root] = static_cast<Index>(blocks.size()), blocks.emplace_back();
    block_of[i] = block_of[root];
    blocks[block_of[i]].l.push_back(mult[i]);
  }
  bool approximate = false;  // a clamped singular value somewhere (P != J)
  std::vector<Eigen::Triplet<Real, int>> dtrip;
  std::vector<int> count(n, 0), acting(n, 0);  // closed blocks whose rows (columns) hold the DOF
  auto place = [](const std::vector<Index>& v, Index k) {
    return static_cast<int>(std::lower_bound(v.begin(), v.end(), k) - v.begin());
  };
  for (Block& b : blocks) {
    const int s = static_cast<int>(b.l.size());
    for (Index m : b.l) {
      for (const auto& [k, v] : mrow[slot[m]])
        if (!is_multiplier[k] && v != 0) b.cu.push_back(k);
      for (SparseMatrix::InnerIterator it(J, m); it; ++it)
        if (!is_multiplier[it.row()] && it.value() != 0) b.bu.push_back(it.row());
    }
    for (auto* v : {&b.cu, &b.bu}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    MatX M = MatX::Zero(s, s), B = MatX::Zero(static_cast<Index>(b.bu.size()), s);
    b.C = MatX::Zero(s, static_cast<Index>(b.cu.size()));
    for (int a = 0; a < s; ++a) {
      for (const auto& [k, v] : mrow[slot[b.l[a]]])
        if (is_multiplier[k]) M(a, place(b.l, k)) = v;
        else if (v != 0) b.C(a, place(b.cu, k)) = v;
      for (SparseMatrix::InnerIterator it(J, b.l[a]); it; ++it)
        if (!is_multiplier[it.row()] && it.value() != 0) B(place(b.bu, it.row()), a) = it.value();
    }
    Eigen::JacobiSVD<MatX> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    VecX sigma = svd.singularValues();
    const Real smax = s > 0 ? sigma(0) : 0.0;
    int rank = 0;
    while (rank < s && sigma(rank) > kNullSingular * smax) ++rank;
    for (int a = 0; a < rank; ++a)
      if (sigma(a) < kClampedSingular * smax) sigma(a) = kClampedSingular * smax, approximate = true;
    const int k = s - rank;
    b.V1 = svd.matrixV().leftCols(rank);
    b.V0 = svd.matrixV().rightCols(k);
    b.U0t = svd.matrixU().rightCols(k).transpose();
    b.SU1t = sigma.head(rank).cwiseInverse().asDiagonal() * svd.matrixU().leftCols(rank).transpose();
    b.W = B * b.V1 * b.SU1t;
    b.Ct = b.U0t * b.C;
    b.Bt = B * b.V0;
    if (k > 0 && b.Ct.cwiseAbs().maxCoeff() == 0)
      throw SolverError("a contact multiplier's row is empty: the system is singular");
    const MatX delta = -b.W * b.C;
    for (Index i = 0; i < delta.rows(); ++i)
      for (Index j = 0; j < delta.cols(); ++j)
        if (delta(i, j) != 0) dtrip.emplace_back(static_cast<int>(b.bu[i]), static_cast<int>(b.cu[j]), delta(i, j));
    if (k == 0) continue;
    for (Index j = 0; j < b.Ct.cols(); ++j)
      if (b.Ct.col(j).cwiseAbs().maxCoeff() > 0) ++count[b.cu[j]];
    for (Index i = 0; i < b.Bt.rows(); ++i)
      if (b.Bt.row(i).cwiseAbs().maxCoeff() > 0) ++acting[b.bu[i]];
  }
  // Pivots: per block with closed rows, k DOFs that no other block's closed rows touch and on
  // whose rows no other block's multipliers act, chosen among those subsets (at most a node's
  // few DOFs) for the best conditioned C~_P and B~_P.
  std::vector<Index> pivot_of(n, -1);  // DOF -> its block
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    Block& b = blocks[bi];
    const int k = static_cast<int>(b.Ct.rows());
    if (k == 0) continue;
    std::vector<int> cand;  // places in cu
    for (int j = 0; j < static_cast<int>(b.cu.size()); ++j) {
      const Index d = b.cu[j];
      if (count[d] != 1 || acting[d] != 1 || b.Ct.col(j).cwiseAbs().maxCoeff() == 0) continue;
      const int pb = place(b.bu, d);
      if (pb < static_cast<int>(b.bu.size()) && b.bu[pb] == d) cand.push_back(j);
    }
    const Real cmax = b.Ct.cwiseAbs().maxCoeff(), bmax = b.Bt.cwiseAbs().maxCoeff();
    // The k-subsets of the candidates, in lexicographic order.
    Real best = 0;
    std::vector<int> pick(static_cast<size_t>(k)), chosen;
    std::function<void(int, int)> subsets = [&](int from, int depth) {
      if (depth == k) {
        MatX cp(k, k), bp(k, k);
        for (int a = 0; a < k; ++a) {
          cp.col(a) = b.Ct.col(cand[pick[a]]);
          bp.row(a) = b.Bt.row(place(b.bu, b.cu[cand[pick[a]]]));
        }
        Eigen::JacobiSVD<MatX> sc(cp), sb(bp);
        const Real q = std::min(sc.singularValues()(k - 1) / cmax, sb.singularValues()(k - 1) / bmax);
        if (q > best) best = q, chosen.assign(pick.begin(), pick.end());
        return;
      }
      for (int c = from; c < static_cast<int>(cand.size()); ++c) {
        pick[depth] = c;
        subsets(c + 1, depth + 1);
      }
    };
    if (static_cast<int>(cand.size()) >= k && cand.size() <= 12) subsets(0, 0);
    if (best < kPivotQuality) {
      why_not_ = static_cast<int>(cand.size()) < k
                     ? "a node's closed constraints have too few DOFs of their own (two-pass, or a slave node that is "
                       "also a master node)"
                     : "a node's closed constraints have no well-conditioned block of DOFs of their own";
      return false;
    }
    MatX cp(k, k), bp(k, k);
    for (int a = 0; a < k; ++a) {
      const int j = cand[chosen[a]];
      b.pivot.push_back(b.cu[j]);
      b.pc.push_back(j);
      b.pb.push_back(place(b.bu, b.cu[j]));
      cp.col(a) = b.Ct.col(j);
      bp.row(a) = b.Bt.row(b.pb.back());
      pivot_of[b.cu[j]] = static_cast<Index>(bi);
    }
    b.CtP.compute(cp);
    b.BtP.compute(bp);
    b.BtPm = bp;
  }
  SparseMatrix Delta(n, n);
  Delta.setFromTriplets(dtrip.begin(), dtrip.end());
  decltype(dtrip)().swap(dtrip);
  // T and Z: identity on the kept DOFs; a pivot p's rows T_P = -C~_P^-1 C~_K and
  // Z_P = -B~_P^-T B~_K^T over the block's other DOFs K.
  const bool keep_places = solver_.wants_layout(n);
  std::vector<Index> ridx(n, -1);
  Index nr = 0;
  for (Index k = 0; k < n; ++k)
    if (!is_multiplier[k] && (keep_places || pivot_of[k] < 0)) ridx[k] = nr++;
  std::vector<Eigen::Triplet<Real, int>> trip;
  trip.reserve(static_cast<size_t>(nr));
  for (Index k = 0; k < n; ++k)
    if (ridx[k] >= 0 && pivot_of[k] < 0) trip.emplace_back(static_cast<int>(k), static_cast<int>(ridx[k]), 1.0);
  std::vector<std::vector<std::pair<Index, Real>>> left(static_cast<size_t>(n));
  for (const Block& b : blocks) {
    const int k = static_cast<int>(b.pivot.size());
    if (k == 0) continue;
    const MatX tp = -b.CtP.solve(b.Ct);                // k x cu
    const MatX zp = -b.BtPm.transpose().partialPivLu().solve(b.Bt.transpose());  // k x bu
    for (int a = 0; a < k; ++a) {
      for (Index j = 0; j < tp.cols(); ++j)
        if (pivot_of[b.cu[j]] < 0 && tp(a, j) != 0)
          trip.emplace_back(static_cast<int>(b.pivot[a]), static_cast<int>(ridx[b.cu[j]]), tp(a, j));
      for (Index i = 0; i < zp.cols(); ++i)
        if (pivot_of[b.bu[i]] < 0 && zp(a, i) != 0) left[b.pivot[a]].emplace_back(ridx[b.bu[i]], zp(a, i));
    }
  }
  SparseMatrix T(n, nr);
  T.setFromTriplets(trip.begin(), trip.end());
  decltype(trip)().swap(trip);
  const SparseMatrix Kr = reduced_product(J, &Delta, T, ridx, pivot_of, left, is_multiplier);
  follow_pattern(Kr, keep_places, ridx);
  const bool inexact = approximate && solver_.iterative(n);
  const Real outer = inexact ? std::max(kRefinementTolerance, tolerance_ > 0 ? tolerance_ : rtol_) : kRefinementTolerance;
  solver_.set_tolerance(approximate ? (inexact ? kInnerTolerance : 0.0) : tolerance_);
  // K~ v on the displacement rows (v without multipliers).
  auto times_K = [&](const VecX& v) -> VecX {
    VecX y = J * v + Delta * v;
    for (Index m : mult) y(m) = 0;
    return y;
  };
  // out = P^-1 rhs through the elimination; the first call factorizes Kr.
  bool factorized = false;
  auto apply = [&](const VecX& rhs, VecX& out) {
    VecX rt = rhs;  // r~ on the displacement rows
    for (Index m : mult) rt(m) = 0;
    VecX z0 = VecX::Zero(n);
    std::vector<VecX> rl(blocks.size());
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      VecX& v = rl[bi];
      v.resize(static_cast<Index>(b.l.size()));
      for (size_t a = 0; a < b.l.size(); ++a) v(static_cast<Index>(a)) = rhs(b.l[a]);
      const VecX w = b.W * v;
      for (size_t i = 0; i < b.bu.size(); ++i) rt(b.bu[i]) -= w(static_cast<Index>(i));
      if (b.pivot.empty()) continue;
      const VecX zp = b.CtP.solve(b.U0t * v);
      for (size_t a = 0; a < b.pivot.size(); ++a) z0(b.pivot[a]) = zp(static_cast<Index>(a));
    }
    const VecX y = rt - times_K(z0);
    VecX rr = VecX::Zero(nr);
    for (Index a = 0; a < n; ++a) {
      if (is_multiplier[a]) continue;
      if (pivot_of[a] >= 0) {
        for (const auto& [i, w] : left[a]) rr(i) += w * y(a);
      } else {
        rr(ridx[a]) += y(a);
      }
    }
    VecX ur;
    if (!factorized) {
      solver_.solve(Kr, false, rr, ur);
      factorized = true;
    } else if (!solver_.solve_again(rr, ur)) {
      throw SolverError("linear solver " + solver_.last_used() + " failed in the refinement of a condensed solve: " +
                        solver_.failure());
    }
    iterations_ += solver_.last_iterations();
    out = T * ur + z0;
    const VecX Ku = times_K(out);
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      VecX cu(static_cast<Index>(b.cu.size()));
      for (size_t j = 0; j < b.cu.size(); ++j) cu(static_cast<Index>(j)) = out(b.cu[j]);
      VecX dl = b.V1 * (b.SU1t * (rl[bi] - b.C * cu));
      if (!b.pivot.empty()) {
        VecX rp(static_cast<Index>(b.pivot.size()));
        for (size_t a = 0; a < b.pivot.size(); ++a) rp(static_cast<Index>(a)) = rt(b.pivot[a]) - Ku(b.pivot[a]);
        dl += b.V0 * b.BtP.solve(rp);
      }
      for (size_t a = 0; a < b.l.size(); ++a) out(b.l[a]) = dl(static_cast<Index>(a));
    }
  };
  apply(r, dz);
  log::debug("    condensed solve (multiplier blocks): {} unknowns, {} nonzeros ({}); resident memory {:.0f} MiB",
             Kr.rows(), Kr.nonZeros(), solver_.last_used(), log::memory_mib());
  if (!approximate) return true;
  const Real rnorm = r.norm();
  const FlexibleGmresResult g = flexible_gmres([&](const VecX& v) -> VecX { return J * v; }, apply, r, dz,
                                               outer * rnorm, kMaxRefinements);
  refinements_ = g.steps;
  if (g.residual <= std::max(kRefinementAccepted, 2 * outer) * rnorm) return true;
  why_not_ = fmt::format(
      "a node barely slipping: GMRES on the condensed preconditioner stalls at {:.1e} of the right-hand side after {} "
      "steps",
      g.residual / rnorm, g.steps);
  return false;
}

FlexibleGmresResult flexible_gmres(const std::function<VecX(const VecX&)>& times_A,
                                   const std::function<void(const VecX&, VecX&)>& precondition, const VecX& r, VecX& x,
                                   Real tolerance, int max_steps) {
  VecX res = r - times_A(x);
  const Real beta = res.norm();
  if (!(beta > tolerance)) return {0, beta};
  std::vector<VecX> V, Z;
  MatX H = MatX::Zero(max_steps + 1, max_steps);
  VecX cs = VecX::Zero(max_steps), sn = VecX::Zero(max_steps), g = VecX::Zero(max_steps + 1);
  g(0) = beta;
  V.push_back(res / beta);
  int k = 0;
  Real err = beta;
  for (; k < max_steps && err > tolerance; ++k) {
    VecX z;
    precondition(V[k], z);
    VecX w = times_A(z);
    for (int i = 0; i <= k; ++i) {  // modified Gram-Schmidt
      H(i, k) = w.dot(V[i]);
      w -= H(i, k) * V[i];
    }
    H(k + 1, k) = w.norm();
    Z.push_back(std::move(z));
    V.push_back(H(k + 1, k) > 0 ? VecX(w / H(k + 1, k)) : VecX(w));
    for (int i = 0; i < k; ++i) {  // the earlier Givens rotations, then this column's
      const Real t = cs(i) * H(i, k) + sn(i) * H(i + 1, k);
      H(i + 1, k) = -sn(i) * H(i, k) + cs(i) * H(i + 1, k);
      H(i, k) = t;
    }
    const Real d = std::hypot(H(k, k), H(k + 1, k));
    cs(k) = d > 0 ? H(k, k) / d : 1;
    sn(k) = d > 0 ? H(k + 1, k) / d : 0;
    H(k, k) = d;
    H(k + 1, k) = 0;
    g(k + 1) = -sn(k) * g(k);
    g(k) = cs(k) * g(k);
    err = std::abs(g(k + 1));
  }
  const VecX y = H.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
  for (int i = 0; i < k; ++i) x += y(i) * Z[i];
  return {k, (r - times_A(x)).norm()};
}

}  // namespace signorini
