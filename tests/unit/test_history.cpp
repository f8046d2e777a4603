// History variables: a material's trial state is visible only after the increment commits,
// and a reverted (cut back) increment leaves the committed state untouched.
#include <gtest/gtest.h>

#include "common.hpp"
#include "signorini/core/error.hpp"
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

// Starts from a history the material sets (a plastic F_p starts at I, not 0): here 5.
class StartsAtFive final : public Material {
 public:
  std::string model() const override { return "starts_at_five"; }
  int history_size() const override { return 2; }
  void initialize_history(Real* h) const override { h[0] = 5, h[1] = -1; }
  std::vector<std::string> history_names() const override { return {"count", "sign"}; }
  void compute(const MaterialInput& in, Vec6& s, Mat6& d) const override {
    d = isotropic_elasticity(1, 1);
    s = d * in.strain;
    s(0) += in.history_old[0] * in.history_old[1];
    in.history_new[0] = in.history_old[0];
    in.history_new[1] = in.history_old[1];
  }
  Real stiffness_scale() const override { return 1; }
};

Real sxx_sum(const Body& b, const Mesh& m, const DofMap& d, const VecX& u, const QuadratureHistory& h) {
  CellResults r = b.results(m.nodes, u, d, &h);
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
  QuadratureHistory h(b);  // the analysis owns it
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u, h), 0);
  b.assemble(m.nodes, u, d, f, nullptr, &h);  // trial = 1
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u, h), 0) << "trial state leaked before commit";
  h.revert();
  b.assemble(m.nodes, u, d, f, nullptr, &h);
  h.commit();
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u, h), 2.0);  // two cells, count 1 each
  b.assemble(m.nodes, u, d, f, nullptr, &h);
  h.revert();
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u, h), 2.0) << "revert changed the committed state";
  // Without its storage a material with history is an error, not a crash.
  EXPECT_THROW(b.assemble(m.nodes, u, d, f, nullptr), Error);
}

TEST(History, InitialisedByTheMaterialWithItsNames) {
  Mesh m = structured_rectangle(ElementType::quad4, 2, 1, 2, 1);
  AnalysisSettings st;
  Body b("b", m.regions["domain"], std::make_shared<StartsAtFive>(), st);
  DofMap d(m.num_nodes(), 2, test::cells_of(b));
  VecX u = VecX::Zero(d.num_dofs());
  QuadratureHistory h(b);
  ASSERT_EQ(h.per_point(), 2);
  EXPECT_EQ(h.names(), (std::vector<std::string>{"count", "sign"}));
  // 2 cells x 4 points x 2 values, every point (5, -1).
  ASSERT_EQ(h.committed_values().size(), 16u);
  for (size_t k = 0; k < 16; k += 2) {
    EXPECT_EQ(h.committed_values()[k], 5);
    EXPECT_EQ(h.committed_values()[k + 1], -1);
  }
  EXPECT_DOUBLE_EQ(sxx_sum(b, m, d, u, h), -10.0);  // each cell's mean s_xx = 5 x -1
}
