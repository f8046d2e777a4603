// Nitsche's integration points shared out over ranks (issue 15; ContactInterface::share_points,
// EnforcementInput::share): two ranks, played here by two threads over an in-process exchange,
// each build and assemble the points of their own slave facets. Each rank's matrix holds its
// own points' entries (the backend carries them to their rows' owners), so the two matrices sum
// to the one-process matrix; the residual and the per-node state are summed over the ranks, so
// both ranks hold the one-process values, and the same bits.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "common.hpp"
#include "signorini/contact/contact_interface.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/rank_exchange.hpp"
#include "signorini/fem/boundary_traction.hpp"
#include "signorini/material/material.hpp"

using namespace signorini;
using signorini::test::DenseMatrix;

namespace {

// Ranks as threads of one process: allgather waits until every rank has given its bytes (at
// most a minute: a rank that failed and left never comes, and the test fails instead of
// hanging).
class ThreadRanks {
 public:
  explicit ThreadRanks(int size) : slots_(static_cast<size_t>(size)) {}
  std::vector<std::string> allgather(int rank, const std::string& mine) {
    std::unique_lock<std::mutex> lock(m_);
    slots_[static_cast<size_t>(rank)] = mine;
    if (++arrived_ == static_cast<int>(slots_.size())) {
      result_ = slots_;
      arrived_ = 0;
      ++generation_;
      cv_.notify_all();
    } else {
      const long generation = generation_;
      if (!cv_.wait_for(lock, std::chrono::seconds(60), [&] { return generation_ != generation; }))
        throw Error("thread rank " + std::to_string(rank) + ": the other ranks did not come to the allgather");
    }
    ++calls_;
    return result_;
  }
  long calls() const { return calls_; }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  std::vector<std::string> slots_, result_;
  int arrived_ = 0;
  long generation_ = 0, calls_ = 0;
};

class ThreadRank final : public RankExchange {
 public:
  ThreadRank(ThreadRanks& all, int rank, int size) : all_(all), rank_(rank), size_(size) {}
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> allgather(const std::string& mine) const override { return all_.allgather(rank_, mine); }
  void broadcast(std::string&, int) const override { throw Error("not used here"); }

 private:
  ThreadRanks& all_;
  int rank_, size_;
};

// What one rank (or the one process) assembled.
struct Assembled {
  VecX r;
  MatX k;
  EnforcementOutput state;
  size_t points = 0;
  std::string error;
};

// Two blocks pressed into each other (the upper one tilted, so that some points are open),
// with segment_to_segment and Nitsche's method, then moved tangentially in the increment.
struct TwoBlocks {
  TwoBlocks(bool three, const std::string& friction) : three(three) {
    const Vec3 off = three ? Vec3(0.02, 0.03, 0.49) : Vec3(0, 0.49, 0);
    mesh = test::two_blocks(three ? ElementType::hex8 : ElementType::quad4, three ? 3 : 4, three ? 4 : 5, 1.0, 0.5, off,
                            three, three ? ElementType::hex8 : ElementType::quad4, 1);
    if (three)
      for (Index n : mesh.node_sets.at("upper_domain"))
        for (int d = 0; d < 2; ++d) mesh.nodes[n](d) = 0.05 + 0.9 * mesh.nodes[n](d);
    orient_facets(mesh);
    as.dimension = three ? Dimension::three_d : Dimension::plane_strain;
    for (auto& [n, blocks] : mesh.regions)
      for (auto& b : blocks) cells.push_back(&b);
    dofs = DofMap(mesh.num_nodes(), as.spatial_dim(), cells);
    cs.name = "c";
    cs.method = "nitsche";
    cs.discretization = "segment_to_segment";
    cs.master = three ? "lower_zmax" : "lower_ymax";
    cs.slave = three ? "upper_zmin" : "upper_ymin";
    cs.friction = friction;
    cs.friction_parameter = 0.3;
    const int vert = three ? 2 : 1;
    z0 = VecX::Zero(dofs.num_dofs());
    for (Index n : mesh.node_sets.at("upper_domain")) {
      const Vec3& X = mesh.nodes[n];
      z0(dofs.dof(n, vert)) = -0.004 - 0.008 * std::sin(7 * X(0) + 3 * X(1)) + 0.03 * X(0);
    }
    z = z0;
    for (Index n : mesh.node_sets.at("upper_domain")) {
      const Vec3& X = mesh.nodes[n];
      z(dofs.dof(n, 0)) += 0.004 * std::cos(5 * X(0) + 2 * X(vert)) + 0.002;
      if (three) z(dofs.dof(n, 1)) += 0.003 * std::sin(4 * X(0));
    }
    for (auto& [name, blocks] : mesh.regions)
      for (auto& b : blocks) bodies.push_back({&b, &elastic});
  }

  // The pair's lifecycle (detect, begin_increment, assemble with the matrix) on one rank of
  // `ranks` (null: one process).
  Assembled run(const RankExchange* ranks) const {
    Assembled a;
    try {
      // Each rank its own boundary traction, as each MPI process has (locating the slave facets
      // adds to its table).
      BoundaryTraction traction(bodies, mesh.nodes, as);
      ContactInterface pair(cs, mesh, as, 100.0, false);
      pair.set_rank_exchange(ranks);
      pair.set_boundary_traction(&traction);
      EXPECT_EQ(pair.share_points(), ranks != nullptr);
      const std::vector<Vec3> x0 = test::cells_of_positions(mesh, dofs, z0);
      pair.detect(x0, 0.05);
      pair.begin_increment(x0, z0);
      DenseMatrix K(dofs.num_dofs());
      a.r = VecX::Zero(dofs.num_dofs());
      pair.assemble(test::cells_of_positions(mesh, dofs, z), z, dofs, a.r, &K);
      a.k = K.k;
      a.state = pair.state();
      a.points = pair.integration_points()->size();
    } catch (const std::exception& e) {
      a.error = e.what();
    }
    return a;
  }

  bool three;
  Mesh mesh;
  AnalysisSettings as;
  std::vector<const ElementBlock*> cells;
  DofMap dofs;
  ContactPairSettings cs;
  VecX z0, z;
  LinearElastic elastic{100.0, 0.3};
  std::vector<BoundaryTraction::Cells> bodies;
};

void check_shared(bool three, const std::string& friction) {
  SCOPED_TRACE((three ? "3D " : "2D ") + friction);
  const TwoBlocks b(three, friction);
  const Assembled one = b.run(nullptr);
  ASSERT_TRUE(one.error.empty()) << one.error;
  ThreadRanks all(2);
  const ThreadRank r0(all, 0, 2), r1(all, 1, 2);
  Assembled a0, a1;
  std::thread t([&] { a1 = b.run(&r1); });
  a0 = b.run(&r0);
  t.join();
  ASSERT_TRUE(a0.error.empty() && a1.error.empty()) << a0.error << a1.error;
  EXPECT_GT(all.calls(), 0);
  // Every point built once, by one rank, and both ranks built some.
  EXPECT_EQ(a0.points + a1.points, one.points);
  EXPECT_GT(a0.points, 0u);
  EXPECT_GT(a1.points, 0u);
  // Some points pressed, some open (else the test proves less).
  Index closed = 0;
  for (char c : one.state.active) closed += c;
  EXPECT_GT(closed, 0);
  EXPECT_LT(closed, static_cast<Index>(one.state.active.size()));
  // The matrices sum to the one-process matrix; each rank's alone does not.
  const Real kmax = one.k.cwiseAbs().maxCoeff();
  ASSERT_GT(kmax, 0);
  EXPECT_LE((a0.k + a1.k - one.k).cwiseAbs().maxCoeff(), 1e-12 * kmax);
  EXPECT_GT((a0.k - one.k).cwiseAbs().maxCoeff(), 1e-3 * kmax);
  // The residual and the state: the one-process values, the same bits on both ranks.
  const Real rmax = one.r.cwiseAbs().maxCoeff();
  ASSERT_GT(rmax, 0);
  EXPECT_LE((a0.r - one.r).cwiseAbs().maxCoeff(), 1e-12 * rmax);
  EXPECT_TRUE(a0.r == a1.r);
  EXPECT_EQ(a0.state.active, one.state.active);
  EXPECT_EQ(a0.state.active, a1.state.active);
  EXPECT_TRUE(a0.state.pressure == a1.state.pressure);
  for (size_t j = 0; j < one.state.pressure.size(); ++j)
    EXPECT_NEAR(a0.state.pressure[j], one.state.pressure[j], 1e-12 * (1 + std::abs(one.state.pressure[j]))) << j;
  EXPECT_LE((a0.state.slave_force - one.state.slave_force).norm(), 1e-12 * one.state.slave_force.norm());
  EXPECT_TRUE(a0.state.slave_force == a1.state.slave_force);
  if (friction == "none") return;
  EXPECT_EQ(a0.state.slip, one.state.slip);
  EXPECT_EQ(a0.state.slip, a1.state.slip);
  Index stick = 0, slip = 0;
  for (size_t j = 0; j < one.state.slip.size(); ++j)
    if (one.state.active[j]) (one.state.slip[j] ? slip : stick)++;
  EXPECT_GT(stick + slip, 0);
  for (size_t j = 0; j < one.state.traction.size(); ++j) {
    EXPECT_LE((a0.state.traction[j] - one.state.traction[j]).norm(), 1e-12 * (1 + one.state.traction[j].norm())) << j;
    EXPECT_TRUE(a0.state.traction[j] == a1.state.traction[j]) << j;
    EXPECT_NEAR(a0.state.cone_excess[j], one.state.cone_excess[j], 1e-12 * (1 + std::abs(one.state.cone_excess[j]))) << j;
  }
}

}  // namespace

TEST(NitscheShare, TwoRanksAssembleTheOneProcessSystem2dFriction) { check_shared(false, "coulomb"); }
TEST(NitscheShare, TwoRanksAssembleTheOneProcessSystem3dFrictionless) { check_shared(true, "none"); }
TEST(NitscheShare, TwoRanksAssembleTheOneProcessSystem3dFriction) { check_shared(true, "coulomb"); }
