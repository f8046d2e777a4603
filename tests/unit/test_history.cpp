// History variables: a material's trial state is visible only after the increment commits,
// and a reverted (cut back) increment leaves the committed state untouched.
#include <gtest/gtest.h>

#include "common.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;

namespace {
// Counts how often it was evaluated since the last commit, from its history.
class CountingMaterial final : public Material {
 public:
  std::string model() const override { return "counting"; }
  int history_size() const override { return 1; }
  void compute(const MaterialInput& in, Vec6& s, Mat6& d) const override {
    d = isotropic_elasticity(1, 1);
    s = d * in.strain;
    in.history_new[0] = in.history_old[0] + 1;
    s(0) += in.history_old[0];  // the committed count shows in the stress
  }
  Real stiffness_scale() const override { return 1; }
};

Real sxx_sum(Body& b, const Mesh& m, const DofMap& d, const VecX& u) {
  VecX f = VecX::Zero(d.num_dofs());
  CellResults r = b.results(m.nodes, u, d);
  Real s = 0;
  for (auto& v : r.stress) s += v(0);
  return s;
}
}  // namespace

TEST(History, CommittedOnlyOnCommit) {
  Mesh m = structured_rectangle(ElementType::quad4, 2, 1, 2, 1);
  AnalysisSettings st;
  Body b("b", m.regions["domain"], std::make_shared<CountingMaterial>(), st);
  DofMap d(m.num_nodes(), 2, test::cells_of(b));
  VecX u = VecX::Zero(d.num_dofs()), f = u;
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u), 0);
  b.assemble(m.nodes, u, d, f, nullptr);  // trial = 1
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u), 0) << "trial state leaked before commit";
  b.revert();
  b.assemble(m.nodes, u, d, f, nullptr);
  b.commit();
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u), 2.0);  // two cells, count 1 each
  b.assemble(m.nodes, u, d, f, nullptr);
  b.revert();
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u), 2.0) << "revert changed the committed state";
}
