// Each discretization x enforcement pair: the contact residual's tangent against central
// differences (displacements and multipliers), in 2D and 3D, with a mix of open and closed
// slave nodes; and the semi-smooth Newton's active set rule.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "common.hpp"
#include "signorini/contact/contact_interface.hpp"
#include "signorini/core/error.hpp"

using namespace signorini;
using signorini::test::DenseMatrix;

namespace {

struct PairCase {
  std::string discretization;
  std::string method;
  bool three_d;
  ElementType type;
  std::string smoothing = "none";
};

std::string name_of(const ::testing::TestParamInfo<PairCase>& i) {
  return i.param.discretization + "_" + i.param.method + "_" + element_info(i.param.type).name +
         (i.param.smoothing == "none" ? "" : "_" + i.param.smoothing);
}

// A smoothed master only differs from the faceted one where it is curved: a wave on the
// lower block's top (the master) makes the Hermite curve bend between its nodes.
void bend_lower_block(const Mesh& mesh, const DofMap& dofs, int dim, VecX& z) {
  for (Index n : mesh.node_sets.at("lower_domain")) {
    const Vec3& X = mesh.nodes[n];
    z(dofs.dof(n, dim - 1)) += 0.03 * std::sin(9 * X(0)) * X(dim - 1);
    if (dim == 3) z(dofs.dof(n, 2)) += 0.02 * std::sin(7 * X(1) + 4 * X(0)) * X(2);  // curved both ways, twisted
  }
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
  cs.smoothing = pc.smoothing;
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
  if (pc.smoothing != "none") bend_lower_block(mesh, dofs, dim, z);
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
    ASSERT_FALSE(ci.augment(test::cells_of_positions(mesh, dofs, z), z, pen));
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
      std::printf("slave %lld nodes %d kind %d gap %g active %d\n", (long long)ci.constraints()[j].slave, (int)ci.constraints()[j].nodes.size(),
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
                      PairCase{"node_to_segment", "augmented_lagrangian", true, ElementType::hex8},
                      PairCase{"node_to_segment", "penalty", false, ElementType::quad4, "hermite"},
                      PairCase{"node_to_segment", "lagrange", false, ElementType::quad4, "hermite"},
                      PairCase{"node_to_segment", "penalty", true, ElementType::hex8, "hermite"},
                      PairCase{"node_to_segment", "lagrange", true, ElementType::hex8, "hermite"}),
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
    cs.turns = true;
    ContactInterface ci(cs, mesh, as, 100.0, false);
    std::vector<const ElementBlock*> cells;
    for (auto& b : mesh.regions["domain"]) cells.push_back(&b);
    DofMap dofs(mesh.num_nodes(), 2, cells);
    ci.set_multiplier_offset(dofs.num_dofs());
    ci.set_obstacle_dofs(dofs.num_dofs() + ci.num_multipliers());
    ASSERT_EQ(ci.num_obstacle_dofs(), 3);  // plane strain: two translations and the angle
    const Index nz = dofs.num_dofs() + ci.num_multipliers() + 3;
    VecX z = VecX::Zero(nz);
    for (Index n = 0; n < mesh.num_nodes(); ++n) z(dofs.dof(n, 0)) = 0.01 * std::sin(3.0 * n);
    z(nz - 3) = 0.02;   // the obstacle moves sideways and down into the block, and turns
    z(nz - 2) = -0.03;
    z(nz - 1) = 0.05;
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
      ci.augment(test::cells_of_positions(mesh, dofs, z), z, pen);
    }
    DenseMatrix K(nz);
    const VecX r0 = residual(z, &K);
    Index active = 0;
    for (char a : ci.state().active) active += a;
    ASSERT_GT(active, 0) << method;
    // The obstacle feels the opposite of the slave nodes' contact forces.
    EXPECT_GT(std::abs(r0(nz - 2)), 0) << method;
    EXPECT_LT(std::abs(r0(nz - 1)), 1e-12 * std::abs(r0(nz - 2)))
        << method << ": frictionless, a turning circle feels no moment (but round-off)";
    const Real maxerr =
        test::central_difference_error([&](const VecX& zz) { return residual(zz, nullptr); }, z, K.k, 1e-7);
    EXPECT_LT(maxerr, 1e-6 * K.k.cwiseAbs().maxCoeff()) << method;
  }
}

// A meshed rigid body that turns, in plane strain (one angle) and in 3D (a rotation vector):
// the lower block rigid, its nodes sharing the DOFs of the body and turning about (0.5, 0, 0)
// by angles of their own; the contact residual's tangent against central differences in every
// unknown (the elastic block's nodes, the rigid body's translation and angles, the
// multipliers), frictionless and with Coulomb friction (sticking and slipping nodes), for each
// method. The angles enter by the chain rule (ContactInterface::add_rigid_rotations),
// friction's slip origin on the rigid body too. The positions are rotated here with the
// rotation matrix written out (plane) or Eigen's AngleAxis (3D), independently of
// geometry/rotation.hpp.
TEST(ContactTangent, TurningRigidMasterBody) {
  for (bool three : {false, true})
    for (const char* friction : {"none", "coulomb"})
      for (const char* method : {"penalty", "lagrange", "augmented_lagrangian"}) {
        SCOPED_TRACE(std::string(three ? "3D, " : "plane strain, ") + method + ", " + friction);
        const int dim = three ? 3 : 2, na = three ? 3 : 1, vert = dim - 1;
        Mesh mesh = three ? test::two_blocks(ElementType::hex8, 2, 3, 1.0, 0.5, Vec3(0, 0, 0.49), true)
                          : test::two_blocks(ElementType::quad4, 3, 4, 1.0, 0.5, Vec3(0, 0.49, 0));
        orient_facets(mesh);
        AnalysisSettings as;
        if (three) as.dimension = Dimension::three_d;
        std::vector<const ElementBlock*> cells;
        for (auto& [n, blocks] : mesh.regions)
          for (auto& b : blocks) cells.push_back(&b);
        const std::vector<Index>& rigid = mesh.node_sets.at("lower_domain");
        DofMap dofs(mesh.num_nodes(), dim, cells, {rigid});
        ContactPairSettings cs;
        cs.name = "c";
        cs.method = method;
        cs.master = three ? "lower_zmax" : "lower_ymax";
        cs.slave = three ? "upper_zmin" : "upper_ymin";
        cs.friction = friction;
        cs.friction_parameter = 0.3;
        cs.tangential_penalty = 20000;
        cs.stick_predictor = false;  // the return map's own stick/slip statuses (the predictor: FrictionGrid*)
        ContactInterface ci(cs, mesh, as, 100.0, false);
        const Index nd = dofs.num_dofs(), nm = ci.num_multipliers(), nz = nd + nm + na;
        RigidRotations rr;
        rr.angles = na;
        rr.body_of_node.assign(mesh.num_nodes(), -1);
        for (Index n : rigid) rr.body_of_node[n] = 0;
        rr.dof = {nd + nm};
        rr.ref = {Vec3(0.5, 0, 0)};
        rr.reference = &mesh.nodes;
        ci.set_multiplier_offset(nd);
        ci.set_rigid_rotations(&rr);
        auto positions = [&](const VecX& z) {
          std::vector<Vec3> x = test::cells_of_positions(mesh, dofs, z);
          Mat3 R = Mat3::Identity();
          if (three) {
            const Vec3 th(z(nd + nm), z(nd + nm + 1), z(nd + nm + 2));
            if (th.norm() > 0) R = Eigen::AngleAxis<Real>(th.norm(), th.normalized()).toRotationMatrix();
          } else {
            const Real th = z(nz - 1);
            R(0, 0) = R(1, 1) = std::cos(th);
            R(1, 0) = std::sin(th);
            R(0, 1) = -std::sin(th);
          }
          for (Index n : rigid) {
            Vec3 u = Vec3::Zero();
            for (int d = 0; d < dim; ++d) u(d) = z(dofs.dof(n, d));
            x[n] = rr.ref[0] + u + R * (mesh.nodes[n] - rr.ref[0]);
          }
          return x;
        };
        // Start of the increment: the upper block pressed in, the rigid body turned; then the
        // upper block moves sideways and the rigid body turns on.
        const Real turn0[3] = {0.004, -0.006, 0.01}, turn1[3] = {0.007, -0.002, 0.016};
        VecX z0 = VecX::Zero(nz);
        for (Index n : mesh.node_sets.at("upper_domain"))
          z0(dofs.dof(n, vert)) = -(0.006 + 0.006 * std::sin(7 * mesh.nodes[n](0) + 2 * mesh.nodes[n](1)));
        z0(dofs.dof(rigid[0], 0)) = 0.003;
        for (int i = 0; i < na; ++i) z0(nd + nm + i) = turn0[three ? i : 2];
        // Multipliers: pressures of both signs, and (friction) tractions some inside the cone,
        // some beyond it.
        const Index ns = ci.slave().nodes.size();
        for (Index j = 0; j < nm; ++j)
          z0(nd + j) = j < ns ? 0.5 * (j % 3) - 0.2 : 0.12 * std::sin(2.0 * j) + (j % 4 == 0 ? 0.3 : 0.0);
        ci.detect(positions(z0), 0.1);
        ci.begin_increment(positions(z0), z0);
        VecX z = z0;
        for (Index n : mesh.node_sets.at("upper_domain")) {
          z(dofs.dof(n, 0)) += 0.003 * std::cos(5 * mesh.nodes[n](0)) + 0.001;
          if (three) z(dofs.dof(n, 1)) += 0.002 * std::sin(4 * mesh.nodes[n](0)) - 0.001;
        }
        for (int i = 0; i < na; ++i) z(nd + nm + i) = turn1[three ? i : 2];
        auto residual = [&](const VecX& zz, GlobalMatrix* K) {
          VecX r = VecX::Zero(nz);
          ci.assemble(positions(zz), zz, dofs, r, K);
          return r;
        };
        if (std::string(method) == "augmented_lagrangian") {
          residual(z, nullptr);
          Real pen = 0;
          ci.augment(positions(z), z, pen);
          for (Index n : mesh.node_sets.at("upper_domain")) z(dofs.dof(n, vert)) -= 0.001;
        }
        DenseMatrix K(nz);
        const VecX r0 = residual(z, &K);
        Index closed = 0, open = 0, slip = 0;
        for (size_t j = 0; j < ci.constraints().size(); ++j) {
          if (ci.constraints()[j].kind == ConstraintKind::none) continue;
          ci.state().active[j] ? ++closed : ++open;
          if (ci.state().active[j] && ci.frictional()) slip += ci.state().slip[j];
        }
        ASSERT_GT(closed, 0);
        EXPECT_NE(r0(nz - 1), 0) << "the contact forces have a moment about the turning point";
        const Real err =
            test::central_difference_error([&](const VecX& zz) { return residual(zz, nullptr); }, z, K.k, 1e-7);
        std::printf("%s, %s, %s: %lld closed (%lld slip), %lld open; tangent error %.2e of max |K| %.2e\n",
                    three ? "3D" : "plane strain", method, friction, (long long)closed, (long long)slip, (long long)open,
                    err / K.k.cwiseAbs().maxCoeff(), K.k.cwiseAbs().maxCoeff());
        EXPECT_LT(err, 1e-6 * K.k.cwiseAbs().maxCoeff());
        if (std::string(friction) == "coulomb" && std::string(method) != "augmented_lagrangian") {
          EXPECT_GT(slip, 0) << "some closed nodes slip";
          EXPECT_LT(slip, closed) << "and some stick";
        }
      }
}

// ---------------------------------------------------------------------------------------
// Friction (penalty): the return map, and the frictional residual's tangent against central
// differences with sticking and slipping nodes mixed, for node-to-segment (2D, 3D),
// node-to-node and a rigid obstacle with its own unknowns.

TEST(Friction, ReturnMapStickSlipAndApex) {
  const Vec3 trial(0.3, -0.4, 0.0);  // |trial| = 0.5
  ReturnMap st = return_map(trial, 0.6);
  EXPECT_FALSE(st.slip);
  EXPECT_EQ(st.traction, trial);
  ReturnMap sl = return_map(trial, 0.2);
  EXPECT_TRUE(sl.slip);
  EXPECT_NEAR(sl.traction.norm(), 0.2, 1e-15);
  EXPECT_NEAR(sl.traction.dot(trial) / (0.2 * 0.5), 1.0, 1e-15) << "slip keeps the trial direction";
  ReturnMap apex = return_map(trial, 0.0);
  EXPECT_TRUE(apex.slip);
  EXPECT_EQ(apex.traction, Vec3::Zero());
  // The chattering guard's holds: slip from inside the disc goes to the rim, stick from
  // outside keeps the trial traction.
  ReturnMap held_slip = return_map(trial, 0.6, StickSlip::slip);
  EXPECT_TRUE(held_slip.slip);
  EXPECT_NEAR(held_slip.traction.norm(), 0.6, 1e-15);
  EXPECT_NEAR(held_slip.traction.dot(trial) / (0.6 * 0.5), 1.0, 1e-15);
  ReturnMap held_stick = return_map(trial, 0.2, StickSlip::stick);
  EXPECT_FALSE(held_stick.slip);
  EXPECT_EQ(held_stick.traction, trial);
  // Derivatives in the slip state against central differences.
  const Real h = 1e-7;
  for (int k = 0; k < 3; ++k) {
    Vec3 tp = trial, tm = trial;
    tp(k) += h;
    tm(k) -= h;
    const Vec3 fd = (return_map(tp, 0.2).traction - return_map(tm, 0.2).traction) / (2 * h);
    EXPECT_LT((fd - sl.d_trial.col(k)).norm(), 1e-7) << k;
  }
  const Vec3 fdb = (return_map(trial, 0.2 + h).traction - return_map(trial, 0.2 - h).traction) / (2 * h);
  EXPECT_LT((fdb - sl.d_bound).norm(), 1e-7);
  auto coulomb = make_friction_law("coulomb", 0.3);
  EXPECT_DOUBLE_EQ(coulomb->bound(2.0), 0.6);
  EXPECT_DOUBLE_EQ(coulomb->bound(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(make_friction_law("tresca", 0.7)->bound(5.0), 0.7);
  EXPECT_THROW(make_friction_law("stribeck", 1.0), Error);
}

namespace {
struct FrictionCase {
  std::string discretization;
  bool three_d;
  bool rigid;
  std::string method = "penalty";
  std::string smoothing = "none";
};
std::string friction_name(const ::testing::TestParamInfo<FrictionCase>& i) {
  return (i.param.rigid ? std::string("rigid_cylinder") : i.param.discretization + (i.param.three_d ? "_3d" : "_2d")) +
         (i.param.method == "penalty" ? "" : "_" + i.param.method) +
         (i.param.smoothing == "none" ? "" : "_" + i.param.smoothing);
}
}  // namespace

class FrictionTangent : public ::testing::TestWithParam<FrictionCase> {};

TEST_P(FrictionTangent, MatchesCentralDifferences) {
  const FrictionCase fc = GetParam();
  const bool ntn = fc.discretization == "node_to_node";
  const ElementType type = fc.three_d ? ElementType::hex8 : ElementType::quad4;
  Mesh mesh = fc.rigid ? structured_rectangle(ElementType::quad4, 6, 2, 1.0, 0.5)
              : fc.three_d
                  ? test::two_blocks(type, 3, ntn ? 3 : 4, 1.0, 0.5, Vec3(ntn ? 0 : 0.02, ntn ? 0 : 0.03, 0.5 - 0.01), true)
                  : test::two_blocks(type, 3, ntn ? 3 : 4, 1.0, 0.5, Vec3(0, 0.5 - 0.01, 0));
  orient_facets(mesh);
  AnalysisSettings as;
  as.dimension = fc.three_d ? Dimension::three_d : Dimension::plane_strain;
  const int dim = as.spatial_dim();
  std::vector<const ElementBlock*> cells;
  for (auto& [n, blocks] : mesh.regions)
    for (auto& b : blocks) cells.push_back(&b);
  DofMap dofs(mesh.num_nodes(), dim, cells);
  // Start of the increment: the slave side pressed in; then a tangential motion of varying
  // size, so that some closed nodes stick and others slip.
  const Index nu = dofs.num_dofs() + (fc.rigid ? dim + 1 : 0);  // the roller: translations and angle
  VecX z0 = VecX::Zero(nu);
  const int vert = dim - 1;
  const std::string moving = fc.rigid ? "domain" : "upper_domain";
  for (Index n : mesh.node_sets[moving]) {
    const Vec3& X = mesh.nodes[n];
    z0(dofs.dof(n, vert)) = (fc.rigid ? 1 : -1) * (0.004 + 0.006 * std::sin(7 * X(0) + 3 * X(1)));
  }
  if (fc.rigid) z0(dofs.num_dofs() + 1) = -0.04;  // the roller moves down into the block (3 nodes touch)
  if (fc.rigid) z0(nu - 1) = 0.02;                // and has turned
  if (fc.smoothing != "none") bend_lower_block(mesh, dofs, dim, z0);
  VecX z = z0;
  for (Index n : mesh.node_sets[moving]) {
    const Vec3& X = mesh.nodes[n];
    z(dofs.dof(n, 0)) += 0.004 * std::cos(5 * X(0) + 2 * X(vert)) + 0.002;
    if (dim == 3) z(dofs.dof(n, 1)) += 0.003 * std::sin(4 * X(0));
  }
  if (fc.rigid) z(dofs.num_dofs()) = 0.003;
  if (fc.rigid) z(nu - 1) = 0.03;  // it turns on in the increment: the slip origins move on a circle
  // The tangential penalty that gives a mix of sticking and slipping nodes for this motion.
  bool checked = false;
  for (Real epst : {4000.0, 1000.0, 16000.0, 250.0, 64000.0, 60.0}) {
    ContactPairSettings cs;
    cs.name = "c";
    cs.method = fc.method;
    cs.discretization = fc.discretization;
    cs.friction = "coulomb";
    cs.friction_parameter = 0.3;
    cs.tangential_penalty = epst;
    cs.stick_predictor = false;  // the return map's own stick/slip statuses (the predictor: FrictionGrid*)
    cs.smoothing = fc.smoothing;
    if (fc.rigid) {
      cs.slave = "ymax";
      cs.rigid = true;
      cs.obstacle.shape = "cylinder";
      cs.obstacle.point = Vec3(0.5, 1.5, 0);
      cs.obstacle.radius = 1.0;
      cs.turns = true;
    } else {
      cs.master = fc.three_d ? "lower_zmax" : "lower_ymax";
      cs.slave = fc.three_d ? "upper_zmin" : "upper_ymin";
    }
    ContactInterface ci(cs, mesh, as, 100.0, false);
    ASSERT_TRUE(ci.frictional());
    ASSERT_FALSE(ci.symmetric());
    // Unknowns: displacements, multipliers (Lagrange: normal, then dim tangential per slave
    // node), the obstacle's displacement.
    const Index nm = ci.num_multipliers(), nz = nu + nm;
    ci.set_multiplier_offset(dofs.num_dofs());
    ci.set_obstacle_dofs(dofs.num_dofs() + nm);
    auto with_multipliers = [&](const VecX& u) {
      VecX zz = VecX::Zero(nz);
      zz.head(dofs.num_dofs()) = u.head(dofs.num_dofs());
      zz.tail(nu - dofs.num_dofs()) = u.tail(nu - dofs.num_dofs());
      // Pressures of both signs (open and closed nodes), tangential tractions of varying size.
      const Index ns = nm / (1 + dim);
      for (Index j = 0; j < ns; ++j) {
        zz(dofs.num_dofs() + j) = 0.6 * (j % 3) - 0.2;
        for (int d = 0; d < dim; ++d) zz(dofs.num_dofs() + ns + j * dim + d) = 0.15 * std::sin(2.0 * j + d);
      }
      return zz;
    };
    const VecX zs = with_multipliers(z0);
    ci.detect(test::cells_of_positions(mesh, dofs, zs), 0.05);
    ci.begin_increment(test::cells_of_positions(mesh, dofs, zs), zs);
    auto residual = [&](const VecX& zz, GlobalMatrix* K) {
      VecX r = VecX::Zero(nz);
      ci.assemble(test::cells_of_positions(mesh, dofs, zz), zz, dofs, r, K);
      return r;
    };
    VecX zc = with_multipliers(z);
    if (fc.method == "augmented_lagrangian") {
      // One Uzawa update at z (normal and tangential multipliers, slip origins moved), then
      // the check at a state moved further.
      residual(zc, nullptr);
      Real pen = 0;
      ASSERT_FALSE(ci.augment(test::cells_of_positions(mesh, dofs, zc), zc, pen));
      for (Index n : mesh.node_sets[moving]) zc(dofs.dof(n, 0)) += 0.002 * std::sin(9 * mesh.nodes[n](0));
    }
    DenseMatrix K(nz);
    residual(zc, &K);
    Index stick = 0, slip = 0;
    for (size_t j = 0; j < ci.constraints().size(); ++j)
      if (ci.state().active[j] && ci.constraints()[j].has_slip) ci.state().slip[j] ? ++slip : ++stick;
    if (stick == 0 || slip == 0) continue;
    std::printf("%s: eps_T %g, %lld stick, %lld slip\n", friction_name({fc, 0}).c_str(), epst, (long long)stick,
                (long long)slip);
    const Real maxerr =
        test::central_difference_error([&](const VecX& zz) { return residual(zz, nullptr); }, zc, K.k, 1e-7);
    EXPECT_LT(maxerr, 1e-6 * K.k.cwiseAbs().maxCoeff());
    EXPECT_GT((K.k - K.k.transpose()).cwiseAbs().maxCoeff(), 1e-6 * K.k.cwiseAbs().maxCoeff())
        << "the frictional tangent should be unsymmetric";
    checked = true;
    break;
  }
  EXPECT_TRUE(checked) << "no tangential penalty gave both sticking and slipping nodes: nothing was checked";
}

INSTANTIATE_TEST_SUITE_P(Methods, FrictionTangent,
                         ::testing::Values(FrictionCase{"node_to_segment", false, false},
                                           FrictionCase{"node_to_segment", true, false},
                                           FrictionCase{"node_to_node", false, false},
                                           FrictionCase{"node_to_segment", false, true},
                                           FrictionCase{"node_to_segment", false, false, "augmented_lagrangian"},
                                           FrictionCase{"node_to_segment", true, false, "augmented_lagrangian"},
                                           FrictionCase{"node_to_segment", false, false, "penalty", "hermite"},
                                           FrictionCase{"node_to_segment", false, false, "augmented_lagrangian",
                                                        "hermite"},
                                           FrictionCase{"node_to_segment", false, false, "lagrange"},
                                           FrictionCase{"node_to_segment", true, false, "lagrange"},
                                           FrictionCase{"node_to_node", false, false, "lagrange"},
                                           FrictionCase{"node_to_node", true, false, "lagrange"},
                                           FrictionCase{"node_to_segment", false, true, "lagrange"},
                                           FrictionCase{"node_to_segment", false, false, "lagrange", "hermite"},
                                           FrictionCase{"node_to_segment", true, false, "penalty", "hermite"},
                                           FrictionCase{"node_to_segment", true, false, "lagrange", "hermite"}),
                         friction_name);

// The stick/slip chattering guard: a closed node whose status flips more than max_flips times
// among the accepted iterates of an increment is held in its status; at convergence a hold on
// the wrong side of the friction disc is swapped once (fix_held_nodes), and one still wrong is
// reported (frozen_in_tension), so the increment would be cut back.
namespace {
// Two quad4 blocks in plane strain, the upper one's bottom (slave) 0.01 above the lower one's top
// (master), and a node-to-segment pair between them with Coulomb friction (mu = 0.3) and the
// return map's own statuses (no stick predictor).
struct FrictionBlocks {
  explicit FrictionBlocks(const std::string& method) {
    mesh = test::two_blocks(ElementType::quad4, 3, 4, 1.0, 0.5, Vec3(0, 0.5 - 0.01, 0));
    orient_facets(mesh);
    as.dimension = Dimension::plane_strain;
    std::vector<const ElementBlock*> cells;
    for (auto& [n, blocks] : mesh.regions)
      for (auto& b : blocks) cells.push_back(&b);
    dofs = DofMap(mesh.num_nodes(), 2, cells);
    cs.name = "c";
    cs.method = method;
    cs.master = "lower_ymax";
    cs.slave = "upper_ymin";
    cs.friction = "coulomb";
    cs.friction_parameter = 0.3;
    cs.stick_predictor = false;
  }
  Mesh mesh;
  AnalysisSettings as;
  DofMap dofs;
  ContactPairSettings cs;
};
}  // namespace

TEST(Friction, ChatteringGuardHoldsStickSlipAndChecksIt) {
  FrictionBlocks blocks("penalty");
  Mesh& mesh = blocks.mesh;
  const DofMap& dofs = blocks.dofs;
  ContactPairSettings& cs = blocks.cs;
  const Index nz = dofs.num_dofs();
  VecX z0 = VecX::Zero(nz);
  for (Index n : mesh.node_sets["upper_domain"]) z0(dofs.dof(n, 1)) = -0.005;  // pressed in uniformly
  // Rigid tangential shifts of the upper block: small (every closed node sticks), large (slips).
  auto shifted = [&](Real s) {
    VecX z = z0;
    for (Index n : mesh.node_sets["upper_domain"]) z(dofs.dof(n, 0)) += s;
    return z;
  };
  cs.tangential_penalty = 5000;
  cs.max_flips = 2;  // the guard on the return map's own stick/slip statuses
  ContactInterface ci(cs, mesh, blocks.as, 100.0, false);
  ci.set_multiplier_offset(nz);
  ci.detect(test::cells_of_positions(mesh, dofs, z0), 0.05);
  ci.begin_increment(test::cells_of_positions(mesh, dofs, z0), z0);
  auto evaluate = [&](const VecX& z) {
    VecX r = VecX::Zero(nz);
    ci.assemble(test::cells_of_positions(mesh, dofs, z), z, dofs, r, nullptr);
  };
  auto count = [&](bool slip) {
    Index n = 0;
    for (size_t j = 0; j < ci.state().active.size(); ++j) n += ci.state().active[j] && ci.state().slip[j] == slip;
    return n;
  };
  const VecX stick = shifted(1e-6), slip = shifted(0.02);
  evaluate(stick);
  const Index closed = count(false);
  ASSERT_GT(closed, 0);
  ASSERT_EQ(count(true), 0) << "a tiny shift should leave every closed node sticking";
  evaluate(slip);
  // (the slave's end node, shifted beyond the master's end, may stay as it was)
  const Index flipping = count(true);
  ASSERT_GE(flipping, closed - 1) << "a large shift should make the closed nodes slip";
  // Flip the status max_flips + 1 times: the nodes are then held in the status they have. Each
  // accepted iterate counts the closed nodes that slip and those that turned to slip or to stick
  // (the Newton log's "[N closed +a -b, S slip +c -d]"); at the first, every node closes (from
  // the increment's open start): none turned.
  for (int k = 0; k <= cs.max_flips; ++k) {
    evaluate(k % 2 == 0 ? slip : stick);
    ci.count_status_changes();
    const ContactInterface::IterateStatus& is = ci.iterate_status();
    EXPECT_EQ(is.closed, closed) << "iterate " << k;
    EXPECT_EQ(is.slipping, k % 2 == 0 ? flipping : 0) << "iterate " << k;
    EXPECT_EQ(is.to_slip, k % 2 == 0 && k > 0 ? flipping : 0) << "iterate " << k;
    EXPECT_EQ(is.to_stick, k % 2 == 1 ? flipping : 0) << "iterate " << k;
  }
  evaluate(stick);
  EXPECT_EQ(count(true), flipping) << "held in slip, the nodes slip even where the trial traction is inside the disc";
  EXPECT_EQ(ci.frozen_in_tension(), flipping) << "held slip with the trial deep inside the disc is a violation";
  EXPECT_EQ(ci.fix_held_nodes(), flipping) << "the wrong hold is swapped once";
  evaluate(stick);
  EXPECT_EQ(count(false), closed);
  EXPECT_EQ(ci.frozen_in_tension(), 0);
  evaluate(slip);
  EXPECT_EQ(ci.frozen_in_tension(), flipping) << "held in stick now, a large slip is a violation";
  EXPECT_EQ(ci.fix_held_nodes(), 0) << "a hold is swapped only once";
}

// The first Newton matrix of an increment that starts where the last one converged (no
// predictor moved the bodies): a closed node has not slipped, its trial is its committed
// traction, on the rim of its disc if it slipped, the return map's kink; it takes the stick
// branch there (ContactInterface::begin_increment's `unmoved`), in that matrix only. The
// tangential multipliers are set outside the disc here, so that the return map's own choice is
// slip and the test sees which branch was taken: stick in the first assembly with a matrix of
// an unmoved increment, slip in residual-only assemblies, in the next assembly, and in a moved
// increment. Lagrange multipliers; and penalty with its nodes slipped, so not at the kink.
TEST(Friction, UnmovedIncrementStartsInStick) {
  for (const std::string method : {"lagrange", "penalty"}) {
    SCOPED_TRACE(method);
    FrictionBlocks blocks(method);
    Mesh& mesh = blocks.mesh;
    const DofMap& dofs = blocks.dofs;
    ContactInterface ci(blocks.cs, mesh, blocks.as, 100.0, false);
    const Index nd = dofs.num_dofs(), nm = ci.num_multipliers(), nz = nd + nm;
    ci.set_multiplier_offset(nd);
    VecX z = VecX::Zero(nz);
    for (Index n : mesh.node_sets["upper_domain"]) z(dofs.dof(n, 1)) = -0.005;  // pressed in uniformly
    const Index ns = nm / 3;
    for (Index j = 0; j < ns; ++j) {
      z(nd + j) = 1.0;                        // Lagrange: closed
      z(nd + ns + 2 * j) = -1e8;              // Lagrange: far outside the disc
    }
    const std::vector<Vec3> x = test::cells_of_positions(mesh, dofs, z);
    ci.detect(x, 0.05);
    // Penalty: the committed traction is the last increment's (end_increment), zero in a first
    // increment, so its slip is made by a tangential shift of the assemblies' state (which is
    // then not the unmoved state: such a node is not at the kink and keeps the return map's choice).
    VecX zs = z;
    if (method == "penalty")
      for (Index n : mesh.node_sets["upper_domain"]) zs(dofs.dof(n, 0)) += 0.02;
    auto statuses = [&](bool matrix) {
      VecX r = VecX::Zero(nz);
      DenseMatrix K(nz);
      ci.assemble(test::cells_of_positions(mesh, dofs, zs), zs, dofs, r, matrix ? &K : nullptr);
      std::pair<Index, Index> stick_slip{0, 0};
      for (size_t j = 0; j < ci.state().active.size(); ++j) {
        if (ci.state().active[j] && ci.constraints()[j].has_slip) ++(ci.state().slip[j] ? stick_slip.second : stick_slip.first);
      }
      return stick_slip;
    };
    ci.begin_increment(x, z, true);
    const auto own = statuses(false);
    ASSERT_GT(own.second, 0) << "the return map's own choice should be slip";
    const auto first = statuses(true);
    if (method == "penalty") {
      // A node that has slipped (the shift) is not at the kink: the return map decides.
      EXPECT_EQ(first, own) << "a slipped node keeps the return map's choice";
      continue;
    }
    EXPECT_EQ(first.second, 0) << "the first Newton matrix of an unmoved increment takes the stick branch";
    EXPECT_EQ(first.first, own.first + own.second);
    EXPECT_EQ(statuses(true), own) << "in that matrix only";
    ci.begin_increment(x, z, false);
    EXPECT_EQ(statuses(true), own) << "a moved increment keeps the return map's choice";
  }
}

// The chattering guard's open/closed hold acts on penalty and the augmented Lagrangian as on
// the multipliers: a node held closed keeps p = lambda-bar - eps g with the bodies apart (a
// tensile p, which fix_held_nodes then releases), and one held open puts no force while it
// penetrates. Until session 65 Penalty::assemble ignored the hold: the log said the nodes were
// held, and the next iterate decided their status afresh.
TEST(ChatteringGuard, PenaltyAndAugmentedLagrangianHonourTheOpenClosedHold) {
  for (const char* method : {"penalty", "augmented_lagrangian"}) {
    for (const bool hold_closed : {true, false}) {
      SCOPED_TRACE(std::string(method) + (hold_closed ? ", held closed" : ", held open"));
      FrictionBlocks blocks(method);
      Mesh& mesh = blocks.mesh;
      const DofMap& dofs = blocks.dofs;
      ContactPairSettings& cs = blocks.cs;
      cs.friction = "none";
      // Closed, open, closed: the third change holds closed (max_flips 2); closed, open: the
      // second holds open (max_flips 1).
      cs.max_flips = hold_closed ? 2 : 1;
      const Index nz = dofs.num_dofs();
      auto lifted = [&](Real s) {
        VecX z = VecX::Zero(nz);
        for (Index n : mesh.node_sets["upper_domain"]) z(dofs.dof(n, 1)) = s;
        return z;
      };
      const VecX pressed = lifted(-0.005), apart = lifted(0.03);
      ContactInterface ci(cs, mesh, blocks.as, 100.0, false);
      ci.detect(test::cells_of_positions(mesh, dofs, pressed), 0.1);
      ci.begin_increment(test::cells_of_positions(mesh, dofs, pressed), pressed);
      VecX r;
      auto evaluate = [&](const VecX& z) {
        r = VecX::Zero(nz);
        ci.assemble(test::cells_of_positions(mesh, dofs, z), z, dofs, r, nullptr);
      };
      auto closed = [&] {
        Index n = 0;
        for (char a : ci.state().active) n += a != 0;
        return n;
      };
      evaluate(pressed);
      const Index touching = closed();
      ASSERT_GT(touching, 0);
      ASSERT_GT(r.norm(), 0);
      evaluate(apart);
      ASSERT_EQ(closed(), 0) << "lifted clear, every node is open";
      // The accepted iterates: pressed, apart (, pressed).
      for (int k = 0; k <= cs.max_flips; ++k) {
        evaluate(k % 2 == 0 ? pressed : apart);
        ci.count_status_changes();
      }
      if (hold_closed) {
        evaluate(apart);
        EXPECT_EQ(closed(), touching) << "held closed, the nodes stay closed with the bodies apart";
        Real most = -1e300;
        for (size_t j = 0; j < ci.state().active.size(); ++j)
          if (ci.state().active[j]) most = std::max(most, ci.state().pressure[j]);
        EXPECT_LT(most, 0) << "apart, a held node's pressure is tensile";
        EXPECT_GT(r.norm(), 0) << "and it pulls the bodies together";
        EXPECT_EQ(ci.frozen_in_tension(), touching);
        EXPECT_EQ(ci.fix_held_nodes(), touching) << "held closed in tension: held open instead";
        evaluate(apart);
        EXPECT_EQ(closed(), 0);
        EXPECT_EQ(r.norm(), 0);
      } else {
        evaluate(pressed);
        EXPECT_EQ(closed(), 0) << "held open, the nodes stay open while they penetrate";
        EXPECT_EQ(r.norm(), 0) << "and put no force on the bodies";
        EXPECT_EQ(ci.frozen_in_tension(), touching) << "held open and penetrating 0.005 is a violation";
      }
    }
  }
}
