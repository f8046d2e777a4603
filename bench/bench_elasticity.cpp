// Benchmark: assembly and solve of 3D linear elasticity on a structured unit cube (hex8 or
// tet10) of about the requested number of DOFs. Reports DOFs per second for the pattern
// build, assembly and solve, the matrix size and the peak memory of the process.
// Usage: bench_elasticity [--type hex8|tet10] [--dofs N] [--threads T] [--solver NAME]
#include <CLI/CLI.hpp>
#include <omp.h>

#include <cmath>

#include "signorini/core/log.hpp"
#include "signorini/fem/body.hpp"
#include "signorini/fem/surface_load.hpp"
#include "signorini/mesh/structured.hpp"
#include "signorini/solver/linear_solver.hpp"
#ifdef SIGNORINI_HAVE_PETSC
#include "signorini/solver/petsc_solver.hpp"
#endif

using namespace signorini;

int main(int argc, char** argv) {
  CLI::App app{"Signorini elasticity benchmark"};
  std::string type = "hex8", solver = "auto";
  double target = 1e6;
  int threads = 0;
  bool no_solve = false;
  app.add_option("--type", type, "hex8 or tet10")->check(CLI::IsMember({"hex8", "tet10", "hex20", "tet4"}));
  app.add_option("--dofs", target, "approximate number of DOFs");
  app.add_option("--threads", threads, "threads (default: all)");
  app.add_option("--solver", solver, "linear solver (default: auto)")->check(CLI::IsMember(linear_solver_names()));
  app.add_flag("--no-solve", no_solve, "assembly only");
  CLI11_PARSE(app, argc, argv);
  if (threads > 0) omp_set_num_threads(threads);
  const ElementType et = element_type_from_name(type);
  const int order = element_info(et).order;
  const int n = std::max(1, static_cast<int>(std::lround((std::cbrt(target / 3.0) - 1) / order)));

  log::Timer t_mesh;
  Mesh mesh = structured_box(et, n, n, n, 1, 1, 1);
  orient_facets(mesh);
  const double mesh_s = t_mesh.seconds();
  AnalysisSettings s;
  s.dimension = Dimension::three_d;
  Body body("cube", mesh.regions["domain"], std::make_shared<LinearElastic>(210e9, 0.3), s);
  std::vector<const ElementBlock*> cells;
  for (auto& b : body.blocks()) cells.push_back(&b);
  DofMap dofs(mesh.num_nodes(), 3, cells);
  const double ndof = static_cast<double>(dofs.num_dofs());

  log::Timer t_pattern;
  SparseSystem sys;
  sys.build_pattern(dofs, cells);
  const double pattern_s = t_pattern.seconds();

  VecX u = VecX::Zero(dofs.num_dofs()), fint = u, fext = u;
  log::Timer t_asm;
  sys.zero();
  body.assemble(mesh.nodes, u, dofs, fint, &sys);
  const double assembly_s = t_asm.seconds();

  // Clamp the bottom, pull the top with a traction.
  std::vector<char> constrained(dofs.num_dofs(), 0);
  for (Index nd : mesh.node_sets["zmin"])
    for (int i = 0; i < 3; ++i) constrained[dofs.dof(nd, i)] = 1;
  FacetLoad load{&mesh.facet_sets["zmax"], Vec3(0, 0, 1e6), 0, false, false};
  add_facet_load(load, s, mesh.nodes, u, dofs, 1.0, fext, nullptr);
  for (Index i = 0; i < fext.size(); ++i)
    if (constrained[i]) fext(i) = 0;
  sys.apply_dirichlet(constrained, sys.mean_abs_diagonal());

  std::printf("benchmark: %s, %d^3 cells, %.0f DOFs, %lld matrix nonzeros, %d threads\n", type.c_str(), n, ndof,
              static_cast<long long>(sys.nonzeros()), omp_get_max_threads());
  std::printf("  mesh      %8.3f s\n", mesh_s);
  std::printf("  pattern   %8.3f s  (%.3g DOFs/s)\n", pattern_s, ndof / pattern_s);
  std::printf("  assembly  %8.3f s  (%.3g DOFs/s)\n", assembly_s, ndof / assembly_s);
  std::fflush(stdout);
  if (!no_solve) {
    log::Timer t_solve;
    AutoLinearSolver ls(LinearSolverSettings(solver), true);
    if (ls.wants_layout(dofs.num_dofs())) {  // algebraic multigrid: the rigid-body modes from the nodes
      auto layout = std::make_shared<UnknownLayout>();
      layout->dim = 3;
      layout->x.resize(dofs.num_dofs());
      layout->comp.resize(dofs.num_dofs());
      for (Index nd = 0; nd < mesh.num_nodes(); ++nd)
        for (int c = 0; c < 3 && dofs.has_dofs(nd); ++c) {
          layout->x[dofs.dof(nd, c)] = mesh.nodes[nd];
          layout->comp[dofs.dof(nd, c)] = static_cast<signed char>(c);
        }
      ls.set_layout(layout);
    }
    VecX du;
    ls.solve(sys.matrix(), true, fext, du);
    const double solve_s = t_solve.seconds();
    // Check: relative residual of the linear system, and the mean top displacement against
    // the uniaxial-strain estimate sigma H / E_oedometric (a sanity bound, not a reference).
    const double rel = (sys.matrix() * du - fext).norm() / fext.norm();
    std::printf("  solve     %8.3f s  (%.3g DOFs/s, %s, %d Krylov iterations, relative residual %.1e)\n", solve_s,
                ndof / solve_s, ls.last_used().c_str(), ls.last_iterations(), rel);
    if (!(rel < 1e-6)) {
      std::printf("error: the solve is inaccurate\n");
      return 1;
    }
  }
  std::printf("  peak memory %.0f MiB\n", log::peak_memory_mib());
#ifdef SIGNORINI_HAVE_PETSC
  finalize_petsc();
#endif
  return 0;
}
