// Lamé's thick-walled cylinder (lame_problem.hpp), plane strain (quarter annulus) and
// axisymmetric (a slice with u_z = 0, which is the same plane-strain state): nodal u_r and
// the hoop stress at cell centres against Timoshenko & Goodier (1970), sec. 28.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lame_problem.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {
using namespace signorini::test::lame;

struct Errors {
  Real u = 0, stress = 0;
};

Errors solve(Dimension dim, ElementType type, int n) {
  Model m = model(dim, type, n);
  Analysis an(m);
  AnalysisSummary sum = an.run();
  EXPECT_TRUE(sum.completed) << sum.failure;
  Errors err;
  for (Index nd = 0; nd < m.mesh.num_nodes(); ++nd) {
    const Vec3 x = m.mesh.nodes[nd];
    const Real r = std::hypot(x(0), dim == Dimension::axisymmetric ? 0.0 : x(1));
    const Vec3 dir = dim == Dimension::axisymmetric ? Vec3(1, 0, 0) : Vec3(x(0) / r, x(1) / r, 0);
    const Real u_r = an.displacement()(an.dofs().dof(nd, 0)) * dir(0) + an.displacement()(an.dofs().dof(nd, 1)) * dir(1);
    err.u = std::max(err.u, std::abs(u_r - ur(r)) / ur(a));
  }
  // Hoop stress at the cell centres against the formula (cell averages: O(h^2) off).
  CellResults res = m.bodies[0]->results(m.mesh.nodes, an.displacement(), an.dofs());
  const ElementBlock& blk = m.bodies[0]->blocks()[0];
  for (Index e = 0; e < blk.size(); ++e) {
    Vec3 c = Vec3::Zero();
    const int nc = element_info(blk.type).num_corners;
    for (int k = 0; k < nc; ++k) c += m.mesh.nodes[blk.element(e)[k]] / nc;
    Real r, sig_t;
    if (dim == Dimension::axisymmetric) {
      r = c(0);
      sig_t = res.stress[e](2);
    } else {
      r = c.norm();
      const Real ct = c(0) / r, snt = c(1) / r;
      const Vec6& sg = res.stress[e];
      sig_t = sg(0) * snt * snt + sg(1) * ct * ct - 2 * sg(5) * snt * ct;
    }
    err.stress = std::max(err.stress, std::abs(sig_t - sigma_theta(r)) / p);
  }
  return err;
}
}  // namespace

TEST(Lame, PlaneStrainQuad8) {
  Errors e = solve(Dimension::plane_strain, ElementType::quad8, 8);
  EXPECT_LT(e.u, 1e-4);
  EXPECT_LT(e.stress, 0.02);
}

TEST(Lame, PlaneStrainTri6) {
  Errors e = solve(Dimension::plane_strain, ElementType::tri6, 8);
  EXPECT_LT(e.u, 5e-4);
  EXPECT_LT(e.stress, 0.03);
}

TEST(Lame, AxisymmetricQuad9) {
  Errors e = solve(Dimension::axisymmetric, ElementType::quad9, 8);
  EXPECT_LT(e.u, 1e-4);
  EXPECT_LT(e.stress, 0.02);
}

TEST(Lame, AxisymmetricQuad4ConvergesAtOrderTwoInDisplacement) {
  Errors c = solve(Dimension::axisymmetric, ElementType::quad4, 8), f = solve(Dimension::axisymmetric, ElementType::quad4, 16);
  const Real order = std::log2(c.u / f.u);
  std::printf("axisymmetric quad4 Lame: max u_r error %.3e -> %.3e, order %.2f\n", c.u, f.u, order);
  EXPECT_GT(order, 1.8);
  EXPECT_LT(f.u, 2e-3);
}
