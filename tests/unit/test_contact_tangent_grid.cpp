// The finite-difference tangent grid: for every combination the compatibility table allows
// (contact/compatibility.hpp: analysis x slave and master facets x discretization, one or two
// passes, self-contact, rigid plane/cylinder/sphere x enforcement x friction x smoothing), the contact
// residual's tangent against central differences of the residual, at a state with open and
// closed slave nodes (and, with friction, an increment's tangential motion from the slip
// origins), through the pair's whole lifecycle (detect, begin_increment, assemble, and for the
// augmented Lagrangian one Uzawa update). Adding a discretization or an enforcement to the
// table adds its cases here.
#include <gtest/gtest.h>

#include <omp.h>

#include <random>
#include <set>

#include "common.hpp"
#include "signorini/contact/compatibility.hpp"
#include "signorini/contact/contact_interface.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/boundary_traction.hpp"

using namespace signorini;
using signorini::test::DenseMatrix;

namespace {

// The cell type whose faces are the given facet type.
ElementType cell_of(ElementType facet) {
  switch (facet) {
    case ElementType::line2: return ElementType::quad4;
    case ElementType::line3: return ElementType::quad9;
    case ElementType::tri3: return ElementType::tet4;
    case ElementType::tri6: return ElementType::tet10;
    case ElementType::quad4: return ElementType::hex8;
    case ElementType::quad8: return ElementType::hex20;
    default: return ElementType::hex27;
  }
}

// One combination (ASSERTs return from here; the failure names the combination).
// theta: Nitsche's variant; finite: finite strain (Nitsche: theta 0, the current normal and the
// nominal traction of a Saint Venant-Kirchhoff body).
void check_combination(const ContactCombination& c, int theta = 1, bool finite = false) {
  const std::string variant =
      c.method == "nitsche" ? " theta " + std::to_string(theta) + (finite ? " finite strain" : "") : std::string();
  SCOPED_TRACE(c.text() + variant);
  const bool three = c.dimension == Dimension::three_d;
  const bool ntn = c.discretization == "node_to_node";
  const int vert = three ? 2 : 1;
  // Two blocks (the upper one's bottom is slave, non-matching unless node-to-node, shifted so
  // that no slave node sits on a master facet's edge), or one block under a rigid obstacle.
  Mesh mesh;
  std::string moving;
  if (c.rigid()) {
    const ElementType t = cell_of(c.slave_facet);
    mesh = three ? structured_box(t, 3, 3, 1, 1.0, 1.0, 0.5) : structured_rectangle(t, 4, 1, 1.0, 0.5);
    moving = "domain";
  } else {
    const Vec3 off = three ? Vec3(ntn ? 0 : 0.02, ntn ? 0 : 0.03, 0.49) : Vec3(0, 0.49, 0);
    const int nl = three ? 2 : 3, nu = ntn ? nl : nl + 1;
    mesh = test::two_blocks(cell_of(c.master_facet), nl, nu, 1.0, 0.5, off, three, cell_of(c.slave_facet), 1);
    moving = "upper_domain";
    // In 3D the shifted upper block is shrunk in x and y so that no slave node overhangs the
    // master's edge (where the constraint switches between segment, edge and none: kinks).
    if (three && !ntn)
      for (Index n : mesh.node_sets.at(moving))
        for (int d = 0; d < 2; ++d) mesh.nodes[n](d) = 0.05 + 0.9 * mesh.nodes[n](d);
  }
  orient_facets(mesh);
  AnalysisSettings as;
  as.dimension = c.dimension;
  as.finite_strain = finite;
  const int dim = as.spatial_dim();
  std::vector<const ElementBlock*> cells;
  for (auto& [n, blocks] : mesh.regions)
    for (auto& b : blocks) cells.push_back(&b);
  DofMap dofs(mesh.num_nodes(), dim, cells);
  const Index nd = dofs.num_dofs();

  ContactPairSettings cs;
  cs.name = "c";
  cs.method = c.method;
  cs.passes = c.passes;
  cs.smoothing = c.smoothing;
  cs.friction = c.friction;
  cs.friction_parameter = c.friction == "coulomb" ? 0.3 : 0.05;
  cs.stick_predictor = false;  // stick and slip from the return map at every grid state
  if (c.rigid()) {
    cs.rigid = true;
    cs.slave = three ? "zmax" : "ymax";
    RigidObstacle& ob = cs.obstacle;
    ob.shape = c.discretization.substr(6);
    cs.turns = true;  // the rotation is an unknown (but in axisymmetry)
    if (ob.shape == "plane") {
      ob.point = three ? Vec3(0, 0, 0.505) : Vec3(0, 0.505, 0);
      ob.normal = -Vec3::Unit(vert);
    } else {
      // Axisymmetric: the sphere's centre on the axis (r = 0).
      const Real cx = c.dimension == Dimension::axisymmetric ? 0.0 : 0.5;
      ob.point = three ? Vec3(0.5, 0.5, 1.5) : Vec3(cx, 1.5, 0);
      ob.radius = 1.0;
      ob.axis = Vec3::UnitY();
    }
  } else {
    cs.discretization = c.discretization;
    cs.master = three ? "lower_zmax" : "lower_ymax";
    cs.slave = three ? "upper_zmin" : "upper_ymin";
    if (c.self) {
      // Self-contact: the two faces as one facet set (every node of either is a slave of the
      // other's facets).
      auto& both = mesh.facet_sets["both"];
      for (const std::string& set : {cs.master, cs.slave})
        for (const ElementBlock& b : mesh.facet_sets.at(set)) both.push_back(b);
      cs.self = true;
      cs.master = cs.slave = "both";
    }
  }
  ASSERT_TRUE(check_contact_combination(c).message.empty());

  // Start of the increment: the slave side pressed in (a wave, so some nodes open); then a
  // tangential motion of varying size.
  // A rigid obstacle's unknowns: dim translations, and (but in axisymmetry) its angles: one in
  // plane problems, a rotation vector in 3D.
  const int angles = !c.rigid() || c.dimension == Dimension::axisymmetric ? 0 : (three ? 3 : 1);
  const Index nu = nd + (c.rigid() ? dim + angles : 0);
  VecX z0 = VecX::Zero(nu);
  for (Index n : mesh.node_sets[moving]) {
    const Vec3& X = mesh.nodes[n];
    z0(dofs.dof(n, vert)) = (c.rigid() ? 1 : -1) * (0.004 + 0.008 * std::sin(7 * X(0) + 3 * X(1)));
    // Nitsche decides per integration point, and the blocks start 0.01 into each other: the
    // upper one tilted up on its right, where its points open. So is 3D mortar's, whose weighted
    // gaps average the wave over the facets around a node (all closed without the tilt).
    if (c.method == "nitsche" || (three && c.discretization == "mortar")) z0(dofs.dof(n, vert)) += 0.03 * X(0);
  }
  if (c.rigid()) z0(nd + vert) = c.discretization == "rigid_plane" ? 0.0 : -0.04;
  // Turned (a plane about its point, so its normal tilts; a cylinder or sphere about its centre
  // or axis point, which moves friction's slip origins), and turned further in the increment.
  const Real turn0[3] = {-0.005, 0.004, 0.003}, turn1[3] = {-0.008, 0.007, -0.002};
  for (int i = 0; i < angles; ++i) z0(nd + dim + i) = turn0[i];
  if (c.smoothing != "none") {
    // A curved master, so that smoothing differs from the faceted surface.
    for (Index n : mesh.node_sets.at("lower_domain")) {
      const Vec3& X = mesh.nodes[n];
      z0(dofs.dof(n, vert)) += 0.03 * std::sin(9 * X(0)) * X(vert);
    }
  }
  VecX z = z0;
  for (Index n : mesh.node_sets[moving]) {
    const Vec3& X = mesh.nodes[n];
    z(dofs.dof(n, 0)) += 0.004 * std::cos(5 * X(0) + 2 * X(vert)) + 0.002;
    if (three) z(dofs.dof(n, 1)) += 0.003 * std::sin(4 * X(0));
  }
  if (c.rigid()) z(nd) = 0.003;
  for (int i = 0; i < angles; ++i) z(nd + dim + i) = turn1[i];

  // Tangential stiffness: automatic first; others until some closed nodes stick and others slip.
  const std::vector<Real> tangential =
      c.friction == "none" ? std::vector<Real>{0.0} : std::vector<Real>{0.0, 4000.0, 250.0, 64000.0, 30.0, 12000.0, 20000.0, 100.0};
  // Nitsche: the bodies' stress at the slave facets (one elastic material, E the stiffness
  // scale the pairs are given), and the Newton matrix with the gap's whole second variation.
  const LinearElastic elastic(100.0, 0.3);
  std::vector<BoundaryTraction::Cells> cells_of_bodies;
  for (auto& [name, blocks] : mesh.regions)
    for (auto& b : blocks) cells_of_bodies.push_back({&b, &elastic});
  BoundaryTraction traction(cells_of_bodies, mesh.nodes, as);
  cs.nitsche_exact_tangent = true;
  cs.nitsche_theta = theta;
  // Nitsche's tangential parameter is its normal one: the friction coefficient (or Tresca's
  // bound) varies instead.
  const Real friction0 = cs.friction_parameter;
  const std::vector<Real> bound_scale = {1.0, 0.5, 2.0, 0.3, 3.0, 0.1, 10.0, 0.03, 30.0, 100.0, 200.0, 150.0, 300.0, 500.0, 700.0, 1000.0};
  const size_t attempts = c.method == "nitsche" && c.friction != "none" ? bound_scale.size() : tangential.size();
  // Nitsche with friction: a state where one of the many integration points sits on its stick/slip
  // boundary within the differences' step is a kink (the one-sided differences differ, and the
  // Newton matrix is one of them): the attempt is repeated with the bound 1 % larger, at most
  // three times (the quad8 slave on tri3 and tri6 masters with mortar's cells: a point 2e-6 of
  // the bound from it).
  int nudges = 0;
  for (size_t attempt = 0; attempt < attempts; ++attempt) {
    cs.tangential_penalty = tangential[std::min(attempt, tangential.size() - 1)];
    if (c.method == "nitsche") cs.friction_parameter = friction0 * bound_scale[attempt] * std::pow(1.01, nudges);
    std::vector<std::unique_ptr<ContactInterface>> pairs;
    pairs.push_back(std::make_unique<ContactInterface>(cs, mesh, as, 100.0, false));
    if (c.passes == 2) pairs.push_back(std::make_unique<ContactInterface>(cs, mesh, as, 100.0, true));
    for (auto& p : pairs)
      if (p->needs_boundary_traction()) p->set_boundary_traction(&traction);
    Index nm = 0;
    for (auto& p : pairs) {
      p->set_multiplier_offset(nd + nm);
      nm += p->num_multipliers();
    }
    for (auto& p : pairs) p->set_obstacle_dofs(nd + nm);
    ASSERT_EQ(pairs[0]->num_obstacle_dofs(), nu - nd);
    const Index nz = nu + nm;
    // Unknowns: displacements, multipliers (per pair: normal, then dim tangential per slave
    // node) with pressures of both signs and tractions of varying size, the obstacle's motion.
    auto with_multipliers = [&](const VecX& u) {
      VecX zz = VecX::Zero(nz);
      zz.head(nd) = u.head(nd);
      zz.tail(nu - nd) = u.tail(nu - nd);
      for (auto& p : pairs) {
        const Index ns = p->num_multipliers() / (p->frictional() ? 1 + dim : 1);
        for (Index j = 0; j < ns; ++j) {
          zz(p->multiplier_offset() + j) = 0.6 * (j % 3) - 0.2;
          if (p->frictional())
            for (int d = 0; d < dim; ++d) zz(p->multiplier_offset() + ns + j * dim + d) = 0.15 * std::sin(2.0 * j + d);
        }
      }
      return zz;
    };
    const VecX zs = with_multipliers(z0);
    for (auto& p : pairs) {
      p->detect(test::cells_of_positions(mesh, dofs, zs), 0.05);
      p->begin_increment(test::cells_of_positions(mesh, dofs, zs), zs);
    }
    auto residual = [&](const VecX& zz, GlobalMatrix* K) {
      VecX r = VecX::Zero(nz);
      for (auto& p : pairs) p->assemble(test::cells_of_positions(mesh, dofs, zz), zz, dofs, r, K);
      return r;
    };
    VecX zc = with_multipliers(z);
    if (c.method == "augmented_lagrangian") {
      // One Uzawa update (lambda-bar, and with friction the tractions and slip origins), then
      // the check at a state moved further.
      residual(zc, nullptr);
      bool updated = false;
      for (auto& p : pairs) {
        Real pen = 0;
        updated = !p->augment(test::cells_of_positions(mesh, dofs, zc), zc, pen) || updated;
      }
      ASSERT_TRUE(updated) << "no Uzawa update: the augmented Lagrangian's multipliers would be zero";
      // Nowhere zero, and pressing further: a node that stays put sits on the rim of the Tresca
      // disc (it slipped at the update), one that only slides on a flat master at p = 0 (the
      // update made lambda-bar its force), both kinks.
      for (Index n : mesh.node_sets[moving]) {
        zc(dofs.dof(n, 0)) += 0.002 * (1.5 + std::sin(9 * mesh.nodes[n](0)));
        zc(dofs.dof(n, vert)) += (c.rigid() ? 1 : -1) * 0.00137;
      }
    }
    DenseMatrix K(nz);
    residual(zc, &K);
    Index closed = 0, open = 0, stick = 0, slip = 0;
    for (auto& p : pairs)
      for (size_t j = 0; j < p->constraints().size(); ++j) {
        if (p->constraints()[j].kind == ConstraintKind::none) continue;
        p->state().active[j] ? ++closed : ++open;
        if (p->frictional() && p->state().active[j] && p->constraints()[j].has_slip)
          p->state().slip[j] ? ++slip : ++stick;
      }
    ASSERT_GT(closed, 0) << "no closed node: the check would be empty";
    if (three && c.discretization == "mortar") {
      ASSERT_GT(open, 0) << "no open node: one branch unchecked";
    }
    // Nitsche decides per integration point: both branches (P > 0 and P <= 0) must be in the
    // check, and with friction its points' stick and slip (the nodes' are an average).
    for (auto& p : pairs)
      if (const auto* pts = p->integration_points()) {
        Index active = 0;
        for (const PointConstraint& pc : *pts) active += pc.pressure - pc.stiffness * pc.gap > 0;
        ASSERT_GT(active, 0) << "no active integration point";
        ASSERT_LT(active, static_cast<Index>(pts->size())) << "no open integration point";
        std::printf("  %lld of %zu integration points active\n", (long long)active, pts->size());
        if (p->frictional()) {
          stick = slip = 0;
          for (signed char s : p->state().point_slip) s == 0 ? ++stick : s == 1 ? ++slip : 0;
        }
      }
    const bool mixed = c.friction == "none" || (stick > 0 && slip > 0);
    if (!mixed && attempt + 1 < attempts) continue;
    if (c.method == "nitsche") {
      EXPECT_TRUE(mixed) << "no integration point sticks, or none slips";
    }
    // The unknowns the contact residual depends on (the others' columns are zero).
    std::set<Index> involved;
    for (auto& p : pairs) {
      std::vector<std::vector<Index>> groups;
      p->couplings(dofs, groups);
      for (auto& g : groups)
        for (Index i : g)
          if (i >= 0) involved.insert(i);
    }
    const Real h = 1e-7;
    Real err = 0;
    bool kink = false;  // the one-sided differences differ (directional differences only)
    const Real maxk = K.k.cwiseAbs().maxCoeff();
    if (!std::getenv("SIGNORINI_GRID_COLUMNS")) {
      // Central differences along 6 pseudo-random directions v over the involved unknowns
      // (components uniform in [-1, 1], a fixed seed): K v against -(r(z + h v) - r(z - h v)) / 2h,
      // 12 residuals instead of two per involved unknown. A wrong entry K_ij shows in (K v)_i
      // unless v_j is tiny in all six (one entry moved by 1e-5 max |K| on purpose failed every
      // row of the 3D table, docs/contact.md). SIGNORINI_GRID_COLUMNS=1: column by column (the
      // long ctests).
      std::mt19937 rng(12345);
      const VecX r0 = residual(zc, nullptr);
      for (int k = 0; k < 6; ++k) {
        VecX v = VecX::Zero(nz);
        for (Index j : involved) v(j) = 2.0 * (static_cast<Real>(rng()) / 4294967295.0) - 1.0;
        const VecX rp = residual(zc + h * v, nullptr), rm = residual(zc - h * v, nullptr);
        const VecX d = -(rp - rm) / (2 * h);
        const Real e = (d - K.k * v).cwiseAbs().maxCoeff();
        err = std::max(err, e);
        if (e >= 1e-6 * maxk && ((rp - r0) + (rm - r0)).cwiseAbs().maxCoeff() / h > 1e-4 * maxk) kink = true;
      }
    } else {
      for (Index j : involved) {
        VecX zp = zc, zm = zc;
        zp(j) += h;
        zm(j) -= h;
        const VecX d = -(residual(zp, nullptr) - residual(zm, nullptr)) / (2 * h);
        Index row = 0;
        const Real e = (d - K.k.col(j)).cwiseAbs().maxCoeff(&row);
        if (e > err && std::getenv("SIGNORINI_TEST_VERBOSE"))
          std::printf("  column %lld row %lld: FD %.6e tangent %.6e (one-sided %.6e %.6e)\n", (long long)j,
                      (long long)row, d(row), K.k(row, j), -(residual(zp, nullptr) - residual(zc, nullptr))(row) / h,
                      -(residual(zc, nullptr) - residual(zm, nullptr))(row) / h);
        err = std::max(err, e);
      }
    }
    std::printf("%s%s: %lld closed, %lld open, %lld stick, %lld slip; tangent error %.2e of max |K| %.2e\n",
                c.text().c_str(), variant.c_str(), (long long)closed, (long long)open, (long long)stick, (long long)slip, err / maxk,
                maxk);
    if (err >= 1e-6 * maxk && kink && c.method == "nitsche" && c.friction != "none" && nudges < 3) {
      std::printf("  a kink at this state: the bound nudged by 1 %%\n");
      ++nudges;
      --attempt;
      continue;
    }
    EXPECT_LT(err, 1e-6 * maxk) << c.text();
    break;
  }
}

}  // namespace

// The whole table in two tests, 2D and 3D (a ctest process per combination would cost 0.3 s
// each in start-up alone; two let ctest -j run them side by side). The log has a line per
// combination; together they cover every supported one. One thread each: the small contact
// assemblies of the central differences gain nothing from a second one (3D: 88 s on one
// thread, 80 s on two), and under ctest -j2 two threads per test oversubscribe the cores (the
// 3D test then took 233 s).
struct OneThread {
  int before = omp_get_max_threads();
  OneThread() { omp_set_num_threads(1); }
  ~OneThread() { omp_set_num_threads(before); }
};

// SIGNORINI_GRID_FILTER=<text>: only the combinations whose description contains it (a quick
// check of one discretization while developing; the suite runs them all).
bool selected(const ContactCombination& c) {
  const char* f = std::getenv("SIGNORINI_GRID_FILTER");
  return !f || c.text().find(f) != std::string::npos;
}

TEST(TangentGrid, EveryCombinationOfTheTableMatchesCentralDifferences) {
  OneThread one;
  const auto all = supported_contact_combinations();
  ASSERT_GT(all.size(), 100u);
  for (const ContactCombination& c : all)
    if (c.dimension != Dimension::three_d && selected(c)) {
      check_combination(c);
      // Nitsche's other variants (theta 0 and -1 change only the weights of its terms; 2D
      // suffices), and at finite strain (theta 0).
      if (c.method == "nitsche") {
        for (int theta : {0, -1}) check_combination(c, theta);
        check_combination(c, 0, true);
      }
    }
}

// The 3D table but mortar and Nitsche: every row (561), in about 14 s with the directional
// central differences (100 s column by column for 486 of them; the ctest
// long.TangentGrid.Every3DCombinationColumnByColumn, label long, checks every row column by column).
TEST(TangentGrid, Every3DCombinationMatchesCentralDifferences) {
  OneThread one;
  int rows = 0;
  for (const ContactCombination& c : supported_contact_combinations())
    if (c.dimension == Dimension::three_d && c.method != "nitsche" && c.discretization != "mortar" && selected(c)) {
      check_combination(c);
      ++rows;
    }
  std::printf("%d 3D rows checked\n", rows);
  if (!std::getenv("SIGNORINI_GRID_FILTER")) {
    EXPECT_EQ(rows, 561) << "the 3D table (but mortar and Nitsche) changed: update the count";
  }
}

// 3D mortar's combinations on their own (its weighted gaps' derivatives are hyper-dual numbers
// over up to 52 coordinates per pair of facets; the residuals of the central differences are
// differentiated to first order only, Discretization::set_second_variation), beside the rest of
// the 3D table. Every linear slave's row (tri3, quad4 on every master: 108 rows, 18 of them
// self-contact) and the tet10 pair's, tri6 on tri6 with Lagrange multipliers and Coulomb
// friction. Quadratic slaves (tri6, quad8, quad9) cost about a second a row even with the
// directional differences (the Newton matrix's second derivatives), and 30 s and more column by
// column: their 45 Coulomb rows (every method and master; frictionless and Tresca differ from
// Coulomb in the friction law only, which the linear rows check) with SIGNORINI_GRID_ALL=1 (70 s
// in all; the ctest long.TangentGrid.Every3DMortarCombinationColumnByColumn, label long, checks
// these 153 rows column by column).
TEST(TangentGrid, Every3DMortarCombinationMatchesCentralDifferences) {
  OneThread one;
  const bool all = std::getenv("SIGNORINI_GRID_ALL") != nullptr;
  auto linear = [](ElementType t) { return t == ElementType::tri3 || t == ElementType::quad4; };
  int rows = 0;
  for (const ContactCombination& c : supported_contact_combinations())
    if (c.dimension == Dimension::three_d && c.discretization == "mortar" && c.method != "nitsche" && selected(c)) {
      if (!linear(c.slave_facet)) {
        const bool tet10 = c.slave_facet == ElementType::tri6 && c.master_facet == ElementType::tri6 &&
                           c.method == "lagrange";
        if (c.friction != "coulomb" || !(all || tet10)) continue;
      }
      check_combination(c);
      ++rows;
    }
  std::printf("%d 3D mortar rows checked\n", rows);
  if (!std::getenv("SIGNORINI_GRID_FILTER")) {
    EXPECT_EQ(rows, all ? 153 : 109) << "linear slaves: 54 on linear masters (18 of them self-contact), 54 on quadratic "
                                       "masters; quadratic slaves: 45 Coulomb rows (1 by default)";
  }
}

// Nitsche's 3D combinations on their own (its residual reads the cells' stress): on
// segment_to_segment's points and on mortar's cells, each 25 frictionless, 25 Coulomb and 25
// Tresca. Quadratic slaves (tri6, quad8, quad9) cost 7-15 s per slave type for their 40 rows
// (31 s of the 36 s in one process, session 66): by default their Coulomb rows only
// (frictionless and Tresca differ from Coulomb in the friction law only, which the linear
// slaves' rows check), every row with SIGNORINI_GRID_ALL=1 (the ctest
// long.TangentGrid.Every3DNitscheCombinationColumnByColumn, label long: column by column).
TEST(TangentGrid, Every3DNitscheCombinationMatchesCentralDifferences) {
  OneThread one;
  const bool all = std::getenv("SIGNORINI_GRID_ALL") != nullptr;
  auto linear = [](ElementType t) { return t == ElementType::tri3 || t == ElementType::quad4; };
  int rows = 0;
  for (const ContactCombination& c : supported_contact_combinations())
    if (c.dimension == Dimension::three_d && c.method == "nitsche" && selected(c)) {
      if (!all && !linear(c.slave_facet) && c.friction != "coulomb") continue;
      check_combination(c);
      ++rows;
      // At finite strain (theta 0), every Coulomb row (frictionless and Tresca differ in the
      // friction law only).
      if (c.friction == "coulomb") {
        check_combination(c, 0, true);
        ++rows;
      }
    }
  std::printf("%d 3D Nitsche rows checked\n", rows);
  if (!std::getenv("SIGNORINI_GRID_FILTER")) {
    EXPECT_EQ(rows, all ? 200 : 140) << "segment_to_segment and mortar, each 25 frictionless, 25 Coulomb and 25 Tresca "
                                        "rows (quadratic slaves' frictionless and Tresca rows, 60, with SIGNORINI_GRID_ALL "
                                        "only), and the 25 Coulomb rows at finite strain";
  }
}

// Nitsche reads the slave body's stress: a slave facet that no deformable cell owns (here the
// upper block's cells are left out, as a rigid body's are) is refused when the pair gets the
// bodies' traction, naming the facet's mesh nodes.
// A Nitsche pair of test::two_blocks' faces (the upper block's bottom slave).
ContactPairSettings nitsche_pair(const std::string& discretization, int theta = 1) {
  ContactPairSettings cs;
  cs.name = "c";
  cs.master = "lower_ymax";
  cs.slave = "upper_ymin";
  cs.discretization = discretization;
  cs.method = "nitsche";
  cs.nitsche_theta = theta;
  return cs;
}

TEST(Nitsche, SlaveFacetWithoutACellIsRefused) {
  Mesh mesh = test::two_blocks(ElementType::quad4, 3, 4, 1.0, 0.5, Vec3(0, 0.49, 0), false, ElementType::quad4, 1);
  orient_facets(mesh);
  AnalysisSettings as;
  ContactInterface pair(nitsche_pair("segment_to_segment"), mesh, as, 100.0, false);
  ASSERT_TRUE(pair.needs_boundary_traction());
  const LinearElastic elastic(100.0, 0.3);
  std::vector<BoundaryTraction::Cells> lower;
  for (auto& b : mesh.regions.at("lower_domain")) lower.push_back({&b, &elastic});
  BoundaryTraction traction(lower, mesh.nodes, as);
  try {
    pair.set_boundary_traction(&traction);
    FAIL() << "a slave facet without a deformable cell was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to no cell of a deformable body"), std::string::npos) << e.what();
  }
  // With the upper block's cells it is accepted.
  std::vector<BoundaryTraction::Cells> both = lower;
  for (auto& b : mesh.regions.at("upper_domain")) both.push_back({&b, &elastic});
  BoundaryTraction all(both, mesh.nodes, as);
  EXPECT_NO_THROW(pair.set_boundary_traction(&all));
}

// At finite strain Nitsche is theta 0 only (the deck refuses the others with the key's line): a
// pair given theta 1 by hand at finite strain refuses to assemble rather than give a Newton
// matrix without the pressure's second derivative; theta 0 assembles.
TEST(Nitsche, FiniteStrainTakesThetaZeroOnly) {
  Mesh mesh = test::two_blocks(ElementType::quad4, 3, 4, 1.0, 0.5, Vec3(0, 0.49, 0), false, ElementType::quad4, 1);
  orient_facets(mesh);
  AnalysisSettings as;
  as.finite_strain = true;
  std::vector<const ElementBlock*> blocks;
  for (auto& [n, bs] : mesh.regions)
    for (auto& b : bs) blocks.push_back(&b);
  DofMap dofs(mesh.num_nodes(), 2, blocks);
  const LinearElastic elastic(100.0, 0.3);
  std::vector<BoundaryTraction::Cells> cells;
  for (auto& [n, bs] : mesh.regions)
    for (auto& b : bs) cells.push_back({&b, &elastic});
  BoundaryTraction traction(cells, mesh.nodes, as);
  for (int theta : {1, 0}) {
    ContactInterface pair(nitsche_pair("mortar", theta), mesh, as, 100.0, false);
    pair.set_boundary_traction(&traction);
    VecX z = VecX::Zero(dofs.num_dofs());
    for (Index n : mesh.node_sets.at("upper_domain")) z(dofs.dof(n, 1)) = -0.02;
    const std::vector<Vec3> x = test::cells_of_positions(mesh, dofs, z);
    pair.detect(x, 0.05);
    pair.begin_increment(x, z);
    VecX r = VecX::Zero(dofs.num_dofs());
    if (theta == 1) {
      EXPECT_THROW(pair.assemble(x, z, dofs, r, nullptr), Error);
    } else {
      EXPECT_NO_THROW(pair.assemble(x, z, dofs, r, nullptr));
      EXPECT_GT(r.norm(), 0) << "the blocks overlap by 0.01: contact forces";
    }
  }
}

TEST(CompatibilityTable, EveryRuleHasACaseAndAMessage) {
  // Each rule excludes at least one combination, with its own message; supported ones pass.
  ContactCombination tri6;
  tri6.dimension = Dimension::three_d;
  tri6.slave_facet = tri6.master_facet = ElementType::tri6;
  EXPECT_NE(check_contact_combination(tri6).message.find("tri6"), std::string::npos);
  ContactCombination sphere;
  sphere.discretization = "rigid_sphere";
  EXPECT_EQ(check_contact_combination(sphere).key, "master.rigid");
  sphere.dimension = Dimension::axisymmetric;
  EXPECT_TRUE(check_contact_combination(sphere).message.empty());
  ContactCombination ntn;
  ntn.discretization = "node_to_node";
  ntn.slave_facet = ntn.master_facet = ElementType::line3;
  EXPECT_EQ(check_contact_combination(ntn).key, "discretization");
  ContactCombination two;
  two.passes = 2;
  two.friction = "coulomb";
  EXPECT_EQ(check_contact_combination(two).key, "friction");
  ContactCombination mortar3d;
  mortar3d.discretization = "mortar";
  mortar3d.dimension = Dimension::three_d;
  mortar3d.slave_facet = mortar3d.master_facet = ElementType::tri3;
  EXPECT_TRUE(check_contact_combination(mortar3d).message.empty()) << "3D mortar on linear facets";
  ContactCombination mortar3d_quadratic = mortar3d;
  mortar3d_quadratic.master_facet = ElementType::quad9;
  EXPECT_TRUE(check_contact_combination(mortar3d_quadratic).message.empty()) << "3D mortar on a quadratic master";
  for (ElementType t : {ElementType::tri6, ElementType::quad8, ElementType::quad9}) {
    mortar3d_quadratic.slave_facet = t;
    EXPECT_TRUE(check_contact_combination(mortar3d_quadratic).message.empty()) << "3D mortar on a quadratic slave";
  }
  mortar3d_quadratic.self = true;
  mortar3d_quadratic.master_facet = mortar3d_quadratic.slave_facet;
  EXPECT_NE(check_contact_combination(mortar3d_quadratic).message.find("quad9"), std::string::npos);
  EXPECT_EQ(check_contact_combination(mortar3d_quadratic).key, "self");
  ContactCombination mortar3d_friction = mortar3d;
  mortar3d_friction.friction = "coulomb";
  EXPECT_TRUE(check_contact_combination(mortar3d_friction).message.empty()) << "3D mortar with friction";
  ContactCombination mortar3d_self = mortar3d;
  mortar3d_self.self = true;
  EXPECT_TRUE(check_contact_combination(mortar3d_self).message.empty()) << "3D self-contact with mortar";
  ContactCombination mortar_friction;
  mortar_friction.discretization = "mortar";
  mortar_friction.friction = "coulomb";
  EXPECT_TRUE(check_contact_combination(mortar_friction).message.empty()) << "mortar has friction in 2D";
  ContactCombination sts_friction;
  sts_friction.discretization = "segment_to_segment";
  sts_friction.friction = "coulomb";
  EXPECT_TRUE(check_contact_combination(sts_friction).message.empty()) << "segment_to_segment has friction in 2D";
  sts_friction.dimension = Dimension::three_d;
  sts_friction.slave_facet = sts_friction.master_facet = ElementType::tri6;
  EXPECT_TRUE(check_contact_combination(sts_friction).message.empty()) << "3D friction on a quadratic master";
  sts_friction.master_facet = ElementType::quad4;
  EXPECT_TRUE(check_contact_combination(sts_friction).message.empty()) << "3D friction, tri6 slave on quad4";
  ContactCombination nitsche;
  nitsche.method = "nitsche";
  EXPECT_EQ(check_contact_combination(nitsche).key, "enforcement.method") << "nitsche on node_to_segment";
  nitsche.discretization = "segment_to_segment";
  EXPECT_TRUE(check_contact_combination(nitsche).message.empty()) << "nitsche on segment_to_segment";
  nitsche.friction = "coulomb";
  EXPECT_TRUE(check_contact_combination(nitsche).message.empty()) << "nitsche with friction";
  nitsche.dimension = Dimension::three_d;
  nitsche.slave_facet = nitsche.master_facet = ElementType::tri6;
  EXPECT_TRUE(check_contact_combination(nitsche).message.empty()) << "nitsche with friction, tri6 on tri6";
  nitsche.master_facet = ElementType::tri3;
  EXPECT_TRUE(check_contact_combination(nitsche).message.empty()) << "nitsche with friction, tri6 on tri3";
  nitsche.discretization = "mortar";
  EXPECT_TRUE(check_contact_combination(nitsche).message.empty()) << "nitsche on mortar integration, tri6 on tri3";
  nitsche.self = true;
  nitsche.slave_facet = nitsche.master_facet = ElementType::tri3;
  EXPECT_EQ(check_contact_combination(nitsche).key, "enforcement.method") << "nitsche with self-contact";
  ContactCombination smooth;
  smooth.smoothing = "hermite";
  smooth.master_facet = ElementType::line3;
  EXPECT_NE(check_contact_combination(smooth).message.find("line2"), std::string::npos);
  ContactCombination self;
  self.self = true;
  EXPECT_TRUE(check_contact_combination(self).message.empty()) << "self-contact node_to_segment";
  self.friction = "coulomb";
  EXPECT_TRUE(check_contact_combination(self).message.empty()) << "self-contact with friction";
  self.friction = "none";
  self.discretization = "mortar";
  EXPECT_TRUE(check_contact_combination(self).message.empty()) << "self-contact with mortar (one pass)";
  self.discretization = "segment_to_segment";
  EXPECT_EQ(check_contact_combination(self).key, "self");
  self.discretization = "node_to_segment";
  self.smoothing = "hermite";
  EXPECT_EQ(check_contact_combination(self).key, "self");
  // The supported list has no duplicates and is what the table allows.
  const auto all = supported_contact_combinations();
  std::set<std::string> names;
  for (const auto& c : all) {
    EXPECT_TRUE(check_contact_combination(c).message.empty()) << c.text();
    names.insert(c.text());
  }
  EXPECT_EQ(names.size(), all.size());
  EXPECT_NE(contact_compatibility_text().find(std::to_string(all.size()) + " combinations"), std::string::npos);
}

