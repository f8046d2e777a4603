// Each discretization x enforcement pair: the contact residual's tangent against central
// differences (displacements and multipliers), in 2D and 3D, with a mix of open and closed
// slave nodes; and the semi-smooth Newton's active set rule.
#include <gtest/gtest.h>

#include "common.hpp"
#include "signorini/contact/contact_interface.hpp"

using namespace signorini;
using signorini::test::DenseMatrix;

namespace {

struct PairCase {
  std::string discretization;
  std::string method;
  bool three_d;
  ElementType type;
};

std::string name_of(const ::testing::TestParamInfo<PairCase>& i) {
  return i.param.discretization + "_" + i.param.method + "_" + element_info(i.param.type).name;
}

}  // namespace

class ContactTangent : public ::testing::TestWithParam<PairCase> {};

TEST_P(ContactTangent, MatchesCentralDifferences) {
  const PairCase pc = GetParam();
  // The upper block sits on the lower one with a small overlap, its mesh finer (non-matching
  // for node-to-segment, matching for node-to-node).
  const bool ntn = pc.discretization == "node_to_node";
  Mesh mesh = test::two_blocks(pc.type, 3, ntn ? 3 : 4, 1.0, 0.5, Vec3(0, 0.5 - 0.01, 0), pc.three_d);
  if (pc.three_d) {
    // The box's y faces are the contact faces in 2D; in 3D use z: rebuild the offset along z.
    // Shifted in x and y so that no slave node lies on a master facet edge (where the
    // constraint switches between segment and vertex and is not differentiable).
    mesh = test::two_blocks(pc.type, 3, ntn ? 3 : 4, 1.0, 0.5, Vec3(ntn ? 0 : 0.02, ntn ? 0 : 0.03, 0.5 - 0.01), true);
  }
  orient_facets(mesh);
  AnalysisSettings as;
  as.dimension = pc.three_d ? Dimension::three_d : Dimension::plane_strain;
  const int dim = as.spatial_dim();
  ContactPairSettings cs;
  cs.name = "c";
  cs.master = pc.three_d ? "lower_zmax" : "lower_ymax";
  cs.slave = pc.three_d ? "upper_zmin" : "upper_ymin";
  cs.discretization = pc.discretization;
  cs.method = pc.method;
  ContactInterface ci(cs, mesh, as, 100.0, false);
  std::vector<const ElementBlock*> cells;
  for (auto& [n, blocks] : mesh.regions)
    for (auto& b : blocks) cells.push_back(&b);
  DofMap dofs(mesh.num_nodes(), dim, cells);
  ci.set_multiplier_offset(dofs.num_dofs());
  const Index nz = dofs.num_dofs() + ci.num_multipliers();
  // A wavy displacement of the upper block's bottom: some nodes penetrate, some open.
  VecX z = VecX::Zero(nz);
  for (Index n : mesh.node_sets["upper_domain"]) {
    const Vec3& X = mesh.nodes[n];
    const int vert = dim - 1;
    z(dofs.dof(n, vert)) = 0.02 * std::sin(7 * X(0) + 3 * X(1));
    z(dofs.dof(n, 0)) += 0.003 * std::cos(5 * X(vert));
  }
  for (Index j = 0; j < ci.num_multipliers(); ++j) z(dofs.dof(0, 0) * 0 + dofs.num_dofs() + j) = (j % 3) * 0.7;
  ci.detect(test::cells_of_positions(mesh, dofs, z), 0.05);
  auto residual = [&](const VecX& zz, GlobalMatrix* K) {
    VecX r = VecX::Zero(nz);
    ci.assemble(test::cells_of_positions(mesh, dofs, zz), zz, dofs, r, K);
    return r;
  };
  if (pc.method == "augmented_lagrangian") {
    // Non-zero multipliers lambda-bar: one Uzawa update from this state.
    residual(z, nullptr);
    Real pen = 0;
    ASSERT_FALSE(ci.uzawa_update(pen));
  }
  DenseMatrix K(nz);
  residual(z, &K);
  Index active = 0, open = 0;
  for (size_t j = 0; j < ci.constraints().size(); ++j) {
    if (ci.constraints()[j].kind == ConstraintKind::none) continue;
    ci.state().active[j] ? ++active : ++open;
  }
  if (std::getenv("SIGNORINI_TEST_VERBOSE"))
    for (size_t j = 0; j < ci.constraints().size(); ++j)
      std::printf("slave %lld kind %d gap %g active %d\n", (long long)ci.constraints()[j].slave,
                  (int)ci.constraints()[j].kind, ci.constraints()[j].gap, (int)ci.state().active[j]);
  ASSERT_GT(active, 0) << "no closed node: the test would check nothing";
  ASSERT_GT(open, 0) << "no open node";
  const Real maxk = K.k.cwiseAbs().maxCoeff();
  const Real maxerr =
      test::central_difference_error([&](const VecX& zz) { return residual(zz, nullptr); }, z, K.k, 1e-7);
  EXPECT_LT(maxerr, 1e-6 * maxk) << pc.discretization << " " << pc.method;
}

INSTANTIATE_TEST_SUITE_P(
    EveryPair, ContactTangent,
    ::testing::Values(PairCase{"node_to_segment", "penalty", false, ElementType::quad4},
                      PairCase{"node_to_segment", "lagrange", false, ElementType::quad4},
                      PairCase{"node_to_segment", "penalty", false, ElementType::quad9},
                      PairCase{"node_to_segment", "lagrange", false, ElementType::quad9},
                      PairCase{"node_to_node", "penalty", false, ElementType::quad4},
                      PairCase{"node_to_node", "lagrange", false, ElementType::quad4},
                      PairCase{"node_to_segment", "penalty", true, ElementType::hex8},
                      PairCase{"node_to_segment", "lagrange", true, ElementType::hex8},
                      PairCase{"node_to_node", "lagrange", true, ElementType::hex8},
                      PairCase{"node_to_segment", "augmented_lagrangian", false, ElementType::quad4},
                      PairCase{"node_to_segment", "augmented_lagrangian", true, ElementType::hex8}),
    name_of);

TEST(ContactTangent, RigidObstacleWithItsOwnUnknowns) {
  // A block's top against a rigid cylinder whose displacement is two unknowns: residual and
  // tangent (nodes, multipliers, obstacle) against central differences, for each method.
  for (const char* method : {"penalty", "lagrange", "augmented_lagrangian"}) {
    Mesh mesh = structured_rectangle(ElementType::quad4, 6, 2, 1.0, 0.5);
    orient_facets(mesh);
    AnalysisSettings as;
    ContactPairSettings cs;
    cs.name = "roller";
    cs.slave = "ymax";
    cs.rigid = true;
    cs.method = method;
    cs.obstacle.shape = "cylinder";
    cs.obstacle.point = Vec3(0.5, 1.5, 0);
    cs.obstacle.radius = 1.0;
    ContactInterface ci(cs, mesh, as, 100.0, false);
    std::vector<const ElementBlock*> cells;
    for (auto& b : mesh.regions["domain"]) cells.push_back(&b);
    DofMap dofs(mesh.num_nodes(), 2, cells);
    ci.set_multiplier_offset(dofs.num_dofs());
    ci.set_obstacle_dofs(dofs.num_dofs() + ci.num_multipliers());
    const Index nz = dofs.num_dofs() + ci.num_multipliers() + 2;
    VecX z = VecX::Zero(nz);
    for (Index n = 0; n < mesh.num_nodes(); ++n) z(dofs.dof(n, 0)) = 0.01 * std::sin(3.0 * n);
    z(nz - 2) = 0.02;   // the obstacle moves sideways and down into the block
    z(nz - 1) = -0.03;
    for (Index j = 0; j < ci.num_multipliers(); ++j) z(dofs.num_dofs() + j) = 0.5 * (j % 2);
    ci.detect(test::cells_of_positions(mesh, dofs, z), 0.1);
    auto residual = [&](const VecX& zz, GlobalMatrix* K) {
      VecX r = VecX::Zero(nz);
      ci.assemble(test::cells_of_positions(mesh, dofs, zz), zz, dofs, r, K);
      return r;
    };
    if (std::string(method) == "augmented_lagrangian") {
      residual(z, nullptr);
      Real pen = 0;
      ci.uzawa_update(pen);
    }
    DenseMatrix K(nz);
    const VecX r0 = residual(z, &K);
    Index active = 0;
    for (char a : ci.state().active) active += a;
    ASSERT_GT(active, 0) << method;
    // The obstacle feels the opposite of the slave nodes' contact forces.
    EXPECT_GT(std::abs(r0(nz - 1)), 0) << method;
    const Real maxerr =
        test::central_difference_error([&](const VecX& zz) { return residual(zz, nullptr); }, z, K.k, 1e-7);
    EXPECT_LT(maxerr, 1e-6 * K.k.cwiseAbs().maxCoeff()) << method;
  }
}
