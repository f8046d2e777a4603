#include "signorini/solver/analysis.hpp"

#include <algorithm>
#include <csignal>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "signorini/contact/discretization/rigid_obstacle.hpp"
#include "signorini/core/binary_io.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/interrupt.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/atomic_file.hpp"
#ifdef SIGNORINI_HAVE_PETSC
#include "signorini/solver/petsc_solver.hpp"
#endif

namespace signorini {

namespace {

// Pseudo-transient continuation's budget, in multiples of solver.max_iterations: its damped
// steps cross a limit point in some 100 to 200 iterations (the arch of
// tests/verification/test_stabilization.cpp: 172-175; the ironing's 88 crossings: 119 on average).
constexpr int kContinuationBudget = 8;
// Attempts of pseudo-transient continuation at one limit point: from the step's first increment
// size, then cut back like a plain increment (the ironing without stabilization crossed 88
// limit points, most at the first attempt, one at the second and one at the fourth, from
// 0.002 down to 0.00025; with one attempt it gave up at t = 1.846).
constexpr int kContinuationAttempts = 4;

// A rigid motion of the body that no Dirichlet condition stops, described in words, or ""
// if there is none. The rigid modes (translations, rotations about the centroid scaled by
// the body size) restricted to the constrained DOFs must have full rank.
std::string free_rigid_motion(const std::vector<Index>& nodes, const Mesh& mesh, const DofMap& dofs,
                              const std::vector<char>& constrained, Dimension dim) {
  Vec3 lo = Vec3::Constant(1e300), hi = -lo, c = Vec3::Zero();
  for (Index n : nodes) {
    lo = lo.cwiseMin(mesh.nodes[n]);
    hi = hi.cwiseMax(mesh.nodes[n]);
    c += mesh.nodes[n];
  }
  c /= static_cast<Real>(std::max<size_t>(nodes.size(), 1));
  const Real size = std::max((hi - lo).norm(), 1e-300);
  const int nd = dofs.dofs_per_node();
  std::vector<std::string> names;
  // Mode value at node x for component i.
  std::vector<std::function<Real(const Vec3&, int)>> modes;
  auto translation = [](int k) { return [k](const Vec3&, int i) { return i == k ? 1.0 : 0.0; }; };
  auto rotation = [&](int axis) {
    return [axis, c, size](const Vec3& x, int i) {
      const Vec3 r = (x - c) / size, w = Vec3::Unit(axis);
      return w.cross(r)(i);
    };
  };
  if (dim == Dimension::axisymmetric) {
    modes = {translation(1)};
    names = {"translate along the axis (z)"};
  } else if (nd == 2) {
    modes = {translation(0), translation(1), rotation(2)};
    names = {"translate in x", "translate in y", "rotate in the plane"};
  } else {
    modes = {translation(0), translation(1), translation(2), rotation(0), rotation(1), rotation(2)};
    names = {"translate in x", "translate in y", "translate in z", "rotate about x", "rotate about y", "rotate about z"};
  }
  const int m = static_cast<int>(modes.size());
  MatX G = MatX::Zero(m, m);
  for (Index n : nodes) {
    for (int i = 0; i < nd; ++i) {
      const Index d = dofs.dof(n, i);
      if (d < 0 || !constrained[d]) continue;
      VecX row(m);
      for (int k = 0; k < m; ++k) row(k) = modes[k](mesh.nodes[n], i);
      G += row * row.transpose();
    }
  }
  Eigen::SelfAdjointEigenSolver<MatX> eig(G);
  const Real top = std::max(eig.eigenvalues().maxCoeff(), 1.0);
  if (eig.eigenvalues()(0) > 1e-10 * top) return "";
  // Name the free motion by its largest component.
  const VecX v = eig.eigenvectors().col(0);
  int k;
  v.cwiseAbs().maxCoeff(&k);
  return names[k];
}

std::vector<const ElementBlock*> all_cells(const Model& m) {
  std::vector<const ElementBlock*> v;
  for (auto& b : m.bodies)
    for (auto& blk : b->blocks()) v.push_back(&blk);
  return v;
}

// The nodes of each rigid body with its reference nodes: they share one set of DOFs.
std::vector<std::vector<Index>> rigid_groups(const Model& m) {
  std::vector<std::vector<Index>> groups;
  for (auto& b : m.bodies) {
    if (!b->rigid()) continue;
    std::vector<Index> g = b->reference_nodes();
    for (auto& blk : b->blocks()) g.insert(g.end(), blk.conn.begin(), blk.conn.end());
    std::sort(g.begin(), g.end());
    g.erase(std::unique(g.begin(), g.end()), g.end());
    groups.push_back(std::move(g));
  }
  return groups;
}

// Whether the Newton iterations' Krylov solves get forcing terms (Analysis::forcing_term):
// `adaptive`, or `auto` on a nonlinear model (contact, finite strain, material history).
bool adaptive_forcing(const Model& model) {
  const std::string& forcing = model.linear_solver.forcing;
  if (forcing != "auto") return forcing == "adaptive";
  bool nonlinear = !model.contacts.empty() || model.settings.finite_strain;
  for (const auto& b : model.bodies) nonlinear = nonlinear || (!b->rigid() && b->material().history_size() > 0);
  return nonlinear;
}

// The nodes of the body's cells (those it holds), ascending.
std::vector<Index> nodes_of_cells(const Body& body) {
  std::vector<Index> nodes;
  for (const ElementBlock& blk : body.blocks()) nodes.insert(nodes.end(), blk.conn.begin(), blk.conn.end());
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

// Whether `loads` has a load on a body's cells (body force, centrifugal).
bool has_body_loads(const std::vector<Load>& loads) {
  for (const Load& l : loads)
    if (l.kind == LoadKind::body_force || l.kind == LoadKind::centrifugal) return true;
  return false;
}

}  // namespace

// GAMG's prolongator smoothing. Smoothed aggregation (Vanek, Mandel & Brezina 1996)
// converges in fewer iterations, but its Galerkin products P^T A P are the bulk of the
// setup: on the 3D tet4 Hertz model at 148k DOFs, 2 ranks, 8 Newton iterations, the setup
// took 21.2 s and the CG 4.0 s; plain aggregation 4.8 s and 5.0 s (more, cheaper CG
// iterations; docs/performance.md).
// Under adaptive forcing the preconditioner is set up at every Newton iteration (the contact
// condensation changes the matrix's pattern) for a solve to a loose tolerance, so the setup
// is what counts: plain aggregation. A linear model solves once to rtol: smoothed aggregation
// (at 292k hex8 DOFs to 1e-8, 8.5 s against 12.3 s).
LinearSolverSettings solver_settings(const Model& model) {
  LinearSolverSettings s = model.linear_solver;
  s.amg_smoothing = adaptive_forcing(model) ? 0 : 1;
  return s;
}

Analysis::Analysis(Model& model)
    : model_(model),
      dofs_(model.mesh.num_nodes(), model.settings.spatial_dim(), all_cells(model), rigid_groups(model)),
      backend_(make_serial_backend(solver_settings(model), model.settings.dimension == Dimension::three_d)),
      cells_(all_cells(model)) {
  for (auto& b : model.bodies) linear_bodies_ = linear_bodies_ || b->linear();
  Real stiffness = 0;
  for (auto& b : model.bodies)
    if (!b->rigid()) stiffness = std::max(stiffness, b->material().stiffness_scale());
  Index unknowns = dofs_.num_dofs();
  for (const ContactPairSettings& cs : model.contacts)
    for (int pass = 0; pass < cs.passes; ++pass) {
      auto ci = std::make_unique<ContactInterface>(cs, model.mesh, model.settings, stiffness, pass == 1);
      ci->set_multiplier_offset(unknowns);
      unknowns += ci->num_multipliers();
      ci->set_obstacle_dofs(unknowns);
      unknowns += ci->num_obstacle_dofs();
      symmetric_ = symmetric_ && ci->symmetric();
      contacts_.push_back(std::move(ci));
    }
#ifdef SIGNORINI_HAVE_PETSC
  // Several MPI ranks: mortar shares its slave facets' integration out over them.
  if (!contacts_.empty()) rank_exchange_ = make_rank_exchange();
  for (auto& c : contacts_) c->set_rank_exchange(rank_exchange_.get());
#endif
  // Nitsche's method: the deformable bodies' cells give the pressure at the slave facets.
  for (auto& c : contacts_)
    if (c->needs_boundary_traction()) {
      if (!boundary_traction_) {
        std::vector<BoundaryTraction::Cells> cells;
        for (auto& b : model.bodies)
          if (!b->rigid())
            for (const ElementBlock& blk : b->blocks()) cells.push_back({&blk, &b->material()});
        boundary_traction_ = std::make_unique<BoundaryTraction>(std::move(cells), model.mesh.nodes, model.settings);
      }
      c->set_boundary_traction(boundary_traction_.get());
    }
  // Meshed rigid bodies that turn: an angle each about the first reference node in plane
  // problems, a rotation vector in 3D; contact reaches them through the chain rule
  // (RigidRotations).
  const int sdim = model.settings.spatial_dim();
  rotations_.angles = sdim == 3 ? 3 : 1;
  rotations_.reference = &model.mesh.nodes;
  rotations_.body_of_node.assign(model.mesh.num_nodes(), -1);
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = *model.bodies[b];
    if (!body.rigid() || !body.turns() || body.reference_nodes().empty()) continue;
    const int k = static_cast<int>(rotations_.dof.size());
    rotations_.dof.push_back(unknowns);
    unknowns += rotations_.angles;
    rotations_.ref.push_back(model.mesh.nodes[body.reference_nodes()[0]]);
    turning_bodies_.push_back(b);
    for (const ElementBlock& blk : body.blocks())
      for (Index n : blk.conn) rotations_.body_of_node[n] = k;
    for (Index n : body.reference_nodes()) rotations_.body_of_node[n] = k;
  }
  if (!turning_bodies_.empty())
    for (auto& c : contacts_) c->set_rigid_rotations(&rotations_);
  // A turning obstacle's angle: its row is a moment, measured in the norms as a force at the
  // obstacle's radius (a plane: at its farthest slave node), so that a distant contact point
  // does not inflate the force scale. A turning rigid body's likewise, at its farthest node.
  for (size_t k = 0; k < turning_bodies_.size(); ++k) {
    Real L = 0;
    for (Index n = 0; n < model.mesh.num_nodes(); ++n)
      if (rotations_.body_of_node[n] == static_cast<int>(k))
        L = std::max(L, (model.mesh.nodes[n] - rotations_.ref[k]).norm());
    for (int i = 0; i < rotations_.angles; ++i) moment_rows_.emplace_back(rotations_.dof[k] + i, L > 0 ? 1 / L : 1.0);
  }
  for (const auto& c : contacts_) {
    if (!c->rigid() || c->num_obstacle_dofs() <= sdim) continue;
    const RigidObstacle& ob = c->settings().obstacle;
    Real L = ob.radius;
    for (Index n : c->slave().nodes) L = std::max(L, (model.mesh.nodes[n] - ob.point).norm());
    for (int i = sdim; i < c->num_obstacle_dofs(); ++i) moment_rows_.emplace_back(c->obstacle_dofs() + i, L > 0 ? 1 / L : 1.0);
  }
  u_ = VecX::Zero(unknowns);
  u_converged_ = u_;
  reactions_ = u_;
  constrained_.assign(unknowns, 0);
  // Follower pressure makes the tangent unsymmetric, and so does a moment in 3D (its work on
  // the rotation vector, T(theta)^T M, has an unsymmetric derivative).
  for (auto& s : model.steps)
    for (auto& l : s.loads) {
      if (l.kind == LoadKind::pressure && model.settings.finite_strain) symmetric_ = body_symmetric_ = false;
      if (l.moment && sdim == 3) symmetric_ = body_symmetric_ = false;
    }
  is_multiplier_.assign(unknowns, 0);
  for (auto& c : contacts_)
    for (Index j = 0; j < c->num_multipliers(); ++j) is_multiplier_[c->multiplier_offset() + j] = 1;
  has_multipliers_ = std::find(is_multiplier_.begin(), is_multiplier_.end(), 1) != is_multiplier_.end();
  refuse_symmetric_only_solver();
  choose_algebra();
  // Partitioned assembly: Nitsche's points built and assembled by one rank each.
  if (backend_->ranks() > 1)
    for (auto& c : contacts_) c->share_points();
  if (!contacts_.empty()) detect_contact(0);
  rebuild_pattern();
  // The bodies' quadrature-point history, once the cells are shared out: partitioned, each
  // rank holds its own cells' only (it alone updates them, and writes them in its piece of the
  // output; a restart file gathers them), never the whole of it.
  for (size_t i = 0; i < model.bodies.size(); ++i)
    history_.emplace_back(*model.bodies[i], owned_cells_.empty() ? nullptr : &owned_cells_[i]);
}

// Several MPI ranks with a PETSc solver: partitioned assembly (each rank its own cells, into
// its rows of one distributed matrix). Algebraic multigrid needs the contact multipliers
// condensed: the distributed backend does it, each closed constraint eliminating a slave DOF
// of its own (node-to-segment, node-to-node) or, for coupled rows (mortar,
// segment-to-segment, two passes), the DOF where it dominates, with flexible GMRES on the
// whole system (condensed_solve.hpp's method); Lagrange friction's multipliers node by node
// (multiplier_blocks.hpp). Where that fails, `auto` takes the whole system to MUMPS; gamg or
// hypre chosen in the deck stop the run, as in one process.
void Analysis::choose_algebra() {
  const int ranks = parallel_ranks();
  if (ranks <= 1) return;
  if (model_.linear_solver.type == "auto") {
    // Under mpirun `auto` picks a solver PETSc distributes, as it does in one process: algebraic
    // multigrid for a symmetric 3D system above iterative_above unknowns, a direct solver
    // (MUMPS: LDL^T when symmetric, else LU; any saddle point of multipliers) otherwise. With
    // algebraic multigrid the contact multipliers are condensed, and a system the condensation
    // cannot take goes whole to MUMPS (direct_fallback), as one process's `auto` takes UMFPACK.
    // Unsymmetric 3D systems go to GMRES over GAMG at any size, as in one process (an LU of
    // them fills badly: examples/cattaneo_sphere_3d, penalty friction, 11.8k unknowns on 2 ranks,
    // 13.7 s with MUMPS against 2.8 s; docs/performance.md): Lagrange friction on symmetric
    // bodies, its multipliers condensed node by node (friction's multiplier blocks), and a
    // system without multipliers (penalty or augmented Lagrangian friction, follower pressure)
    // as it is; the whole system to MUMPS where the blocks cannot be condensed or GMRES fails.
    const bool three_d = model_.settings.dimension == Dimension::three_d;
    const bool symmetric = symmetric_solves(), blocks = !symmetric && has_multipliers_ && body_symmetric_;
    const bool displacements = !symmetric && !has_multipliers_;
    const bool amg = three_d && ((symmetric && num_unknowns() > model_.linear_solver.iterative_above) || blocks ||
                                 displacements);
    model_.linear_solver.type = amg ? "gamg" : "mumps";
    model_.linear_solver.direct_fallback = amg;
    log::info("  linear     auto under mpirun: {} ({} unknowns{})", model_.linear_solver.type, num_unknowns(),
              !amg ? ""
              : symmetric ? ", symmetric, 3D, above iterative_above"
              : blocks    ? ", 3D, friction's multipliers condensed for GMRES at any size"
                          : ", 3D, unsymmetric: GMRES at any size, MUMPS where it fails");
  }
  const std::string& linear = model_.linear_solver.type;
  if (!is_petsc_solver(linear)) {
    algebra_ = fmt::format("replicated on {} ranks (linear solver {} runs on each: only gamg, hypre, mumps and petsc "
                           "are distributed)", ranks, linear);
    return;
  }
#ifdef SIGNORINI_HAVE_PETSC
  backend_ = make_petsc_backend(solver_settings(model_));
  backend_->set_coordinates(&model_.mesh.nodes);
  algebra_ = fmt::format("partitioned over {} ranks (each assembles its own cells into its rows of one PETSc matrix; "
                         "cells shared out by {})",
                         ranks, model_.linear_solver.partition == "ptscotch" ? "PT-Scotch" : "coordinate bisection");
#endif
}

std::string Analysis::contact_evaluation() const {
  if (contacts_.empty()) return "no contact pair";
  if (!rank_exchange_) return "one process";
  std::vector<std::string> shared, points;
  for (const auto& c : contacts_) {
    if (c->shares_evaluation()) shared.push_back(c->label());
    if (c->shares_points()) points.push_back(c->label());
  }
  const int ranks = rank_exchange_->size();
  const size_t whole = contacts_.size() - shared.size() - points.size();
  if (shared.empty() && points.empty()) return fmt::format("every pair evaluated whole on each of the {} ranks", ranks);
  std::string s;
  if (!shared.empty())
    s = fmt::format("mortar's slave facets dealt out to the {} ranks, each integrating its share (pair{} {}); "
                    "the constraints then the same on every rank",
                    ranks, shared.size() > 1 ? "s" : "", fmt::join(shared, ", "));
  if (!points.empty())
    s += fmt::format("{}Nitsche's points dealt out to the {} ranks by slave facet, each building and assembling its "
                     "share (pair{} {}); the gaps and constraints whole on every rank",
                     s.empty() ? "" : "; ", ranks, points.size() > 1 ? "s" : "", fmt::join(points, ", "));
  if (whole > 0) s += "; the other pairs evaluated whole on each rank";
  return s;
}

// The deck reader refuses a solver for symmetric systems on a model whose systems are
// unsymmetric (symmetric_solver_refusal); a Model made otherwise (the Python module, tests) is
// refused here, before the first solve. (The multipliers' saddle point is not refused: the
// backend condenses it.)
void Analysis::refuse_symmetric_only_solver() const {
  if (!is_symmetric_only_solver(model_.linear_solver.type) || symmetric_solves()) return;
  throw InputError(model_.linear_solver_where.empty() ? model_.deck_path : model_.linear_solver_where, "solver.linear",
                   symmetric_solver_refusal(model_, true));
}

bool Analysis::symmetric_solves() const {
  if (!symmetric_ && !(has_multipliers_ && body_symmetric_)) return false;
  for (const ContactPairSettings& cs : model_.contacts)
    if (cs.method == "lagrange" && cs.friction != "none") return false;
  return true;
}

std::vector<Vec3> Analysis::positions(const VecX& u) const {
  std::vector<Vec3> x = model_.mesh.nodes;
  const int dim = dofs_.dofs_per_node();
  for (Index n = 0; n < dofs_.num_nodes(); ++n)
    if (dofs_.has_dofs(n))
      for (int d = 0; d < dim; ++d) x[n](d) += u(dofs_.dof(n, d));
  // A turning rigid body's nodes: x = X_ref + u_ref + R(theta) (X - X_ref), R once per body.
  if (!turning_bodies_.empty()) {
    std::vector<Mat3> R;
    for (Index first : rotations_.dof) R.push_back(rotation(u.data() + first, rotations_.angles).R);
    for (Index n = 0; n < dofs_.num_nodes(); ++n) {
      const int k = rotations_.body_of_node[n];
      if (k < 0 || !dofs_.has_dofs(n)) continue;
      const Vec3 X = model_.mesh.nodes[n] - rotations_.ref[k];
      x[n] = x[n] - X + R[k] * X;
    }
  }
  return x;
}

void Analysis::report_contact_pressures() {
  for (size_t i = 0; i < contacts_.size(); ++i) {
    if (i > 0 && contacts_[i - 1]->settings().name == contacts_[i]->settings().name) continue;  // done with pass 1
    std::vector<Vec3> f(model_.mesh.num_nodes(), Vec3::Zero());
    size_t end = i;
    while (end < contacts_.size() && contacts_[end]->settings().name == contacts_[i]->settings().name)
      contacts_[end++]->add_nodal_forces(f);
    for (size_t k = i; k < end; ++k) contacts_[k]->set_reported_pressure(f);
  }
}

void Analysis::detect_contact(Real max_step) {
  if (contacts_.empty()) return;
  const std::vector<Vec3> x = positions(u_);
  for (auto& c : contacts_) c->detect(x, max_step);
}

// Partitioned assembly, after the first pattern: each rank keeps its own cells (and the cells
// whose stress Nitsche's boundary traction reads at the slave facets, which every rank
// evaluates alike) and drops the others, with what the analysis still needs of the whole
// mesh's cells taken first: each body's nodes (the rigid-body check) and the nodes in no cell
// (rank 0's piece of the output). The rows keep the owners the whole mesh gave them.
void Analysis::share_out_cells() {
  Index mine = 0, all = 0, kept = 0;
  std::vector<char> in_cells(static_cast<size_t>(model_.mesh.num_nodes()), 0);
  for (auto& b : model_.bodies) {
    body_nodes_.push_back(nodes_of_cells(*b));
    for (Index n : body_nodes_.back()) in_cells[static_cast<size_t>(n)] = 1;
  }
  for (Index n = 0; n < model_.mesh.num_nodes(); ++n)
    if (!in_cells[static_cast<size_t>(n)]) cellless_nodes_.push_back(n);
  for (auto& b : model_.bodies) {
    std::vector<std::vector<char>> keep;
    for (const ElementBlock& blk : b->blocks()) {
      keep.emplace_back(static_cast<size_t>(blk.size()), 0);
      for (Index e = 0; e < blk.size(); ++e) {
        keep.back()[e] = backend_->cell_owner(&blk, e) == backend_->rank();
        mine += keep.back()[e];
      }
      if (boundary_traction_) boundary_traction_->mark_needed(&blk, keep.back());
      all += blk.size();
      std::vector<Index> index(static_cast<size_t>(blk.size()), -1);
      Index next = 0;
      for (Index e = 0; e < blk.size(); ++e)
        if (keep.back()[e]) index[e] = next++;
      kept += next;
      backend_->keep_cells(&blk, keep.back());
      if (boundary_traction_) boundary_traction_->renumber(&blk, index);
    }
    b->keep_cells(keep);
    owned_cells_.emplace_back();
    for (const ElementBlock& blk : b->blocks()) {
      owned_cells_.back().emplace_back(static_cast<size_t>(blk.size()));
      for (Index e = 0; e < blk.size(); ++e)
        owned_cells_.back().back()[e] = backend_->cell_owner(&blk, e) == backend_->rank();
    }
  }
  log::debug("rank {} assembles {} of the {} cells and holds {} (the others dropped), rows {} to {}", backend_->rank(),
             mine, all, kept, backend_->owned_begin(), backend_->owned_end());
}

void Analysis::rebuild_pattern() {
  std::vector<std::vector<Index>> couplings;
  for (auto& c : contacts_) c->couplings(dofs_, couplings);
  // The angles of a body or obstacle couple with each other (a moment's load stiffness in 3D).
  for (Index first : rotations_.dof) {
    couplings.emplace_back();
    for (int i = 0; i < rotations_.angles; ++i) couplings.back().push_back(first + i);
  }
  for (auto& c : contacts_)
    if (c->rigid() && c->num_obstacle_dofs() > 0) {
      couplings.emplace_back();
      for (int i = 0; i < c->num_obstacle_dofs(); ++i) couplings.back().push_back(c->obstacle_dofs() + i);
    }
  if (!couplings_.empty() && couplings == couplings_ && backend_->rows() == num_unknowns()) return;
  couplings_ = std::move(couplings);
  backend_->build_pattern(dofs_, cells_, couplings_, num_unknowns());
  if (backend_->ranks() > 1 && owned_cells_.empty()) share_out_cells();  // the partition is made once
  if (!factor_assessed_) {  // once, on the first pattern
    factor_assessed_ = true;
    if (symmetric_solves()) backend_->assess_factor();
  }
  if (backend_->wants_layout()) {
    // Where each unknown sits (algebraic multigrid's rigid-body modes).
    auto layout = std::make_shared<UnknownLayout>();
    const int dim = dofs_.dofs_per_node();
    layout->dim = dim;
    layout->axisymmetric = model_.settings.dimension == Dimension::axisymmetric;
    layout->x.assign(static_cast<size_t>(num_unknowns()), Vec3::Zero());
    layout->comp.assign(static_cast<size_t>(num_unknowns()), -1);
    for (Index node = dofs_.num_nodes() - 1; node >= 0; --node)  // a shared DOF takes its group's first node
      for (int c = 0; c < dim && dofs_.has_dofs(node); ++c) {
        const Index d = dofs_.dof(node, c);
        layout->x[d] = model_.mesh.nodes[node];
        layout->comp[d] = static_cast<signed char>(c);
      }
    backend_->set_layout(layout);
  }
  log::debug("sparse pattern rebuilt: {} unknowns, {} nonzeros", num_unknowns(), backend_->nonzeros());
}

void Analysis::add_loads(const std::vector<Load>& loads, Real scale, VecX& fext, bool tangent, VecX* cell_loads) {
  if (scale == 0) return;
  const auto& X = model_.mesh.nodes;
  const int dim = dofs_.dofs_per_node();
  for (const Load& l : loads) {
    switch (l.kind) {
      case LoadKind::nodal_force: {
        const auto& ns = model_.mesh.node_sets.at(l.set);
        Index n = 0;
        for (Index node : ns) n += dofs_.has_dofs(node);
        for (Index node : ns)
          if (dofs_.has_dofs(node))
            for (int i = 0; i < dim; ++i) fext(dofs_.dof(node, i)) += scale * l.vector(i) / n;
        break;
      }
      case LoadKind::traction:
      case LoadKind::pressure: {
        FacetLoad fl;
        fl.facets = &model_.mesh.facet_sets.at(l.set);
        fl.is_pressure = l.kind == LoadKind::pressure;
        fl.traction = l.vector;
        fl.pressure = l.pressure;
        fl.follower = model_.settings.finite_strain;
        add_facet_load(fl, model_.settings, X, u_, dofs_, scale, fext, tangent ? &backend_->matrix() : nullptr);
        break;
      }
      case LoadKind::body_force:
        for (size_t i = 0; i < model_.bodies.size(); ++i)
          if (model_.bodies[i]->name() == l.set)
            model_.bodies[i]->add_body_force(X, dofs_, l.vector, scale, cell_loads ? *cell_loads : fext, owned_cells(i));
        break;
      case LoadKind::centrifugal: {
        const Centrifugal& cf = l.centrifugal;
        const Real k = cf.density * cf.omega * cf.omega;
        const auto b = [&](const Vec3& x) {
          const Vec3 d = x - cf.origin;
          return Vec3(k * (d - d.dot(cf.axis) * cf.axis));
        };
        for (size_t i = 0; i < model_.bodies.size(); ++i)
          if (model_.bodies[i]->name() == l.set)
            model_.bodies[i]->add_body_force(X, dofs_, b, scale, cell_loads ? *cell_loads : fext, owned_cells(i));
        break;
      }
      case LoadKind::body_moment:
        for (size_t k = 0; k < turning_bodies_.size(); ++k)
          if (model_.bodies[turning_bodies_[k]]->name() == l.set && l.moment)
            add_moment(rotations_.dof[k], rotations_.angles, *l.moment, scale, fext, tangent);
        break;
      case LoadKind::obstacle_force:
        for (auto& c : contacts_) {
          if (c->settings().name != l.set || !c->rigid()) continue;
          const int sd = model_.settings.spatial_dim();
          if (l.obstacle_translations)
            for (int i = 0; i < sd; ++i) fext(c->obstacle_dofs() + i) += scale * l.vector(i);
          if (l.moment && c->num_obstacle_dofs() > sd)
            add_moment(c->obstacle_dofs() + sd, c->num_obstacle_dofs() - sd, *l.moment, scale, fext, tangent);
        }
        break;
    }
  }
}

void Analysis::add_moment(Index first, int n, const Vec3& M, Real scale, VecX& fext, bool tangent) {
  const Rotation rot = rotation(u_.data() + first, n);
  const Mat3 T = rot.T();
  for (int i = 0; i < n; ++i) fext(first + i) += scale * T.col(i).dot(M);
  if (!tangent || n == 1) return;  // about z the work is M theta: no stiffness
  const auto dT = rot.dT();
  MatX k(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) k(i, j) = -scale * dT[j].col(i).dot(M);
  std::vector<Index> dofs(n);
  for (int i = 0; i < n; ++i) dofs[i] = first + i;
  backend_->matrix().add(dofs.data(), n, k);
}

Vec3 Analysis::rotation_of(Index first, int n) const {
  Vec3 r = Vec3::Zero();
  for (int i = 0; i < n; ++i) r(rotation_component(i, n)) = u_(first + i);
  return r;
}

Vec3 Analysis::moment_of(Index first, int n) const {
  if (n == 1) return Vec3(0, 0, reactions_(first));
  const Mat3 T = rotation(u_.data() + first, n).T();
  Vec3 f;
  for (int i = 0; i < 3; ++i) f(i) = reactions_(first + i);
  return T.transpose().partialPivLu().solve(f);
}

Real Analysis::evaluate(Real lambda, bool tangent, VecX& residual) {
  log::Timer t;
  double contact_time = 0;
  const Index n = num_unknowns();
  VecX fint = VecX::Zero(n), fext = VecX::Zero(n), fc = VecX::Zero(n);
  for (int attempt = 0;; ++attempt) {
    fint.setZero();
    fext.setZero();
    fc.setZero();
    // Each rank its own cells (partitioned assembly; one rank: all of them). A failure on one
    // rank stops every rank, with its message.
    auto assemble_bodies = [&](auto&& which) {
      backend_->begin_cells();
      std::string failure;
      try {
        for (size_t i = 0; i < model_.bodies.size(); ++i)
          if (which(*model_.bodies[i]))
            model_.bodies[i]->assemble(model_.mesh.nodes, u_, dofs_, fint, tangent ? &backend_->matrix() : nullptr,
                                       &history_[i], dt_, owned_cells_.empty() ? nullptr : &owned_cells_[i]);
      } catch (const SolverError& e) {
        if (backend_->ranks() == 1) throw;
        failure = e.what();
      }
      backend_->end_cells();
      if (backend_->ranks() > 1 && backend_->any_failed(failure)) throw SolverError(failure);
    };
    // The bodies whose internal force is linear in u (Body::linear): their tangent K_lin is
    // assembled once per sparse pattern (a pattern lasts an increment, or more), kept by the
    // backend, and put back at the next evaluations with f_int = K_lin u; the other bodies
    // are assembled on top. On the 3D tet4 Hertz model (148k DOFs, 2 ranks, 8 Newton iterations)
    // the assembly went from 16.5 s to 1.4 s (docs/performance.md).
    const bool split = tangent && linear_bodies_;
    const bool reused = split && backend_->restore_values();
    if (tangent && !reused) backend_->zero();
    summary_.tangent_evaluations += tangent ? 1 : 0;
    summary_.linear_tangent_assemblies += split && !reused ? 1 : 0;
    VecX f_linear;
    if (reused) {
      backend_->multiply(u_, f_linear);
    } else if (split) {
      assemble_bodies([](const Body& b) { return b.linear(); });
      backend_->save_values();
    }
    assemble_bodies([&](const Body& b) { return !split || !b.linear(); });
    if (backend_->ranks() > 1) {
      log::Timer ts;
      backend_->sum_cell_forces(fint);
      log::debug("internal forces summed over {} ranks in {:.4f} s", backend_->ranks(), ts.seconds());
    }
    if (reused) fint += f_linear;
    // Partitioned, the body forces come from each rank's own cells and are summed by the
    // owners of their rows, as the internal forces are.
    const bool cell_sum = !owned_cells_.empty() && (has_body_loads(previous_loads_) || has_body_loads(*current_loads_));
    VecX cell_loads = cell_sum ? VecX::Zero(n) : VecX();
    add_loads(previous_loads_, 1 - lambda, fext, tangent, cell_sum ? &cell_loads : nullptr);
    add_loads(*current_loads_, lambda, fext, tangent, cell_sum ? &cell_loads : nullptr);
    if (cell_sum) {
      backend_->sum_cell_forces(cell_loads);
      fext += cell_loads;
    }
    if (!contacts_.empty()) {
      log::Timer tc;
      const std::vector<Vec3> x = positions(u_);
      for (auto& c : contacts_) {
        if (c->update_each_iteration()) c->detect(x, 0);
        // A pair whose points are shared out adds its points' entries into any rank's rows,
        // which the backend carries to their owners as it does the cells'.
        const bool own_share = tangent && c->shares_points();
        if (own_share) backend_->begin_cells();
        c->assemble(x, u_, dofs_, fc, tangent ? &backend_->matrix() : nullptr, &constrained_);
        if (own_share) backend_->end_cells();
      }
      contact_time += tc.seconds();
    }
    // A contact constraint outside the pattern (the search moved, or sliding went beyond
    // the neighbourhood): rebuild the pattern with the current couplings and assemble again.
    if (tangent && backend_->missed() && attempt == 0) {
      couplings_.clear();
      rebuild_pattern();
      continue;
    }
    if (tangent && backend_->missed()) throw SolverError("contact coupling outside the sparse pattern");
    break;
  }
  const Real stab_force = add_stabilization(fint, tangent);
  residual = fext - fint + fc;
  Real lift_force = 0;
  for (Index i = 0; i < residual.size(); ++i)
    if (constrained_[i]) {
      reactions_(i) = -residual(i);
      residual(i) = 0;
    } else {
      reactions_(i) = 0;
    }
  if (tangent) {
    // Prescribed values not reached yet (the increment's prescribed motion beyond the
    // predictor): the Newton step takes them on, linearized, R_f - K_fc (u_c* - u_c), instead
    // of moving those nodes alone first, which would shear (or invert, at finite strain) the
    // elements beside them before the rest can follow.
    const Real diag = backend_->mean_abs_diagonal();
    VecX lift = VecX::Zero(residual.size());
    lift_pending_ = false;
    for (const Prescribed& p : prescribed_) {
      lift(p.dof) = p.value(lambda) - u_(p.dof);
      lift_pending_ = lift_pending_ || std::abs(lift(p.dof)) > 1e-14 * (std::abs(u_(p.dof)) + std::abs(p.end - p.start));
    }
    if (lift_pending_) {
      VecX klift;
      backend_->multiply(lift, klift);
      for (Index i = 0; i < residual.size(); ++i) residual(i) = constrained_[i] ? diag * lift(i) : residual(i) - klift(i);
      lift_force = klift.norm();
    }
    backend_->apply_dirichlet(constrained_, diag);
    dirichlet_diagonal_ = diag;
  }
  summary_.contact_seconds += contact_time;
  summary_.assembly_seconds += t.seconds() - contact_time;
  // The force scale leaves the moment rows of the reactions out: a moment's size follows its
  // lever arm, which a body sliding away along a turning obstacle makes as large as it likes.
  // An applied moment counts (as a force at the body's size): a body loaded by a moment alone
  // has no other force to measure its residual by.
  const Real scale = std::max({force_norm(fint, false), force_norm(fext, true), force_norm(fc, false), lift_force});
  stab_ratio_ = scale > 0 ? stab_force / scale : 0;
  return scale;
}

// A step that ends with the stabilizing force above 1 % of the force scale has not reached the
// model's equilibrium: f_v carries that share of the load (measured: examples/hertz_sphere_3d
// with mortar and Nitsche, stabilization 1e-4 and one increment, ended at |f_v|/F = 0.43 with a
// contact force of 1420 for a load of 2500). The per-increment ratio was in the log and
// summary.json only; the step's end now says it (the shallow ironing's stabilized run ends
// its sliding steps below 6.3e-3, examples/long/shallow_ironing/README.md).
void Analysis::warn_stabilization(const Step& step) {
  constexpr Real kLargest = 1e-2;
  if (!(model_.newton.stabilization > 0) || summary_.increments.empty()) return;
  const IncrementRecord& last = summary_.increments.back();
  if (last.step != step_ || !(last.stabilization_ratio > kLargest)) return;
  const std::string text = fmt::format(
      "step '{}' ended with the stabilizing force at {:.3g} % of the force scale (|f_v|/F = {:.2e} > {:.0e}): its "
      "state is an equilibrium with that artificial force, not the model's. Lower solver.stabilization ({:.3g}): the "
      "stabilized state approaches the model's equilibrium as it goes to 0",
      step.name, 100 * last.stabilization_ratio, last.stabilization_ratio, kLargest, model_.newton.stabilization);
  log::warning("{}", text);
  summary_.warnings.push_back(text);
}

// Stabilization (solver.stabilization = alpha): f_v = c (u - u_p) on the free displacement
// DOFs, c = alpha D / dl, u_p the increment's predicted state (the last increment's motion
// extrapolated; u_n without a predictor). As dl is cut back c grows, so that a local snap of
// the discrete problem (a limit point with no equilibrium near the last one, e.g. a stick-slip
// release) is crossed by a sequence of damped states instead of a failed Newton iteration.
// Measured from the predicted state rather than from u_n (a damping of the pseudo-velocity
// would drag every steadily moving body, e.g. a sliding indenter), it only resists departures
// from the extrapolated path, like an inertia term of implicit dynamics; on smooth increments
// it is a small perturbation, reported per increment (|f_v| / F) so that the user can judge
// it. D is one scale for all DOFs, the mean diagonal of the first tangent.
// Returns |f_v|.
Real Analysis::add_stabilization(VecX& fint, bool tangent) {
  const Real alpha = model_.newton.stabilization;
  if (!(alpha > 0) || !(stab_dl_ > 0)) return 0;
  if (stab_scale_ == 0) {
    if (!tangent) return 0;
    stab_scale_ = backend_->mean_abs_diagonal();
  }
  const Real c = alpha * stab_scale_ / stab_dl_;
  Real f2 = 0;
  for (Index i = 0; i < dofs_.num_dofs(); ++i) {
    if (constrained_[i]) continue;
    const Real du = u_(i) - u_predicted_(i);
    fint(i) += c * du;
    f2 += c * du * c * du;
  }
  if (tangent) add_free_diagonal(c);
  return std::sqrt(f2);
}

void Analysis::add_free_diagonal(Real c) {
  MatX one = MatX::Constant(1, 1, c);
  for (Index i = 0; i < dofs_.num_dofs(); ++i)
    if (!constrained_[i]) backend_->matrix().add(&i, 1, one);
}

void Analysis::begin_step(int s) {
  step_ = s;
  const Step& step = model_.steps[s];
  std::fill(constrained_.begin(), constrained_.end(), 0);
  prescribed_.clear();
  std::vector<Index> where(dofs_.num_dofs(), -1);
  for (const auto& d : step.dirichlet) {
    for (Index node : model_.mesh.node_sets.at(d.set)) {
      const Index dof = dofs_.dof(node, d.component);
      if (dof < 0) continue;
      Prescribed p{dof, d.start ? *d.start : u_(dof), d.hold ? u_(dof) : d.end};
      if (where[dof] >= 0) prescribed_[where[dof]] = p;  // a later condition wins
      else {
        where[dof] = static_cast<Index>(prescribed_.size());
        prescribed_.push_back(p);
      }
      constrained_[dof] = 1;
    }
  }
  current_loads_ = &step.loads;
  // Rigid obstacles: each component prescribed, loaded by a force, or held where it is; the
  // angle (plane problems: the unknown after the translations) prescribed, loaded by a
  // moment, or held.
  const int sdim = model_.settings.spatial_dim();
  for (auto& c : contacts_) {
    if (!c->rigid()) continue;
    bool forced = false, turned = false;
    for (const auto& l : step.loads)
      if (l.kind == LoadKind::obstacle_force && l.set == c->settings().name) {
        forced = forced || l.obstacle_translations;
        turned = turned || l.moment.has_value();
      }
    for (int i = 0; i < c->num_obstacle_dofs(); ++i) {
      const Index dof = c->obstacle_dofs() + i;
      std::optional<Real> value;
      for (const auto& om : step.obstacles) {
        if (om.pair != c->settings().name) continue;
        if (i < sdim && om.u[i]) value = om.u[i];
        if (i >= sdim && om.rotation)
          value = (*om.rotation)(rotation_component(i - sdim, c->num_obstacle_dofs() - sdim));
      }
      if (!value && (i < sdim ? forced : turned)) continue;  // free, driven by the force or the moment
      prescribed_.push_back({dof, u_(dof), value ? *value : u_(dof)});
      constrained_[dof] = 1;
    }
  }
  // Turning rigid bodies: the rotation prescribed, loaded by a moment, or held.
  for (size_t k = 0; k < turning_bodies_.size(); ++k) {
    const std::string& name = model_.bodies[turning_bodies_[k]]->name();
    std::optional<Vec3> value;
    for (const auto& t : step.body_turns)
      if (t.body == name) value = t.rotation;
    bool turned = false;
    for (const auto& l : step.loads) turned = turned || (l.kind == LoadKind::body_moment && l.set == name);
    if (!value && turned) continue;  // free, driven by the moment
    for (int i = 0; i < rotations_.angles; ++i) {
      const Index dof = rotations_.dof[k] + i;
      prescribed_.push_back({dof, u_(dof), value ? (*value)(rotation_component(i, rotations_.angles)) : u_(dof)});
      constrained_[dof] = 1;
    }
  }
  std::vector<char> in_contact(model_.mesh.num_nodes(), 0);
  for (const auto& cs : model_.contacts)
    for (const auto* set : {&cs.master, &cs.slave})
      if (!set->empty())
        for (Index nd : model_.mesh.node_sets.at(*set)) in_contact[nd] = 1;
  for (size_t bi = 0; bi < model_.bodies.size(); ++bi) {
    const Body* b = model_.bodies[bi].get();
    // The body's nodes: its cells' (partitioned, each rank holds its own cells only: the
    // nodes of all of them, kept when the others were dropped).
    const std::vector<Index> own = body_nodes_.empty() ? nodes_of_cells(*b) : std::vector<Index>();
    const std::vector<Index>& nodes = body_nodes_.empty() ? own : body_nodes_[bi];
    // A body in contact may be held by its contact: the check does not apply (yet).
    bool touches = false;
    for (Index nd : nodes) touches = touches || in_contact[nd];
    if (touches) continue;
    const std::string motion = free_rigid_motion(nodes, model_.mesh, dofs_, constrained_, model_.settings.dimension);
    if (!motion.empty())
      throw FatalModelError("step '" + step.name + "': body '" + b->name() + "' is free to " + motion +
                            ": no Dirichlet condition stops this rigid-body motion, so the solution is not unique "
                            "(add supports, e.g. a symmetry condition)");
  }
}

std::map<Index, std::string> Analysis::contact_view() const {
  std::map<Index, std::string> v;
  for (auto& c : contacts_)
    for (size_t j = 0; j < c->constraints().size(); ++j) {
      const Constraint& k = c->constraints()[j];
      v[k.slave] += fmt::format(" [kind {} facet {} gap {:.3e} active {} slip {}]", static_cast<int>(k.kind), k.facet,
                                k.gap, static_cast<int>(c->state().active[j]),
                                j < c->state().slip.size() ? static_cast<int>(c->state().slip[j]) : -1);
    }
  return v;
}

void Analysis::check_tangent(Real lambda, const VecX& u0, const VecX& du, Real du_max) {
  // The tangent along the Newton direction against central differences of the residual,
  // -dR/du du ~ K du. A large error points at an inconsistent tangent or a kink of the
  // residual (a status change: the constraints on either side are logged).
  const Real h = 1e-6 / std::max(du_max, Real(1e-300));
  VecX rp, rm;
  VecX kd;
  backend_->multiply(du, kd);  // before the evaluations below
  u_ = u0 + h * du;
  evaluate(lambda, false, rp);
  const auto view_p = contact_view();
  u_ = u0 - h * du;
  evaluate(lambda, false, rm);
  const auto view_m = contact_view();
  u_ = u0;
  const VecX fd = (rm - rp) / (2 * h);
  // The displacement rows (forces) and the rows after them (the constraints' gaps and slips,
  // whose scale is a length) apart: an error in a gap row is invisible against the forces.
  Real err = 0, ref = 0, err_c = 0, ref_c = 0;
  Index worst = -1, worst_c = -1;
  for (Index i = 0; i < fd.size(); ++i) {
    if (constrained_[i]) continue;
    const Real e = std::abs(fd(i) - kd(i));
    if (i < dofs_.num_dofs()) {
      if (e > err) err = e, worst = i;
      ref = std::max(ref, std::abs(kd(i)));
    } else {
      if (e > err_c) err_c = e, worst_c = i;
      ref_c = std::max(ref_c, std::abs(kd(i)));
    }
  }
  Index big = 0;
  du.head(dofs_.num_dofs()).cwiseAbs().maxCoeff(&big);
  log::info("    tangent check: max |K du - FD| / max |K du| = {:.3e} (at {}), max |du| {:.3e} (at {})",
            ref > 0 ? err / ref : err, describe_unknown(worst), du_max, describe_unknown(big));
  if (worst_c >= 0)
    log::info("    tangent check, constraint rows: {:.3e} (at {}: K du {:.6e}, FD {:.6e})", ref_c > 0 ? err_c / ref_c : err_c,
              describe_unknown(worst_c), kd(worst_c), fd(worst_c));
  const Index nd = node_of_unknown(worst);
  if (view_p.count(nd)) log::info("      at +h:{}\n      at -h:{}", view_p.at(nd), view_m.at(nd));
}

int Analysis::rank() const { return backend_->rank(); }
int Analysis::ranks() const { return backend_->ranks(); }
bool Analysis::any_rank_failed(std::string& message) const { return backend_->any_failed(message); }

int Analysis::interrupt_on_any_rank() const {
  // mpirun passes a signal on to every rank, but each notices it at its own point of the
  // code: the ranks agree on it here, so that all stop at the same check (the collectives of
  // the next iteration, partitioned assembly's or a distributed solve's, would otherwise wait
  // for a rank that has stopped).
  const int sig = interrupt_signal();
  return parallel_ranks() > 1 ? max_over_ranks(sig) : sig;
}

Index Analysis::node_of_unknown(Index unknown) const {
  if (unknown < 0 || unknown >= dofs_.num_dofs()) return -1;
  for (Index nd = 0; nd < dofs_.num_nodes(); ++nd)
    if (dofs_.has_dofs(nd) && unknown >= dofs_.dof(nd, 0) && unknown < dofs_.dof(nd, 0) + dofs_.dofs_per_node())
      return nd;
  return -1;
}

std::string Analysis::describe_unknown(Index unknown) const {
  if (unknown < 0) return "no unknown";
  if (unknown >= dofs_.num_dofs()) {
    // The unknowns after the displacements: each pair's multipliers (one normal per slave node,
    // then dim tangential per node with friction), a rigid obstacle's displacement, a turning
    // rigid body's angles.
    static const char* kAxis[] = {"x", "y", "z"};
    for (const auto& c : contacts_) {
      const Index o = c->multiplier_offset(), n = static_cast<Index>(c->slave().nodes.size());
      if (c->num_multipliers() > 0 && unknown >= o && unknown < o + c->num_multipliers()) {
        const Index k = unknown - o;
        if (k < n)
          return fmt::format("unknown {} (contact '{}': the normal multiplier of slave mesh node {})", unknown, c->label(),
                             model_.mesh.node_ids[c->slave().nodes[k]]);
        const int dim = model_.settings.spatial_dim();
        return fmt::format("unknown {} (contact '{}': a tangential multiplier of slave mesh node {})", unknown, c->label(),
                           model_.mesh.node_ids[c->slave().nodes[(k - n) / dim]]);
      }
      if (c->num_obstacle_dofs() > 0 && unknown >= c->obstacle_dofs() && unknown < c->obstacle_dofs() + c->num_obstacle_dofs())
        return fmt::format("unknown {} (contact '{}': the rigid obstacle's displacement along {})", unknown, c->label(),
                           kAxis[std::min<Index>(unknown - c->obstacle_dofs(), 2)]);
    }
    for (size_t b = 0; b < rotations_.dof.size(); ++b)
      if (unknown >= rotations_.dof[b] && unknown < rotations_.dof[b] + rotations_.angles)
        return fmt::format("unknown {} (an angle of the turning rigid body '{}')", unknown,
                           model_.bodies[turning_bodies_[b]]->name());
    return fmt::format("unknown {} (a contact multiplier or a rigid body's)", unknown);
  }
  const Index nd = node_of_unknown(unknown);
  if (nd < 0) return fmt::format("unknown {}", unknown);
  static const char* kCartesian[] = {"u_x", "u_y", "u_z"};
  static const char* kAxisymmetric[] = {"u_r", "u_z"};
  const bool axisym = model_.settings.dimension == Dimension::axisymmetric;
  const auto comp = static_cast<size_t>(unknown - dofs_.dof(nd, 0));
  const char* name = comp < 3 ? (axisym ? (comp < 2 ? kAxisymmetric[comp] : "?") : kCartesian[comp]) : "?";
  if (dofs_.shared(nd)) return fmt::format("rigid body of mesh node {}, {}", model_.mesh.node_ids[nd], name);
  return fmt::format("mesh node {}, {}", model_.mesh.node_ids[nd], name);
}

std::string Analysis::largest_residual(const VecX& r) const {
  Index at = -1;
  Real big = -1;
  for (Index i = 0; i < r.size(); ++i)
    if (!(i < static_cast<Index>(constrained_.size()) && constrained_[i]) && std::abs(r(i)) > big) big = std::abs(r(i)), at = i;
  return at < 0 ? std::string() : fmt::format("largest residual {:.3e} at {}", big, describe_unknown(at));
}

void Analysis::predict(Real dl) {
  u_ = u_converged_;
  stab_dl_ = dl;
  // Predictor: the free DOFs continue along the last increment of this step, scaled.
  if (model_.newton.predictor && last_dl_ > 0) u_ += (dl / last_dl_) * last_du_;
  u_predicted_ = u_;
  // Prescribed DOFs: where the predictor puts them; the first Newton step takes them the
  // rest of the way (evaluate). Without a predictor, from the converged state.
  for (auto& h : history_) h.revert();
}

void Analysis::begin_contact_increment(Real lambda) {
  if (contacts_.empty()) return;
  // Detection at the start of the increment, on the predicted configuration; d_max grows
  // with the largest nodal motion of the prediction.
  Real step = 0;
  const int dim = dofs_.dofs_per_node();
  std::vector<Real> target(num_unknowns(), 0.0);
  for (const Prescribed& p : prescribed_) target[p.dof] = p.value(lambda);
  for (Index nd = 0; nd < dofs_.num_nodes(); ++nd)
    if (dofs_.has_dofs(nd)) {
      Real m2 = 0;
      for (int d = 0; d < dim; ++d) {
        const Index dof = dofs_.dof(nd, d);
        const Real v = (constrained_[dof] ? target[dof] : u_(dof)) - u_converged_(dof);
        m2 += v * v;
      }
      step = std::max(step, std::sqrt(m2));
    }
  log::Timer tc;
  detect_contact(step);
  const std::vector<Vec3> x0 = positions(u_converged_);
  // Without an extrapolated predictor the first Newton matrix is assembled at u_converged_.
  const bool unmoved = !(model_.newton.predictor && last_dl_ > 0);
  for (auto& c : contacts_) c->begin_increment(x0, u_converged_, unmoved);
  // The first increment from the undeformed state: slave nodes that touch their master to
  // within 1e-6 of their facet size start closed (a body held only by contact then has its
  // support; the hold is released after convergence if it ends in tension).
  if (summary_.increments.empty() && u_converged_.isZero(0))
    for (auto& c : contacts_) c->hold_touching(x0, u_converged_);
  rebuild_pattern();
  summary_.contact_seconds += tc.seconds();
}

// Inexact Newton (Eisenstat & Walker 1996, SIAM J. Sci. Comput. 17, "choice 2" with gamma 0.9,
// alpha 2): a Krylov solve need only reduce its residual by eta_k = 0.9 (rho_k / rho_(k-1))^2,
// rho the Newton iteration's |R| / F, so that the steps far from the solution (where the
// residual falls slowly and the active set still changes) do not pay for digits the next
// iteration throws away, while quadratic convergence at the end asks for more and more. The
// first iteration of an increment asks kForcingMax; as Kelley (1995, Iterative Methods for
// Linear and Nonlinear Equations, eq. 6.20, with 0.5 there) eta stays above 0.1 tol / rho_k,
// where the step only has to take the residual below the Newton tolerance tol; the deck's rtol
// is the tightest asked. Iterative solvers only: a direct factorization ignores it. `auto`: on
// nonlinear models (contact, finite strain, material history), which take several Newton
// iterations anyway; a linear one converges in one iteration from a solve to rtol, where the
// forcing terms would take three or four.
// While the contact statuses change, eta stays at kForcingMax: the ratio rho_k / rho_(k-1)
// measures a Newton iteration's rate on one smooth piece of the residual, and a step that
// opened or closed slave nodes crossed a kink of the semi-smooth residual, so its ratio says how
// good the active-set guess was, not how close the solution is; the next step goes to another
// piece again. Measured on the 3D Hertz model at 1.4M DOFs: a fall of the residual by 170 at
// an iteration that still changed 273 statuses asked the next solve for 3.1e-5 (63 CG
// iterations, the most of the run), whose step then changed 158 more (docs/performance.md).
Real Analysis::forcing_term(int it, const NewtonSettings& ns, const IncrementRecord& rec) const {
  const LinearSolverSettings& ls = model_.linear_solver;
  if (!adaptive_forcing(model_)) return 0;
  constexpr Real kForcingMax = 1e-2;
  const size_t n = rec.residuals.size();
  Real eta = kForcingMax;
  const bool statuses_changed = !rec.status_changes.empty() && rec.status_changes.back() > 0;
  if (it > 1 && n >= 2 && rec.residuals[n - 2] > 0 && !statuses_changed) {
    const Real ratio = rec.residuals[n - 1] / rec.residuals[n - 2];
    eta = 0.9 * ratio * ratio;
  }
  if (n >= 1 && rec.residuals[n - 1] > 0) eta = std::max(eta, 0.1 * ns.residual_tolerance / rec.residuals[n - 1]);
  return std::max(std::min(eta, kForcingMax), ls.rtol);
}

void Analysis::solve_newton_step(int it, const NewtonSettings& ns, const VecX& R, VecX& du, IncrementRecord& rec) {
  log::Timer ts;
  try {
    NewtonSolveRequest q;
    q.symmetric = symmetric_;
    q.body_symmetric = body_symmetric_;
    q.is_multiplier = has_multipliers_ ? &is_multiplier_ : nullptr;
    q.condense_contact = ns.condense_contact;
    q.rtol = last_forcing_ = forcing_term(it, ns, rec);
    if (ptc_shift_ > 0) add_free_diagonal(ptc_shift_);
    rec.linear_solver = backend_->solve(q, R, du);
    rec.linear_method = backend_->last_method();
    rec.krylov_iterations.push_back(backend_->last_iterations());
    rec.krylov_rtol.push_back(q.rtol);
    // A prescribed DOF's row is diag du = diag lift: its step is known exactly, and an
    // iterative solve's round-off there would leave the prescribed value forever "pending".
    if (dirichlet_diagonal_ > 0)
      for (Index i = 0; i < static_cast<Index>(constrained_.size()); ++i)
        if (constrained_[i]) du(i) = R(i) / dirichlet_diagonal_;
  } catch (const FatalModelError&) {
    // Already diagnosed (out of memory, or a solver unfit for the system: algebraic multigrid
    // refusing a contact system it cannot condense): not a sign of missing supports.
    throw;
  } catch (const SolverError& e) {
    // Singular at the very first solve, from the undeformed state: cutting back cannot
    // help, the model is missing supports.
    if (it == 1 && summary_.increments.empty() && u_converged_.isZero(0))
      throw FatalModelError(std::string(e.what()) +
                            " at the first solve from the undeformed state: the model probably "
                            "lacks supports (a rigid-body motion is free) in some direction" + open_contact_hint());
    throw;
  }
  // A free rigid-body motion that the factorization did not flag as singular: its pivot is
  // round-off, and the step's displacements are the forces amplified by ~1e16 over the
  // stiffness scale. The amplification du_max D / |R|_max (D the mean stiffness diagonal) is
  // unit-free: a supported model stays far below 1e13 (its conditioning), whatever the load,
  // so a huge load (5e30) is not taken for a missing support. (Displacements only: a first
  // multiplier estimate may be large, a pressure.)
  const Real du_max = du.head(dofs_.num_dofs()).cwiseAbs().maxCoeff();
  const Real r_max = R.head(dofs_.num_dofs()).cwiseAbs().maxCoeff();
  const Real amplification = r_max > 0 ? du_max * backend_->mean_abs_diagonal() / r_max : 0.0;
  if (!du.allFinite() || (it == 1 && summary_.increments.empty() && u_converged_.isZero(0) && amplification > 1e13))
    throw FatalModelError(fmt::format("the first solve from the undeformed state gives unbounded displacements (the "
                                      "forces amplified {:.1e} times over the stiffness scale): the model probably "
                                      "lacks supports (a rigid-body motion is free) in some direction{}",
                                      amplification, open_contact_hint()));
  summary_.solve_seconds += ts.seconds();
}

// A body held only by its contact (a sphere pushed by a force onto a block) has no support at
// the first solve unless a contact constraint is closed there. The node-based methods
// (multipliers, penalty, the augmented Lagrangian) start the slave nodes that touch closed
// (hold_touching; penalty since session 65); Nitsche's integration points away from the
// touching point start open: measured on examples/hertz_sphere_3d under its force, mortar and
// segment_to_segment with Nitsche stop at the first solve, every node-based pair runs. The
// failure then names the open pairs and what to do instead of leaving the supports suspect
// alone.
std::string Analysis::open_contact_hint() const {
  std::vector<std::string> open;
  for (const auto& c : contacts_) {
    const std::vector<char>& active = c->state().active;
    if (std::find(active.begin(), active.end(), 1) != active.end()) return "";
    open.push_back(fmt::format("'{}' ({}, {})", c->label(), c->settings().discretization, c->settings().method));
  }
  if (open.empty()) return "";
  return fmt::format("; or a body held only by its contact: no contact constraint is closed at this solve (pair{} {}). "
                     "The node-based methods (lagrange, penalty, augmented_lagrangian) start closed the slave nodes "
                     "that touch (a gap within {:g} of their facet size); Nitsche's method starts none closed where the "
                     "gap is not yet zero at its points. Use enforcement: lagrange (or penalty) with the bodies touching, "
                     "or bring the bodies into contact by a prescribed displacement first",
                     open.size() > 1 ? "s" : "", fmt::join(open, ", "), kTouching);
}

void Analysis::limit_turn(VecX& du) const {
  // The largest turn of one Newton step, 0.1 rad: a body turned by a moment whose contact
  // slips everywhere has next to no rotational stiffness in the step's tangent, and the full
  // step would spin it off its contact (or, in 3D, onto the rotation vector's singularity at
  // an angle of 2 pi, where the moment's work T^T M vanishes).
  // Prescribed angles are left out: their step is the prescribed one, taken whole.
  constexpr Real kMaxTurn = 0.1;
  Real turn = 0;
  auto measure = [&](Index first, int n) {
    Real t = 0;
    for (int i = 0; i < n; ++i)
      if (!constrained_[first + i]) t += du(first + i) * du(first + i);
    turn = std::max(turn, std::sqrt(t));
  };
  for (Index first : rotations_.dof) measure(first, rotations_.angles);
  const int sd = model_.settings.spatial_dim();
  for (const auto& c : contacts_)
    if (c->rigid() && c->num_obstacle_dofs() > sd) measure(c->obstacle_dofs() + sd, c->num_obstacle_dofs() - sd);
  if (!(turn > kMaxTurn)) return;
  log::info("    a rigid body would turn by {:.3g} rad in one Newton step: the step is scaled to {} rad", turn, kMaxTurn);
  du *= kMaxTurn / turn;
}

std::vector<std::vector<Real>> Analysis::contact_penetrations() const {
  std::vector<std::vector<Real>> p;
  for (const auto& c : contacts_) p.push_back(c->penetrations());
  return p;
}

std::vector<char> Analysis::contact_statuses() const {
  std::vector<char> s;
  for (const auto& c : contacts_) {
    const EnforcementOutput& st = c->state();
    s.insert(s.end(), st.active.begin(), st.active.end());
    s.insert(s.end(), st.slip.begin(), st.slip.end());
  }
  return s;
}

Real Analysis::line_search(Real lambda, const NewtonSettings& ns, const VecX& u0, const VecX& du, Real rnorm,
                           VecX& Rtrial, Real& new_scale, Real& new_norm, const std::vector<char>* statuses,
                           const std::vector<std::vector<Real>>* penetrations) {
  // Backtracking on the residual norm (full steps when the line search is off). With
  // `statuses` (contact multipliers, whose semi-smooth Newton method takes full steps: the
  // statuses at u0), only while the full step keeps every contact status: the residual is then
  // a smooth function along the step (the material's nonlinearity, e.g. plastic flow, is what
  // the backtracking guards against), and a step that changes the active set is the method's
  // own update, taken whole. A full step that cannot be evaluated (an inverted element) is
  // shortened.
  Real alpha = 1;
  bool search = ns.line_search;
  int limits = 0;
  std::string why;  // the last evaluation's failure, for the message when no step can be evaluated
  for (int ls = 0;; ++ls) {
    u_ = u0 + alpha * du;
    bool ok = true;
    try {
      new_scale = evaluate(lambda, true, Rtrial);
      new_norm = force_norm(Rtrial);
      ok = std::isfinite(new_norm);
      if (!ok) why = "a non-finite residual";
    } catch (const FatalModelError&) {
      throw;  // no shorter step cures it
    } catch (const SolverError& e) {
      ok = false;  // e.g. an element turned inside out: shorten the step
      why = e.what();
    }
    if (statuses && ls == 0) search = !ok || contact_statuses() == *statuses;
    // Penetration limit (`penetration_step`, kappa facet sizes; Lagrange multipliers and
    // Nitsche, whose steps are otherwise full): the linearization of an open slave node carries
    // no contact force, so a step that drives it far through its master leaves the region
    // where the step means anything. A body held only by contact (a force-controlled sphere
    // from its touching point) has almost no stiffness in the first tangent, and its full step
    // pushed it several facet sizes into the other body; from such a state the active set
    // cycled (3D mortar: 25 iterations and a cutback on the quarter sphere at hc = 0.02; with
    // the limit, 6 iterations). The step is scaled by about kappa / growth (the penetration
    // of an open node grows roughly linearly along the step), at most four times. Closed nodes
    // are left out (their step is the linearized constraint's), and so are penalty and the
    // augmented Lagrangian, whose line search is on and whose penetration is part of the
    // solution (measured: the limit made the penalty drag over a smoothed mound cut back).
    if (ok && penetrations && ns.penetration_step > 0 && limits <= 4) {
      Real growth = 0;
      Index node = -1;
      for (size_t i = 0; i < contacts_.size() && i < penetrations->size(); ++i) {
        if (!contacts_[i]->full_newton_steps()) continue;
        const auto [g, n] = contacts_[i]->penetration_growth((*penetrations)[i]);
        if (g > growth) growth = g, node = n;
      }
      // Still beyond the limit after four cuts (each by up to 20x): the step is no Newton step
      // of this state but the answer of a (near) singular system, e.g. a body left with no
      // closed node to hold it, whose full step measured 1e13 facet sizes (the finite-strain
      // Nitsche patch on quad8, slid, on AVX-512 BLAS kernels: taken, it ended in another,
      // absurd equilibrium). The iteration fails, and the increment is cut back.
      if (growth > ns.penetration_step && limits == 4)
        throw SolverError(fmt::format("the Newton step is not usable: cut four times (to {:.3g}), it would still drive "
                                      "slave node {} {:.3g} facet sizes deeper (a near-singular system, e.g. a body "
                                      "held by no closed contact node)",
                                      alpha, node, growth));
      if (growth > ns.penetration_step) {
        ++limits;
        const Real factor = std::clamp(0.9 * ns.penetration_step / growth, 0.05, 0.5);
        log::info("      step {:.3g}: slave node {} would penetrate {:.3g} facet sizes deeper; step x {:.3g}", alpha, node,
                  growth, factor);
        alpha *= factor;
        continue;
      }
    }
    // A step that cannot be evaluated (an element turned inside out) is shortened after a
    // penetration limit and, with `residual_growth`, where the steps are otherwise full (the
    // multipliers' semi-smooth Newton method; with the line search on, its backtracking below
    // shortens it): the state it would reach has no
    // meaning, and a shorter step in the same direction keeps the iteration going where a
    // failure would cut the increment back. Not by default for full steps: from a halved step the
    // finite-strain Nitsche patch test on quad8 (ContactPatch.NitscheOnMortarIntegration...)
    // ended at another equilibrium accepted as stagnated, where the cutback finds the right one.
    // Pseudo-transient continuation rejects the step instead.
    if (!ok && ls < 6 && ptc_shift_ == 0 && (limits > 0 || ns.residual_growth > 0)) {
      alpha *= 0.5;
      continue;
    }
    // Residual growth limit (`residual_growth`, Lagrange multipliers and Nitsche, whose steps
    // are otherwise full): the residual norm is no merit function of the semi-smooth method, whose
    // active-set updates may raise it, so a step is accepted unless it raises the norm more
    // than that factor; then it is halved, at most six times (the sixth halving is taken).
    if (ok && !search && ns.residual_growth > 0 && ptc_shift_ == 0 && new_norm > ns.residual_growth * rnorm &&
        ls < 6) {
      alpha *= 0.5;
      continue;
    }
    if (ok && (!search || new_norm <= (1 - 1e-4 * alpha) * rnorm || ls >= 6)) break;
    if (!search || ls >= 6) {
      if (!ok)
        throw SolverError((alpha < 1 ? "non-physical state even with a short step: "
                                     : "non-physical state after a full Newton step: ") +
                          why);
      break;
    }
    alpha *= 0.5;
  }
  return alpha;
}

Analysis::AfterConvergence Analysis::after_convergence(NewtonState& st, IncrementRecord& rec, std::string& why) {
  // A node held closed by the chattering guard that ended in tension: held open instead.
  Index released = 0;
  for (auto& c : contacts_) released += c->fix_held_nodes();
  if (released > 0 && st.released_rounds++ < 3) {
    log::info("    {} node(s) held closed by the chattering guard ended in tension: held open, Newton goes on",
              released);
    return AfterConvergence::iterate;
  }
  for (auto& c : contacts_)
    if (const Index n = c->frozen_in_tension()) {
      why = fmt::format("contact '{}': {} node(s) held by the chattering guard violate the contact conditions (closed "
                        "in tension, open and penetrating, or held in stick/slip on the wrong side of the friction disc)",
                        c->label(), n);
      return AfterConvergence::fail;
    }
  // The chattering guard broke a cycle by holding nodes, and Newton converged with them
  // held: a solution within the guard's tolerance, not necessarily the exact one. From this
  // state, near the solution, the semi-smooth Newton method converges locally: the holds the
  // state violates are released once and Newton goes on, so the result is the exact solution
  // when the method reaches it (a node that flips again is held at its first flip, and that
  // held state is accepted).
  if (!st.polished) {
    Index held = 0;
    for (auto& c : contacts_) held += c->release_holds();
    if (held > 0) {
      st.polished = true;
      log::info("    converged with {} node(s) held by the chattering guard in a status the state violates: released, Newton goes on", held);
      return AfterConvergence::iterate;
    }
  }
  // Augmented Lagrangian: Uzawa updates of the multipliers until the penetration is within
  // the tolerance; Newton goes on from the current state after each update. Each pair has its
  // own limit (enforcement.max_uzawa).
  bool satisfied = true;
  const std::vector<Vec3> xc = positions(u_);
  for (size_t i = 0; i < contacts_.size(); ++i) {
    ContactInterface& c = *contacts_[i];
    Real pen = 0;
    if (c.augment(xc, u_, pen)) continue;
    satisfied = false;
    log::info("    Uzawa update {} of '{}': max penetration {:.3e} > {:.3e}", st.augmentations[i] + 1, c.label(), pen,
              c.gap_tolerance());
    if (++st.augmentations[i] > c.max_augmentations()) {
      why = fmt::format("contact '{}': the augmented Lagrangian did not reach its gap tolerance in {} Uzawa updates",
                        c.label(), c.max_augmentations());
      return AfterConvergence::fail;
    }
  }
  if (satisfied) {
    rec.uzawa_updates = st.uzawa;
    return AfterConvergence::accept;
  }
  ++st.uzawa;
  return AfterConvergence::iterate;
}

bool Analysis::solve_increment(Real lambda, Real dl, IncrementRecord& rec, std::string& why, bool pseudo_transient) {
  NewtonSettings ns = model_.newton;
  ptc_shift_ = 0;
  // The residual norm is no merit function for the semi-smooth Newton method of contact
  // multipliers (and of Nitsche's method, Enforcement::full_steps): a line search on it
  // stalls the active-set updates, so steps that change the
  // active set are full; the others are searched (line_search's `statuses`).
  // Only for bodies whose material has history (plasticity): there the material's own kinks
  // (loading/unloading) make full steps overshoot; with elastic bodies full steps are the
  // method's (a search there slowed frictional cases from 8 to 11 iterations per increment).
  bool multipliers = false, history = false;  // multipliers: full semi-smooth steps
  for (auto& c : contacts_) multipliers = multipliers || c->full_newton_steps();
  for (const auto& b : model_.bodies) history = history || (!b->rigid() && b->material().history_size() > 0);
  const bool within_active_set = multipliers && history && ns.line_search;
  if (multipliers) ns.line_search = false;
  predict(dl);
  begin_contact_increment(lambda);
  VecX R, du, Rtrial;
  rec.residuals.clear();
  rec.energies.clear();
  try {
    NewtonState st;
    st.augmentations.assign(contacts_.size(), 0);
    st.scale = evaluate(lambda, true, R);
    st.rnorm = force_norm(R);
    // A floor under the force scale: the force that 1e-3 of the largest displacement would
    // take across one element (mean stiffness diagonal). Without it, a body moved rigidly by
    // prescribed displacements before it touches anything has only round-off forces, and
    // the relative residual of round-off never converges.
    const Real floor =
        1e-3 * backend_->mean_abs_diagonal() * (dofs_.num_dofs() ? u_.head(dofs_.num_dofs()).cwiseAbs().maxCoeff() : 0.0);
    auto converged_residual = [&](Real r, Real sc) {
      return !lift_pending_ &&
             (r <= std::max(ns.residual_tolerance * std::max(sc, floor), ns.absolute_tolerance) || sc < 1e-300);
    };
    rec.residuals.push_back(st.scale > 0 ? st.rnorm / st.scale : st.rnorm);
    log::info("    iter {:2d}  |R|/F = {:.3e}", 0, rec.residuals.back());
    // Pseudo-transient continuation (the last resort of run_steps, at a limit point): each
    // Newton matrix gets the shift s on the diagonal of its free displacement rows, the
    // residual stays as it is, so the fixed point is the exact equilibrium. s starts at D, the
    // mean diagonal, and is halved after each step that lowers |R|, doubled after one that
    // raises it; a step that inverts an element or raises |R| tenfold is rejected and retried
    // with a doubled shift. Budget: kContinuationBudget times the Newton iterations.
    const Real d_mean = backend_->mean_abs_diagonal();
    Real last_rnorm = st.rnorm;
    rec.pseudo_transient = pseudo_transient;
    if (pseudo_transient) {
      ns.max_iterations *= kContinuationBudget;
      ns.line_search = false;
    }
    if (converged_residual(st.rnorm, st.scale)) {
      rec.iterations = 0;
      return true;
    }
    for (int it = 1; it - st.cycle_start < ns.max_iterations; ++it) {
      if (const int sig = interrupt_on_any_rank()) throw Interrupted(sig);
      if (pseudo_transient) {
        if (it == 1) ptc_shift_ = d_mean;
        else if (last_rnorm > 0) ptc_shift_ *= st.rnorm < last_rnorm ? 0.5 : 2.0;
        ptc_shift_ = std::clamp(ptc_shift_, 1e-12 * d_mean, 1e3 * d_mean);
        last_rnorm = st.rnorm;
      }
      solve_newton_step(it, ns, R, du, rec);
      limit_turn(du);
      const Real energy = std::abs(du.dot(R));
      const VecX u0 = u_;
      const std::vector<char> statuses = within_active_set ? contact_statuses() : std::vector<char>();
      const std::vector<std::vector<Real>> pen0 = contact_penetrations();
      std::map<Index, std::string> view_before;
      if (check_tangent_ && ptc_shift_ == 0) {  // (a shifted matrix is not the tangent)
        view_before = contact_view();
        check_tangent(lambda, u0, du, du.head(dofs_.num_dofs()).cwiseAbs().maxCoeff());
      }
      Real new_scale = 0, new_norm = 0;
      Real alpha = 1;
      if (pseudo_transient) {
        bool inverted = false;
        try {
          alpha = line_search(lambda, ns, u0, du, st.rnorm, Rtrial, new_scale, new_norm);
        } catch (const FatalModelError&) {
          throw;
        } catch (const SolverError&) {
          inverted = true;
        }
        if (inverted || !(new_norm <= 10 * st.rnorm)) {
          // Rejected: back to u0 (its residual and tangent), a doubled shift, the step again.
          u_ = u0;
          ptc_shift_ = std::min(2 * ptc_shift_, 1e3 * d_mean);
          st.scale = std::max(st.scale, evaluate(lambda, true, R));
          log::info("    iter {:2d}  step rejected ({}); shift {:.3g} D", it,
                    inverted ? std::string("an element inverts") : fmt::format("|R|/F = {:.3e}", new_norm / st.scale),
                    ptc_shift_ / d_mean);
          last_rnorm = 0;
          continue;
        }
      } else {
        alpha = line_search(lambda, ns, u0, du, st.rnorm, Rtrial, new_scale, new_norm,
                            within_active_set ? &statuses : nullptr, &pen0);
      }
      if (check_tangent_) {
        const auto view_after = contact_view();
        for (auto& [node, text] : view_after)
          if (view_before.count(node) && view_before.at(node) != text)
            log::info("      node {}:{}\n        ->{}", node, view_before.at(node), text);
      }
      R.swap(Rtrial);
      st.rnorm = new_norm;
      for (auto& c : contacts_) c->count_status_changes();
      // The stick predictor (penalty and augmented Lagrangian friction, ContactInterface) ends
      // once the normal statuses hold, after a step the line search cut short, or when the
      // residual it shapes has converged: the residual of the free friction law is then
      // evaluated here, before convergence is judged.
      Index released = 0;
      const bool would_converge = converged_residual(st.rnorm, std::max(st.scale, new_scale));
      for (auto& c : contacts_) released += c->end_stick_predictor(would_converge, alpha, it == st.cycle_start);
      if (released > 0) {
        new_scale = std::max(new_scale, evaluate(lambda, true, R));
        st.rnorm = force_norm(R);
        log::info("      stick predictor released: {} node(s) that closed in this increment are free to slip; "
                  "|R|/F = {:.3e}",
                  released, st.rnorm / std::max(st.scale, new_scale));
      }
      st.scale = std::max(st.scale, new_scale);
      const Real rel = st.scale > 0 ? st.rnorm / st.scale : st.rnorm;
      rec.residuals.push_back(rel);
      rec.energies.push_back(energy);
      rec.iterations = it;
      const int krylov = rec.krylov_iterations.empty() ? 0 : rec.krylov_iterations.back();
      std::string statuses_text;
      int changes = 0;
      for (auto& c : contacts_) {
        const auto& is = c->iterate_status();
        statuses_text += fmt::format("  [{} closed +{} -{}{}]", is.closed, is.newly_closed, is.newly_opened,
                                     c->frictional() && c->node_statuses()
                                         ? fmt::format(", {} slip +{} -{}", is.slipping, is.to_slip, is.to_stick)
                                         : std::string());
        changes += static_cast<int>(is.newly_closed + is.newly_opened);
      }
      rec.status_changes.push_back(changes);
      log::info("    iter {:2d}  |R|/F = {:.3e}  |du.R| = {:.3e}{}{}{}{}", it, rel, energy,
                alpha < 1 ? fmt::format("  (line search {:.3g})", alpha) : std::string(),
                ptc_shift_ > 0 ? fmt::format("  (shift {:.3g} D)", ptc_shift_ / d_mean) : std::string(),
                krylov > 0 ? fmt::format("  [{} Krylov iterations{}]", krylov,
                                         last_forcing_ > 0 ? fmt::format(", rtol {:.1e}", last_forcing_) : std::string())
                           : std::string(),
                statuses_text);
      if (!std::isfinite(st.rnorm)) {
        why = "residual is not finite";
        return false;
      }
      if (it == st.cycle_start) st.energy0 = energy;
      const bool energy_ok = it > st.cycle_start && energy <= ns.energy_tolerance * st.energy0;
      // The bound beside the tolerance: 1e3 times it, for the energy criterion.
      const Real bound = 1e3 * std::max(ns.residual_tolerance * st.scale, ns.absolute_tolerance);
      const bool within_bound = !lift_pending_ && st.rnorm <= bound;
      // Stagnation's bound: the same, and at least 1e-4 of the force scale. A jump of the
      // residual is a property of the discretization, not of the tolerance asked for, and it
      // grows with the load (the angle between neighbouring master facets grows as they
      // deform): Taylor's 2D patch test with segment_to_segment stagnates at 8e-6 at 30 % of
      // its load, 2.7e-5 at the full load.
      const Real stagnation_bound = std::max(bound, 1e-4 * st.scale);
      const bool within_stagnation_bound = !lift_pending_ && st.rnorm <= stagnation_bound;
      // Stagnation, the last resort before a cutback: at the last iteration of the budget, the
      // contact statuses unchanged over the last three iterations, and either the last five
      // residuals within 1 % of each other (flat) or the last ten within the bound with no
      // progress (the best of the last five no better than half the best of the five before: a
      // cycle, e.g. penalty's line search at 1/64 on CalculiX's fine tet4 Hertz mesh, a
      // period-5 cycle between 2.9e-5 and 5e-5 at every increment size). Newton then cycles
      // between states on either side of a jump of the residual, e.g. an integration point (segment-to-segment) or a slave node (node-to-segment) on the
      // edge between two master facets, where the contact force follows each facet's own
      // normal: the force jumps by about (the point's force) x (the angle between the normals).
      // No state there meets the tolerance; one within the bound is the solution to that
      // accuracy, accepted and reported (summary.json: "stagnated"). Only at the end of the
      // budget: a frictional node on the stick/slip kink may stall for three iterations with
      // the statuses unchanged and then converge (FrictionGrid, mu 0.3, Q/(mu P) 0.6).
      const int left = ns.max_iterations - (it - st.cycle_start + 1);  // iterations left in the budget
      if (left < 3) st.statuses.push_back(contact_statuses());
      const size_t nres = rec.residuals.size();
      bool stagnated = false;
      const bool last = left <= 0;
      // Only with contact, whose force is what jumps (a model without contact near a limit point
      // converges slowly, not stagnates), and not under pseudo-transient continuation (its
      // residual may crawl while the state moves).
      if (!contacts_.empty() && !pseudo_transient && last && within_stagnation_bound && it - st.cycle_start >= 4 &&
          nres >= 5 && st.statuses.size() == 3 && st.statuses[0] == st.statuses[1] && st.statuses[1] == st.statuses[2]) {
        const auto [lo, hi] = std::minmax_element(rec.residuals.end() - 5, rec.residuals.end());
        stagnated = *hi <= 1.01 * *lo;
        if (!stagnated && it - st.cycle_start >= 9 && nres >= 10 && st.scale > 0) {
          const Real before = *std::min_element(rec.residuals.end() - 10, rec.residuals.end() - 5);
          stagnated = *std::max_element(rec.residuals.end() - 10, rec.residuals.end()) <= stagnation_bound / st.scale &&
                      *lo >= 0.5 * before;
        }
      }
      const bool converged = converged_residual(st.rnorm, st.scale) || (energy_ok && within_bound);
      if (stagnated && !converged) {
        rec.stagnated = true;
        rec.stagnated_residual = rel;
        log::warning("Newton stagnates at |R|/F = {:.3e} ({}) above the tolerance {:.1e}: a jump of the residual, "
                  "accepted",
                  rel, largest_residual(R), ns.residual_tolerance);
      }
      if (converged || stagnated) {
        switch (after_convergence(st, rec, why)) {
          case AfterConvergence::accept: return true;
          case AfterConvergence::fail: return false;
          case AfterConvergence::iterate:
            // Newton goes on from here (a new cycle: its own energy reference).
            rec.stagnated = false;
            st.statuses.clear();
            st.cycle_start = it + 1;
            st.scale = evaluate(lambda, true, R);
            st.rnorm = force_norm(R);
            rec.residuals.push_back(st.scale > 0 ? st.rnorm / st.scale : st.rnorm);
            continue;
        }
      }
      if (it - st.cycle_start > 2 && rel > 1e8 * rec.residuals.front()) {
        why = "residual diverges";
        return false;
      }
    }
    why = fmt::format("no convergence in {} iterations (relative residual {:.3e}; {})", ns.max_iterations,
                      rec.residuals.back(), largest_residual(R));
    return false;
  } catch (const FatalModelError&) {
    throw;
  } catch (const SolverError& e) {
    why = e.what();
    return false;
  }
}

AnalysisSummary Analysis::run() {
  try {
    return run_steps();
  } catch (const FatalModelError& e) {
    summary_.failure = e.what();
  } catch (const Interrupted& e) {
    summary_.interrupted = true;
    summary_.failure = fmt::format("interrupted by signal {} ({}); the last converged increment is kept", e.signal,
                                   e.signal == SIGINT ? "SIGINT" : e.signal == SIGTERM ? "SIGTERM" : "a signal");
  }
  // Back to the last converged increment, the state the writer keeps on disk.
  for (auto& h : history_) h.revert();
  u_ = u_converged_;
  return summary_;
}

AnalysisSummary Analysis::run_steps() {
  log::Timer total;
  summary_ = {};
  summary_.first_step = first_step_;
  previous_loads_.clear();
  if (first_step_ > 0) previous_loads_ = model_.steps[first_step_ - 1].loads;
  static const std::vector<Load> none;
  current_loads_ = &none;
  for (int s = first_step_; s < static_cast<int>(model_.steps.size()); ++s) {
    const Step& step = model_.steps[s];
    begin_step(s);
    last_dl_ = 0;  // a new step changes the loading path: no extrapolation across it
    log::info("step {} '{}': {} Dirichlet conditions, {} loads", s + 1, step.name, step.dirichlet.size(),
              step.loads.size());
    Real lambda = 0, dl = std::min(step.initial_increment, step.max_increment);
    int inc = 0, cutbacks = 0, failed_iterations = 0;
    bool continuation = false;
    int continuation_attempts = 0;
    while (lambda < 1 - 1e-12) {
      if (const int sig = interrupt_on_any_rank()) throw Interrupted(sig);
      if (inc >= step.max_increments) {
        summary_.failure = fmt::format("step '{}': more than {} increments", step.name, step.max_increments);
        summary_.total_seconds = total.seconds();
        return summary_;
      }
      dl = std::min(dl, 1 - lambda);
      IncrementRecord rec;
      rec.step = s;
      rec.increment = inc + 1;
      log::Timer t;
      std::string why;
      dt_ = dl * step.duration;
      const bool ok = solve_increment(lambda + dl, dl, rec, why, continuation);
      if (!ok) {
        ++cutbacks;
        failed_iterations += rec.iterations;
        summary_.failed_iterations += rec.iterations;
        const Real next = dl * model_.newton.cutback_factor;
        // Pseudo-transient continuation is the last resort: cut back to at most
        // kContinuationAttempts attempts.
        const bool give_up = next < step.min_increment * (1 - 1e-12) ||
                             (continuation && continuation_attempts >= kContinuationAttempts);
        log::warning("step '{}' increment {} (fraction {:.4g} -> {:.4g}) failed: {}{}", step.name, inc + 1, lambda,
                     lambda + dl, why, give_up ? std::string() : fmt::format("; cutting back to {:.3g}", next));
        // The last resort: a limit point (no equilibrium near the last one, e.g. a snap of an
        // arch, a stick-slip release, a slave node passing a master corner). Cutting back brings
        // the increment ever closer to the limit, where the distant equilibrium is hardest to
        // reach; pseudo-transient continuation from the step's first increment size (beyond the
        // limit by a finite amount) follows a damped path to it. Tried once: where no
        // equilibrium exists (a load above the limit load), each attempt costs its budget, so
        // they are few (kContinuationAttempts).
        if (give_up && !continuation && model_.newton.pseudo_transient) {
          continuation = true;
          continuation_attempts = 1;
          dl = std::min({step.initial_increment, step.max_increment, 1 - lambda});
          log::warning("step '{}' at fraction {:.6g}: the increment reached its minimum; pseudo-transient continuation "
                       "from an increment of {:.4g}",
                       step.name, lambda, dl);
          continue;
        }
        if (give_up) {
          u_ = u_converged_;
          for (auto& h : history_) h.revert();
          summary_.failure =
              continuation
                  ? fmt::format("step '{}' at fraction {:.6g}: the increment fell to its minimum {:.3g} after {} "
                                "cutbacks, and pseudo-transient continuation failed too ({} attempt{}, the last from "
                                "an increment of {:.4g}: {}). The last converged state is kept.",
                                step.name, lambda, step.min_increment, cutbacks - continuation_attempts,
                                continuation_attempts, continuation_attempts > 1 ? "s" : "", dl, why)
                  : fmt::format("step '{}' at fraction {:.6g}: {}; the increment would fall below the minimum {:.3g} "
                                "after {} cutbacks. The last converged state is kept.",
                                step.name, lambda, why, step.min_increment, cutbacks);
          summary_.total_seconds = total.seconds();
          return summary_;
        }
        if (continuation) ++continuation_attempts;
        dl = next;
        continue;
      }
      lambda += dl;
      if (1 - lambda < 1e-12) lambda = 1;
      ++inc;
      last_du_ = u_ - u_converged_;
      last_dl_ = dl;
      u_converged_ = u_;
      for (auto& h : history_) h.commit();  // partitioned: each rank its own cells
      for (auto& c : contacts_) rec.contact.push_back(c->commit());
      report_contact_pressures();
      rec.fraction = lambda;
      rec.time = s + lambda;
      rec.cutbacks = cutbacks;
      rec.failed_iterations = failed_iterations;
      rec.seconds = t.seconds();
      rec.stabilization_ratio = stab_ratio_;
      cutbacks = failed_iterations = 0;
      continuation = false;
      summary_.total_iterations += rec.iterations;
      summary_.increments.push_back(rec);
      std::string contact;
      for (auto& c : rec.contact)
        contact += c.sticking + c.slipping > 0
                       ? fmt::format("  [{}: {} closed ({} stick, {} slip), {} changed]", c.label, c.active,
                                     c.sticking, c.slipping, c.changes)
                       : fmt::format("  [{}: {} closed, {} changed]", c.label, c.active, c.changes);
      if (model_.newton.stabilization > 0)
        contact += fmt::format("  [stabilization |f_v|/F {:.2e}]", rec.stabilization_ratio);
      if (rec.pseudo_transient) contact += "  [pseudo-transient continuation]";
      log::info("step {} '{}'  inc {:3d}  fraction {:.4f} (+{:.4g})  iters {:2d}  |R|/F {:.2e}  {:.2f} s  [{:.1f} s]{}",
                s + 1, step.name, inc, lambda, dl, rec.iterations, rec.residuals.back(), rec.seconds,
                log::elapsed(), contact);
      // Which contact nodes changed status (open/closed, stick/slip), by mesh node id.
      for (auto& c : rec.contact)
        if (!c.changed_nodes.empty()) {
          std::string ids;
          for (size_t k = 0; k < c.changed_nodes.size() && k < 12; ++k)
            ids += fmt::format("{}{}", k ? ", " : "", model_.mesh.node_ids[c.changed_nodes[k]]);
          log::info("    {}: status changed at node{} {}{}{}", c.label, c.changed_nodes.size() > 1 ? "s" : "", ids,
                    c.changed_nodes.size() > 12 ? fmt::format(" and {} more", c.changed_nodes.size() - 12) : "",
                    c.stick_slip_changes ? fmt::format(" ({} stick/slip)", c.stick_slip_changes) : "");
        }
      if (rec.iterations <= model_.newton.easy_iterations)
        dl = std::min(dl * model_.newton.growth_factor, step.max_increment);
      if (observer_) observer_(*this, rec);
    }
    warn_stabilization(step);
    previous_loads_ = step.loads;
    if (step_observer_) step_observer_(*this, s);
  }
  summary_.completed = true;
  summary_.total_seconds = total.seconds();
  return summary_;
}

namespace {
constexpr char kRestartMagic[] = "SIGNORINI-RESTART-1\n";
}

void Analysis::write_restart(const std::string& path) const {
  using namespace binary;
  std::ostringstream os(std::ios::binary);
  os.write(kRestartMagic, sizeof(kRestartMagic) - 1);
  put<std::int32_t>(os, step_ + 1);  // steps completed
  put<std::int64_t>(os, model_.mesh.num_nodes());
  put<std::int64_t>(os, static_cast<std::int64_t>(model_.steps.size()));
  put_vec(os, u_converged_);
  put_vec(os, last_du_);
  put<Real>(os, last_dl_);
  put<std::int64_t>(os, static_cast<std::int64_t>(history_.size()));
  for (const auto& h : history_) {
    // Partitioned over MPI ranks each rank holds its own cells' history: summed into the
    // whole layout (zeros elsewhere, so every cell gets its owner's bits).
    std::vector<Real> whole = h.whole_committed();
    if (!owned_cells_.empty() && !whole.empty()) backend_->sum_over_ranks(whole.data(), static_cast<Index>(whole.size()));
    put_vector(os, whole);
  }
  put<std::int64_t>(os, static_cast<std::int64_t>(contacts_.size()));
  for (const auto& c : contacts_) c->save(os);
  // Rank 0 writes; its failure stops every rank alike (collective).
  std::string failure;
  if (rank() == 0) try {
      write_file_atomically(path, os.str());
    } catch (const Error& e) {
      failure = e.what();
    }
  if (ranks() > 1 ? any_rank_failed(failure) : !failure.empty()) throw Error(failure);
}

void Analysis::read_restart(const std::string& path) {
  using namespace binary;
  std::ifstream is(path, std::ios::binary);
  if (!is) throw InputError(path, "--restart", "cannot open the restart file");
  try {
    std::string magic(sizeof(kRestartMagic) - 1, '\0');
    if (!is.read(magic.data(), static_cast<std::streamsize>(magic.size())) || magic != kRestartMagic)
      throw Error("not a Signorini restart file (version 1)");
    const auto done = get<std::int32_t>(is);
    const auto nodes = get<std::int64_t>(is);
    const auto steps = get<std::int64_t>(is);
    if (nodes != model_.mesh.num_nodes())
      throw Error(fmt::format("written for a mesh of {} nodes, this deck's has {}", nodes, model_.mesh.num_nodes()));
    if (steps != static_cast<std::int64_t>(model_.steps.size()) || done < 1 || done > steps)
      throw Error(fmt::format("written after step {} of {}, this deck has {} steps", done, steps, model_.steps.size()));
    VecX u = get_vec(is, num_unknowns(), "unknowns");
    VecX du = get_vec(is, -1, "last increment");
    const Real dl = get<Real>(is);
    if (get<std::int64_t>(is) != static_cast<std::int64_t>(history_.size())) throw Error("the bodies differ");
    std::vector<std::vector<Real>> hist;
    for (const auto& h : history_)
      hist.push_back(get_vector<Real>(is, static_cast<std::int64_t>(h.whole_size()), "history"));
    if (get<std::int64_t>(is) != static_cast<std::int64_t>(contacts_.size())) throw Error("the contact pairs differ");
    for (auto& c : contacts_) c->load(is);
    if (is.peek() != std::char_traits<char>::eof()) throw Error("unexpected data at the end");
    u_ = u_converged_ = u;
    last_du_ = du.size() == u.size() ? du : VecX::Zero(u.size());
    last_dl_ = dl;
    for (size_t i = 0; i < history_.size(); ++i) history_[i].restore(hist[i]);
    first_step_ = done;
    step_ = done - 1;
    log::info("restart: continuing after step {} '{}' from {}", done, model_.steps[done - 1].name, path);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    throw InputError(path, "--restart", std::string("cannot restart from it: ") + e.what());
  }
}

Vec3 Analysis::reaction_sum(const std::string& node_set) const {
  Vec3 r = Vec3::Zero();
  auto it = model_.mesh.node_sets.find(node_set);
  if (it == model_.mesh.node_sets.end()) return r;
  std::vector<Index> seen;  // the nodes of a rigid body share their DOFs: count each once
  for (Index node : it->second)
    for (int i = 0; i < dofs_.dofs_per_node(); ++i) {
      Index d = dofs_.dof(node, i);
      if (d < 0) continue;
      if (dofs_.shared(node)) {
        if (std::find(seen.begin(), seen.end(), d) != seen.end()) continue;
        seen.push_back(d);
      }
      r(i) += reactions_(d);
    }
  return r;
}

Real Analysis::force_norm(const VecX& v, bool moments) const {
  if (moment_rows_.empty()) return v.norm();
  Real s = v.squaredNorm();
  for (auto [i, w] : moment_rows_)
    if (i < v.size()) s += ((moments ? w * w : 0.0) - 1) * v(i) * v(i);
  return std::sqrt(std::max(s, Real(0)));
}

Vec3 Analysis::obstacle_reaction(const ContactInterface& c) const {
  Vec3 r = Vec3::Zero();
  for (int i = 0; i < std::min<Index>(c.num_obstacle_dofs(), model_.settings.spatial_dim()); ++i)
    r(i) = reactions_(c.obstacle_dofs() + i);
  return r;
}

Vec3 Analysis::obstacle_displacement(const ContactInterface& c) const {
  Vec3 r = Vec3::Zero();
  for (int i = 0; i < std::min<Index>(c.num_obstacle_dofs(), model_.settings.spatial_dim()); ++i)
    r(i) = u_(c.obstacle_dofs() + i);
  return r;
}

Vec3 Analysis::obstacle_moment(const ContactInterface& c) const {
  const int sd = model_.settings.spatial_dim();
  return c.num_obstacle_dofs() > sd ? moment_of(c.obstacle_dofs() + sd, c.num_obstacle_dofs() - sd) : Vec3::Zero();
}

Vec3 Analysis::obstacle_rotation(const ContactInterface& c) const {
  const int sd = model_.settings.spatial_dim();
  return c.num_obstacle_dofs() > sd ? rotation_of(c.obstacle_dofs() + sd, c.num_obstacle_dofs() - sd) : Vec3::Zero();
}

Vec3 Analysis::body_rotation(const std::string& body) const {
  for (size_t k = 0; k < turning_bodies_.size(); ++k)
    if (model_.bodies[turning_bodies_[k]]->name() == body) return rotation_of(rotations_.dof[k], rotations_.angles);
  return Vec3::Zero();
}

Vec3 Analysis::body_moment(const std::string& body) const {
  for (size_t k = 0; k < turning_bodies_.size(); ++k)
    if (model_.bodies[turning_bodies_[k]]->name() == body) return moment_of(rotations_.dof[k], rotations_.angles);
  return Vec3::Zero();
}

std::vector<std::string> Analysis::reaction_sets() const {
  std::vector<std::string> v;
  for (auto& d : model_.steps[step_].dirichlet)
    if (std::find(v.begin(), v.end(), d.set) == v.end()) v.push_back(d.set);
  return v;
}

std::string oversized_displacement(const Analysis& a) {
  const Model& m = a.model();
  if (m.settings.finite_strain || m.mesh.nodes.empty()) return "";
  Vec3 lo = m.mesh.nodes[0], hi = lo;
  for (const Vec3& x : m.mesh.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Real size = (hi - lo).norm();
  Real umax = 0;
  Index at = -1;
  const DofMap& d = a.dofs();
  for (Index n = 0; n < m.mesh.num_nodes(); ++n) {
    if (!d.has_dofs(n)) continue;
    Real u2 = 0;
    for (int c = 0; c < d.dofs_per_node(); ++c) u2 += std::pow(a.displacement()(d.dof(n, c)), 2);
    if (!(std::sqrt(u2) <= umax)) umax = std::sqrt(u2), at = n;  // NaN counts as large
  }
  if (at < 0 || umax <= size) return "";
  return fmt::format("the largest displacement, {:.3g} at node {}, is larger than the model ({:.3g} across): a "
                     "small-strain answer is then meaningless; check the magnitude and units of the loads and "
                     "prescribed displacements",
                     umax, m.mesh.node_ids[at], size);
}

}  // namespace signorini

