#include "signorini/solver/multiplier_blocks.hpp"

#include <algorithm>
#include <functional>

#include "signorini/core/error.hpp"

namespace signorini {

namespace {
int place(const std::vector<Index>& v, Index k) {
  return static_cast<int>(std::lower_bound(v.begin(), v.end(), k) - v.begin());
}
}  // namespace

MultiplierBlocks analyse_multiplier_blocks(Index n, const std::vector<char>& is_multiplier, const std::vector<Index>& mult,
                                           const std::vector<std::vector<std::pair<Index, Real>>>& rows,
                                           const std::vector<std::vector<std::pair<Index, Real>>>& cols) {
  MultiplierBlocks mb;
  const Index nm = static_cast<Index>(mult.size());
  auto slot = [&](Index m) { return place(mult, m); };
  // The blocks: multipliers connected through their rows' pattern (union-find on the slots): a
  // node's normal and tangential multipliers, whose closed rows share the node's DOFs.
  std::vector<Index> parent(static_cast<size_t>(nm));
  for (Index i = 0; i < nm; ++i) parent[i] = i;
  auto find = [&](Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (Index i = 0; i < nm; ++i)
    for (const auto& [k, v] : rows[i])
      if (is_multiplier[k]) {
        const Index a = find(i), b = find(slot(k));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
  std::vector<Index> block_of(static_cast<size_t>(nm), -1);
  std::vector<MultiplierBlock>& blocks = mb.blocks;
  for (Index i = 0; i < nm; ++i) {
    const Index root = find(i);
    if (block_of[root] < 0) block_of[root] = static_cast<Index>(blocks.size()), blocks.emplace_back();
    block_of[i] = block_of[root];
    blocks[block_of[i]].l.push_back(mult[i]);
  }
  std::vector<int> count(static_cast<size_t>(n), 0), acting(static_cast<size_t>(n), 0);  // closed blocks whose rows (columns) hold the DOF
  for (MultiplierBlock& b : blocks) {
    const int s = static_cast<int>(b.l.size());
    for (Index m : b.l) {
      for (const auto& [k, v] : rows[slot(m)])
        if (!is_multiplier[k]) b.cu.push_back(k);
      for (const auto& [i, v] : cols[slot(m)]) b.bu.push_back(i);
    }
    for (auto* v : {&b.cu, &b.bu}) {
      std::sort(v->begin(), v->end());
      v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    MatX M = MatX::Zero(s, s), B = MatX::Zero(static_cast<Index>(b.bu.size()), s);
    b.C = MatX::Zero(s, static_cast<Index>(b.cu.size()));
    for (int a = 0; a < s; ++a) {
      for (const auto& [k, v] : rows[slot(b.l[a])])
        if (is_multiplier[k]) M(a, place(b.l, k)) += v;
        else b.C(a, place(b.cu, k)) += v;
      for (const auto& [i, v] : cols[slot(b.l[a])]) B(place(b.bu, i), a) += v;
    }
    Eigen::JacobiSVD<MatX> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    VecX sigma = svd.singularValues();
    const Real smax = s > 0 ? sigma(0) : 0.0;
    int rank = 0;
    while (rank < s && sigma(rank) > kNullSingular * smax) ++rank;
    for (int a = 0; a < rank; ++a)
      if (sigma(a) < kClampedSingular * smax) sigma(a) = kClampedSingular * smax, mb.approximate = true;
    const int k = s - rank;
    b.V1 = svd.matrixV().leftCols(rank);
    b.V0 = svd.matrixV().rightCols(k);
    b.U0t = svd.matrixU().rightCols(k).transpose();
    b.SU1t = sigma.head(rank).cwiseInverse().asDiagonal() * svd.matrixU().leftCols(rank).transpose();
    b.W = B * b.V1 * b.SU1t;
    b.Ct = b.U0t * b.C;
    b.Bt = B * b.V0;
    if (k > 0 && (b.Ct.size() == 0 || !(b.Ct.cwiseAbs().maxCoeff() > 0)))
      throw SolverError("a contact multiplier's row is empty: the system is singular");
    if (rank > 0) {
      const MatX delta = -b.W * b.C;
      for (Index i = 0; i < delta.rows(); ++i)
        for (Index j = 0; j < delta.cols(); ++j) mb.delta.push_back({{b.bu[i], b.cu[j]}, delta(i, j)});
    }
    if (k == 0) continue;
    for (Index j = 0; j < b.Ct.cols(); ++j)
      if (b.Ct.col(j).cwiseAbs().maxCoeff() > 0) ++count[b.cu[j]];
    for (Index i = 0; i < b.Bt.rows(); ++i)
      if (b.Bt.row(i).cwiseAbs().maxCoeff() > 0) ++acting[b.bu[i]];
  }
  // Dependent closed rows (the whole system singular but for round-off): on a symmetry axis a
  // slave node and its master node move along the axis only, and while the master facet is
  // tilted (the first iterations of a press) the stick row across the slip is a multiple of
  // the gap row, the multipliers' columns likewise (the enforcement releases such directions
  // once the normal is the axis, prescribed_slip_directions). The dependent combinations of the
  // rows, and of the multipliers, are released: not eliminated, their multipliers' step zero,
  // where a factorization of the whole system divides by round-off.
  for (MultiplierBlock& b : blocks) {
    const int k = static_cast<int>(b.Ct.rows());
    if (k <= 1) continue;
    Eigen::JacobiSVD<MatX> sc(b.Ct, Eigen::ComputeFullU), sb(b.Bt, Eigen::ComputeFullV);
    auto rank_of = [&](const VecX& sv) {
      int q = 0;
      while (q < sv.size() && sv(q) > kDependentRows * sv(0)) ++q;
      return q;
    };
    const int kr = std::min(rank_of(sc.singularValues()), rank_of(sb.singularValues()));
    if (kr < k) {
      mb.released += k - kr;
      const MatX uc = sc.matrixU().leftCols(kr), vb = sb.matrixV().leftCols(kr);
      b.U0t = (uc.transpose() * b.U0t).eval();
      b.Ct = (uc.transpose() * b.Ct).eval();
      b.V0 = (b.V0 * vb).eval();
      b.Bt = (b.Bt * vb).eval();
    }
  }
  // Pivots: per block with closed rows, k DOFs chosen for the best conditioned C~_P and B~_P
  // among its candidates (the 8 best ranked by their column of C~ and row of B~: the slave
  // node's DOFs first, as a rule, whose coefficients are 1 where a master node's are its shape
  // function; a node alone on a quad8 master facet has 27, C(27, 3) subsets). Exclusive pass: the
  // candidates are DOFs that no other block's closed rows touch and on whose rows only the
  // block's own multipliers act, and the elimination is exact. Coupled pass, where a block has
  // none (mortar's friction: a node's weighted gap and slip rows also see its facets' other
  // nodes): any DOF of the block not yet another block's pivot, and the other blocks' entries at
  // a block's pivots (their C~ columns and B~ rows there) are left out of T and Z, so that the
  // elimination is that of a nearby matrix (`approximate`: flexible GMRES on J corrects it, as
  // for the coupled rows of the frictionless condensation).
  auto choose = [&](bool coupled) -> std::string {
    mb.pivot_of.assign(static_cast<size_t>(n), -1);
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      MultiplierBlock& b = blocks[bi];
      b.pivot.clear();
      const int k = static_cast<int>(b.Ct.rows());
      if (k == 0) continue;
      std::vector<int> cand;  // places in cu
      for (int j = 0; j < static_cast<int>(b.cu.size()); ++j) {
        const Index d = b.cu[j];
        if (!(b.Ct.col(j).cwiseAbs().maxCoeff() > 0)) continue;
        if (coupled ? mb.pivot_of[d] >= 0 : (count[d] != 1 || acting[d] != 1)) continue;
        const int pb = place(b.bu, d);  // this block's multipliers must act on the DOF's row
        if (pb < static_cast<int>(b.bu.size()) && b.bu[pb] == d && b.Bt.row(pb).cwiseAbs().maxCoeff() > 0)
          cand.push_back(j);
      }
      if (cand.empty())
        return "a node's closed constraints have no DOF of their own (two-pass, or a slave node that is also a "
               "master node)";
      // In the coupled pass the closed rows of C~ and the columns of B~ are measured at unit norm:
      // mortar's gap rows (c w) and stick rows (c_T w) are orders apart, and scaling them changes
      // neither T_P nor Z_P.
      MatX Cs = b.Ct, Bs = b.Bt;
      if (coupled) {
        for (Index a = 0; a < Cs.rows(); ++a)
          if (const Real q = Cs.row(a).norm(); q > 0) Cs.row(a) /= q;
        for (Index a = 0; a < Bs.cols(); ++a)
          if (const Real q = Bs.col(a).norm(); q > 0) Bs.col(a) /= q;
      }
      const Real cmax = Cs.cwiseAbs().maxCoeff(), bmax = Bs.cwiseAbs().maxCoeff();
      if (static_cast<int>(cand.size()) > kPivotCandidates) {
        std::vector<std::pair<Real, int>> scored;
        for (int j : cand)
          scored.emplace_back(std::min(Cs.col(j).norm() / cmax, Bs.row(place(b.bu, b.cu[j])).norm() / bmax), j);
        std::stable_sort(scored.begin(), scored.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
        cand.clear();
        for (int c = 0; c < kPivotCandidates; ++c) cand.push_back(scored[static_cast<size_t>(c)].second);
      }
      Real best = 0;
      std::vector<int> pick(static_cast<size_t>(k)), chosen;
      std::function<void(int, int)> subsets = [&](int from, int depth) {
        if (depth == k) {
          MatX cp(k, k), bp(k, k);
          for (int a = 0; a < k; ++a) {
            cp.col(a) = Cs.col(cand[pick[a]]);
            bp.row(a) = Bs.row(place(b.bu, b.cu[cand[pick[a]]]));
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
      if (static_cast<int>(cand.size()) >= k) subsets(0, 0);
      if (best < kPivotQuality)
        return static_cast<int>(cand.size()) < k
                   ? "a node's closed constraints have too few DOFs of their own (two-pass, or a slave node that is "
                     "also a master node)"
                   : "a node's closed constraints have no well-conditioned block of DOFs of their own";
      for (int a = 0; a < k; ++a) {
        b.pivot.push_back(b.cu[cand[chosen[a]]]);
        mb.pivot_of[b.pivot.back()] = static_cast<Index>(bi);
      }
    }
    return std::string();
  };
  std::string why = choose(false);
  if (!why.empty()) {
    const std::string coupled_why = choose(true);
    if (!coupled_why.empty()) {
      mb.why_not = why + ", nor pivots shared among the blocks (" + coupled_why + ")";
      return mb;
    }
    mb.coupled = mb.approximate = true;
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      MultiplierBlock& b = blocks[bi];
      if (b.pivot.empty()) continue;
      for (size_t j = 0; j < b.cu.size(); ++j)
        if (const Index o = mb.pivot_of[b.cu[j]]; o >= 0 && o != static_cast<Index>(bi)) b.Ct.col(static_cast<Index>(j)).setZero();
      for (size_t i = 0; i < b.bu.size(); ++i)
        if (const Index o = mb.pivot_of[b.bu[i]]; o >= 0 && o != static_cast<Index>(bi)) b.Bt.row(static_cast<Index>(i)).setZero();
    }
  }
  for (MultiplierBlock& b : blocks) {
    const int k = static_cast<int>(b.pivot.size());
    if (k == 0) continue;
    MatX cp(k, k), bp(k, k);
    for (int a = 0; a < k; ++a) {
      cp.col(a) = b.Ct.col(place(b.cu, b.pivot[a]));
      bp.row(a) = b.Bt.row(place(b.bu, b.pivot[a]));
    }
    b.CtP.compute(cp);
    b.BtP.compute(bp);
    b.Tp = -b.CtP.solve(b.Ct);
    b.Zp = -bp.transpose().partialPivLu().solve(b.Bt.transpose());
  }
  mb.delta_in_reduced.assign(mb.delta.size(), 1);
  if (mb.coupled) {
    std::vector<Real> largest(static_cast<size_t>(n), 0.0);
    for (const auto& [ij, v] : mb.delta) largest[ij.first] = std::max(largest[ij.first], std::abs(v));
    for (size_t e = 0; e < mb.delta.size(); ++e)
      mb.delta_in_reduced[e] = std::abs(mb.delta[e].second) >= kSharedDofsDrop * largest[mb.delta[e].first.first];
  }
  return mb;
}

bool in_reduced_matrix(const MultiplierBlocks& mb, const MultiplierBlock& b, Index a, bool z, size_t j) {
  if (mb.pivot_of[(z ? b.bu : b.cu)[j]] >= 0) return false;
  return !mb.coupled || std::abs((z ? b.Zp : b.Tp)(a, static_cast<Index>(j))) >= kSharedDofsDrop;
}

void blocks_reduce_rhs(const MultiplierBlocks& mb, const VecX& rhs, VecX& rt, VecX& z0) {
  rt = rhs;
  z0 = VecX::Zero(rhs.size());
  for (const MultiplierBlock& b : mb.blocks) {
    VecX v(static_cast<Index>(b.l.size()));
    for (size_t a = 0; a < b.l.size(); ++a) v(static_cast<Index>(a)) = rhs(b.l[a]), rt(b.l[a]) = 0;
    const VecX w = b.W * v;
    for (size_t i = 0; i < b.bu.size(); ++i) rt(b.bu[i]) -= w(static_cast<Index>(i));
    if (b.pivot.empty()) continue;
    const VecX zp = b.CtP.solve(b.U0t * v);
    for (size_t a = 0; a < b.pivot.size(); ++a) z0(b.pivot[a]) = zp(static_cast<Index>(a));
  }
}

void blocks_recover_multipliers(const MultiplierBlocks& mb, const VecX& rhs, const VecX& rt, const VecX& Ku, VecX& out) {
  for (const MultiplierBlock& b : mb.blocks) {
    VecX rl(static_cast<Index>(b.l.size())), cu(static_cast<Index>(b.cu.size()));
    for (size_t a = 0; a < b.l.size(); ++a) rl(static_cast<Index>(a)) = rhs(b.l[a]);
    for (size_t j = 0; j < b.cu.size(); ++j) cu(static_cast<Index>(j)) = out(b.cu[j]);
    VecX dl = b.V1 * (b.SU1t * (rl - b.C * cu));
    if (!b.pivot.empty()) {
      VecX rp(static_cast<Index>(b.pivot.size()));
      for (size_t a = 0; a < b.pivot.size(); ++a) rp(static_cast<Index>(a)) = rt(b.pivot[a]) - Ku(b.pivot[a]);
      dl += b.V0 * b.BtP.solve(rp);
    }
    for (size_t a = 0; a < b.l.size(); ++a) out(b.l[a]) = dl(static_cast<Index>(a));
  }
}

}  // namespace signorini
