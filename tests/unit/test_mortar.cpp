// The 2D dual mortar kinematics (contact/discretization/mortar.hpp): the segments tile the
// slave surface, the weighted gaps integrate the gap exactly, and the weighted gap with its
// gradient is continuous and matches central differences when master nodes cross slave nodes
// (the segmentation changes there).
#include <gtest/gtest.h>

#include <cmath>

#include "signorini/contact/discretization/mortar.hpp"

using namespace signorini;

namespace {

// A slave curve of `ns` line2 facets over [-1, 1] at height y_s(x) (its outward normal points
// down), over a master curve of `nm` facets over [-1.6, 1.5] at height y_m(x) shifted by
// `shift` in x (outward normal up). Nodes: slave first, then master.
struct TwoCurves {
  MasterSurface slave, master;
  std::vector<Vec3> x;
  int ns, nm;
  TwoCurves(int ns_, int nm_, Real shift, Real (*ys)(Real), Real (*ym)(Real)) : ns(ns_), nm(nm_) {
    for (int i = 0; i <= ns; ++i) {
      const Real X = -1 + 2.0 * i / ns;
      x.emplace_back(X, ys(X), 0);
    }
    for (int i = 0; i <= nm; ++i) {
      const Real X = -1.6 + 3.1 * i / nm + shift;
      x.emplace_back(X, ym(X), 0);
    }
    auto make = [&](MasterSurface& s, int first, int n, bool reverse) {
      s.node_facets.assign(x.size(), {});
      for (int i = 0; i < n; ++i) {
        std::vector<Index> f = {first + i, first + i + 1};
        if (reverse) std::swap(f[0], f[1]);
        s.type.push_back(ElementType::line2);
        s.facets.push_back(f);
        for (Index k : f) s.node_facets[k].push_back(i);
      }
      for (int i = 0; i <= n; ++i) s.nodes.push_back(first + i);
    };
    make(slave, 0, ns, false);       // left to right: normal (t_y, -t_x) points down
    make(master, ns + 1, nm, true);  // right to left: normal up
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
        MortarFacetResult r = mortar_element_2d(slave, e, master, all, x, ms, grad != nullptr);
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
    VecX g;
    MatX H;
    const Index j = 2;  // the slave node at x = 0
    c.weighted_gap(j, &g, &H);
    const Real step = 1e-6;
    Real err_g = 0, err_h = 0;
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
    EXPECT_LT(err_g, 1e-8 * g.cwiseAbs().maxCoeff()) << side;
    EXPECT_LT(err_h, 1e-6 * H.cwiseAbs().maxCoeff()) << side;
  }
  // Continuity of the value and gradient across the crossing.
  VecX ga, gb;
  MatX Ha, Hb;
  TwoCurves a(4, nm, s0 - 1e-7, wavy_slave, wavy_master), b(4, nm, s0 + 1e-7, wavy_slave, wavy_master);
  const Real va = a.weighted_gap(2, &ga, &Ha), vb = b.weighted_gap(2, &gb, &Hb);
  EXPECT_NEAR(va, vb, 1e-6 * std::abs(va));  // the shift moves it by about 2e-10
  EXPECT_LT((ga - gb).cwiseAbs().maxCoeff(), 1e-5 * ga.cwiseAbs().maxCoeff());
}

