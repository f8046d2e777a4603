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

// Partitioned over MPI ranks each rank holds its own cells' history (issue 15): the others'
// values take no memory, assembling the held cells updates only them, the whole layout puts
// zeros where another rank holds the values (so that a sum over the ranks is every cell's
// owner's), a restart takes back the held cells' part, and a cell held elsewhere is an error.
TEST(History, EachRankHoldsItsOwnCells) {
  Mesh m = structured_rectangle(ElementType::quad4, 3, 1, 3, 1);
  AnalysisSettings st;
  Body b("b", m.regions["domain"], std::make_shared<CountingMaterial>(), st);
  DofMap d(m.num_nodes(), 2, test::cells_of(b));
  VecX u = VecX::Zero(d.num_dofs()), f = u;
  const std::vector<std::vector<char>> held{{1, 0, 1}}, others{{0, 1, 0}};
  QuadratureHistory whole(b), mine(b, &held), theirs(b, &others);
  ASSERT_EQ(whole.whole_size(), 12);  // 3 cells x 4 points x 1 value
  EXPECT_EQ(mine.committed_values().size(), 8u);
  EXPECT_EQ(theirs.committed_values().size(), 4u);
  EXPECT_EQ(mine.whole_size(), 12);
  EXPECT_TRUE(mine.holds(0, 0));
  EXPECT_FALSE(mine.holds(0, 1));
  EXPECT_THROW(mine.committed(0, 1), Error);
  EXPECT_THROW(theirs.trial(0, 2), Error);
  // Two increments of the whole body, and of each share on its cells.
  for (int inc = 0; inc < 2; ++inc) {
    b.assemble(m.nodes, u, d, f, nullptr, &whole);
    b.assemble(m.nodes, u, d, f, nullptr, &mine, 0, &held);
    b.assemble(m.nodes, u, d, f, nullptr, &theirs, 0, &others);
    for (QuadratureHistory* h : {&whole, &mine, &theirs}) h->commit();
  }
  const std::vector<Real> w = whole.whole_committed(), a = mine.whole_committed(), c = theirs.whole_committed();
  ASSERT_EQ(a.size(), w.size());
  ASSERT_EQ(c.size(), w.size());
  for (size_t k = 0; k < w.size(); ++k) {
    EXPECT_EQ(w[k], 2);
    const bool in_mine = k / 4 != 1;  // cell 1 is the other rank's
    EXPECT_EQ(a[k], in_mine ? 2 : 0) << k;
    EXPECT_EQ(c[k], in_mine ? 0 : 2) << k;
    EXPECT_EQ(a[k] + c[k], w[k]) << k;
  }
  // The output of a share: its own cells from its history, and only those (cells 0 and 2).
  CellResults r = b.results(m.nodes, u, d, &mine, &held);
  ASSERT_EQ(r.stress.size(), 2u);
  ASSERT_EQ(r.von_mises.size(), 2u);
  EXPECT_DOUBLE_EQ(r.stress[0](0), 2);
  EXPECT_DOUBLE_EQ(r.stress[1](0), 2);
  EXPECT_EQ(b.results(m.nodes, u, d, &whole).stress.size(), 3u);
  // A restart in the whole layout: each share keeps its cells' values.
  std::vector<Real> restart(12);
  for (size_t k = 0; k < restart.size(); ++k) restart[k] = static_cast<Real>(k);
  mine.restore(restart);
  EXPECT_EQ(mine.committed(0, 2)[0], 8);
  EXPECT_EQ(mine.whole_committed(), (std::vector<Real>{0, 1, 2, 3, 0, 0, 0, 0, 8, 9, 10, 11}));
  EXPECT_THROW(mine.restore(std::vector<Real>(11)), Error);
  // A mask per block, of the block's size.
  const std::vector<std::vector<char>> short_mask{{1, 0}}, no_mask{};
  EXPECT_THROW(QuadratureHistory(b, &short_mask), Error);
  EXPECT_THROW(QuadratureHistory(b, &no_mask), Error);
}

// Partitioned over MPI ranks, each rank keeps its own cells of a body (Body::keep_cells, issue
// 15) and drops the others: the kept cells stay in order with their nodes and ids, the history
// of the share keeps the whole body's layout (a restart file), and the body force of the
// shares adds up to the whole body's.
TEST(History, ABodyKeepsItsShareOfTheCells) {
  Mesh m = structured_rectangle(ElementType::quad4, 3, 1, 3, 1);
  AnalysisSettings st;
  const std::vector<ElementBlock> cells = m.regions["domain"];
  Body whole("b", cells, std::make_shared<CountingMaterial>(), st), mine("b", cells, std::make_shared<CountingMaterial>(), st),
      theirs("b", cells, std::make_shared<CountingMaterial>(), st);
  DofMap d(m.num_nodes(), 2, test::cells_of(whole));
  mine.keep_cells({{1, 0, 1}});
  theirs.keep_cells({{0, 1, 0}});
  ASSERT_EQ(mine.num_cells(), 2);
  ASSERT_EQ(theirs.num_cells(), 1);
  EXPECT_EQ(mine.whole_cells(0), 3);
  EXPECT_EQ(mine.whole_index(0, 1), 2);
  EXPECT_EQ(theirs.whole_index(0, 0), 1);
  EXPECT_EQ(whole.whole_index(0, 2), 2);
  const ElementBlock& all = whole.blocks()[0];
  EXPECT_EQ(mine.blocks()[0].ids, (std::vector<Index>{all.ids[0], all.ids[2]}));
  for (int a = 0; a < 4; ++a) {
    EXPECT_EQ(mine.blocks()[0].element(1)[a], all.element(2)[a]);
    EXPECT_EQ(theirs.blocks()[0].element(0)[a], all.element(1)[a]);
  }
  // The memory of the dropped cells is given back.
  EXPECT_EQ(mine.blocks()[0].conn.capacity(), 8u);
  // The shares' histories in the whole layout: each cell's values where the whole body has them.
  const std::vector<std::vector<char>> held_mine{{1, 1}}, held_theirs{{1}};
  QuadratureHistory hw(whole), hm(mine, &held_mine), ht(theirs, &held_theirs);
  ASSERT_EQ(hm.whole_size(), 12);
  ASSERT_EQ(ht.whole_size(), 12);
  EXPECT_THROW(QuadratureHistory(mine, nullptr), Error);  // a share needs its mask
  VecX u = VecX::Zero(d.num_dofs()), f = u;
  whole.assemble(m.nodes, u, d, f, nullptr, &hw);
  mine.assemble(m.nodes, u, d, f, nullptr, &hm, 0, &held_mine);
  hw.commit();
  hm.commit();
  EXPECT_EQ(hm.whole_committed(), (std::vector<Real>{1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(ht.whole_committed(), (std::vector<Real>(12, 0.0)));
  std::vector<Real> restart(12);
  for (size_t k = 0; k < restart.size(); ++k) restart[k] = static_cast<Real>(k);
  ht.restore(restart);
  EXPECT_EQ(ht.committed(0, 0)[0], 4);  // the whole body's cell 1
  EXPECT_EQ(ht.whole_committed(), (std::vector<Real>{0, 0, 0, 0, 4, 5, 6, 7, 0, 0, 0, 0}));
  // Kept again (a share of the share): the whole body's indices carry through.
  Body again("b", cells, std::make_shared<CountingMaterial>(), st);
  again.keep_cells({{1, 0, 1}});
  again.keep_cells({{0, 1}});
  ASSERT_EQ(again.num_cells(), 1);
  EXPECT_EQ(again.whole_index(0, 0), 2);
  EXPECT_EQ(again.whole_cells(0), 3);
  // The body force: the shares' sum is the whole body's.
  VecX fw = VecX::Zero(d.num_dofs()), fs = fw;
  whole.add_body_force(m.nodes, d, Vec3(1, -2, 0), 0.5, fw);
  mine.add_body_force(m.nodes, d, Vec3(1, -2, 0), 0.5, fs);
  theirs.add_body_force(m.nodes, d, Vec3(1, -2, 0), 0.5, fs);
  EXPECT_LT((fs - fw).norm(), 1e-14 * fw.norm());
  // With an ownership mask, only the owned cells add.
  VecX fo = VecX::Zero(d.num_dofs());
  const std::vector<std::vector<char>> first{{1, 0}};
  mine.add_body_force(m.nodes, d, Vec3(1, -2, 0), 0.5, fo, &first);
  EXPECT_NEAR(fo.sum(), -0.5 * whole.volume(m.nodes) / 3, 1e-14);
  EXPECT_THROW(mine.keep_cells({{1, 0, 1}}), Error);  // a mask per held cell
}
