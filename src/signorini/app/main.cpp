// The `signorini` command: run a deck, check a deck, describe a registered type.
// Exit codes: 0 success, 1 bad input, 2 the analysis gave up, 3 a reference check failed.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#ifdef SIGNORINI_HAVE_PETSC
#include "signorini/solver/petsc_solver.hpp"
#endif
#include "signorini/app/bench_search.hpp"
#include "signorini/contact/compatibility.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/interrupt.hpp"
#include "signorini/core/log.hpp"
#include "signorini/core/rank_exchange.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/io/results_writer.hpp"
#include "signorini/version.hpp"

using namespace signorini;

namespace {

void print_model(const Model& m, const DeckReport& rep) {
  Index nset = m.mesh.node_sets.size(), fset = m.mesh.facet_sets.size();
  fmt::print("Model '{}'\n", m.title);
  fmt::print("  analysis   {}, {}{}\n", to_string(m.settings.dimension),
             m.settings.finite_strain ? "finite strain (total Lagrangian)" : "small strain",
             (m.settings.dimension == Dimension::plane_strain || m.settings.dimension == Dimension::plane_stress)
                 ? fmt::format(", thickness {}", m.settings.thickness)
                 : std::string());
  fmt::print("  mesh       {} nodes, {} cells, {} node sets, {} facet sets\n", m.mesh.num_nodes(), m.mesh.num_cells(),
             nset, fset);
  if (rep.reoriented_cells) fmt::print("             {} cells had clockwise/mirrored node order and were re-ordered\n", rep.reoriented_cells);
  if (rep.orphan_facets) fmt::print("             {} facets belong to no cell (their orientation is as given)\n", rep.orphan_facets);
  for (auto& b : m.bodies) {
    std::string types;
    for (auto& blk : b->blocks()) types += (types.empty() ? "" : "+") + element_info(blk.type).name;
    if (b->rigid())
      fmt::print("  body       {}: {} cells ({}), rigid, {} reference node(s)\n", b->name(), b->num_cells(), types,
                 b->reference_nodes().size());
    else
      fmt::print("  body       {}: {} cells ({}), material {} (E = {:g})\n", b->name(), b->num_cells(), types,
                 b->material().model(), b->material().stiffness_scale());
  }
  for (auto& c : m.contacts) {
    std::string enf = c.method;
    if (c.method == "nitsche")
      enf += fmt::format(" (theta {}, gamma0 {:g}{})", c.nitsche_theta, c.nitsche_gamma > 0 ? c.nitsche_gamma : kNitscheGamma,
                         c.nitsche_gamma > 0 ? "" : " auto");
    else if (c.method != "lagrange")
      enf += c.penalty > 0 ? fmt::format(" (penalty {:g})", c.penalty) : " (penalty auto)";
    const std::string fr = c.friction == "coulomb" ? fmt::format(", Coulomb mu = {:g}", c.friction_parameter)
                           : c.friction == "tresca" ? fmt::format(", Tresca bound {:g}", c.friction_parameter)
                                                    : ", frictionless";
    fmt::print("  contact    {}: slave {} on {} {}, {}, {}\n", c.name, c.slave, c.rigid ? "rigid" : "master",
               c.rigid ? c.obstacle.shape : c.master, c.rigid ? "node_to_surface" : c.discretization, enf + fr);
  }
  for (auto& s : m.steps)
    fmt::print("  step       {}: {} Dirichlet conditions, {} loads, increments {:g} [{:g}, {:g}]\n", s.name,
               s.dirichlet.size(), s.loads.size(), s.initial_increment, s.min_increment, s.max_increment);
  fmt::print("  solver     linear {}, Newton up to {} iterations, relative tolerance {:g}\n", m.linear_solver.type,
             m.newton.max_iterations, m.newton.residual_tolerance);
}

int run(const std::string& deck, const std::string& outdir, bool check_only, const std::string& restart, int rank) {
  const Registry registry = default_registry();
  DeckReport rep;
  install_interrupt_handlers();  // Ctrl-C while a .geo is meshed stops the gmsh process too
  // Under mpirun rank 0 alone reads the mesh (gmsh, then the API) and sends it to the others.
#ifdef SIGNORINI_HAVE_PETSC
  const std::unique_ptr<RankExchange> ranks_exchange = make_rank_exchange();  // null: one process
#else
  const std::unique_ptr<RankExchange> ranks_exchange;
#endif
  Model model = read_deck(deck, registry, &rep, ranks_exchange.get());
  if (interrupt_signal()) {  // arrived while reading (the readers do not stop by themselves)
    fmt::print(stderr, "error: interrupted while reading '{}'\n", deck);
    return 128 + interrupt_signal();
  }
  print_model(model, rep);
  log::debug("peak memory {:.0f} MiB with the deck and mesh read", log::peak_memory_mib());
  if (check_only) {
    fmt::print("Deck and mesh are valid; nothing solved ('signorini run' solves).\n");
    return 0;
  }
  const std::string dir = outdir.empty() ? model.output.directory : outdir;
  // Several MPI ranks: each runs the same analysis; PETSc distributes the linear solves.
  const int ranks = launched_ranks();
  // `auto` picks one of those itself (Analysis::choose_algebra) in a build with PETSc.
  if (ranks > 1 && !is_petsc_solver(model.linear_solver.type) &&
      !(model.linear_solver.type == "auto" && petsc_available()))
    throw InputError(model.linear_solver_where.empty() ? deck : model.linear_solver_where, "solver.linear",
                     fmt::format("this run has {} MPI ranks: the linear solver must be one that PETSc distributes "
                                 "(gamg, hypre, mumps or petsc{}), not '{}'",
                                 ranks, petsc_available() ? ", or auto" : "; this build has no PETSc",
                                 model.linear_solver.type));
  ResultsWriter writer(model, dir, rank);
  Analysis analysis(model);
  log::debug("peak memory {:.0f} MiB with the analysis set up (DOF map, sparse pattern)", log::peak_memory_mib());
  if (!restart.empty()) {
    analysis.read_restart(restart);
    fmt::print("  restart    from {}: steps 1 to {} done, continuing with step {} '{}'\n", restart,
               analysis.first_step(), analysis.first_step() + 1,
               analysis.first_step() < static_cast<int>(model.steps.size()) ? model.steps[analysis.first_step()].name
                                                                              : std::string("(none left)"));
  }
  if (model.output.restart == "every_step")
    analysis.on_step([&](const Analysis& a, int step) {  // every rank: it gathers the history
      const std::string path = fmt::format("{}/restart_{:04d}.bin", dir, step + 1);
      a.write_restart(path);
      if (rank == 0) log::info("restart file {} written", path);
    });
  fmt::print("  unknowns   {} DOFs, {} threads{}\n", analysis.dofs().num_dofs(), omp_get_max_threads(),
             ranks > 1 ? fmt::format(" per rank, {} MPI ranks", ranks) : std::string());
  if (ranks > 1) fmt::print("  algebra    {}\n", analysis.algebra());
  if (ranks > 1 && !analysis.contacts().empty()) fmt::print("  contact    {}\n", analysis.contact_evaluation());
  std::fflush(stdout);
  AnalysisSummary s;
  std::vector<CheckResult> checks;
  try {
    writer.write_initial(analysis);
    install_interrupt_handlers();
    analysis.on_increment([&](const Analysis& a, const IncrementRecord& r) { writer.write_increment(a, r); });
    s = analysis.run();
    checks = evaluate_checks(analysis);
    writer.finish(analysis, s, checks);
  } catch (const std::exception& e) {
    // The files of the last converged increment stay; summary.json says why the run stopped
    // (until session 71 it said `running` after a full disk stopped the run).
    writer.record_error(analysis, e.what());
    throw;
  }
  fmt::print("\n");
  if (const std::string w = oversized_displacement(analysis); !w.empty()) log::warning("{}", w);
  if (!s.completed) {
    fmt::print("Analysis {}: {}\n", s.interrupted ? "interrupted" : "gave up", s.failure);
    if (s.increments.empty())
      fmt::print("No increment converged; the initial state is in {}/ (ParaView: {})\n", dir, writer.pvd_path());
    else
      fmt::print("Results up to the last converged increment (time {:.6g}) are in {}/ (ParaView: {})\n",
                 s.increments.back().time, dir, writer.pvd_path());
    return s.interrupted ? 128 + interrupt_signal() : 2;
  }
  fmt::print("Solved '{}': {} steps, {} increments, {} Newton iterations, {:.2f} s (assembly {:.2f} s, {}linear solve "
             "{:.2f} s), peak memory {:.0f} MiB\n",
             model.title, model.steps.size(), s.increments.size(), s.total_iterations, s.total_seconds,
             s.assembly_seconds, model.contacts.empty() ? std::string() : fmt::format("contact {:.2f} s, ", s.contact_seconds),
             s.solve_seconds, log::peak_memory_mib());
  bool all = true;
  if (!checks.empty()) {
    fmt::print("\nComparison with the reference:\n");
    fmt::print("  {:<44} {:>14} {:>14} {:>10} {:>8}  {}\n", "quantity", "computed", "reference", "error", "tol", "");
    for (auto& c : checks) {
      fmt::print("  {:<44} {:>14.6e} {:>14.6e} {:>9.3f}% {:>7.2f}%  {}\n", c.check.name, c.computed, c.check.expected,
                 100 * c.error, 100 * c.check.tolerance, c.pass ? "ok" : "FAILED");
      all = all && c.pass;
    }
    for (auto& c : checks)
      if (!c.check.reference.empty()) {
        fmt::print("  reference: {}\n", c.check.reference);
        break;
      }
  }
  fmt::print("\nResults in {}/: ParaView {}, reactions {}/reactions.csv, summary {}/summary.json\n", dir,
             writer.pvd_path(), dir, dir);
  // Said where they arose, perhaps thousands of lines back: repeated where the run ends.
  if (!s.warnings.empty()) {
    fmt::print("\nRead these results with {}:\n", s.warnings.size() > 1 ? "these warnings" : "this warning");
    for (const std::string& w : s.warnings) fmt::print("  - {}\n", w);
  }
  return all ? 0 : 3;
}

}  // namespace

// An error under mpirun: the ranks run the same code, but one rank alone may fail (rank 0
// writes the output): the others would wait for it forever, so every rank is stopped.
int stop_all_ranks(int ranks, int code) {
#ifdef SIGNORINI_HAVE_PETSC
  if (ranks > 1) {
    std::fflush(stdout);
    std::fflush(stderr);
    abort_all_ranks(code);
  }
#endif
  return code;
}

int main(int argc, char** argv) {
  CLI::App app{"Signorini: finite element solver for contact mechanics"};
  app.set_version_flag("--version", std::string("signorini ") + SIGNORINI_VERSION);
  app.require_subcommand(1);
  std::string deck, outdir, type, restart;
  int threads = 0;
  bool quiet = false, verbose = false;
  auto* run_cmd = app.add_subcommand("run", "solve a deck");
  run_cmd->add_option("deck", deck, "deck file (.yaml)")->required();
  run_cmd->add_option("-o,--output", outdir, "output directory (default: the deck's output.directory)");
  run_cmd->add_option("--threads", threads, "number of threads (default: all cores)")->check(CLI::Range(1, 1024));
  run_cmd->add_flag("-q,--quiet", quiet, "print only warnings, errors and the final summary");
  run_cmd->add_option("--restart", restart, "continue from a restart file (output: {restart: every_step})");
  run_cmd->add_flag("-v,--verbose", verbose, "print debugging output (Gmsh's too)");
  auto* check_cmd = app.add_subcommand("check", "read a deck and its mesh, print the model, solve nothing");
  check_cmd->add_option("deck", deck, "deck file (.yaml)")->required();
  auto* describe_cmd = app.add_subcommand("describe", "print the parameters of a registered type or deck section");
  describe_cmd->add_option("type", type, "type name (no name: list them all)");
  auto* bench_cmd = app.add_subcommand("bench", "benchmarks");
  bench_cmd->require_subcommand(1);
  auto* bench_search_cmd = bench_cmd->add_subcommand("search", "contact search on two curved 3D surfaces");
  BenchSearchOptions bso;
  bench_search_cmd->add_option("--slave-nodes", bso.slave_nodes, "number of slave nodes")->check(CLI::Range(4, 100000000));
  bench_search_cmd->add_option("--master-facets", bso.master_facets, "number of master triangles")
      ->check(CLI::Range(2, 100000000));
  bench_search_cmd->add_option("--threads", threads, "number of threads (default: all cores)")->check(CLI::Range(1, 1024));
  bench_search_cmd->add_option("--method", bso.method, "one method (default: bucket_grid and bvh)")
      ->check(CLI::IsMember({"bucket_grid", "bvh"}));
  bench_search_cmd->add_option("--check", bso.check_subset, "slave nodes checked against all_to_all");
  bench_search_cmd->add_option("--gap", bso.gap, "height of the generated slave sheet above the master (default 1e-3)")
      ->check(CLI::Range(0.0, 1.0));
  bench_search_cmd->add_flag("--quads", bso.quads, "generated master facets: quadrilaterals (--master-facets of them) instead of triangles");
  bench_search_cmd->add_option("--repeats", bso.repeats, "build + query passes per method (the first is the first pass, the others re-detections; default 2)")
      ->check(CLI::Range(1, 1000));
  bench_search_cmd->add_option("--slave", bso.slave_file, "a Gmsh .msh whose nodes are the slave nodes");
  bench_search_cmd->add_option("--master", bso.master_file, "a Gmsh .msh whose triangles/quadrilaterals are the master");
  bench_search_cmd->add_option("--write-surfaces", bso.write_dir, "write the surfaces searched as slave.msh and master.msh");
  CLI11_PARSE(app, argc, argv);

  if (threads > 0) omp_set_num_threads(threads);
  if (quiet) log::set_level(log::Level::warning);
  if (verbose) log::set_level(log::Level::debug);
#ifdef SIGNORINI_HAVE_PETSC
  // PETSc (and MPI) start on the first PETSc solver's use, or now under mpirun, and end here,
  // after the run's objects.
  struct PetscGuard {
    ~PetscGuard() { finalize_petsc(); }
  } petsc_guard;
  const MpiInfo mpi = run_cmd->parsed() ? start_petsc_if_launched_by_mpi() : MpiInfo{};
#else
  const struct {
    int rank = 0, size = 1;
  } mpi;
  if (run_cmd->parsed() && launched_ranks() > 1) {
    fmt::print(stderr, "error: launched on {} MPI ranks, but this build has no PETSc/MPI (install petsc-dev, "
                       "reconfigure)\n", launched_ranks());
    return 1;
  }
#endif
  // Under mpirun rank 0 speaks for all: run knows its rank from MPI; check, describe and
  // bench (every rank does the same, none starts MPI) from the launcher's environment.
  const int rank = run_cmd->parsed() ? mpi.rank : launched_ranks() > 1 ? launched_rank() : 0;
  if (rank != 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
  }
  // The cores are shared between the ranks.
  if (mpi.size > 1 && threads == 0) omp_set_num_threads(std::max(1, omp_get_num_procs() / mpi.size));
  try {
    if (bench_search_cmd->parsed()) return bench_search(bso);
    if (describe_cmd->parsed()) {
      const Registry r = default_registry();
      if (type.empty()) {
        for (auto* s : r.all()) fmt::print("{:<14} {:<16} {}\n", s->category, s->name, s->doc);
        return 0;
      }
      const TypeSpec* s = r.find_any(type);
      if (!s) {
        std::string names;
        for (auto* t : r.all()) names += (names.empty() ? "" : ", ") + t->name;
        fmt::print(stderr, "error: no type named '{}' (known: {})\n", type, names);
        return 1;
      }
      fmt::print("{}", r.describe(*s));
      if (s->name == "contact") fmt::print("\n{}", contact_compatibility_text());
      return 0;
    }
    return run(deck, outdir, check_cmd->parsed(), restart, mpi.rank);
  } catch (const InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return stop_all_ranks(mpi.size, interrupt_signal() ? 128 + interrupt_signal() : 1);
  } catch (const SolverError& e) {
    fmt::print(stderr, "error: the analysis failed: {}\n", e.what());
    return stop_all_ranks(mpi.size, 2);
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return stop_all_ranks(mpi.size, 1);
  }
}
