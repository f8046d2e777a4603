// The condensed solve of contact-multiplier systems (solver/condensed_solve.hpp) against a
// dense LU of the whole system J = [K B; C D]: the same step, whether each closed row has an
// unknown of its own (exact elimination) or the rows are coupled as segment_to_segment's
// weighted gaps are on quadratic facets (elimination of P, then GMRES on J).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "signorini/solver/condensed_solve.hpp"

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

TEST(CondensedSolve, CoupledRowsGiveTheWholeSystemsStep) {
  // coupled_rows(): no unknown belongs to one closed row, the exact elimination does not
  // apply, the refined one must give the whole system's step.
  const Saddle s = make_system(60, coupled_rows(), 3);
  CondensedContactSolver solver(false);
  VecX dz;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz)) << solver.why_not();
  EXPECT_GT(solver.refinements(), 0);
  EXPECT_LE(solver.refinements(), CondensedContactSolver::kMaxRefinements);
  EXPECT_LT(error_against_dense(s, dz), 1e-10);
  // The second solve with the same pattern reuses the symbolic analysis.
  VecX dz2;
  ASSERT_TRUE(solver.solve(s.J, s.is_multiplier, true, s.r, dz2));
  EXPECT_EQ(solver.analyses(), 1);
  EXPECT_LT((dz2 - dz).norm(), 1e-12 * dz.norm());
}

TEST(CondensedSolve, CoupledRowsWithAKrylovInnerSolveStopAtTheForcingTerm) {
  // The coupled rows above with CG (incomplete Cholesky) as the inner solver, as with
  // algebraic multigrid: flexible GMRES stops at the Newton iteration's forcing term (the
  // tolerance asked of the solve), not at kRefinementTolerance, and the Krylov iterations
  // reported are those of all the inner solves.
  // A softer chain, so that incomplete Cholesky is not exact and CG takes several steps.
  Saddle s = make_system(60, coupled_rows(), 3);
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

}  // namespace
}  // namespace signorini
