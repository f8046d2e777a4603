#include "signorini/solver/condensed_solve.hpp"

#include <algorithm>
#include <cmath>

#include "signorini/core/error.hpp"

namespace signorini {

bool CondensedContactSolver::solve(const SparseMatrix& J, const std::vector<char>& is_multiplier, bool symmetric,
                                   const VecX& r, VecX& dz) {
  // Notation: a multiplier row m of J is either closed, a_m . du = r_m over displacement
  // unknowns (its own diagonal zero), or open, J_mm dl_m = r_m. The displacement rows hold
  // the multipliers' columns b_m (parallel to a_m). Eliminating the pivot DOF p of each
  // closed row, du_p = (r_m - sum_{k != p} a_mk du_k) / a_mp, gives du = T u~ + z0 with
  // a_m^T T = 0, so T^T J T u~ = T^T (r - J z0) no longer sees the multipliers. Row p of J
  // then gives dl_m = (r_p - (J dz)_p) / J_pm (Wriggers 2006, sec. 6.3, for the elimination of
  // linear constraints; here applied to the active set of each Newton iteration).
  const Index n = J.rows();
  const SparseMatrix Jt = J.transpose();  // column m of Jt is row m of J
  why_not_.clear();
  VecX z0 = VecX::Zero(n);
  std::vector<Index> closed;
  std::vector<int> count(n, 0);  // closed rows whose support holds the unknown
  for (Index m = 0; m < n; ++m) {
    if (!is_multiplier[m]) continue;
    bool has_u = false;
    Real diag = 0;
    for (SparseMatrix::InnerIterator it(Jt, m); it; ++it) {
      if (it.value() == 0) continue;
      if (it.row() == m) diag = it.value();
      else if (is_multiplier[it.row()]) {
        why_not_ = "a multiplier row couples two multipliers";
        return false;
      } else has_u = true;
    }
    if (has_u && diag != 0) {
      why_not_ = "a closed multiplier row has a diagonal";
      return false;
    }
    if (!has_u) {
      if (diag == 0) throw SolverError("a contact multiplier's row is empty: the system is singular");
      z0(m) = r(m) / diag;
      continue;
    }
    closed.push_back(m);
    for (SparseMatrix::InnerIterator it(Jt, m); it; ++it)
      if (it.value() != 0 && it.row() != m) ++count[it.row()];
  }
  // Pivots: in each closed row, the largest coefficient on an unknown no other closed row
  // touches, whose own row carries no other closed multiplier.
  std::vector<Index> pivot_of(n, -1);  // unknown -> its closed row
  std::vector<Index> pivot(closed.size(), -1);
  for (size_t c = 0; c < closed.size(); ++c) {
    const Index m = closed[c];
    Real amax = 0, best = 0;
    for (SparseMatrix::InnerIterator it(Jt, m); it; ++it)
      if (it.row() != m) amax = std::max(amax, std::abs(it.value()));
    for (SparseMatrix::InnerIterator it(Jt, m); it; ++it) {
      const Index k = it.row();
      if (k == m || count[k] != 1 || std::abs(it.value()) < 0.1 * amax || std::abs(it.value()) <= best) continue;
      if (J.coeff(k, m) == 0) continue;  // the multiplier must act on its pivot's row
      best = std::abs(it.value());
      pivot[c] = k;
    }
    if (pivot[c] < 0) {
      why_not_ = "a closed constraint has no DOF of its own (two-pass, or a slave node that is also a master node)";
      return false;
    }
    pivot_of[pivot[c]] = static_cast<Index>(c);
  }
  // The pivot's row must hold no other closed multiplier (else dl_m is not recovered alone).
  std::vector<char> is_closed(n, 0);
  for (Index m : closed) is_closed[m] = 1;
  for (size_t c = 0; c < closed.size(); ++c)
    for (SparseMatrix::InnerIterator it(Jt, pivot[c]); it; ++it)  // column p of Jt = row p of J
      if (it.value() != 0 && is_closed[it.row()] && it.row() != closed[c]) {
        why_not_ = "an eliminated DOF's row holds two closed multipliers";
        return false;
      }
  // Reduced numbering and T. Algebraic multigrid keeps the pivots' places (their columns of
  // T empty, a decoupled diagonal added below), so that the unknowns stay in node blocks.
  const bool keep_places = solver_.wants_layout();
  std::vector<Index> ridx(n, -1);
  Index nr = 0;
  for (Index k = 0; k < n; ++k)
    if (!is_multiplier[k] && (keep_places || pivot_of[k] < 0)) ridx[k] = nr++;
  std::vector<Eigen::Triplet<Real, int>> trip;
  trip.reserve(static_cast<size_t>(nr) + 16 * closed.size());
  for (Index k = 0; k < n; ++k)
    if (ridx[k] >= 0 && pivot_of[k] < 0) trip.emplace_back(static_cast<int>(k), static_cast<int>(ridx[k]), 1.0);
  for (size_t c = 0; c < closed.size(); ++c) {
    const Index m = closed[c], p = pivot[c];
    const Real ap = Jt.coeff(p, m);
    z0(p) = r(m) / ap;
    for (SparseMatrix::InnerIterator it(Jt, m); it; ++it) {
      const Index k = it.row();
      if (k == m || k == p || it.value() == 0) continue;
      trip.emplace_back(static_cast<int>(p), static_cast<int>(ridx[k]), -it.value() / ap);
    }
  }
  SparseMatrix T(n, nr);
  T.setFromTriplets(trip.begin(), trip.end());
  const SparseMatrix JT = J * T;
  SparseMatrix Kr = SparseMatrix(T.transpose()) * JT;
  if (keep_places && !closed.empty()) {
    // The pivots' rows and columns of Kr are empty: a diagonal of the mean magnitude there.
    Real mean = 0;
    for (Index k = 0; k < Kr.outerSize(); ++k) mean += std::abs(Kr.coeff(k, k));
    mean = nr ? mean / static_cast<Real>(nr) : 1.0;
    SparseMatrix D(nr, nr);
    std::vector<Eigen::Triplet<Real, int>> dt;
    for (Index p : pivot) dt.emplace_back(static_cast<int>(ridx[p]), static_cast<int>(ridx[p]), mean > 0 ? mean : 1.0);
    D.setFromTriplets(dt.begin(), dt.end());
    Kr += D;
  }
  Kr.makeCompressed();
  const VecX rr = T.transpose() * (r - J * z0);
  VecX ur;
  // The reduced pattern follows the active set and the pivots: the symbolic factorization is
  // kept while the pattern is the same as at the last solve (most Newton iterations once the
  // active set has settled) and redone when it changed.
  const bool same_pattern =
      Kr.rows() == pattern_rows_ &&
      std::equal(Kr.outerIndexPtr(), Kr.outerIndexPtr() + Kr.outerSize() + 1, pattern_outer_.begin(),
                 pattern_outer_.end()) &&
      std::equal(Kr.innerIndexPtr(), Kr.innerIndexPtr() + Kr.nonZeros(), pattern_inner_.begin(), pattern_inner_.end());
  if (!same_pattern) {
    solver_.reset();
    pattern_rows_ = Kr.rows();
    pattern_outer_.assign(Kr.outerIndexPtr(), Kr.outerIndexPtr() + Kr.outerSize() + 1);
    pattern_inner_.assign(Kr.innerIndexPtr(), Kr.innerIndexPtr() + Kr.nonZeros());
    ++analyses_;
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
  solver_.solve(Kr, symmetric, rr, ur);
  dz = T * ur + z0;
  // Closed multipliers from their pivots' rows (dz holds 0 for them so far).
  const VecX Jdz = J * dz;
  for (size_t c = 0; c < closed.size(); ++c) {
    const Index m = closed[c], p = pivot[c];
    dz(m) = (r(p) - Jdz(p)) / J.coeff(p, m);
  }
  return true;
}

}  // namespace signorini
