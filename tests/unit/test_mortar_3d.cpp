// The 3D dual mortar kinematics on linear and quadratic facets (contact/discretization/mortar_3d.cpp): the
// clipped cells tile the slave surface without gap or overlap (their areas sum to the slave's
// area, and a uniform gap gives every node its gap times its nodal area), and the weighted gaps'
// gradients and Hessians match central differences on curved, rotated, non-matching sheets
// where the master covers some slave facets only in part; linear and quadratic facets on both
// sides (tri3, quad4, tri6, quad8, quad9).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "signorini/contact/discretization/mortar.hpp"
#include "signorini/contact/discretization/mortar_dual.hpp"

using namespace signorini;

namespace {

// A slave sheet of n x n squares over [-1, 1]^2 at height zs(x, y) (outward normal up, +z),
// under a master sheet of m x m squares over [lo, hi]^2, rotated by `angle` about z, at height
// zm(x, y) (outward normal down). Facets of `nodes` nodes: quad4, quad8, quad9 (one per square)
// or tri3, tri6 (two per square); quadratic ones on a grid of half the spacing (a quad8's
// centre node belongs to no facet). Nodes: slave first.
struct TwoSheets {
  MasterSurface slave, master;
  std::vector<Vec3> x;
  TwoSheets(int n, int slave_nodes, int m, int master_nodes, Real lo, Real hi, Real angle, Real (*zs)(Real, Real),
            Real (*zm)(Real, Real)) {
    auto sheet = [&](MasterSurface& s, int k, int nodes, Real a, Real b, Real rot, Real (*z)(Real, Real), bool up) {
      const Index first = static_cast<Index>(x.size());
      const int q = nodes <= 4 ? 1 : 2, kq = k * q;  // grid points per square side
      for (int j = 0; j <= kq; ++j)
        for (int i = 0; i <= kq; ++i) {
          const Real u = a + (b - a) * i / kq, v = a + (b - a) * j / kq;
          const Real X = std::cos(rot) * u - std::sin(rot) * v, Y = std::sin(rot) * u + std::cos(rot) * v;
          x.emplace_back(X, Y, z(X, Y));
        }
      auto id = [&](int i, int j) { return first + j * (kq + 1) + i; };
      // Corners first, then mid-sides (edge c_i - c_i+1), then the centre; reversed (normal down)
      // by reversing the corners and their edges.
      auto add = [&](std::vector<Index> c, std::vector<Index> mid, Index centre) {
        if (!up) {
          std::reverse(c.begin() + 1, c.end());
          std::reverse(mid.begin(), mid.end());
        }
        std::vector<Index> f = c;
        if (nodes > 4) f.insert(f.end(), mid.begin(), mid.end());
        if (nodes == 9) f.push_back(centre);
        static const ElementType types[10] = {ElementType::tri3, ElementType::tri3, ElementType::tri3,
                                              ElementType::tri3, ElementType::quad4, ElementType::tri3,
                                              ElementType::tri6, ElementType::tri3, ElementType::quad8,
                                              ElementType::quad9};
        s.type.push_back(types[nodes]);
        s.facets.push_back(f);
      };
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i) {
          const int I = q * i, J = q * j, h = q == 2 ? 1 : 0;
          if (nodes == 3 || nodes == 6) {
            add({id(I, J), id(I + q, J), id(I + q, J + q)}, {id(I + h, J), id(I + q, J + h), id(I + h, J + h)}, -1);
            add({id(I, J), id(I + q, J + q), id(I, J + q)}, {id(I + h, J + h), id(I + h, J + q), id(I, J + h)}, -1);
          } else {
            add({id(I, J), id(I + q, J), id(I + q, J + q), id(I, J + q)},
                {id(I + h, J), id(I + q, J + h), id(I + h, J + q), id(I, J + h)}, id(I + h, J + h));
          }
        }
      for (int i = 0; i < (kq + 1) * (kq + 1); ++i) s.nodes.push_back(first + i);
    };
    sheet(slave, n, slave_nodes, -1, 1, 0, zs, true);
    sheet(master, m, master_nodes, lo, hi, angle, zm, false);
    for (MasterSurface* s : {&slave, &master}) {
      s->node_facets.assign(x.size(), {});
      for (Index f = 0; f < s->size(); ++f)
        for (Index k : s->facets[f]) s->node_facets[k].push_back(f);
    }
  }
  // The weighted gap of every slave node (mesh index), with gradients and Hessians over all nodes.
  std::vector<Real> weighted_gaps(std::vector<VecX>* grad = nullptr, std::vector<MatX>* hess = nullptr,
                                  Real* area = nullptr) const {
    const Index nd = 3 * static_cast<Index>(x.size());
    const size_t ns = slave.nodes.size();
    std::vector<Real> g(ns, 0.0);
    if (grad) grad->assign(ns, VecX::Zero(nd));
    if (hess) hess->assign(ns, MatX::Zero(nd, nd));
    std::vector<Index> all(static_cast<size_t>(master.size()));
    for (Index m = 0; m < master.size(); ++m) all[m] = m;
    for (Index e = 0; e < slave.size(); ++e) {
      const MortarFacetResult r = mortar_element_3d(slave, e, master, all, x, grad != nullptr, hess != nullptr);
      if (!r.overlap) continue;
      if (area) *area += r.segment_length;
      for (size_t k = 0; k < slave.facets[e].size(); ++k) {
        const Index j = slave.facets[e][k];
        g[j] += r.gap[k];
        if (!grad) continue;
        for (size_t a = 0; a < r.nodes.size(); ++a) {
          (*grad)[j].segment(3 * r.nodes[a], 3) += r.grad[k].segment(3 * a, 3);
          if (!hess) continue;
          for (size_t b = 0; b < r.nodes.size(); ++b)
            (*hess)[j].block(3 * r.nodes[a], 3 * r.nodes[b], 3, 3) += r.hess[k].block(3 * a, 3 * b, 3, 3);
        }
      }
    }
    return g;
  }
};

Real flat0(Real, Real) { return 0; }
Real flat_gap(Real, Real) { return 0.1; }
Real dome(Real X, Real Y) { return -0.15 * (X * X + 0.6 * Y * Y) + 0.05 * X; }
Real wavy(Real X, Real Y) { return 0.04 + 0.08 * X - 0.05 * Y + 0.1 * X * Y - 0.05 * Y * Y; }

// Facet types by node count: 3 tri3, 4 quad4, 6 tri6, 8 quad8, 9 quad9.
struct Pairing {
  int slave, master;
  int slave_nodes() const { return slave; }
  int masters() const { return master; }
};
// Every linear slave on every master facet type, and every quadratic slave on linear and
// quadratic masters.
const Pairing kPairings[] = {{4, 4}, {4, 3}, {3, 4}, {3, 3}, {4, 6}, {3, 8}, {4, 9}, {3, 9}, {3, 6}, {4, 8},
                             {6, 3}, {6, 4}, {6, 6}, {6, 8}, {6, 9}, {8, 4}, {8, 6}, {8, 8}, {9, 3}, {9, 8},
                             {9, 9}};
std::string pairing_name(const Pairing& p) {
  static const char* names[10] = {"", "", "", "tri3", "quad4", "", "tri6", "", "quad8", "quad9"};
  return std::string(names[p.slave]) + " on " + names[p.master];
}
// The share of a flat facet's area that is node k's weight int N~_k dA (N~ the basis the dual
// basis is built on, mortar_dual.hpp): tri3 1/3, quad4 1/4; tri6 (Bernstein: lambda_i^2,
// 2 lambda_i lambda_j) 1/6 each; quad9 (tensor Bernstein) 1/9 each; quad8 with alpha = 3/8:
// corners -1/12 + 2 (3/8) (1/3) = 1/6, mid-sides (1/4) (1/3) = 1/12.
Real weight_share(int nodes, int k) {
  switch (nodes) {
    case 3: return 1.0 / 3;
    case 4: return 0.25;
    case 6: return 1.0 / 6;
    case 8: return k < 4 ? 1.0 / 6 : 1.0 / 12;
    default: return 1.0 / 9;
  }
}

}  // namespace

// Flat sheets 0.1 apart, the master grid rotated by 0.3 rad and covering the whole slave: the
// cells' areas sum to the slave's area 4 and each node's weighted gap is 0.1 times its nodal
// area int N~_j dA (its share of the facets around it), to round-off.
TEST(Mortar3d, CellsTileTheSlaveAndAUniformGapIsExact) {
  for (const Pairing& p : kPairings) {
    SCOPED_TRACE(pairing_name(p));
    const int n = 3;
    const TwoSheets s(n, p.slave_nodes(), 4, p.masters(), -1.6, 1.6, 0.3, flat0, flat_gap);
    Real area = 0;
    const std::vector<Real> g = s.weighted_gaps(nullptr, nullptr, &area);
    EXPECT_NEAR(area, 4.0, 1e-12) << "the cells tile the slave sheet";
    const Real h = 2.0 / n;
    std::vector<Real> nodal(g.size(), 0.0);
    for (Index f = 0; f < s.slave.size(); ++f) {
      const auto& fc = s.slave.facets[f];
      const Real area = fc.size() == 3 || fc.size() == 6 ? h * h / 2 : h * h;
      for (size_t k = 0; k < fc.size(); ++k) nodal[fc[k]] += weight_share(p.slave_nodes(), static_cast<int>(k)) * area;
    }
    for (size_t node = 0; node < g.size(); ++node) {
      if (p.slave_nodes() == 8 && nodal[node] == 0) continue;  // a quad8's centre: in no facet
      EXPECT_GT(nodal[node], 0);
      EXPECT_NEAR(g[node], 0.1 * nodal[node], 1e-13) << "node " << node;
    }
  }
}

// Curved, tilted sheets; the rotated master covers part of the slave only (facets partly
// covered along two sides): gradients of every slave node's weighted gap against central
// differences in every coordinate, Hessians along 8 directions.
TEST(Mortar3d, WeightedGapsMatchCentralDifferences) {
  for (const Pairing& p : kPairings) {
    SCOPED_TRACE(pairing_name(p));
    TwoSheets s(2, p.slave_nodes(), 3, p.masters(), -0.83, 1.4, 0.37, dome, wavy);
    std::vector<VecX> grad;
    std::vector<MatX> hess;
    const std::vector<Real> g = s.weighted_gaps(&grad, &hess);
    int covered = 0;
    for (size_t j = 0; j < g.size(); ++j) covered += g[j] != 0;
    ASSERT_GE(covered, 4) << "the master overlaps the slave";
    const Real step = 1e-6;
    Real max_grad = 0, max_hess = 0, err_grad = 0, err_hess = 0;
    for (size_t j = 0; j < g.size(); ++j) max_grad = std::max(max_grad, grad[j].cwiseAbs().maxCoeff()),
                                          max_hess = std::max(max_hess, hess[j].cwiseAbs().maxCoeff());
    // The gradient coordinate by coordinate (values only); the Hessian along 8 pseudo-random
    // directions d, against the central difference of the gradient along d.
    const Index nd = 3 * static_cast<Index>(s.x.size());
    for (Index c = 0; c < nd; ++c) {
      Real& xc = s.x[c / 3](c % 3);
      const Real x0 = xc;
      xc = x0 + step;
      const std::vector<Real> fp = s.weighted_gaps();
      xc = x0 - step;
      const std::vector<Real> fm = s.weighted_gaps();
      xc = x0;
      for (size_t j = 0; j < g.size(); ++j)
        err_grad = std::max(err_grad, std::abs((fp[j] - fm[j]) / (2 * step) - grad[j](c)));
    }
    unsigned seed = 12345;
    auto random = [&] {
      seed = seed * 1103515245u + 12345u;
      return static_cast<Real>((seed >> 8) % 2001) / 1000.0 - 1.0;
    };
    for (int k = 0; k < 8; ++k) {
      VecX d(nd);
      for (Index c = 0; c < nd; ++c) d(c) = random();
      const std::vector<Vec3> x0 = s.x;
      std::vector<VecX> gp, gm;  // gradients only (first-order dual numbers)
      for (Index c = 0; c < nd; ++c) s.x[c / 3](c % 3) = x0[c / 3](c % 3) + step * d(c);
      s.weighted_gaps(&gp);
      for (Index c = 0; c < nd; ++c) s.x[c / 3](c % 3) = x0[c / 3](c % 3) - step * d(c);
      s.weighted_gaps(&gm);
      s.x = x0;
      for (size_t j = 0; j < g.size(); ++j)
        err_hess = std::max(err_hess, ((gp[j] - gm[j]) / (2 * step) - hess[j] * d).cwiseAbs().maxCoeff());
    }
    EXPECT_GT(max_hess, 0);
    EXPECT_LT(err_grad, 1e-7 * max_grad) << "gradient";
    EXPECT_LT(err_hess, 1e-6 * max_hess) << "Hessian";
  }
}

// A gap field the slave basis does not interpolate but that is linear on each facet: a tilted flat
// master over a flat slave gives each fully covered node the integral of the gap against its dual
// function, which for a linear gap is D_jj times the gap at the node (biorthogonality).
TEST(Mortar3d, LinearGapIsReproducedAtTheNodes) {
  for (const Pairing& p : kPairings) {
    SCOPED_TRACE(pairing_name(p));
    auto tilted = [](Real X, Real Y) { return 0.2 + 0.05 * X - 0.03 * Y; };
    const TwoSheets s(2, p.slave_nodes(), 5, p.masters(), -1.7, 1.7, 0.21, flat0, +tilted);
    const std::vector<Real> g = s.weighted_gaps();
    // Weights: the nodal areas of the flat slave sheet (as in the first test). A linear gap's
    // coefficients in N~ are its nodal values (T^T g = g: a mid-side value is its edge's mean).
    std::vector<Real> w(g.size(), 0.0);
    for (Index f = 0; f < s.slave.size(); ++f) {
      const auto& fc = s.slave.facets[f];
      const Real a = fc.size() == 3 || fc.size() == 6 ? 0.5 : 1.0;  // facet area (h = 1)
      for (size_t k = 0; k < fc.size(); ++k) w[fc[k]] += a * weight_share(p.slave_nodes(), static_cast<int>(k));
    }
    for (size_t j = 0; j < g.size(); ++j) {
      if (w[j] == 0) continue;  // a quad8's centre
      const Vec3& X = s.x[j];
      // The gap along the slave normal (+z) to the plane z = 0.2 + 0.05 x - 0.03 y.
      EXPECT_NEAR(g[j] / w[j], 0.2 + 0.05 * X(0) - 0.03 * X(1), 1e-12) << "node " << j;
    }
  }
}

// The weighted gaps do not depend on how the master's surface is cut into facets, i.e. on the
// cells the clipping makes: a curved slave sheet under a quadratic master surface (which quad9
// facets of any size interpolate exactly) cut into 1 and into 3 x 3 rotated facets. The
// integrands are not polynomials (curved slave: Jacobian and projection), so the cells' rule
// decides how close the two are. Its degree is that of the slave's N_i N_k (mortar_3d.cpp,
// cell_rule): on quad8 and quad9 slave facets the degree-4 rule made the two differ by 1.5e-5
// and 1.1e-5 of the largest gap (with degrees 6 and 8: 2e-8, 3e-9), the jump that made Newton
// cycle on the 3D tube slice's quad9 fold whenever a clipped polygon gained or lost a vertex.
// tri3, quad4 and tri6 keep the degree-4 rule (tri6: 1.8e-5 here; degree 6 gave 1.2e-8 but cost
// the coarse tet10 Hertz run 42 % of its time for the same p0): a looser bound.
TEST(Mortar3d, WeightedGapsDoNotDependOnTheMastersCells) {
  auto slave_z = [](Real X, Real Y) { return -0.06 * X * X - 0.04 * Y * Y + 0.02 * X * Y; };
  auto master_z = [](Real X, Real Y) { return 0.15 - 0.05 * X * X + 0.03 * Y * Y + 0.04 * X; };
  for (int slave_nodes : {3, 4, 6, 8, 9}) {
    SCOPED_TRACE(pairing_name({slave_nodes, 9}));
    const TwoSheets one(2, slave_nodes, 1, 9, -1.6, 1.6, 0.3, +slave_z, +master_z),
        nine(2, slave_nodes, 3, 9, -1.6, 1.6, 0.3, +slave_z, +master_z);
    const std::vector<Real> g1 = one.weighted_gaps(), g9 = nine.weighted_gaps();
    ASSERT_EQ(g1.size(), g9.size());
    Real largest = 0, worst = 0;
    for (size_t j = 0; j < g1.size(); ++j) {
      largest = std::max(largest, std::abs(g1[j]));
      worst = std::max(worst, std::abs(g1[j] - g9[j]));
    }
    std::printf("%s: largest weighted gap %.3e, the two cuttings differ by %.2e of it\n",
                pairing_name({slave_nodes, 9}).c_str(), largest, worst / largest);
    EXPECT_GT(largest, 0.01);
    EXPECT_LT(worst, (slave_nodes >= 8 ? 1e-7 : 5e-5) * largest);
  }
}

// Friction's slip (mortar.hpp, `relative`, `slip_weight`): per slave node of each facet, the
// dual-weighted int Phi_j (x_s - x_m) dA over the facet's cells as a combination of nodes. Its
// slave coefficients sum to its weight and its master ones to minus it (a common translation
// gives no slip); on flat sheets 0.01 apart it is (0, 0, -0.01) (the points pair along the
// normal), and with the coefficients frozen, the master moved by (0.03, -0.02, 0) gives
// (-0.03, 0.02, -0.01). Biorthogonality: node j's slave coefficients are its weight times
// column j of T^-1 (N = T^-1 N~): on tri3 and quad4 its own position alone, no average over the
// facet's other nodes (the N~ weights of session 60 and before gave those nodes a mass
// matrix's share). The tolerances are round-off of the M^-1 in the dual basis.
TEST(Mortar3d, SlipCombinationMeasuresTheRelativeMotion) {
  auto gap = [](Real, Real) { return 0.01; };
  for (const Pairing& p : kPairings) {
    SCOPED_TRACE(pairing_name(p));
    const TwoSheets s(3, p.slave_nodes(), 4, p.masters(), -1.6, 1.6, 0.3, flat0, +gap);
    const Index first_master = static_cast<Index>(s.slave.nodes.size());
    std::vector<Vec3> moved = s.x;
    for (size_t i = first_master; i < moved.size(); ++i) moved[i] += Vec3(0.03, -0.02, 0);
    std::vector<Index> all(static_cast<size_t>(s.master.size()));
    for (Index m = 0; m < s.master.size(); ++m) all[m] = m;
    const int ns = p.slave_nodes();
    const mortar_detail::BasisTransform tr = mortar_detail::basis_transform(3, ns, false);
    MatX T = MatX::Identity(ns, ns);
    if (!tr.identity)
      for (int i = 0; i < ns; ++i)
        for (int l = 0; l < ns; ++l) T(i, l) = tr.t[i][l];
    const MatX Tinv = T.inverse();
    for (Index e = 0; e < s.slave.size(); ++e) {
      const MortarFacetResult r = mortar_element_3d(s.slave, e, s.master, all, s.x, false);
      ASSERT_TRUE(r.overlap) << e;
      ASSERT_EQ(r.relative.size(), s.slave.facets[e].size());
      for (size_t k = 0; k < r.relative.size(); ++k) {
        Real slave_sum = 0, master_sum = 0;
        Vec3 now = Vec3::Zero(), after = Vec3::Zero();
        for (size_t a = 0; a < r.nodes.size(); ++a) {
          const Real w = r.relative[k](static_cast<Index>(a));
          (r.nodes[a] < first_master ? slave_sum : master_sum) += w;
          now += w * s.x[r.nodes[a]];
          after += w * moved[r.nodes[a]];
        }
        const Real W = r.slip_weight[k];
        ASSERT_GT(W, 0) << "facet " << e << " node " << k;
        EXPECT_NEAR(slave_sum, W, 1e-13 * W);
        EXPECT_NEAR(master_sum, -W, 1e-13 * W);
        EXPECT_LT((now / W - Vec3(0, 0, -0.01)).norm(), 1e-13) << now.transpose() / W;
        EXPECT_LT((after / W - Vec3(-0.03, 0.02, -0.01)).norm(), 1e-13) << after.transpose() / W;
        for (int i = 0; i < ns; ++i)
          EXPECT_NEAR(r.relative[k](i) / W, Tinv(i, static_cast<Index>(k)), 1e-12) << "facet " << e << " node " << k << " slave node " << i;
      }
    }
  }
}

// Without the Hessian (a residual only, Discretization::set_second_variation) the weighted gaps
// are differentiated on first-order dual numbers: the same gaps and gradients as with the
// Hessian, to round-off, and no Hessian.
TEST(Mortar3d, GradientOnlyAgreesWithTheFullDerivatives) {
  for (const Pairing& p : kPairings) {
    SCOPED_TRACE(pairing_name(p));
    const TwoSheets s(2, p.slave_nodes(), 3, p.masters(), -0.83, 1.4, 0.37, dome, wavy);
    std::vector<Index> all(static_cast<size_t>(s.master.size()));
    for (Index m = 0; m < s.master.size(); ++m) all[m] = m;
    int compared = 0;
    for (Index e = 0; e < s.slave.size(); ++e) {
      const MortarFacetResult full = mortar_element_3d(s.slave, e, s.master, all, s.x, true, true);
      const MortarFacetResult first = mortar_element_3d(s.slave, e, s.master, all, s.x, true, false);
      ASSERT_EQ(full.overlap, first.overlap);
      if (!full.overlap) continue;
      ASSERT_EQ(full.nodes, first.nodes);
      EXPECT_TRUE(first.hess.empty());
      ASSERT_EQ(full.hess.size(), full.gap.size());
      for (size_t k = 0; k < full.gap.size(); ++k) {
        EXPECT_NEAR(first.gap[k], full.gap[k], 1e-15);
        EXPECT_LT((first.grad[k] - full.grad[k]).cwiseAbs().maxCoeff(), 1e-13 * full.grad[k].cwiseAbs().maxCoeff());
        ++compared;
      }
    }
    EXPECT_GE(compared, 4);
  }
}
