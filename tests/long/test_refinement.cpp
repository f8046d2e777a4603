// Refinement studies (ctest label `long`, run with `make test-long`): a third and fourth
// mesh level for the 3D cantilever and the axisymmetric Lamé cylinder, printing the error
// tables of docs/validation.md and asserting the asymptotic orders.
#include <gtest/gtest.h>

#include <cmath>

#include "common.hpp"
#include "signorini/core/log.hpp"
#include "signorini/mesh/structured.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {
// Lamé (Timoshenko & Goodier 1970, sec. 28), axisymmetric slice, max nodal error of u_r.
Real lame_error(ElementType type, int n) {
  log::set_level(log::Level::warning);
  const Real a = 0.1, b = 0.2, p = 1e8, E = 210e9, nu = 0.3, A = p * a * a / (b * b - a * a);
  auto ur = [&](Real r) { return (1 + nu) / E * A * ((1 - 2 * nu) * r + b * b / r); };
  StructuredOptions o;
  o.origin = Vec3(a, 0, 0);
  AnalysisSettings s;
  s.dimension = Dimension::axisymmetric;
  Model m = test::model_on(structured_rectangle(type, n, 2, b - a, 0.02, o), s, std::make_shared<LinearElastic>(E, nu));
  Step st;
  st.dirichlet = {test::fix("ymin", 1), test::fix("ymax", 1)};
  Load l;
  l.kind = LoadKind::pressure;
  l.set = "xmin";
  l.pressure = p;
  st.loads = {l};
  m.steps = {st};
  Analysis an(m);
  EXPECT_TRUE(an.run().completed);
  Real err = 0;
  for (Index nd = 0; nd < m.mesh.num_nodes(); ++nd)
    err = std::max(err, std::abs(an.displacement()(an.dofs().dof(nd, 0)) - ur(m.mesh.nodes[nd](0))) / ur(a));
  return err;
}
}  // namespace

TEST(LongRefinement, LameAxisymmetricTables) {
  for (ElementType t : {ElementType::quad4, ElementType::quad8, ElementType::quad9}) {
    Real prev = 0;
    std::printf("Lame axisymmetric, %s: n, max u_r error, order\n", element_info(t).name.c_str());
    for (int n : {4, 8, 16, 32, 64}) {
      const Real e = lame_error(t, n);
      const Real order = prev > 0 ? std::log2(prev / e) : 0;
      std::printf("  %3d  %.3e  %.2f\n", n, e, order);
      if (prev > 0 && e > 1e-11) EXPECT_GT(order, element_info(t).order == 1 ? 1.8 : 2.8) << element_info(t).name << " n=" << n;
      prev = e;
    }
  }
}
