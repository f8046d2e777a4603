// The 2D dual mortar kinematics (contact/discretization/mortar.hpp): the segments tile the
// slave surface, the weighted gaps integrate the gap exactly, and the weighted gap with its
// gradient is continuous and matches central differences when master nodes cross slave nodes
// (the segmentation changes there); on a slave facet a master covers in part, the dual basis of
// the covered part gives each node its gap times its covered area (line2, and line3 on the
// transformed basis of self-contact), with derivatives that match central differences.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstring>
#include <sstream>

#include "signorini/contact/discretization/mortar.hpp"
#include "signorini/contact/discretization/mortar_dual.hpp"
#include "signorini/core/error.hpp"

using namespace signorini;

namespace {

// A slave curve of `ns` facets over [-1, 1] at height y_s(x) (its outward normal points
// down), over a master curve of `nm` facets over [mlo, mhi] at height y_m(x) shifted by `shift`
// in x (outward normal up); line2 facets (order 1) or line3 (order 2: corner, corner, mid-side).
// Nodes: slave first, then master. `positive`: the transformed line3 basis (self-contact's).
struct TwoCurves {
  MasterSurface slave, master;
  std::vector<Vec3> x;
  int ns, nm;
  bool positive = false;
  TwoCurves(int ns_, int nm_, Real shift, Real (*ys)(Real), Real (*ym)(Real), int order = 1, Real mlo = -1.6,
            Real mhi = 1.5, bool positive_ = false)
      : ns(ns_), nm(nm_), positive(positive_) {
    for (int i = 0; i <= order * ns; ++i) {
      const Real X = -1 + 2.0 * i / (order * ns);
      x.emplace_back(X, ys(X), 0);
    }
    for (int i = 0; i <= order * nm; ++i) {
      const Real X = mlo + (mhi - mlo) * i / (order * nm) + shift;
      x.emplace_back(X, ym(X), 0);
    }
    auto make = [&](MasterSurface& s, int first, int n, bool reverse) {
      s.node_facets.assign(x.size(), {});
      for (int i = 0; i < n; ++i) {
        std::vector<Index> f = {first + order * i, first + order * (i + 1)};
        if (reverse) std::swap(f[0], f[1]);
        if (order == 2) f.push_back(first + 2 * i + 1);
        s.type.push_back(order == 2 ? ElementType::line3 : ElementType::line2);
        s.facets.push_back(f);
        for (Index k : f) s.node_facets[k].push_back(i);
      }
      for (int i = 0; i <= order * n; ++i) s.nodes.push_back(first + i);
    };
    make(slave, 0, ns, false);                    // left to right: normal (t_y, -t_x) points down
    make(master, order * ns + 1, nm, true);       // right to left: normal up
  }
  // Weighted gap of slave node j (mesh index) with its gradient and Hessian over all nodes.
  Real weighted_gap(Index j, VecX* grad = nullptr, MatX* hess = nullptr, Real* length = nullptr) const {
    const Index n2 = 2 * static_cast<Index>(x.size());
    if (grad) grad->setZero(n2);
    if (hess) hess->setZero(n2, n2);
    Real g = 0;
    MortarMeasure ms;
    std::vector<Index> all(static_cast<size_t>(master.size()));
    for (Index m = 0; m < master.size(); ++m) all[m] = m;
    for (Index e = 0; e < slave.size(); ++e) {
      MortarFacetResult r = mortar_element_2d(slave, e, master, all, x, ms, grad != nullptr, positive);
      if (!r.overlap) continue;
      if (length && j == 0) *length += r.segment_length;
      for (size_t k = 0; k < slave.facets[e].size(); ++k) {
        if (slave.facets[e][k] != j) continue;
        g += r.gap[k];
        if (!grad) continue;
        for (size_t a = 0; a < r.nodes.size(); ++a) {
          grad->segment(2 * r.nodes[a], 2) += r.grad[k].segment(2 * a, 2);
          for (size_t b = 0; b < r.nodes.size(); ++b)
            hess->block(2 * r.nodes[a], 2 * r.nodes[b], 2, 2) += r.hess[k].block(2 * a, 2 * b, 2, 2);
        }
      }
    }
    return g;
  }
};

// The largest differences between the weighted gap's gradient and Hessian at node j and central
// differences of its value and gradient (step 1e-6), relative to their largest entries.
void central_difference_errors(const TwoCurves& c, Index j, Real& err_g, Real& err_h, Real step = 1e-6) {
  VecX g;
  MatX H;
  c.weighted_gap(j, &g, &H);
  err_g = err_h = 0;
  for (Index i = 0; i < g.size(); ++i) {
    TwoCurves p = c, m = c;
    p.x[i / 2](i % 2) += step;
    m.x[i / 2](i % 2) -= step;
    VecX gp, gm;
    MatX hp, hm;
    const Real fd = (p.weighted_gap(j, &gp, &hp) - m.weighted_gap(j, &gm, &hm)) / (2 * step);
    err_g = std::max(err_g, std::abs(fd - g(i)));
    err_h = std::max(err_h, ((gp - gm) / (2 * step) - H.col(i)).cwiseAbs().maxCoeff());
  }
  err_g /= g.cwiseAbs().maxCoeff();
  err_h /= H.cwiseAbs().maxCoeff();
}

Real flat(Real) { return 0; }
Real below(Real) { return -0.01; }
Real wavy_slave(Real X) { return 0.05 * std::sin(2 * X) + 0.02 * X * X; }
Real wavy_master(Real X) { return -0.03 + 0.04 * std::cos(3 * X) - 0.05; }

}  // namespace

TEST(Mortar, SegmentsTileTheSlaveSurface) {
  // Curved, non-matching: the segments' lengths add up to the slave curve's length.
  for (int nm : {3, 5, 11}) {
    TwoCurves c(4, nm, 0.013, wavy_slave, wavy_master);
    Real length = 0;
    c.weighted_gap(0, nullptr, nullptr, &length);
    Real exact = 0;
    for (int i = 0; i < c.ns; ++i) exact += (c.x[i + 1] - c.x[i]).norm();
    EXPECT_NEAR(length, exact, 1e-12 * exact) << nm << " master facets";
  }
}

TEST(Mortar, WeightedGapsOfAUniformGapAreItTimesTheNodalArea) {
  // Flat surfaces 0.01 apart, non-matching: g~_j = 0.01 D_jj, D_jj = int N_j (h/2 at the ends,
  // h inside), for linear dual shape functions (sum_j Phi_j = 1 and biorthogonality).
  TwoCurves c(4, 7, 0.0, flat, below);
  const Real h = 0.5;
  for (Index j = 0; j <= 4; ++j) {
    const Real D = (j == 0 || j == 4) ? h / 2 : h;
    EXPECT_NEAR(c.weighted_gap(j), 0.01 * D, 1e-15) << j;
  }
}

TEST(Mortar, WeightedGapIsSmoothWhereMasterNodesCrossSlaveNodes) {
  // Master node positions relative to the slave: the master is shifted so that a master node
  // passes the slave node at x = 0 (shift s0), and the master's curvature makes the gap vary.
  // Gradient and Hessian against central differences on both sides, and the gradient
  // continuous across.
  const int nm = 5;
  const Real s0 = -(-1.6 + 3.1 * 3 / nm);  // master node 3 at x = 0
  for (Real side : {-1.0, 1.0}) {
    TwoCurves c(4, nm, s0 + side * 1e-4, wavy_slave, wavy_master);
    Real err_g, err_h;
    central_difference_errors(c, 2, err_g, err_h);  // the slave node at x = 0
    EXPECT_LT(err_g, 1e-8) << side;
    EXPECT_LT(err_h, 1e-6) << side;
  }
  // Continuity of the value and gradient across the crossing.
  VecX ga, gb;
  MatX Ha, Hb;
  TwoCurves a(4, nm, s0 - 1e-7, wavy_slave, wavy_master), b(4, nm, s0 + 1e-7, wavy_slave, wavy_master);
  const Real va = a.weighted_gap(2, &ga, &Ha), vb = b.weighted_gap(2, &gb, &Hb);
  EXPECT_NEAR(va, vb, 1e-6 * std::abs(va));  // the shift moves it by about 2e-10
  EXPECT_LT((ga - gb).cwiseAbs().maxCoeff(), 1e-5 * ga.cwiseAbs().maxCoeff());
}


TEST(Mortar, PartlyCoveredNodeGetsItsGapTimesItsCoveredArea) {
  // A master that ends inside the last slave facet [0.5, 1] (at x = mhi), flat surfaces 0.01
  // apart. The dual basis is built on the covered part (mortar.hpp), so the weighted gap of the
  // partly covered node at x = 1 is 0.01 int_{0.5}^{mhi} N dx = 0.01 (mhi - 0.5)^2 > 0, and its
  // neighbour's 0.01 (0.25 + 0.25 - (1 - mhi)^2). (The dual basis of the whole facet,
  // 2 N_4 - N_3, integrates to 3 (mhi - 0.5)^2 - (mhi - 0.5) over the covered part: -0.0007 at
  // mhi = 0.6, a penetration read across a gap of 0.01.)
  for (Real mhi : {0.6, 0.75, 0.95}) {
    TwoCurves c(4, 7, 0.0, flat, below, 1, -1.6, mhi);
    const Real c4 = mhi - 0.5;
    EXPECT_NEAR(c.weighted_gap(4), 0.01 * c4 * c4, 1e-15) << mhi;
    EXPECT_NEAR(c.weighted_gap(3), 0.01 * (0.5 - (1 - mhi) * (1 - mhi)), 1e-15) << mhi;
    Real sum = 0;
    for (Index j = 0; j <= 4; ++j) sum += c.weighted_gap(j);
    EXPECT_NEAR(sum, 0.01 * (mhi + 1), 1e-15) << "the gap times the covered length";
  }
  // Line3 facets [-1, 0] and [0, 1], the master ending at x = mhi in the second. On its
  // transformed basis (self-contact's: N~_corner = (1 + xi)^2 / 4 >= 0) the corner at x = 1
  // gets 0.01 int_0^mhi N~ dx = 0.01 mhi^3 / 3. On the quadratic basis itself its covered area
  // int_0^mhi N dx is negative for mhi < 1/2 (N = xi (1 + xi) / 2 < 0 for xi < 0), and so is
  // its weighted gap: what the transformed basis is for.
  for (Real mhi : {0.2, 0.5, 0.9}) {
    TwoCurves t(2, 3, 0.0, flat, below, 2, -1.6, mhi, true);
    EXPECT_NEAR(t.weighted_gap(4), 0.01 * mhi * mhi * mhi / 3, 1e-15) << mhi;
    Real sum = 0;
    for (Index j = 0; j <= 4; ++j) {
      const Real g = t.weighted_gap(j);
      EXPECT_GE(g, 0) << mhi << " node " << j;
      sum += g;
    }
    EXPECT_NEAR(sum, 0.01 * (mhi + 1), 1e-15) << "the gap times the covered length";
  }
  TwoCurves q(2, 3, 0.0, flat, below, 2, -1.6, 0.2, false);
  EXPECT_LT(q.weighted_gap(4), 0) << "line3 without the transformation, covered to x = 0.2";
}

TEST(Mortar, PartlyCoveredFacetsMatchCentralDifferences) {
  // Curved, the master ending inside a slave facet: the covered part, and with it the dual
  // basis, moves with the nodes. Line2, and line3 on the transformed basis.
  for (int order : {1, 2}) {
    TwoCurves c(4, 5, 0.013, wavy_slave, wavy_master, order, -1.6, 0.62, order == 2);
    for (Index j : {Index(4 * order), Index(4 * order - 1), Index(4 * order - 2)}) {
      // Step 1e-5: the line3 dual basis of a partly covered facet amplifies round-off (at 1e-6
      // the differences' round-off reaches 2e-6 of the Hessian; at 1e-4 their truncation 4e-7).
      Real err_g, err_h;
      central_difference_errors(c, j, err_g, err_h, 1e-5);
      EXPECT_LT(err_g, 1e-8) << "order " << order << " node " << j;
      EXPECT_LT(err_h, 1e-6) << "order " << order << " node " << j;
    }
  }
}

TEST(Mortar, SliverOfCoverIsLeftOut) {
  // A facet covered on less than 1e-3 of its parameter range has no overlap (its dual basis
  // would be ill-conditioned; its weighted gaps are of the order of the cover).
  MortarMeasure ms;
  for (auto [share, overlap] : {std::pair{5e-4, false}, std::pair{2e-3, true}}) {
    TwoCurves c(4, 7, 0.0, flat, below, 1, -1.6, 0.5 + 0.5 * share);
    const MortarFacetResult r = mortar_element_2d(c.slave, 3, c.master, {0, 1, 2, 3, 4, 5, 6}, c.x, ms, false);
    EXPECT_EQ(r.overlap, overlap) << share;
  }
}

TEST(Mortar, SlipCombinationMeasuresTheRelativeMotion) {
  // Friction's slip (mortar.hpp, `relative`, `slip_weight`): per slave node, the dual-weighted
  // int Phi_j (x_s - x_m(chi)) over its facets' segments as a combination of nodes. Its slave
  // coefficients sum to its weight and its master ones to minus it (a rigid translation of both
  // curves gives no slip); on flat curves 0.01 apart it gives (0, 0.01) (the points pair along
  // the normal), and with the coefficients frozen, a master moved by 0.03 along x gives
  // (-0.03, 0.01). Biorthogonality: node j's slave coefficients are its weight times column j of
  // T^-1 (N~ = T N, line3's non-negative basis), none on the facet's neighbours: on line2 its own
  // position alone. A master ending inside the last facet (x = 0.8), line2 and line3.
  for (int order : {1, 2}) {
    const int ns = order + 1;
    const mortar_detail::BasisTransform tr = mortar_detail::basis_transform(2, ns, true);
    MatX T = MatX::Identity(ns, ns);
    if (!tr.identity)
      for (int i = 0; i < ns; ++i)
        for (int l = 0; l < ns; ++l) T(i, l) = tr.t[i][l];
    const MatX Tinv = T.inverse();
    TwoCurves c(4, 7, 0.0, flat, below, order, -1.6, 0.8);
    std::vector<Index> all(static_cast<size_t>(c.master.size()));
    for (Index m = 0; m < c.master.size(); ++m) all[m] = m;
    const Index first_master = order * 4 + 1;
    std::vector<Vec3> moved = c.x;
    for (size_t i = first_master; i < moved.size(); ++i) moved[i].x() += 0.03;
    for (Index e = 0; e < c.slave.size(); ++e) {
      const MortarFacetResult r = mortar_element_2d(c.slave, e, c.master, all, c.x, MortarMeasure{}, false);
      ASSERT_TRUE(r.overlap) << e;
      ASSERT_EQ(r.relative.size(), c.slave.facets[e].size());
      for (size_t k = 0; k < r.relative.size(); ++k) {
        Real slave_sum = 0, master_sum = 0;
        Vec3 now = Vec3::Zero(), after = Vec3::Zero();
        for (size_t a = 0; a < r.nodes.size(); ++a) {
          const Real w = r.relative[k](static_cast<Index>(a));
          (r.nodes[a] < first_master ? slave_sum : master_sum) += w;
          now += w * c.x[r.nodes[a]];
          after += w * moved[r.nodes[a]];
        }
        const Real W = r.slip_weight[k];
        ASSERT_GT(W, 0) << "order " << order << " facet " << e << " node " << k;
        EXPECT_NEAR(slave_sum, W, 1e-14) << order;
        EXPECT_NEAR(master_sum, -W, 1e-14) << order;
        EXPECT_NEAR(now.x() / W, 0, 1e-14) << order;
        EXPECT_NEAR(now.y() / W, 0.01, 1e-14) << order;
        EXPECT_NEAR(after.x() / W, -0.03, 1e-14) << order;
        EXPECT_NEAR(after.y() / W, 0.01, 1e-14) << order;
        for (size_t a = 0; a < r.nodes.size(); ++a) {
          if (r.nodes[a] >= first_master) continue;
          const auto& f = c.slave.facets[e];
          const auto it = std::find(f.begin(), f.end(), r.nodes[a]);
          const Real expected = it == f.end() ? 0.0 : Tinv(it - f.begin(), static_cast<Index>(k));
          EXPECT_NEAR(r.relative[k](static_cast<Index>(a)) / W, expected, 1e-12)
              << "order " << order << " facet " << e << " node " << k << " slave node " << r.nodes[a];
        }
      }
    }
  }
}

TEST(Mortar, FacetResultCrossesBetweenRanksBitForBit) {
  // A shared-out build (Discretization::set_rank_exchange) sends each facet's result to the other
  // ranks as bytes: read back, every field is the one written, bit for bit (the ranks then go on
  // with the same constraints), with its Hessians and the friction's combinations; bytes cut
  // short are an error, not a silently shorter result.
  TwoCurves c(4, 7, 0.013, wavy_slave, wavy_master, 2);
  std::vector<Index> all(static_cast<size_t>(c.master.size()));
  for (Index m = 0; m < c.master.size(); ++m) all[m] = m;
  std::ostringstream os;
  std::vector<MortarFacetResult> written;
  for (Index e = 0; e < c.slave.size(); ++e) {
    written.push_back(mortar_element_2d(c.slave, e, c.master, all, c.x, MortarMeasure{}, true));
    write_facet_result(os, written.back());
  }
  written.push_back(MortarFacetResult{});  // no overlap, empty fields
  write_facet_result(os, written.back());
  const std::string bytes = os.str();
  std::istringstream is(bytes);
  for (const MortarFacetResult& w : written) {
    const MortarFacetResult r = read_facet_result(is);
    EXPECT_EQ(r.overlap, w.overlap);
    EXPECT_EQ(r.masters, w.masters);
    EXPECT_EQ(r.facet, w.facet);
    EXPECT_EQ(std::memcmp(&r.segment_length, &w.segment_length, sizeof(Real)), 0);
    EXPECT_EQ(r.nodes, w.nodes);
    EXPECT_EQ(r.gap, w.gap);
    EXPECT_EQ(r.slip_weight, w.slip_weight);
    ASSERT_EQ(r.grad.size(), w.grad.size());
    ASSERT_EQ(r.hess.size(), w.hess.size());
    ASSERT_EQ(r.relative.size(), w.relative.size());
    for (size_t k = 0; k < w.grad.size(); ++k) EXPECT_TRUE(r.grad[k] == w.grad[k]) << k;
    for (size_t k = 0; k < w.hess.size(); ++k) {
      ASSERT_EQ(r.hess[k].rows(), w.hess[k].rows());
      ASSERT_EQ(r.hess[k].cols(), w.hess[k].cols());
      EXPECT_TRUE(r.hess[k] == w.hess[k]) << k;
    }
    for (size_t k = 0; k < w.relative.size(); ++k) EXPECT_TRUE(r.relative[k] == w.relative[k]) << k;
  }
  EXPECT_EQ(is.peek(), std::char_traits<char>::eof());
  ASSERT_TRUE(written[1].overlap && !written[1].hess.empty() && written[1].hess[0].size() > 0);
  std::istringstream cut(bytes.substr(0, bytes.size() / 3));
  EXPECT_THROW(
      {
        for (size_t i = 0; i < written.size(); ++i) read_facet_result(cut);
      },
      Error);
}
