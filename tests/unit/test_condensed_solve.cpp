// The condensed solve of contact-multiplier systems (solver/condensed_solve.hpp) against a
// dense LU of the whole system J = [K B; C D]: the same step, whether each closed row has an
// unknown of its own (exact elimination) or the rows are coupled as segment_to_segment's
// weighted gaps are on quadratic facets (elimination of P, then GMRES on J).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include <Eigen/Dense>

#include "signorini/solver/condensed_solve.hpp"
#include "signorini/solver/multiplier_blocks.hpp"

namespace signorini {
namespace {

struct Saddle {
  SparseMatrix J;
  std::vector<char> is_multiplier;
  VecX r;
};

// n displacement unknowns: a chain of springs (symmetric positive definite with the ground
// springs), then the multipliers. Each closed row is (coefficients, unknowns); `open` rows
// get a diagonal only (an open constraint fixes its multiplier).
// `softening` lowers the diagonal (the chain alone: eigenvalues 2 - 2 cos(k pi / (n + 1)) + ...).
Saddle make_system(Index n, const std::vector<std::vector<std::pair<Index, Real>>>& closed, int open,
                   Real softening = 0) {
  std::vector<Eigen::Triplet<Real, int>> t;
  for (Index i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + 0.01 * static_cast<Real>(i % 7) - softening);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  Index m = n;
  for (const auto& row : closed) {
    for (auto [k, a] : row) {
      t.emplace_back(static_cast<int>(m), static_cast<int>(k), a);  // the constraint's row
      t.emplace_back(static_cast<int>(k), static_cast<int>(m), a);  // its force on the unknowns
    }
    ++m;
  }
  for (int o = 0; o < open; ++o, ++m) t.emplace_back(static_cast<int>(m), static_cast<int>(m), 3.0);
  Saddle s;
  s.J.resize(m, m);
  s.J.setFromTriplets(t.begin(), t.end());
  s.is_multiplier.assign(m, 0);
  for (Index k = n; k < m; ++k) s.is_multiplier[k] = 1;
  s.r.resize(m);
  for (Index k = 0; k < m; ++k) s.r(k) = std::sin(0.7 * static_cast<Real>(k) + 0.3);
  return s;
}

// Rows like segment_to_segment's on tri6 facets (docs/contact.md): a mid-side node's row holds
// -1/3 of its weight at the two corners beside it, a corner's row its own unknown only; both
// also see master unknowns. Slave unknowns 30 .. 46, alternately corner and mid-side.
std::vector<std::vector<std::pair<Index, Real>>> coupled_rows() {
  std::vector<std::vector<std::pair<Index, Real>>> rows;
  const Index first = 30;
  for (Index j = 0; j <= 16; ++j) {
    std::vector<std::pair<Index, Real>> row;
    if (j % 2 == 0) row.push_back({first + j, 0.8});
    else row = {{first + j, 0.67}, {first + j - 1, -0.133}, {first + j + 1, -0.133}};
    row.push_back({j, -0.3});
    row.push_back({j + 1, -0.2});
    rows.push_back(row);
  }
  return rows;
}

// Rows like mortar's on quad9 slave facets (the transformed basis a tensor product): corner
// rows on their own unknown, mid-side rows also at the two corners beside them, centre rows at
// a mid-side node and, less, at its corners. Corner C_i = 30 + 3i (i = 0 .. 6), mid-side
// M_i = 31 + 3i and centre Z_i = 32 + 3i (i = 0 .. 5); each row also sees two master unknowns.
std::vector<std::vector<std::pair<Index, Real>>> three_level_rows() {
  std::vector<std::vector<std::pair<Index, Real>>> rows;
  auto C = [](Index i) { return 30 + 3 * i; };
  for (Index i = 0; i <= 6; ++i) rows.push_back({{C(i), 0.8}, {i, -0.3}, {i + 1, -0.2}});
  for (Index i = 0; i < 6; ++i)
    rows.push_back({{C(i) + 1, 0.67}, {C(i), -0.15}, {C(i + 1), -0.15}, {i, -0.2}, {i + 1, -0.3}});
  for (Index i = 0; i < 6; ++i)
    rows.push_back({{C(i) + 2, 0.6}, {C(i) + 1, -0.15}, {C(i), -0.04}, {C(i + 1), -0.04}, {i + 1, -0.25}, {i + 2, -0.1}});
  return rows;
}

// coupled_rows() with the couplings a two-level elimination cannot hold: each corner row also
// sees the next mid-side node's unknown, and each mid-side row the next mid-side's (as a
// normal's variation couples the rows of nearby nodes both ways).
std::vector<std::vector<std::pair<Index, Real>>> cyclic_rows() {
  std::vector<std::vector<std::pair<Index, Real>>> rows = coupled_rows();
  const Index first = 30;
  for (Index j = 0; j + 2 <= 16; ++j) rows[j].push_back({first + j + (j % 2 == 0 ? 1 : 2), 0.03});
  return rows;
}

// The rows' couplings as coupled_rows_levels reads them, each row pivoting on its first
// unknown (its slave one): (row c', |a_{c,p(c')}| / |a_{c,p(c)}|) for each other row's pivot in row c.
std::vector<std::vector<std::pair<size_t, Real>>> coupling_of(const std::vector<std::vector<std::pair<Index, Real>>>& rows) {
  std::map<Index, size_t> row_of_pivot;
  for (size_t j = 0; j < rows.size(); ++j) row_of_pivot[rows[j][0].first] = j;
  std::vector<std::vector<std::pair<size_t, Real>>> coupling(rows.size());
  for (size_t j = 0; j < rows.size(); ++j)
    for (size_t e = 1; e < rows[j].size(); ++e)
      if (const auto it = row_of_pivot.find(rows[j][e].first); it != row_of_pivot.end())
        coupling[j].emplace_back(it->second, std::abs(rows[j][e].second / rows[j][0].second));
  return coupling;
}

Real error_against_dense(const Saddle& s, const VecX& dz) {
  const VecX exact = MatX(s.J).fullPivLu().solve(s.r);
  return (dz - exact).norm() / exact.norm();
}

TEST(CondensedSolve, ExactEliminationWhenEachRowHasAnUnknownOfItsOwn) {
  // Node-to-segment-like rows: a slave unknown of its own (coefficient 1) and two master ones.
  std::vector<std::vector<std::pair<Index, Real>>> rows;
  for (Index j = 0; j < 8; ++j) rows.push_back({{40 + 2 * j, 1.0}, {3 * j, -0.6}, {3 * j + 1, -0.4}});
  const Saddle s = make_system(60, rows, 2);
  CondensedContactSolver solver(false);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_EQ(solver.refinements(), 0);
  EXPECT_LT(error_against_dense(s, dz), 1e-11);
}

TEST(CondensedSolve, CoupledRowsInTwoLevelsAreEliminatedExactly) {
  // coupled_rows(): no unknown belongs to one closed row, but the mid-side rows see the
  // corners' pivots and not the other way round: the mid-side rows are the corners' children
  // (coupled_rows_children), their couplings substituted, and no GMRES step is needed.
  const Saddle s = make_system(60, coupled_rows(), 3);
  CondensedContactSolver solver(false);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_EQ(solver.refinements(), 0);
  EXPECT_LT(error_against_dense(s, dz), 1e-10);
  // The second solve with the same pattern reuses the symbolic analysis.
  VecX dz2;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz2));
  EXPECT_EQ(solver.analyses(), 1);
  EXPECT_LT((dz2 - dz).norm(), 1e-12 * dz.norm());
}

TEST(CondensedSolve, CoupledRowsAreSharedIntoParentsAndChildren) {
  // The rows of coupled_rows() as coupled_rows_children reads them: the mid-side rows (odd j)
  // couple to two corners each (0.133 / 0.67), the corners to nothing: children and parents.
  const auto rows = coupled_rows();
  auto coupling = coupling_of(rows);
  for (size_t j = 1; j < rows.size(); j += 2) ASSERT_EQ(coupling[j].size(), 2u) << j;
  const std::vector<char> child = coupled_rows_children(coupling);
  for (size_t j = 0; j < rows.size(); ++j) EXPECT_EQ(child[j], j % 2 == 1) << j;
  // A weak coupling back (a corner at 0.05 of its pivot on each mid-side pivot beside it)
  // leaves the levels as they are; two rows coupled alike both ways are both parents.
  for (size_t j = 0; j + 1 < rows.size(); j += 2) coupling[j] = {{j + 1, 0.05}};
  EXPECT_EQ(coupled_rows_children(coupling), child);
  EXPECT_EQ(coupled_rows_children({{{1, 0.2}}, {{0, 0.2}}}), std::vector<char>({0, 0}));
}

TEST(CondensedSolve, CoupledRowsInThreeLevelsAreEliminatedExactly) {
  // three_level_rows(): the corners are parents (level 0), the mid-side rows their children
  // (level 1), the centre rows children of both (level 2): every coupling is substituted and
  // no GMRES step is needed.
  const auto rows = three_level_rows();
  const std::vector<int> level = coupled_rows_levels(coupling_of(rows));
  for (size_t j = 0; j < rows.size(); ++j) EXPECT_EQ(level[j], j < 7 ? 0 : j < 13 ? 1 : 2) << j;
  const Saddle s = make_system(60, rows, 2);
  CondensedContactSolver solver(false);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_EQ(solver.refinements(), 0);
  EXPECT_LT(error_against_dense(s, dz), 1e-10);
}

TEST(CondensedSolve, CoupledRowsGiveTheWholeSystemsStep) {
  // cyclic_rows(): couplings both ways between the levels, left to GMRES, which must give the
  // whole system's step.
  const Saddle s = make_system(60, cyclic_rows(), 3);
  CondensedContactSolver solver(false);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_GT(solver.refinements(), 0);
  EXPECT_LE(solver.refinements(), 10);  // measured 8; 16 with every coupling left to GMRES
  EXPECT_LT(error_against_dense(s, dz), 1e-10);
  // The second solve with the same pattern reuses the symbolic analysis.
  VecX dz2;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz2));
  EXPECT_EQ(solver.analyses(), 1);
  EXPECT_LT((dz2 - dz).norm(), 1e-12 * dz.norm());
}

TEST(CondensedSolve, CoupledRowsWithAKrylovInnerSolveStopAtTheForcingTerm) {
  // The cyclic rows above with CG (incomplete Cholesky) as the inner solver, as with
  // algebraic multigrid: flexible GMRES stops at the Newton iteration's forcing term (the
  // tolerance asked of the solve), not at kRefinementTolerance, and the Krylov iterations
  // reported are those of all the inner solves.
  // A softer chain, so that incomplete Cholesky is not exact and CG takes several steps.
  Saddle s = make_system(60, cyclic_rows(), 3);
  for (Index i = 0; i + 5 < 60; i += 4) {
    s.J.coeffRef(i, i + 5) -= 0.3;
    s.J.coeffRef(i + 5, i) -= 0.3;
    s.J.coeffRef(i, i) += 0.3;
    s.J.coeffRef(i + 5, i + 5) += 0.3;
  }
  auto residual = [&](const VecX& dz) { return (s.r - s.J * dz).norm() / s.r.norm(); };
  CondensedContactSolver loose(LinearSolverSettings("eigen_cg"), false);
  loose.set_tolerance(1e-4);
  VecX dz;
  ASSERT_TRUE(loose.solve(s.J, s.is_multiplier, true, s.r, dz)) << loose.why_not();
  EXPECT_LE(residual(dz), 2e-4);
  EXPECT_GT(residual(dz), 1e-12);  // not solved to the refinement's own tolerance
  EXPECT_GE(loose.last_iterations(), loose.refinements() + 1);  // every inner solve counted
  // Asked for the exact step, the same solver gives it.
  CondensedContactSolver tight(LinearSolverSettings("eigen_cg"), false);
  tight.set_tolerance(1e-12);
  ASSERT_TRUE(tight.solve(s.J, s.is_multiplier, true, s.r, dz)) << tight.why_not();
  EXPECT_LT(error_against_dense(s, dz), 1e-9);
  EXPECT_GT(tight.refinements(), loose.refinements());
}

TEST(CondensedSolve, IndefiniteReducedSystemFallsBackToAnIndefiniteFactorization) {
  // The displacement block slightly indefinite (contact's geometric terms can make it so):
  // Cholesky of the reduced system fails, and the fallback (MUMPS's LDL^T with PETSc, else
  // UMFPACK's LU) must still give the whole system's step.
  std::vector<std::vector<std::pair<Index, Real>>> rows;
  for (Index j = 0; j < 3; ++j) rows.push_back({{40 + 2 * j, 1.0}, {3 * j, -0.6}, {3 * j + 1, -0.4}});
  const Saddle s = make_system(60, rows, 1, 0.05);
  ASSERT_LT(Eigen::SelfAdjointEigenSolver<MatX>(MatX(s.J).topLeftCorner(60, 60)).eigenvalues()(0), 0.0);
  CondensedContactSolver solver(false);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_EQ(solver.last_used(), petsc_available() ? "mumps" : "umfpack");
  EXPECT_LT(error_against_dense(s, dz), 1e-10);
  // A definite system stays with Cholesky.
  const Saddle d = make_system(60, rows, 1);
  CondensedContactSolver plain(false);
  ASSERT_TRUE(plain.solve(d.J, d.is_multiplier, true, d.r, dz));
  EXPECT_EQ(plain.last_used(), "cholmod");
  EXPECT_LT(error_against_dense(d, dz), 1e-11);
}

TEST(CondensedSolve, RefusesRowsWithNoUnknownToEliminate) {
  // Two closed rows on the same single unknown: no pivot for the second one.
  const Saddle s = make_system(10, {{{3, 1.0}}, {{3, 0.5}}}, 0);
  CondensedContactSolver solver(false);
  VecX dz;
  EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
  EXPECT_FALSE(solver.why_not().empty());
}


// Lagrange friction's multiplier blocks (enforcement.cpp, LagrangeMultipliers::add_friction):
// per contact node the normal multiplier lambda and the tangential ones lambda_T (dim), after
// the normal ones. A node's rows (w = 1): the gap, c0 grad^T du = r; the friction,
// E_u du + E_l dlambda + D_TT dlambda_T = r_T with D_TT = I - A P (plus Q on prescribed
// directions), A the return map's derivative; its columns: -grad for lambda, D^T for lambda_T.
// grad = D^T n, D = [I, -N_1 I, -N_2 I] over the slave node's DOFs and two master nodes'.
enum class Slip { stick, slip, barely, open, frictionless, prescribed };

// `masters`: the master nodes of each contact node (2, or more: a node alone on a quad8 facet
// has 8, its DOFs candidates for the pivots as its own).
Saddle make_friction_system(int dim, const std::vector<Slip>& states, int masters = 2) {
  const Index nodes = 12 * masters / 2 + static_cast<Index>(states.size()), nu = nodes * dim;
  const Index first_slave = nodes - static_cast<Index>(states.size());
  const Index nc = static_cast<Index>(states.size());
  std::vector<Eigen::Triplet<Real, int>> t;
  for (Index i = 0; i < nu; ++i) {  // a spring chain with ground springs (node blocks coupled)
    t.emplace_back(i, i, 2.5 + 0.01 * static_cast<Real>(i % 7));
    if (i + 1 < nu) t.emplace_back(i, i + 1, -1.0), t.emplace_back(i + 1, i, -1.0);
    if (i + dim < nu) t.emplace_back(i, i + dim, -0.2), t.emplace_back(i + dim, i, -0.2);
  }
  const Real c0 = 2.0, ct = 1.5, mu = 0.4;
  for (Index j = 0; j < nc; ++j) {
    const Index slave = first_slave + j, ml = nu + j;
    std::vector<Index> nodes_of{slave};
    std::vector<Real> N;  // the master nodes' shape functions, summing to 1
    for (int a = 0; a < masters; ++a) {
      nodes_of.push_back((masters * j + a) % first_slave);
      N.push_back(a == 0 ? 0.3 + 0.05 * static_cast<Real>(j) : (0.7 - 0.05 * static_cast<Real>(j)) / (masters - 1));
    }
    std::vector<Index> dofs;
    for (Index node : nodes_of)
      for (int d = 0; d < dim; ++d) dofs.push_back(node * dim + d);
    const int m = static_cast<int>(dofs.size());
    MatX D = MatX::Zero(dim, m);
    D.leftCols(dim) = MatX::Identity(dim, dim);
    for (int a = 0; a < masters; ++a) D.middleCols((a + 1) * dim, dim) = -N[a] * MatX::Identity(dim, dim);
    VecX n = VecX::Zero(dim), e = VecX::Zero(dim);  // an oblique normal, a tangent
    n(0) = 0.3 + 0.1 * static_cast<Real>(j % 3);
    n(dim - 1) = 1;
    n.normalize();
    e(0) = n(dim - 1), e(dim - 1) = -n(0);
    auto cross = [](const VecX& a, const VecX& b) -> VecX { return Vec3(a).cross(Vec3(b)); };
    if (dim == 3) e += 0.5 * cross(n, Vec3(0, 1, 0)), e -= n * n.dot(e), e.normalize();
    const MatX P = MatX::Identity(dim, dim) - n * n.transpose();
    const VecX grad = D.transpose() * n;
    MatX dn = MatX::Zero(dim, m);  // a normal's variation (tangential), for the rows' extra terms
    for (int c = 0; c < m; ++c) dn.col(c) = 0.05 * std::sin(1.3 * c + static_cast<Real>(j)) * e;
    std::vector<Index> lt;
    for (int d = 0; d < dim; ++d) lt.push_back(nu + nc + j * dim + d);
    const Slip st = states[static_cast<size_t>(j)];
    auto put = [&](Index row, Index col, Real v) {
      if (v != 0) t.emplace_back(static_cast<int>(row), static_cast<int>(col), v);
    };
    if (st == Slip::open) {
      put(ml, ml, 1.0);
      for (int d = 0; d < dim; ++d) put(lt[d], lt[d], 1.0);
      continue;
    }
    for (int c = 0; c < m; ++c) {
      put(ml, dofs[c], c0 * grad(c));
      put(dofs[c], ml, -grad(c));
    }
    if (st == Slip::frictionless) {
      for (int d = 0; d < dim; ++d) put(lt[d], lt[d], 1.0);
      continue;
    }
    // The return map at q = |q| qhat: stick A = I, b = 0; slip A = F/|q| (I - qhat qhat^T), b = qhat.
    MatX A = MatX::Identity(dim, dim), Q = MatX::Zero(dim, dim);
    VecX b = VecX::Zero(dim);
    if (st == Slip::slip || st == Slip::barely) {
      const Real ratio = st == Slip::slip ? 0.6 : 1 - 1e-8;  // F / |q|
      A = ratio * (MatX::Identity(dim, dim) - e * e.transpose());
      b = e;
    }
    if (st == Slip::prescribed) {  // one tangential direction released (3D: across e)
      VecX f = dim == 3 ? cross(n, e) : e;
      Q = f * f.transpose();
    }
    const MatX keep = MatX::Identity(dim, dim) - Q;
    const MatX dq = ct * P * D - n * (0.2 * e.transpose() * dn) - 0.1 * dn;
    const MatX Eu = keep * (-A * dq + (mu * c0) * b * grad.transpose());
    const VecX El = keep * (-mu * b);
    const MatX Dtt = keep * (MatX::Identity(dim, dim) - A * P) + Q;
    for (int d = 0; d < dim; ++d) {
      for (int c = 0; c < m; ++c) {
        put(lt[d], dofs[c], Eu(d, c));
        put(dofs[c], lt[d], D(d, c));
      }
      // Stored even where zero, as the assembly's pattern holds them (a sticking node's El).
      t.emplace_back(static_cast<int>(lt[d]), static_cast<int>(ml), El(d));
      for (int d2 = 0; d2 < dim; ++d2) t.emplace_back(static_cast<int>(lt[d]), static_cast<int>(lt[d2]), Dtt(d, d2));
    }
  }
  const Index total = nu + nc * (1 + dim);
  Saddle s;
  s.J.resize(total, total);
  s.J.setFromTriplets(t.begin(), t.end());
  s.is_multiplier.assign(total, 0);
  for (Index k = nu; k < total; ++k) s.is_multiplier[k] = 1;
  s.r.resize(total);
  for (Index k = 0; k < total; ++k) s.r(k) = std::sin(0.7 * static_cast<Real>(k) + 0.3);
  return s;
}

TEST(CondensedSolve, FrictionBlocksGiveTheWholeSystemsStep) {
  // Sticking, slipping, open, frictionless and partly prescribed nodes, alone and mixed, in 2D
  // and 3D: the condensed step (local elimination of each block's range, block pivots, the
  // unsymmetric null-space reduction) is the whole system's, exactly (no refinement).
  using S = Slip;
  const std::vector<std::vector<Slip>> cases = {
      {S::stick, S::stick, S::stick},
      {S::slip, S::slip, S::slip},
      {S::stick, S::slip, S::open, S::frictionless, S::stick, S::slip},
      {S::prescribed, S::stick, S::slip, S::prescribed},
  };
  for (int dim : {2, 3})
    for (size_t c = 0; c <= cases.size(); ++c) {
      // The last case: the mixed nodes over 8 master nodes each (24 + 3 candidate DOFs in 3D,
      // ranked, the best 8 tried).
      const Saddle s = c < cases.size() ? make_friction_system(dim, cases[c]) : make_friction_system(dim, cases[2], 8);
      // A factorization (`auto` in 3D would take GAMG with PETSc): the step exactly.
      CondensedContactSolver solver(false);
      solver.set_condense_blocks_always(true);
      VecX dz;
      ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << dim << "D case " << c << ": " << solver.why_not();
      EXPECT_EQ(solver.refinements(), 0) << dim << "D case " << c;
      EXPECT_LT(error_against_dense(s, dz), 1e-10) << dim << "D case " << c;
    }
}

TEST(CondensedSolve, NodesBarelySlippingAreRefinedToTheWholeSystemsStep) {
  // A node barely past the slip limit (F/|q| = 1 - 1e-8) in 3D: its block's least singular value
  // is 1e-8 of the largest, raised to kClampedSingular for the elimination, and flexible GMRES
  // on J brings the step back to the whole system's.
  const Saddle s = make_friction_system(3, {Slip::stick, Slip::barely, Slip::slip});
  CondensedContactSolver solver(false);  // a factorization
  solver.set_condense_blocks_always(true);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_GT(solver.refinements(), 0);
  EXPECT_LT(error_against_dense(s, dz), 1e-9);
}

TEST(CondensedSolve, FrictionBlocksOnSharedDofsAreRefinedToTheWholeSystemsStep) {
  // Mortar's friction: a node's weighted gap row also sees its facets' other slave nodes, so no
  // block has DOFs of its own. Each node's gap row and multiplier column here reach its
  // neighbours' slave and master DOFs too; the coupled pass takes each block's own slave DOFs as its pivots,
  // leaves the other blocks' entries there out of T and Z, and flexible GMRES on J brings the
  // step back to the whole system's. Stick, slip and mixed, 2D and 3D; the reduced matrix also
  // without its small entries (multiplier_blocks.hpp, kSharedDofsDrop; since session 62).
  using S = Slip;
  for (int dim : {2, 3})
    for (const std::vector<Slip>& states : {std::vector<Slip>{S::stick, S::stick, S::stick, S::stick},
                                            std::vector<Slip>{S::stick, S::slip, S::stick, S::slip}}) {
      Saddle s = make_friction_system(dim, states);
      const Index nc = static_cast<Index>(states.size()), nodes = 12 + nc, nu = nodes * dim, first_slave = 12;
      // Node j's slave node and its two master nodes (make_friction_system's layout).
      auto node_dofs = [&](Index j) {
        std::vector<Index> v;
        for (Index node : {first_slave + j, (2 * j) % first_slave, (2 * j + 1) % first_slave})
          for (int d = 0; d < dim; ++d) v.push_back(node * dim + d);
        return v;
      };
      for (Index j = 0; j < nc; ++j)
        for (Index o : {j - 1, j + 1}) {  // every DOF of a node is touched by a neighbour's rows too
          if (o < 0 || o >= nc) continue;
          const std::vector<Index> dofs = node_dofs(o);
          for (size_t c = 0; c < dofs.size(); ++c) {
            s.J.coeffRef(nu + j, dofs[c]) += 0.3 * std::cos(1.1 * static_cast<Real>(c + j));
            s.J.coeffRef(dofs[c], nu + j) -= 0.2 * std::sin(0.7 * static_cast<Real>(c) + 0.4);
          }
        }
      // Small couplings two nodes away (a tet10 mortar row's far master nodes): below
      // kSharedDofsDrop in T's and Z's pivot rows, left out of the reduced matrix.
      for (Index j = 0; j < nc; ++j)
        for (Index o : {j - 2, j + 2}) {
          if (o < 0 || o >= nc) continue;
          const std::vector<Index> dofs = node_dofs(o);
          for (size_t c = 0; c < dofs.size(); ++c) {
            s.J.coeffRef(nu + j, dofs[c]) += 1e-3 * std::cos(0.9 * static_cast<Real>(c + j));
            s.J.coeffRef(dofs[c], nu + j) -= 1e-3 * std::sin(0.5 * static_cast<Real>(c) + 0.2);
          }
        }
      s.J.makeCompressed();
      // The blocks as the solver analyses them: coupled, and some of T's, Z's and Delta's
      // entries (Delta: the slipping nodes') kept out of the reduced matrix.
      std::vector<Index> mult;
      std::vector<Index> slot(static_cast<size_t>(s.J.rows()), -1);
      for (Index k = 0; k < s.J.rows(); ++k)
        if (s.is_multiplier[k]) slot[k] = static_cast<Index>(mult.size()), mult.push_back(k);
      std::vector<std::vector<std::pair<Index, Real>>> rows(mult.size()), cols(mult.size());
      for (Index col = 0; col < s.J.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(s.J, col); it; ++it) {
          if (slot[it.row()] >= 0) rows[slot[it.row()]].emplace_back(col, it.value());
          else if (slot[col] >= 0) cols[slot[col]].emplace_back(it.row(), it.value());
        }
      const MultiplierBlocks mb = analyse_multiplier_blocks(s.J.rows(), s.is_multiplier, mult, rows, cols);
      ASSERT_TRUE(mb.why_not.empty()) << mb.why_not;
      EXPECT_TRUE(mb.coupled) << dim << "D";
      int left_out = 0, kept = 0;
      for (const MultiplierBlock& b : mb.blocks)
        for (Index a = 0; a < b.closed(); ++a)
          for (const bool z : {false, true})
            for (size_t j = 0; j < (z ? b.bu : b.cu).size(); ++j) {
              if (mb.pivot_of[(z ? b.bu : b.cu)[j]] >= 0) continue;
              (in_reduced_matrix(mb, b, a, z, j) ? kept : left_out)++;
            }
      EXPECT_GT(left_out, 0) << dim << "D: T's and Z's small coefficients";
      EXPECT_GT(kept, 0) << dim << "D";
      const bool slipping = states[1] == S::slip;
      const long delta_out = std::count(mb.delta_in_reduced.begin(), mb.delta_in_reduced.end(), 0);
      ASSERT_EQ(mb.delta_in_reduced.size(), mb.delta.size());
      if (slipping) EXPECT_GT(delta_out, 0) << dim << "D: Delta's small entries";
      CondensedContactSolver solver(false);  // a factorization
      solver.set_condense_blocks_always(true);
      VecX dz;
      ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << dim << "D: " << solver.why_not();
      EXPECT_GT(solver.refinements(), 0) << dim << "D";
      EXPECT_LT(error_against_dense(s, dz), 1e-9) << dim << "D";
      std::printf("%dD%s: %d GMRES steps; %d of T's and Z's pivot-row entries and %ld of Delta's %zu left out of the "
                  "reduced matrix\n", dim, slipping ? " (slip)" : "", solver.refinements(), left_out, delta_out, mb.delta.size());
    }
}

TEST(CondensedSolve, FrictionBlocksRefuseANodeWithoutDofsOfItsOwn) {
  // Two sticking nodes on the same slave node (as a slave node that is also another's master):
  // no block of DOFs of their own, the whole system is solved instead.
  Saddle s = make_friction_system(2, {Slip::stick, Slip::stick});
  // Move the second node's gap row onto the first node's slave DOFs.
  const Index nu = 14 * 2;
  for (Index col = 0; col < nu; ++col) s.J.coeffRef(nu + 1, col) = 0;
  s.J.coeffRef(nu + 1, 24) = 1.0;
  s.J.coeffRef(nu + 1, 25) = 0.5;
  CondensedContactSolver solver(false);
  solver.set_condense_blocks_always(true);
  VecX dz;
  EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
  EXPECT_NE(solver.why_not().find("of their own"), std::string::npos) << solver.why_not();
  EXPECT_EQ(solver.block_analyses(), 1);
  // Refused blocks are not analysed again at once: the next 1, 2, 4, ... solves after each
  // refusal in a row go whole, with the refusal's reason, and a system the analysis accepts
  // resets the count.
  const std::string why = solver.why_not();
  int analyses = 1;
  for (int refusal = 1; refusal <= 3; ++refusal) {
    for (int skipped = 0; skipped < (1 << (refusal - 1)); ++skipped) {
      EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
      EXPECT_EQ(solver.why_not(), why);
      EXPECT_EQ(solver.block_analyses(), analyses) << "refusal " << refusal << ", skipped solve " << skipped;
    }
    EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
    EXPECT_EQ(solver.block_analyses(), ++analyses) << "after refusal " << refusal;
  }
  const Saddle good = make_friction_system(2, {Slip::stick, Slip::stick});
  for (int skipped = 0; skipped < 8; ++skipped) EXPECT_FALSE(solver.solve(good.J, good.is_multiplier, true, good.r, dz));
  EXPECT_TRUE(solver.solve(good.J, good.is_multiplier, true, good.r, dz)) << solver.why_not();
  EXPECT_EQ(solver.block_analyses(), analyses + 1);
  // Refused once more: one solve skipped (the count was reset).
  EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
  EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
  EXPECT_EQ(solver.block_analyses(), analyses + 2);
  EXPECT_FALSE(solver.solve(s.J, s.is_multiplier, true, s.r, dz));
  EXPECT_EQ(solver.block_analyses(), analyses + 3);
}

// `auto`'s forecast of a factorization against the Krylov solves it sent to GAMG
// (FactorizationForecast, linear_solver.hpp: t_Krylov / t_LU = 10 K nnz / n^2), on the inputs
// of the runs it was measured on (docs/performance.md, session 66; whole systems' unknowns and
// nonzeros, Krylov iterations per solve): each on the side that was faster.
TEST(FactorizationForecast, PutsTheMeasuredRunsOnTheSideThatWasFaster) {
  struct Run {
    const char* name;
    long krylov;
    Index rows, nonzeros;
    bool lu_was_faster;
  };
  const Run runs[] = {
      {"tet10 CalculiX quarter, segment_to_segment (LU 13x faster)", 89, 31308, 3588120, true},
      {"tet10 sphere hc 0.02, mortar (LU 5x faster)", 108, 30838, 5705278, true},
      {"tet4 sphere hc 0.008, segment_to_segment (LU 1.5x faster)", 55, 27304, 2348374, true},
      {"tet4 sphere hc 0.006, mortar (GAMG 1.7x faster)", 30, 54415, 4183279, false},
      {"tet4 sphere hc 0.005, mortar (GAMG 3.2x faster)", 30, 85831, 6288151, false},
      {"tet4 sphere hc 0.008, node_to_segment (GAMG 2.2x faster)", 11, 27304, 1421446, false},
      {"tet4 sphere hc 0.004, mortar, session 61 (GAMG 7x faster; 11-54 Krylov per solve)", 54, 154308, 10560594, false},
  };
  for (const Run& r : runs) {
    FactorizationForecast f;
    EXPECT_EQ(f.record(r.krylov, r.rows, r.nonzeros), r.lu_was_faster) << r.name << ": forecast " << f.ratio();
    EXPECT_EQ(f.favours_factorization(), r.lu_was_faster) << r.name;
  }
}

// The mean over the solves so far decides (the first solve of an increment takes fewer Krylov
// iterations), and once it favours the factorization the decision is kept.
TEST(FactorizationForecast, DecidesOnTheMeanAndKeepsTheDecision) {
  FactorizationForecast f;
  EXPECT_FALSE(f.record(13, 31308, 3625926));  // the tet10 quarter's first solve, mortar
  EXPECT_NEAR(f.ratio(), 10.0 * 13 * 3625926 / (31308.0 * 31308.0), 1e-12);
  EXPECT_TRUE(f.record(45, 31308, 3625926));  // its second: mean 29
  EXPECT_DOUBLE_EQ(f.mean_iterations(), 29.0);
  EXPECT_TRUE(f.record(0, 31308, 3625926));  // kept
  EXPECT_DOUBLE_EQ(f.mean_iterations(), 29.0);
  EXPECT_NE(f.describe(31308, 3625926, "mumps").find("29 Krylov iterations per solve"), std::string::npos);
  FactorizationForecast empty;
  EXPECT_FALSE(empty.record(10, 0, 0));
}

}  // namespace
}  // namespace signorini
