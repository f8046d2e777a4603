#include "signorini/solver/condensed_solve.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>

#include <fmt/format.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/solver/multiplier_blocks.hpp"

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

// Kr u = rr: the first call (factorized false) factorizes Kr, the next ones reuse it.
VecX CondensedContactSolver::inner_solve(const SparseMatrix& Kr, bool symmetric, const VecX& rr, bool& factorized) {
  VecX ur;
  if (!factorized) {
    solver_.solve(Kr, symmetric, rr, ur);
    factorized = true;
  } else if (!solver_.solve_again(rr, ur)) {
    throw SolverError("linear solver " + solver_.last_used() + " failed in the refinement of a condensed solve: " +
                      solver_.failure());
  }
  iterations_ += solver_.last_iterations();
  return ur;
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
  solver_.set_unsymmetric_amg_any_size(false);  // solve_blocks sets it for friction's blocks
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
  // Closed row m's best pivot by `score` (|a_mk|, k) among the unknowns not yet a pivot where
  // its coefficient is at least 0.1 of its largest and on whose row its multiplier acts; -1 if none.
  auto best_pivot = [&](Index m, const std::function<Real(Real, Index)>& score) {
    Real amax = 0, best = 0;
    Index chosen = -1;
    for (const auto& [k, v] : row_of(m))
      if (k != m) amax = std::max(amax, std::abs(v));
    for (const auto& [k, v] : row_of(m)) {
      const Real a = std::abs(v);
      if (k == m || a < 0.1 * amax || pivot_of[k] >= 0 || J.coeff(k, m) == 0) continue;
      const Real s = score(a, k);
      if (s <= best) continue;
      best = s;
      chosen = k;
    }
    return chosen;
  };
  auto choose_pivots = [&](bool coupled) {
    std::fill(pivot_of.begin(), pivot_of.end(), -1);
    std::fill(pivot.begin(), pivot.end(), -1);
    for (size_t c = 0; c < closed.size(); ++c) {
      pivot[c] = best_pivot(closed[c], [&](Real a, Index k) { return coupled ? a / column[k] : (count[k] == 1 ? a : 0.0); });
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
    if (coupled_backoff_.skipping()) {
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
  // Coupled rows in levels (coupled_rows_levels): a row's couplings at the pivots of rows on
  // lower levels (its parents) stay in P, eliminated by substitution (the lowest level first),
  // and the parents' pivot rows keep their children's multipliers (recovered from the highest
  // level down); every other coupling at a pivot is left out (E). crow: closed row -> its index in `closed`; ap: its pivot coefficient.
  std::vector<Index> crow(n, -1);
  for (size_t c = 0; c < closed.size(); ++c) crow[closed[c]] = static_cast<Index>(c);
  std::vector<Real> ap(closed.size()), bp(closed.size());
  auto pivot_coefficients = [&]() {
    for (size_t c = 0; c < closed.size(); ++c)
      for (const auto& [k, v] : row_of(closed[c]))
        if (k == pivot[c]) ap[c] = v;
  };
  pivot_coefficients();
  LevelledRows lr(closed.size());
  std::vector<int>& level = lr.level;
  if (coupled) {
    auto levels = [&]() {
      std::vector<std::vector<std::pair<size_t, Real>>> coupling(closed.size());
      for (size_t c = 0; c < closed.size(); ++c)
        for (const auto& [k, v] : row_of(closed[c]))
          if (k != pivot[c] && pivot_of[k] >= 0 && v != 0 && J.coeff(k, closed[c]) != 0)
            coupling[c].emplace_back(static_cast<size_t>(pivot_of[k]), std::abs(v / ap[c]));
      return coupled_rows_levels(coupling);
    };
    level = levels();
    // The parents' pivots chosen again once the children are known: a child's coupling at its
    // parent's pivot is eliminated exactly, so a parent's pivot is to dominate the other
    // parents' rows only (score |a|^2 / sum over parents of |a_m'k|: the row's own DOF rather
    // than a master node's under it, which the column over every row may favour).
    std::vector<Real> column_parents(n, 0.0);
    for (size_t c = 0; c < closed.size(); ++c)
      if (level[c] == 0)
        for (const auto& [k, v] : row_of(closed[c])) column_parents[k] += std::abs(v);
    for (size_t c = 0; c < closed.size(); ++c)
      if (level[c] == 0) pivot_of[pivot[c]] = -1;
    for (size_t c = 0; c < closed.size(); ++c) {
      if (level[c] > 0) continue;
      const Index k = best_pivot(closed[c], [&](Real a, Index j) { return a * a / column_parents[j]; });
      if (k >= 0) pivot[c] = k;  // else the first choice, free again
      pivot_of[pivot[c]] = static_cast<Index>(c);
    }
    pivot_coefficients();
    level = levels();
    for (size_t c = 0; c < closed.size(); ++c) {
      if (level[c] == 0) continue;
      for (const auto& [k, v] : row_of(closed[c])) {
        if (k == pivot[c] || pivot_of[k] < 0 || v == 0 || level[pivot_of[k]] >= level[c]) continue;
        const Real b = J.coeff(k, closed[c]);
        if (b == 0) continue;
        lr.substitute(c, static_cast<size_t>(pivot_of[k]), v, b);
      }
    }
  }
  auto kept = [&](Index c, Index parent) { return lr.substitutes(static_cast<size_t>(c), static_cast<size_t>(parent)); };
  // Coupled rows with an iterative inner solver: loose inner solves, GMRES to the forcing term
  // (kInnerTolerance). With a factorization the inner solve is exact and GMRES goes on to
  // kRefinementTolerance.
  const bool inexact = coupled && solver_.iterative(n);
  const Real outer = inexact ? std::max(kRefinementTolerance, tolerance_ > 0 ? tolerance_ : rtol_) : kRefinementTolerance;
  solver_.set_tolerance(coupled ? (inexact ? kInnerTolerance : 0.0) : tolerance_);
  // P = J - E: J without the couplings at the pivots (coupled rows only; else P = J). E holds
  // the left-out entries, which sit in closed rows and columns only, so P is never formed.
  auto dropped = [&](Index row, Index col) {
    return (is_closed[row] && pivot_of[col] >= 0 && closed[pivot_of[col]] != row && !kept(crow[row], pivot_of[col])) ||
           (is_closed[col] && pivot_of[row] >= 0 && closed[pivot_of[row]] != col && !kept(crow[col], pivot_of[row]));
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
  // T's pivot rows, row by row (T is stored by columns): spread[p] = (reduced column, T(p, .)),
  // the parents' rows before the children's, which add their parents' rows (duplicate columns
  // are summed by the triplets and by reduced_product).
  std::vector<std::vector<std::pair<Index, Real>>> spread(static_cast<size_t>(n));
  for (size_t c : lr.order()) {
    const Index m = closed[c], p = pivot[c];
    bp[c] = J.coeff(p, m);  // never left out: m is p's own row
    for (const auto& [k, v] : row_of(m)) {
      if (k == m || k == p || v == 0 || (coupled && (dropped(m, k) || pivot_of[k] >= 0))) continue;
      spread[p].emplace_back(ridx[k], -v / ap[c]);
    }
    for (const auto& [q, v] : lr.parents_of[c])
      for (const auto& [j, t] : spread[pivot[q]]) spread[p].emplace_back(j, -v / ap[c] * t);
    for (const auto& [j, t] : spread[p]) trip.emplace_back(static_cast<int>(p), static_cast<int>(j), t);
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
    lr.pivot_values(closed, pivot, ap, rhs, z0);
    const VecX rr = T.transpose() * (rhs - times_P(z0));
    out = T * inner_solve(Kr, symmetric, rr, factorized) + z0;
    // Closed multipliers from their pivots' rows (out holds 0 for them so far), the children's
    // before their parents'.
    lr.multipliers(closed, pivot, bp, rhs, times_P(out), out);
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
    coupled_backoff_.succeeded();
    return true;
  }
  coupled_backoff_.failed();  // the whole system for the next 1, 2, 4, ... solves
  why_not_ = fmt::format(
      "coupled contact rows (segment_to_segment, mortar): GMRES on the condensed preconditioner stalls at {:.1e} of "
      "the right-hand side after {} steps",
      final_norm / rnorm, g.steps);
  return false;
}

// Lagrange friction's multiplier blocks (multiplier_blocks.hpp): each block's range eliminated
// locally, its closed rows by block pivots, Z^T (K + Delta) T u~ = Z^T (r~ - (K + Delta) z0).
bool CondensedContactSolver::solve_blocks(const SparseMatrix& J, const std::vector<char>& is_multiplier, const VecX& r,
                                          VecX& dz) {
  const Index n = J.rows();
  solver_.set_unsymmetric_amg_any_size(true);
  std::vector<Index> slot(n, -1), mult;
  for (Index m = 0; m < n; ++m)
    if (is_multiplier[m]) slot[m] = static_cast<Index>(mult.size()), mult.push_back(m);
  // The reduced system's size with the pivots kept in place (algebraic multigrid), which the
  // solver's choice reads.
  const Index reduced = n - static_cast<Index>(mult.size());
  if (!blocks_always_ && !solver_.unsymmetric_iterative(reduced)) {
    why_not_ = "friction's multipliers are condensed for algebraic multigrid only (3D with PETSc, 2D above "
               "iterative_above, or linear: gamg)";
    return false;
  }
  if (blocks_backoff_.skipping()) {
    why_not_ = blocks_why_not_;
    return false;
  }
  // The multipliers' rows and columns with their stored zeros: a sticking node's normal and
  // tangential multipliers are coupled in the pattern only, and the reduced pattern is to
  // follow J's pattern and the pivots, not the values.
  std::vector<std::vector<std::pair<Index, Real>>> rows(mult.size()), cols(mult.size());
  for (Index col = 0; col < J.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(J, col); it; ++it) {
      if (slot[it.row()] >= 0) rows[slot[it.row()]].emplace_back(col, it.value());
      else if (slot[col] >= 0) cols[slot[col]].emplace_back(it.row(), it.value());
    }
  ++block_analyses_;
  const MultiplierBlocks mb = analyse_multiplier_blocks(n, is_multiplier, mult, rows, cols);
  decltype(rows)().swap(rows);
  decltype(cols)().swap(cols);
  if (!mb.why_not.empty()) {
    // Refused blocks are refused again at the next iterations as a rule (mortar's friction: its
    // rows share the slave nodes' DOFs; the analysis was an eighth of the tet10 Hertz quarter's
    // run, at every Newton iteration): the whole system for the next 1, 2, 4, ... solves after
    // each refusal in a row, as after a failed refinement of coupled rows (coupled_backoff_).
    why_not_ = blocks_why_not_ = mb.why_not;
    blocks_backoff_.failed();
    return false;
  }
  const std::vector<Index>& pivot_of = mb.pivot_of;
  // Delta, and the reduced matrix's Delta: without the small entries of blocks on shared DOFs
  // (multiplier_blocks.hpp, kSharedDofsDrop); the elimination's products use Delta whole.
  auto delta_matrix = [&](bool reduced) {
    std::vector<Eigen::Triplet<Real, int>> t;
    t.reserve(mb.delta.size());
    for (size_t e = 0; e < mb.delta.size(); ++e)
      if (!reduced || mb.delta_in_reduced[e])
        t.emplace_back(static_cast<int>(mb.delta[e].first.first), static_cast<int>(mb.delta[e].first.second), mb.delta[e].second);
    SparseMatrix D(n, n);
    D.setFromTriplets(t.begin(), t.end());
    return D;
  };
  const SparseMatrix Delta = delta_matrix(false);
  const SparseMatrix reduced_delta = mb.coupled ? delta_matrix(true) : SparseMatrix();
  // T and Z: identity on the kept DOFs, the blocks' pivot rows T_P and Z_P over their other DOFs.
  const bool keep_places = solver_.wants_layout(reduced);
  std::vector<Index> ridx(n, -1);
  Index nr = 0;
  for (Index k = 0; k < n; ++k)
    if (!is_multiplier[k] && (keep_places || pivot_of[k] < 0)) ridx[k] = nr++;
  std::vector<Eigen::Triplet<Real, int>> trip;
  trip.reserve(static_cast<size_t>(nr));
  for (Index k = 0; k < n; ++k)
    if (ridx[k] >= 0 && pivot_of[k] < 0) trip.emplace_back(static_cast<int>(k), static_cast<int>(ridx[k]), 1.0);
  std::vector<std::vector<std::pair<Index, Real>>> left(static_cast<size_t>(n));
  for (const MultiplierBlock& b : mb.blocks)
    for (int a = 0; a < b.closed(); ++a) {
      for (size_t j = 0; j < b.cu.size(); ++j)
        if (in_reduced_matrix(mb, b, a, false, j))
          trip.emplace_back(static_cast<int>(b.pivot[a]), static_cast<int>(ridx[b.cu[j]]), b.Tp(a, static_cast<Index>(j)));
      for (size_t i = 0; i < b.bu.size(); ++i)
        if (in_reduced_matrix(mb, b, a, true, i)) left[b.pivot[a]].emplace_back(ridx[b.bu[i]], b.Zp(a, static_cast<Index>(i)));
    }
  SparseMatrix T(n, nr);
  T.setFromTriplets(trip.begin(), trip.end());
  decltype(trip)().swap(trip);
  const SparseMatrix Kr = reduced_product(J, mb.coupled ? &reduced_delta : &Delta, T, ridx, pivot_of, left, is_multiplier);
  follow_pattern(Kr, keep_places, ridx);
  const bool inexact = mb.approximate && solver_.unsymmetric_iterative(reduced);
  const Real outer = inexact ? std::max(kRefinementTolerance, tolerance_ > 0 ? tolerance_ : rtol_) : kRefinementTolerance;
  solver_.set_tolerance(mb.approximate ? (inexact ? kInnerTolerance : 0.0) : tolerance_);
  // (K + Delta) v on the displacement rows (v without multipliers).
  auto times_K = [&](const VecX& v) -> VecX {
    VecX y = J * v + Delta * v;
    for (Index m : mult) y(m) = 0;
    return y;
  };
  // out = P^-1 rhs through the elimination; the first call factorizes Kr.
  bool factorized = false;
  auto apply = [&](const VecX& rhs, VecX& out) {
    VecX rt, z0;
    blocks_reduce_rhs(mb, rhs, rt, z0);
    const VecX y = rt - times_K(z0);
    VecX rr = VecX::Zero(nr);  // Z^T y
    for (Index a = 0; a < n; ++a) {
      if (is_multiplier[a]) continue;
      if (pivot_of[a] >= 0) {
        for (const auto& [i, w] : left[a]) rr(i) += w * y(a);
      } else {
        rr(ridx[a]) += y(a);
      }
    }
    out = T * inner_solve(Kr, false, rr, factorized) + z0;
    blocks_recover_multipliers(mb, rhs, rt, times_K(out), out);
  };
  apply(r, dz);
  log::debug("    condensed solve (friction's multiplier blocks{}): {} unknowns, {} nonzeros ({}); resident memory {:.0f} MiB",
             mb.released ? fmt::format(", {} dependent rows released", mb.released) : "", Kr.rows(), Kr.nonZeros(),
             solver_.last_used(), log::memory_mib());
  if (!mb.approximate) {
    blocks_backoff_.succeeded();
    return true;
  }
  // A clamped singular value, or blocks on shared DOFs: GMRES on J, right-preconditioned by the
  // elimination.
  const Real rnorm = r.norm();
  const FlexibleGmresResult g = flexible_gmres([&](const VecX& v) -> VecX { return J * v; }, apply, r, dz,
                                               outer * rnorm, kMaxRefinements);
  refinements_ = g.steps;
  if (g.residual <= std::max(kRefinementAccepted, 2 * outer) * rnorm) {
    blocks_backoff_.succeeded();
    return true;
  }
  why_not_ = fmt::format("{}: GMRES on the condensed preconditioner stalls at {:.1e} of the right-hand side after {} steps",
                         mb.coupled ? "friction's blocks on shared DOFs (mortar)" : "a node barely slipping",
                         g.residual / rnorm, g.steps);
  if (mb.coupled) {  // the same blocks next time: backed off as a refusal (a barely slipping node passes)
    blocks_why_not_ = why_not_;
    blocks_backoff_.failed();
  }
  return false;
}

std::vector<int> coupled_rows_levels(const std::vector<std::vector<std::pair<size_t, Real>>>& coupling) {
  const size_t n = coupling.size();
  std::vector<int> level(n, 0);
  std::vector<char> in_set(n, 1);  // the rows of the level being split
  for (int l = 1; l < kCoupledLevels; ++l) {
    std::vector<std::vector<std::pair<size_t, Real>>> among(n);
    for (size_t c = 0; c < n; ++c)
      if (in_set[c])
        for (const auto& [q, w] : coupling[c])
          if (in_set[q]) among[c].emplace_back(q, w);
    const std::vector<char> child = coupled_rows_children(among);
    bool any = false;
    for (size_t c = 0; c < n; ++c) {
      in_set[c] = in_set[c] && child[c];
      if (in_set[c]) level[c] = l, any = true;
    }
    if (!any) break;
  }
  return level;
}

bool LevelledRows::substitutes(size_t child, size_t parent) const {
  for (const auto& [q, a] : parents_of[child])
    if (q == parent) return true;
  return false;
}

std::vector<size_t> LevelledRows::order() const {
  std::vector<size_t> rows(level.size());
  for (size_t c = 0; c < rows.size(); ++c) rows[c] = c;
  std::stable_sort(rows.begin(), rows.end(), [&](size_t x, size_t y) { return level[x] < level[y]; });
  return rows;
}

void LevelledRows::pivot_values(const std::vector<Index>& closed, const std::vector<Index>& pivot,
                                const std::vector<Real>& ap, const VecX& rhs, VecX& z0) const {
  for (size_t c : order()) {
    Real b = rhs(closed[c]);
    for (const auto& [q, a] : parents_of[c]) b -= a * z0(pivot[q]);
    z0(pivot[c]) = b / ap[c];
  }
}

void LevelledRows::multipliers(const std::vector<Index>& closed, const std::vector<Index>& pivot,
                               const std::vector<Real>& bp, const VecX& rhs, const VecX& Jout, VecX& out) const {
  const std::vector<size_t> rows = order();
  for (auto it = rows.rbegin(); it != rows.rend(); ++it) {
    const size_t c = *it;
    Real b = rhs(pivot[c]) - Jout(pivot[c]);
    for (const auto& [q, v] : children_of[c]) b -= v * out(closed[q]);
    out(closed[c]) = b / bp[c];
  }
}

std::vector<char> coupled_rows_children(const std::vector<std::vector<std::pair<size_t, Real>>>& coupling) {
  std::vector<Real> out(coupling.size(), 0.0), in(coupling.size(), 0.0);
  for (size_t c = 0; c < coupling.size(); ++c)
    for (const auto& [q, w] : coupling[c]) {
      out[c] += w;
      in[q] += w;
    }
  std::vector<char> child(coupling.size(), 0);
  for (size_t c = 0; c < coupling.size(); ++c) child[c] = out[c] > in[c];
  return child;
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
