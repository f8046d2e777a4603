// The analysis driver: loads and their resultants, ramps across steps, automatic cutback,
// giving up with the last converged state, linear solver choices, a model without supports.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "common.hpp"
#include "example_deck.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/mesh/structured.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;
using test::fix;

namespace {

Model block(Dimension dim, bool finite = false, ElementType t = ElementType::quad4) {
  log::set_level(log::Level::warning);
  AnalysisSettings s;
  s.dimension = dim;
  s.finite_strain = finite;
  s.thickness = 0.5;
  Mesh mesh = dim == Dimension::three_d ? structured_box(ElementType::hex8, 2, 4, 2, 1, 2, 1)
                                        : structured_rectangle(t, 2, 4, 1, 2);
  return test::model_on(std::move(mesh), s, std::make_shared<NeoHookean>(1000, 0.3));
}

Load load(LoadKind k, const std::string& set, Vec3 v, Real p = 0) {
  Load l;
  l.kind = k;
  l.set = set;
  l.vector = v;
  l.pressure = p;
  return l;
}

}  // namespace

TEST(Analysis, BodyForceReactionIsWeight) {
  for (Dimension d : {Dimension::plane_strain, Dimension::axisymmetric, Dimension::three_d}) {
    Model m = block(d);
    Step s;
    s.dirichlet = {fix("ymin", 0), fix("ymin", 1)};
    if (d == Dimension::three_d) s.dirichlet.push_back(fix("ymin", 2));
    s.loads = {load(LoadKind::body_force, "body", Vec3(0, -10, 0))};
    m.steps = {s};
    Analysis a(m);
    ASSERT_TRUE(a.run().completed);
    const Real volume = d == Dimension::plane_strain ? 1 * 2 * 0.5 : d == Dimension::axisymmetric ? std::numbers::pi * 2 : 2;
    EXPECT_NEAR(a.reaction_sum("ymin")(1), 10 * volume, 1e-9 * 10 * volume) << to_string(d);
    EXPECT_NEAR(m.bodies[0]->volume(m.mesh.nodes), volume, 1e-12) << to_string(d);
  }
}

TEST(Analysis, NodalForceAndTractionAreBalanced) {
  Model m = block(Dimension::plane_strain);
  Step s;
  s.dirichlet = {fix("ymin", 0), fix("ymin", 1)};
  s.loads = {load(LoadKind::nodal_force, "ymax", Vec3(2, -5, 0)), load(LoadKind::traction, "xmax", Vec3(3, 0, 0))};
  m.steps = {s};
  Analysis a(m);
  ASSERT_TRUE(a.run().completed);
  // Traction 3 on a side of height 2 and thickness 0.5: a force of 3 along x.
  EXPECT_NEAR(a.reaction_sum("ymin")(0), -(2 + 3), 1e-9);
  EXPECT_NEAR(a.reaction_sum("ymin")(1), 5, 1e-9);
}

TEST(Analysis, RampsAcrossSteps) {
  Model m = block(Dimension::plane_strain);
  Step s1, s2, s3;
  s1.name = "pull";
  s1.initial_increment = s1.max_increment = 0.25;
  s1.dirichlet = {fix("xmin", 0), fix("ymin", 1), fix("xmax", 0, 0.01)};
  s2 = s1;
  s2.name = "jump";
  s2.dirichlet[2].start = 0.02;  // {ramp: [0.02, 0.03]}
  s2.dirichlet[2].end = 0.03;
  s3.name = "force then release";
  s3.dirichlet = {fix("xmin", 0), fix("ymin", 1)};
  s3.loads = {load(LoadKind::nodal_force, "xmax", Vec3(1, 0, 0))};
  Step s4 = s3;
  s4.name = "release";
  s4.loads.clear();
  m.steps = {s1, s2, s3, s4};
  Analysis a(m);
  std::vector<std::pair<Real, Real>> history;  // (time, ux at a node of xmax)
  const Index node = m.mesh.node_sets["xmax"].front();
  a.on_increment([&](const Analysis& an, const IncrementRecord& r) {
    history.emplace_back(r.time, an.displacement()(an.dofs().dof(node, 0)));
  });
  ASSERT_TRUE(a.run().completed);
  ASSERT_GE(history.size(), 8u);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(history[k].second, 0.01 * history[k].first, 1e-15);
  EXPECT_NEAR(history[4].second, 0.02 + 0.25 * 0.01, 1e-15);
  EXPECT_NEAR(history[7].second, 0.03, 1e-15);
  // Step 3 starts from the end of step 2 with xmax free: the unloaded bar springs back,
  // and with the force removed in step 4 it ends where it started.
  EXPECT_NEAR(history.back().second, 0.0, 1e-12);
}

// `hold` (DirichletCondition::hold): a component kept where the step finds it, whatever it was
// then: xmax pulled by a force in step 1, then held while the force goes away.
TEST(Analysis, HoldKeepsAComponentWhereTheStepFindsIt) {
  Model m = block(Dimension::plane_strain);
  Step s1, s2;
  s1.dirichlet = {fix("xmin", 0), fix("ymin", 1)};
  s1.loads = {load(LoadKind::nodal_force, "xmax", Vec3(1, 0, 0))};
  s2.dirichlet = s1.dirichlet;
  DirichletCondition held = fix("xmax", 0);
  held.hold = true;
  held.end = 123;  // unused with hold
  s2.dirichlet.push_back(held);
  m.steps = {s1, s2};
  Analysis a(m);
  std::vector<Real> ux;
  const Index node = m.mesh.node_sets["xmax"].front();
  a.on_increment([&](const Analysis& an, const IncrementRecord&) { ux.push_back(an.displacement()(an.dofs().dof(node, 0))); });
  ASSERT_TRUE(a.run().completed);
  ASSERT_EQ(ux.size(), 2u);
  EXPECT_GT(ux[0], 1e-4);
  EXPECT_EQ(ux[1], ux[0]) << "held where step 1 left it";
  EXPECT_NEAR(a.reaction_sum("xmax")(0), 1, 1e-9) << "the support now carries the force the load carried";
}

TEST(Analysis, CutsBackAndRecovers) {
  Model m = block(Dimension::plane_strain, true);
  m.newton.max_iterations = 3;
  Step s;
  s.initial_increment = 1;
  s.dirichlet = {fix("xmin", 0), fix("ymin", 1), fix("xmax", 0, -0.45)};
  m.steps = {s};
  Analysis a(m);
  AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  int cutbacks = 0;
  for (auto& r : sum.increments) cutbacks += r.cutbacks;
  EXPECT_GT(cutbacks, 0);
  EXPECT_NEAR(sum.increments.back().fraction, 1.0, 1e-14);
}

TEST(Analysis, GivesUpWithReasonAndKeepsLastConvergedState) {
  Model m = block(Dimension::plane_strain, true);
  m.newton.max_iterations = 2;
  m.newton.pseudo_transient = false;  // the last resort, which would carry it
  Step s;
  s.initial_increment = 0.5;
  s.max_increment = 0.5;
  s.min_increment = 0.2;
  s.dirichlet = {fix("xmin", 0), fix("ymin", 1), fix("xmax", 0, -0.6)};
  m.steps = {s};
  Analysis a(m);
  AnalysisSummary sum = a.run();
  EXPECT_FALSE(sum.completed);
  EXPECT_NE(sum.failure.find("minimum"), std::string::npos) << sum.failure;
  EXPECT_NE(sum.failure.find("last converged state is kept"), std::string::npos) << sum.failure;
  // The state is the last converged one: zero if none converged, else that increment's.
  const Index node = m.mesh.node_sets["xmax"].front();
  const Real ux = a.displacement()(a.dofs().dof(node, 0));
  const Real expected = sum.increments.empty() ? 0.0 : -0.6 * sum.increments.back().fraction;
  EXPECT_NEAR(ux, expected, 1e-14);
}

TEST(Analysis, MissingSupportsFailFastWithAClearReason) {
  Model m = block(Dimension::plane_strain);
  Step s;
  s.dirichlet = {fix("ymin", 1)};  // x is free: rigid translation
  s.loads = {load(LoadKind::nodal_force, "ymax", Vec3(0, -1, 0))};
  m.steps = {s};
  Analysis a(m);
  AnalysisSummary sum = a.run();
  EXPECT_FALSE(sum.completed);
  EXPECT_NE(sum.failure.find("free to translate in x"), std::string::npos) << sum.failure;
  EXPECT_TRUE(sum.increments.empty());
  // A bottom edge held in y and one node held in x: no rigid motion left.
  Model ok = block(Dimension::plane_strain);
  ok.mesh.node_sets["corner"] = {ok.mesh.node_sets["xmin"].front()};
  Step s2 = s;
  s2.dirichlet.push_back(fix("corner", 0));
  ok.steps = {s2};
  Analysis a2(ok);
  EXPECT_TRUE(a2.run().completed);
  // 3D, only y held on a face: translations in x and z and the rotation about y are free.
  Model rot = block(Dimension::three_d);
  Step s3;
  s3.dirichlet = {fix("ymin", 1)};
  rot.steps = {s3};
  Analysis a3(rot);
  AnalysisSummary sum3 = a3.run();
  EXPECT_FALSE(sum3.completed);
  EXPECT_NE(sum3.failure.find("free to"), std::string::npos) << sum3.failure;
}

// Issue 17: a huge load on a supported model is not a missing support. Small strain is
// linear: the load 5e30 gives 5e30 times the unit load's displacements (a round-off-singular
// model would amplify the forces ~1e16 over the stiffness scale; this one about 1).
TEST(Analysis, HugeLoadIsNotTakenForMissingSupports) {
  VecX unit;
  for (Real f : {1.0, 5e30}) {
    Model m = block(Dimension::plane_strain);
    Step s;
    s.dirichlet = {fix("ymin", 0), fix("ymin", 1)};
    s.loads = {load(LoadKind::traction, "ymax", Vec3(f, -4 * f, 0))};
    m.steps = {s};
    Analysis a(m);
    AnalysisSummary sum = a.run();
    ASSERT_TRUE(sum.completed) << "load " << f << ": " << sum.failure;
    if (f == 1.0) unit = a.displacement();
    else EXPECT_LT((a.displacement() / f - unit).norm(), 1e-10 * unit.norm());
  }
}

TEST(Analysis, EveryLinearSolverGivesTheSameAnswer) {
  VecX reference;
  for (const std::string& solver : linear_solver_names()) {
    if (is_petsc_solver(solver) && !petsc_available()) continue;  // a build without PETSc
    Model m = block(Dimension::plane_strain);
    m.linear_solver = solver;
    Step s;
    s.dirichlet = {fix("ymin", 0), fix("ymin", 1)};
    s.loads = {load(LoadKind::traction, "ymax", Vec3(1, -4, 0))};
    m.steps = {s};
    Analysis a(m);
    AnalysisSummary sum = a.run();
    ASSERT_TRUE(sum.completed) << solver;
    if (solver != "auto") {
      EXPECT_EQ(sum.increments[0].linear_solver, solver);
    }
    if (reference.size() == 0) reference = a.displacement();
    // Krylov solvers stop at rtol 1e-8 on the residual (then Newton's own 1e-8 test).
    const bool krylov = solver == "gamg" || solver == "hypre" || solver == "petsc" || solver == "eigen_cg";
    EXPECT_LT((a.displacement() - reference).norm(), (krylov ? 1e-6 : 1e-10) * reference.norm()) << solver;
  }
}

TEST(Analysis, SymmetricSolversRefuseAnUnsymmetricModelBeforeTheFirstSolve) {
  // A Model made without a deck (the Python module): follower pressure under finite strain
  // makes the tangent unsymmetric, which CHOLMOD, Eigen's LDL^T and CG would solve as its
  // symmetric part. The Analysis refuses them at solver.linear, saying why; UMFPACK runs it.
  for (const char* solver : {"cholmod", "eigen_ldlt", "eigen_cg", "umfpack"}) {
    Model m = block(Dimension::plane_strain, true);
    m.linear_solver = solver;
    Step s;
    s.name = "press";
    s.initial_increment = 0.5;
    s.dirichlet = {fix("ymin", 0), fix("ymin", 1)};
    s.loads = {load(LoadKind::pressure, "ymax", Vec3::Zero(), 50.0)};
    m.steps = {s};
    EXPECT_EQ(unsymmetric_tangent_reasons(m), std::vector<std::string>{"follower pressure (finite strain) in step 'press'"});
    if (std::string(solver) == "umfpack") {
      EXPECT_EQ(symmetric_solver_refusal(m), "");
      Analysis a(m);
      EXPECT_TRUE(a.run().completed);
      continue;
    }
    try {
      Analysis a(m);
      ADD_FAILURE() << solver << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "solver.linear") << e.what();
      EXPECT_NE(e.message().find("follower pressure (finite strain) in step 'press'"), std::string::npos) << e.what();
    }
  }
}

TEST(Analysis, FollowerPressurePicksAnUnsymmetricSolver) {
  Model m = block(Dimension::plane_strain, true);
  Step s;
  s.initial_increment = 0.5;
  s.dirichlet = {fix("ymin", 0), fix("ymin", 1)};
  s.loads = {load(LoadKind::pressure, "ymax", Vec3::Zero(), 50.0)};
  m.steps = {s};
  Analysis a(m);
  AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  EXPECT_EQ(sum.increments[0].linear_solver, "umfpack");
  // Equilibrium: the reaction balances the pressure resultant on the deformed top face,
  // which stays horizontal here by symmetry of the load: -p * current width * thickness.
  Real xmin = 1e9, xmax = -1e9;
  for (Index n : m.mesh.node_sets["ymax"]) {
    const Real x = m.mesh.nodes[n](0) + a.displacement()(a.dofs().dof(n, 0));
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
  }
  EXPECT_NEAR(a.reaction_sum("ymin")(1), 50.0 * (xmax - xmin) * 0.5, 1e-6 * 50);
  // The PETSc solvers on the same unsymmetric tangent (GMRES for gamg, hypre and petsc; LU for
  // mumps): the same state to what rtol 1e-10 and the Newton tolerance fix.
  if (!petsc_available()) return;
  for (const char* solver : {"gamg", "hypre", "mumps", "petsc"}) {
    Model mp = block(Dimension::plane_strain, true);
    mp.steps = {s};
    mp.linear_solver.type = solver;
    mp.linear_solver.rtol = 1e-10;
    Analysis ap(mp);
    AnalysisSummary sp = ap.run();
    ASSERT_TRUE(sp.completed) << solver << ": " << sp.failure;
    EXPECT_EQ(sp.increments[0].linear_solver, solver);
    EXPECT_LT((ap.displacement() - a.displacement()).norm(), 1e-7 * a.displacement().norm()) << solver;
  }
}

TEST(Analysis, RigidBodyTranslatesWithItsReferenceNode) {
  // An elastic block (E = 100, nu = 0, plane strain, fixed at its bottom, x free) under a
  // rigid block pushed down by a force F on its reference node set (its top), frictionless
  // node-to-segment contact on non-matching meshes. The exact state: sigma_yy = -F / w in the
  // elastic block, the rigid block's nodes all moved by the same vector, and the elastic
  // block's bottom reaction equal to F. A second run prescribes the reference's displacement
  // instead, and the reaction at the reference set (counted once, not per node) equals the
  // force that displacement needs.
  for (bool by_force : {true, false}) {
    Model m = test::two_block_model(std::make_shared<LinearElastic>(100, 0.0), nullptr);
    m.bodies.back()->set_reference_nodes(m.mesh.node_sets["upper_ymax"]);
    ASSERT_TRUE(m.bodies.back()->rigid());
    ContactPairSettings cs;
    cs.name = "c";
    cs.master = "upper_ymin";  // the rigid body is master
    cs.slave = "lower_ymax";
    m.contacts = {cs};
    Step st;
    m.mesh.node_sets["lower_corner"] = {m.mesh.node_sets["lower_ymin"].front()};
    st.dirichlet = {fix("lower_ymin", 1), fix("lower_corner", 0), fix("upper_ymax", 0)};
    const Real F = 2.0, w = 1.0, E = 100;
    if (by_force) st.loads = {load(LoadKind::nodal_force, "upper_ymax", Vec3(0, -F, 0))};
    else st.dirichlet.push_back(fix("upper_ymax", 1, -F / (E * w) * 0.5));  // the elastic block's shortening
    m.steps = {st};
    Analysis a(m);
    // The rigid block has 2 DOFs in all.
    Index lower_nodes = 0;
    for (Index n = 0; n < m.mesh.num_nodes(); ++n) lower_nodes += a.dofs().has_dofs(n) && !a.dofs().shared(n);
    EXPECT_EQ(a.dofs().num_dofs(), 2 * lower_nodes + 2);
    AnalysisSummary sum = a.run();
    ASSERT_TRUE(sum.completed) << sum.failure;
    const VecX& u = a.displacement();
    const Index ref = m.mesh.node_sets["upper_ymax"].front();
    for (Index n : m.mesh.node_sets["upper_ymin"])
      for (int d = 0; d < 2; ++d) EXPECT_EQ(u(a.dofs().dof(n, d)), u(a.dofs().dof(ref, d)));
    for (auto& b : m.bodies) {
      CellResults r = b->results(m.mesh.nodes, u, a.dofs());
      for (auto& sg : r.stress) EXPECT_NEAR(sg(1), b->rigid() ? 0.0 : -F / w, 1e-8 * F) << b->name();
    }
    EXPECT_NEAR(a.reaction_sum("lower_ymin")(1), F, 1e-8 * F);
    if (!by_force) EXPECT_NEAR(a.reaction_sum("upper_ymax")(1), -F, 1e-8 * F);
    else EXPECT_NEAR(u(a.dofs().dof(ref, 1)), -F / (E * w) * 0.5, 1e-8);
  }
}

TEST(Analysis, RigidMotionByPrescribedDisplacementConverges) {
  // A body only moved rigidly by its supports (an indenter before it touches anything) has
  // round-off forces only: the relative residual alone would never converge. The force
  // scale's floor (a fraction of the stiffness times the largest displacement) lets each
  // increment converge in a few iterations (the first one strains the body before it follows).
  Model m = block(Dimension::plane_strain, true);
  Step st;
  st.dirichlet = {fix("ymin", 0, 0.5), fix("ymin", 1, -0.25)};
  st.initial_increment = st.max_increment = 0.2;
  m.steps = {st};
  Analysis a(m);
  AnalysisSummary sum = a.run();
  ASSERT_TRUE(sum.completed) << sum.failure;
  EXPECT_EQ(sum.increments.size(), 5u);
  for (auto& inc : sum.increments) EXPECT_LE(inc.iterations, 6);
  EXPECT_NEAR(a.displacement()(a.dofs().dof(m.mesh.node_sets["ymax"].front(), 0)), 0.5, 1e-12);
}

TEST(LinearSolver, CholeskyComesBackAfterAnIndefiniteTangent) {
  // A symmetric indefinite matrix (contact's -p w hess g under a large penetration) makes the
  // automatic solver fall back to an indefinite factorization (MUMPS's LDL^T with PETSc, else
  // UMFPACK's LU); it retries Cholesky after 1, then 2, 4, ... solves
  // (each failure in a row doubles the wait), so a tangent that becomes definite again is
  // solved by Cholesky again instead of by LU for the rest of the run.
  auto matrix = [](Real d1) {
    SparseMatrix a(3, 3);
    std::vector<Eigen::Triplet<Real, int>> t{{0, 0, 4}, {1, 1, d1}, {2, 2, 3}, {0, 1, 1}, {1, 0, 1}};
    a.setFromTriplets(t.begin(), t.end());
    return a;
  };
  const SparseMatrix spd = matrix(5), indefinite = matrix(-5);
  const VecX b = VecX::Ones(3);
  VecX x;
  AutoLinearSolver s("auto");
  const std::string fallback = petsc_available() ? "mumps" : "umfpack";
  s.solve(spd, true, b, x);
  EXPECT_EQ(s.last_used(), "cholmod");
  s.solve(indefinite, true, b, x);
  EXPECT_EQ(s.last_used(), fallback);
  EXPECT_LT((indefinite * x - b).norm(), 1e-12);
  s.solve(spd, true, b, x);
  EXPECT_EQ(s.last_used(), fallback) << "skips one solve after the first failure";
  s.solve(spd, true, b, x);
  EXPECT_EQ(s.last_used(), "cholmod") << "Cholesky again";
  EXPECT_LT((spd * x - b).norm(), 1e-12);
  // Two failures in a row: the second wait is two solves.
  s.solve(indefinite, true, b, x);
  s.solve(indefinite, true, b, x);  // skipped: the fallback
  s.solve(indefinite, true, b, x);  // Cholesky tried, fails again: wait 2
  EXPECT_EQ(s.last_used(), fallback);
  s.solve(spd, true, b, x);
  s.solve(spd, true, b, x);
  EXPECT_EQ(s.last_used(), fallback);
  s.solve(spd, true, b, x);
  EXPECT_EQ(s.last_used(), "cholmod");
}

TEST(LinearSolver, LargeUnsymmetricSystemsGoToMumpsInOneProcess) {
  // `auto` factorizes an unsymmetric system (Lagrange friction's whole contact system) with
  // MUMPS's LU above kMumpsLuAbove unknowns, in one process of a build with PETSc: its nested
  // dissection fills far less than UMFPACK's AMD on 3D meshes (the frictional 3D Hertz sphere
  // at 35k unknowns: 24 s and 750 MiB against 64 s and 2 631 MiB, docs/performance.md). Smaller
  // systems stay with UMFPACK (no PETSc set-up). The operator: convection-diffusion on a g x g
  // grid (upwinded, so unsymmetric), with g = 70 (4 900 unknowns) and g = 101 (10 201).
  auto system = [](int g) {
    std::vector<Eigen::Triplet<Real, int>> t;
    for (int i = 0; i < g; ++i)
      for (int j = 0; j < g; ++j) {
        const int k = i * g + j;
        t.emplace_back(k, k, 4.5);
        if (i > 0) t.emplace_back(k, k - g, -1.3);
        if (i + 1 < g) t.emplace_back(k, k + g, -0.7);
        if (j > 0) t.emplace_back(k, k - 1, -1.2);
        if (j + 1 < g) t.emplace_back(k, k + 1, -0.8);
      }
    SparseMatrix a(g * g, g * g);
    a.setFromTriplets(t.begin(), t.end());
    return a;
  };
  const bool mumps = petsc_available() && launched_ranks() == 1;
  EXPECT_EQ(AutoLinearSolver::indefinite_solver(AutoLinearSolver::kMumpsLuAbove, false), "umfpack");
  EXPECT_EQ(AutoLinearSolver::indefinite_solver(AutoLinearSolver::kMumpsLuAbove + 1, false), mumps ? "mumps" : "umfpack");
  EXPECT_EQ(AutoLinearSolver::indefinite_solver(10, true), mumps ? "mumps" : "umfpack");  // LDL^T, any size
  for (const int g : {70, 101}) {
    const SparseMatrix a = system(g);
    ASSERT_FALSE(a.isApprox(SparseMatrix(a.transpose())));
    VecX b(a.rows()), x;
    for (Index k = 0; k < b.size(); ++k) b(k) = std::cos(0.21 * static_cast<Real>(k));
    AutoLinearSolver s("auto");
    ASSERT_NO_THROW(s.solve(a, false, b, x));
    const bool large = a.rows() > AutoLinearSolver::kMumpsLuAbove;
    EXPECT_EQ(s.last_used(), large && mumps ? "mumps" : "umfpack") << a.rows() << " unknowns";
    EXPECT_LT((a * x - b).norm(), 1e-10 * b.norm());
  }
}

TEST(LinearSolver, GamgGoesOnWithGmresWhenCgFindsTheSystemIndefinite) {
  if (!petsc_available()) GTEST_SKIP() << "built without PETSc";
  // A condensed contact system can be indefinite (the contact's geometric terms); CG then
  // breaks down (KSP_DIVERGED_INDEFINITE_MAT). The 2D Laplacian on a 40 x 40 grid, shifted
  // past its four lowest eigenvalues (8 sin^2(k pi / 82) ...), is such a system: the solver
  // must go on with GMRES on the same preconditioner and reach rtol on the true residual.
  const int g = 40, n = g * g;
  const Real pi = 3.14159265358979323846;
  auto lambda = [&](int i, int j) {
    return 4 * std::pow(std::sin(i * pi / (2.0 * (g + 1))), 2) + 4 * std::pow(std::sin(j * pi / (2.0 * (g + 1))), 2);
  };
  const Real shift = 0.5 * (lambda(2, 2) + lambda(1, 3));  // between the 4th and 5th eigenvalues
  std::vector<Eigen::Triplet<Real, int>> t;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const int k = i * g + j;
      t.emplace_back(k, k, 4.0 - shift);
      if (i > 0) t.emplace_back(k, k - g, -1.0);
      if (i + 1 < g) t.emplace_back(k, k + g, -1.0);
      if (j > 0) t.emplace_back(k, k - 1, -1.0);
      if (j + 1 < g) t.emplace_back(k, k + 1, -1.0);
    }
  SparseMatrix a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  VecX b(n);
  for (int k = 0; k < n; ++k) b(k) = std::sin(0.37 * k + 0.1);
  LinearSolverSettings gamg("gamg");
  gamg.rtol = 1e-8;
  AutoLinearSolver s(gamg);
  VecX x;
  ASSERT_NO_THROW(s.solve(a, true, b, x));
  EXPECT_LT((a * x - b).norm(), 1e-7 * b.norm());
  EXPECT_GT(s.last_iterations(), 0);
  // The next solve of the same matrix starts with GMRES: no breakdown first.
  ASSERT_TRUE(s.solve_again(2 * b, x));
  EXPECT_LT((a * x - 2 * b).norm(), 2e-7 * b.norm());
}

// The unknowns after the displacements in the user's words (the failed increment's "largest
// residual at ..."): the tube crush (examples/tube_crush: two rigid cylinders with Lagrange
// multipliers and a self-contact fold), its fold made frictional so that it has tangential
// multipliers.
TEST(Analysis, DescribesEveryKindOfUnknown) {
  log::set_level(log::Level::warning);
  const test::ExampleDeck ex = test::example_deck_with("tube_crush", "order: 1, nu: 8, nl: 6");
  ASSERT_TRUE(test::replace_in_deck(ex, "{name: fold, surface: Inner, self: true}",
                                    "{name: fold, surface: Inner, self: true, friction: {law: coulomb, mu: 0.3}}"));
  Registry r = default_registry();
  Model m = read_deck(ex.deck.string(), r);
  std::filesystem::remove_all(ex.dir);
  Analysis a(m);
  const ContactInterface *fold = nullptr, *top = nullptr;
  for (const auto& c : a.contacts()) {
    if (c->settings().name == "fold") fold = c.get();
    if (c->settings().name == "top") top = c.get();
  }
  ASSERT_TRUE(fold && top);
  ASSERT_GT(fold->num_multipliers(), 0);
  ASSERT_EQ(top->num_obstacle_dofs(), 2);
  const std::vector<Index>& slaves = fold->slave().nodes;
  const Index o = fold->multiplier_offset(), n = static_cast<Index>(slaves.size());
  const std::string id1 = std::to_string(m.mesh.node_ids[slaves[1]]), id2 = std::to_string(m.mesh.node_ids[slaves[2]]);
  EXPECT_EQ(a.describe_unknown(o + 1),
            "unknown " + std::to_string(o + 1) + " (contact 'fold': the normal multiplier of slave mesh node " + id1 + ")");
  // Two tangential multipliers per node in plane strain, after all the normal ones.
  EXPECT_NE(a.describe_unknown(o + n + 5).find("contact 'fold': a tangential multiplier of slave mesh node " + id2),
            std::string::npos)
      << a.describe_unknown(o + n + 5);
  EXPECT_NE(a.describe_unknown(top->obstacle_dofs() + 1).find("contact 'top': the rigid obstacle's displacement along y"),
            std::string::npos)
      << a.describe_unknown(top->obstacle_dofs() + 1);
  EXPECT_NE(a.describe_unknown(0).find("mesh node"), std::string::npos) << a.describe_unknown(0);
  // A turning meshed rigid body's angle (examples/rolling_rigid_mesh: the roller): its unknown
  // is the last one.
  const test::ExampleDeck roll = test::example_deck_with("rolling_rigid_mesh", "");
  Model mr = read_deck(roll.deck.string(), r);
  std::filesystem::remove_all(roll.dir);
  Analysis ar(mr);
  ASSERT_EQ(ar.turning_bodies().size(), 1u);
  const Index last = ar.num_unknowns() - 1;
  EXPECT_EQ(ar.describe_unknown(last), "unknown " + std::to_string(last) + " (an angle of the turning rigid body 'roller')");
}
