// The nonlinear quasi-static analysis: load steps split into increments (automatic cutback
// on failure, growth on easy convergence), each solved by Newton-Raphson with a
// backtracking line search. It owns the iteration state, the material history of every
// body's quadrature points included; the Model stays read-only.
#pragma once
#include <cstdlib>
#include <map>
#include <functional>
#include <string>
#include <vector>

#include "signorini/contact/contact_interface.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/rank_exchange.hpp"
#include "signorini/fem/boundary_traction.hpp"
#include "signorini/fem/dof_map.hpp"
#include "signorini/fem/global_system.hpp"
#include "signorini/fem/model.hpp"
#include "signorini/fem/surface_load.hpp"
#include "signorini/solver/backend.hpp"

namespace signorini {

// SIGINT/SIGTERM received (core/interrupt.hpp): the run stops at the last converged increment.
class Interrupted : public std::exception {
 public:
  explicit Interrupted(int s) : signal(s) {}
  const char* what() const noexcept override { return "interrupted"; }
  int signal;
};

struct IncrementRecord {
  int step = 0;              // 0-based
  int increment = 0;         // 1-based within the step
  Real fraction = 0;         // load fraction of the step reached
  Real time = 0;             // pseudo-time: step index + fraction
  int iterations = 0;
  int cutbacks = 0;          // failed attempts before this converged increment
  int failed_iterations = 0; // Newton iterations spent in those failed attempts
  std::vector<Real> residuals;  // relative residual norm per iteration (first: before solving)
  std::vector<Real> energies;   // |du . R| per iteration
  double seconds = 0;
  std::string linear_solver;
  std::string linear_method;           // its method and preconditioner in words (the last solve's)
  std::vector<int> krylov_iterations;  // per Newton iteration (iterative linear solvers)
  std::vector<Real> krylov_rtol;       // per Newton iteration: the forcing term asked (0: the configured rtol)
  std::vector<int> status_changes;     // per Newton iteration: contact statuses its step changed
  std::vector<ContactStats> contact;  // per contact interface
  int uzawa_updates = 0;              // augmented Lagrangian multiplier updates
  // Stabilization (solver.stabilization): |f_v| at convergence, relative to the largest of
  // |f_int| and |f_ext|.
  Real stabilization_ratio = 0;
  // Accepted on stagnation: Newton cycled at a residual within 1e-4 of the force scale that it
  // could not reduce (a jump of the residual; analysis.cpp, solve_increment).
  bool stagnated = false;
  Real stagnated_residual = 0;  // the relative residual accepted
  // Converged by pseudo-transient continuation (the last resort at a limit point).
  bool pseudo_transient = false;
};

struct AnalysisSummary {
  bool completed = false;
  std::string failure;       // why the analysis gave up
  std::vector<IncrementRecord> increments;
  int total_iterations = 0;       // Newton iterations of the converged increments
  int failed_iterations = 0;      // Newton iterations of the attempts that were cut back
  bool interrupted = false;       // stopped by SIGINT/SIGTERM (the state is the last converged one)
  double assembly_seconds = 0, solve_seconds = 0, total_seconds = 0;
  double contact_seconds = 0;  // detection, constraints and enforcement (not in assembly_seconds)
  // Tangent evaluations, and how many of them assembled the tangent of the bodies whose
  // internal force is linear in u (the others put back the one kept: Analysis::evaluate).
  int tangent_evaluations = 0, linear_tangent_assemblies = 0;
  int first_step = 0;          // > 0: continued from a restart file written after that many steps
  // What a completed run should be read with (logged as warnings where they arise; main repeats
  // them after its last line): a step that ended with the stabilizing force above 1 % of the
  // force scale (its state is an equilibrium with that artificial force, not the model's).
  std::vector<std::string> warnings;
};

// The deck's linear solver settings with what the analysis decides for them (GAMG's
// prolongator smoothing: plain aggregation under adaptive forcing).
LinearSolverSettings solver_settings(const Model& model);

class Analysis {
 public:
  explicit Analysis(Model& model);

  // Called after every converged increment (to write results) with the record.
  void on_increment(std::function<void(const Analysis&, const IncrementRecord&)> f) { observer_ = std::move(f); }
  // Called after every completed step (0-based index), e.g. to write a restart file.
  void on_step(std::function<void(const Analysis&, int)> f) { step_observer_ = std::move(f); }
  // Restart files (output: {restart: every_step}): the state after a completed step, in a
  // binary file of this model (unknowns, the predictor's last increment, the bodies'
  // quadrature-point history, each contact pair's per-node records). read_restart, before
  // run(), continues from it: the steps before it are skipped. Throws InputError (with the
  // file) when the file is not a restart file of this model. Under MPI write_restart is
  // collective (each rank gives its own cells' history; rank 0 writes the file).
  void write_restart(const std::string& path) const;
  void read_restart(const std::string& path);
  int first_step() const { return first_step_; }  // steps a restart skipped (0: none)
  // Runs every step; never throws for a problem the analysis can diagnose: the summary says
  // completed, or why it gave up (the state is then the last converged one).
  AnalysisSummary run();

  const Model& model() const { return model_; }
  const DofMap& dofs() const { return dofs_; }
  // How the algebra is shared between MPI ranks: "serial", or a sentence (main prints it).
  const std::string& algebra() const { return algebra_; }
  // Whether the Newton systems are ones a Cholesky factorization (or CG) takes: symmetric, or
  // symmetric bodies with contact multipliers the condensation removes (no Lagrange friction).
  // The deck reader decides the same from the Model alone (unsymmetric_tangent_reasons, to name
  // the key and line); tests/verification/test_hertz.cpp holds the two together on every example.
  bool symmetric_solves() const;
  // How the ranks share the contact evaluation out (summary.json; the log under mpirun):
  // "no contact pair", "one process", or with several ranks which pairs' evaluation each rank
  // does a share of.
  std::string contact_evaluation() const;
  // Partitioned assembly under mpirun: this rank, the number of ranks, and per block of body
  // `b` the cells this rank owns (null when the cells are not shared out: one rank, or the
  // algebra replicated).
  int rank() const;
  int ranks() const;
  const std::vector<std::vector<char>>* owned_cells(size_t b) const {
    return owned_cells_.empty() ? nullptr : &owned_cells_[b];
  }
  // Partitioned: the nodes that no cell of the whole mesh uses (each rank holds its own cells
  // only; a rigid body's reference node, say), ascending; null when the cells are not shared out.
  const std::vector<Index>* cellless_nodes() const { return owned_cells_.empty() ? nullptr : &cellless_nodes_; }
  // Collective under mpirun (every rank calls it at the same point): whether any rank reports
  // a failure (its `message` not empty); the lowest such rank's message is then in `message`
  // on every rank. One rank: whether `message` is not empty.
  bool any_rank_failed(std::string& message) const;
  // The signal (SIGINT, SIGTERM) that asked the run to stop, if any rank has received one;
  // collective under mpirun. 0: none.
  int interrupt_on_any_rank() const;
  // Unknowns: the displacement DOFs, then the contact multipliers.
  Index num_unknowns() const { return static_cast<Index>(u_.size()); }
  const std::vector<std::unique_ptr<ContactInterface>>& contacts() const { return contacts_; }
  // The quadrature-point history of body i (model order), committed at each converged increment.
  const QuadratureHistory& history(size_t i) const { return history_[i]; }
  // Current positions X + u of every node.
  std::vector<Vec3> positions(const VecX& u) const;
  const VecX& displacement() const { return u_; }
  // Reaction forces (fint - fext) at the DOFs constrained in the current step, 0 elsewhere.
  const VecX& reactions() const { return reactions_; }
  const std::vector<char>& constrained() const { return constrained_; }
  const AnalysisSummary& summary() const { return summary_; }
  int current_step() const { return step_; }
  // Sum of reactions over a node set (x, y, z).
  Vec3 reaction_sum(const std::string& node_set) const;
  // Reaction on a rigid obstacle's prescribed or held components, and its displacement.
  Vec3 obstacle_reaction(const ContactInterface& c) const;
  Vec3 obstacle_displacement(const ContactInterface& c) const;
  // A turning obstacle: the reaction moment on its rotation when the rotation is prescribed or
  // held, and the rotation (plane problems: the angle about z as the z component; 3D: the
  // rotation vector, and the moment T^-T f of the angles' generalized reaction f,
  // geometry/rotation.hpp). Zero for an obstacle that does not turn.
  Vec3 obstacle_moment(const ContactInterface& c) const;
  Vec3 obstacle_rotation(const ContactInterface& c) const;
  // A turning meshed rigid body: the same for its rotation about its reference node.
  Vec3 body_rotation(const std::string& body) const;
  Vec3 body_moment(const std::string& body) const;
  // The turning rigid bodies (model order indices) and their angles' unknowns.
  const std::vector<size_t>& turning_bodies() const { return turning_bodies_; }
  // Whether mesh node n follows a turning rigid body (its cells' nodes and reference nodes).
  bool node_turns(Index n) const { return !turning_bodies_.empty() && rotations_.body_of_node[static_cast<size_t>(n)] >= 0; }
  // The node sets that carry a Dirichlet condition in the current step, in deck order.
  std::vector<std::string> reaction_sets() const;
  // An unknown in the user's words, for the messages that point at one (the largest residual
  // of a failed increment): "mesh node 812, u_x", a pair's normal or tangential multiplier and
  // its slave node, a rigid obstacle's displacement, a turning body's angle.
  std::string describe_unknown(Index unknown) const;

 private:
  struct Prescribed {
    Index dof;
    Real start, end;
    Real value(Real lambda) const { return start + lambda * (end - start); }  // at step fraction lambda
  };
  // Residual (fext - fint, zero at constrained DOFs) at u for the step fraction lambda;
  // assembles the tangent too if asked. Returns the force scale for the relative test.
  Real evaluate(Real lambda, bool tangent, VecX& residual);
  // The Euclidean norm with each turning obstacle's moment row divided by its length
  // (moment_rows_): forces and moments in one measure; without `moments`, those rows left out.
  Real force_norm(const VecX& v, bool moments = true) const;
  std::vector<std::pair<Index, Real>> moment_rows_;  // (unknown, 1 / length)
  RigidRotations rotations_;             // turning meshed rigid bodies (ContactInterface reads it)
  std::vector<size_t> turning_bodies_;   // their model indices, in rotations_'s order
  // Adds c to the diagonal of every free displacement row of the global matrix.
  void add_free_diagonal(Real c);
  Real add_stabilization(VecX& fint, bool tangent);
  // At a step's end: a warning (log and summary) when the stabilizing force is above 1 % of the force scale.
  void warn_stabilization(const Step& step);
  // `cell_loads` (partitioned assembly): where the body forces go, from this rank's own cells
  // (summed over the ranks by the caller); null: into fext.
  void add_loads(const std::vector<Load>& loads, Real scale, VecX& fext, bool tangent, VecX* cell_loads = nullptr);
  void share_out_cells();
  // A moment M on the n angles from unknown `first`: its generalized force T^T M and, in 3D
  // with `tangent`, minus its derivative in the angles into the matrix.
  void add_moment(Index first, int n, const Vec3& M, Real scale, VecX& fext, bool tangent);
  // The moment T^-T f of the generalized reaction f on the n angles from unknown `first`.
  Vec3 moment_of(Index first, int n) const;
  Vec3 rotation_of(Index first, int n) const;
  AnalysisSummary run_steps();
  void detect_contact(Real max_step);
  // Output pressures from the nodal contact forces of each pair (both passes together).
  void report_contact_pressures();
  // Rebuilds the sparse pattern from the cells and the contact couplings.
  void choose_algebra();
  // Throws an InputError at solver.linear when the deck names a solver for symmetric systems
  // (is_symmetric_only_solver) and the solves are unsymmetric.
  void refuse_symmetric_only_solver() const;
  // For the failure of a first solve without supports: a hint when no contact constraint is
  // closed (a body held only by its contact), naming the open pairs; empty otherwise.
  std::string open_contact_hint() const;
  void rebuild_pattern();
  void begin_step(int s);
  // One increment, to the step fraction lambda from the last converged state (size dl), in
  // named steps: predict, begin_contact_increment, then Newton iterations (solve_newton_step,
  // line_search, the contact status count) until the residual converges and
  // after_convergence accepts. False with `why` when it fails (the caller cuts back).
  bool solve_increment(Real lambda, Real dl, IncrementRecord& rec, std::string& why, bool pseudo_transient = false);
  // The state of one increment's Newton iterations.
  struct NewtonState {
    Real scale = 0, rnorm = 0, energy0 = 0;
    int cycle_start = 1;        // first iteration of the current cycle (after a Uzawa update or a release)
    int uzawa = 0;              // Uzawa rounds
    int released_rounds = 0;    // rounds of held-closed nodes released in tension
    bool polished = false;      // the chattering guard's holds were released once after convergence
    std::vector<int> augmentations;  // Uzawa updates per pair
    std::vector<std::vector<char>> statuses;  // contact statuses of the budget's last three iterations
  };
  enum class AfterConvergence { accept, iterate, fail };
  // The predictor: u from the last converged state along the last increment of the step.
  void predict(Real dl);
  // Contact detection on the predicted configuration, slip origins, the sparse pattern.
  void begin_contact_increment(Real lambda);
  // The Newton step du from J du = R (condensed contact multipliers when possible); throws
  // FatalModelError for a model without supports.
  void solve_newton_step(int it, const NewtonSettings& ns, const VecX& R, VecX& du, IncrementRecord& rec);
  // The relative tolerance a Krylov solve of this Newton iteration is asked for (0: the deck's).
  Real forcing_term(int it, const NewtonSettings& ns, const IncrementRecord& rec) const;
  Real last_forcing_ = 0;  // the last solve's, for the iteration log
  bool linear_bodies_ = false;  // a body's internal force is linear in u (evaluate keeps its tangent)
  // Scales a Newton step whose turn of a rigid body or obstacle (its free angles) exceeds
  // 0.1 rad down to that.
  void limit_turn(VecX& du) const;
  // u = u0 + alpha du with backtracking on |R|; returns alpha (Rtrial: the residual there).
  Real line_search(Real lambda, const NewtonSettings& ns, const VecX& u0, const VecX& du, Real rnorm, VecX& Rtrial,
                   Real& new_scale, Real& new_norm, const std::vector<char>* statuses = nullptr,
                   const std::vector<std::vector<Real>>* penetrations = nullptr);
  // Every contact pair's slave penetrations at the last evaluation (the step's start).
  std::vector<std::vector<Real>> contact_penetrations() const;
  // Every contact pair's statuses (closed, and stick/slip), concatenated.
  std::vector<char> contact_statuses() const;
  // Once the residual has converged: the chattering guard's checks and release, the
  // augmented Lagrangian's Uzawa updates; accept, iterate on, or fail (with `why`).
  AfterConvergence after_convergence(NewtonState& st, IncrementRecord& rec, std::string& why);
  // Diagnostics of SIGNORINI_CHECK_TANGENT: each slave node's contact constraints (kind,
  // facet, gap, closed, slip) as text, from the last evaluation; the tangent along the Newton
  // step du from u0 against central differences of the residual, logged.
  std::map<Index, std::string> contact_view() const;
  void check_tangent(Real lambda, const VecX& u0, const VecX& du, Real du_max);
  // The mesh node whose displacement `unknown` is (-1: none).
  Index node_of_unknown(Index unknown) const;
  // Where the largest free entry of the residual r sits, for a failed increment's message.
  std::string largest_residual(const VecX& r) const;

  Model& model_;
  DofMap dofs_;
  std::unique_ptr<AlgebraBackend> backend_;  // the global tangent, its pattern and the Newton solve
  // Under mpirun with a PETSc solver: how the ranks share the algebra ("partitioned": each
  // assembles its own cells into its rows of one distributed matrix; "replicated": each
  // assembles the whole system, PETSc distributes the solve: only for a solver PETSc does not
  // distribute, which the deck check refuses under mpirun), and why when replicated.
  std::string algebra_ = "serial";
  // Per body and block, whether this rank assembles each cell (partitioned assembly only).
  std::vector<std::vector<std::vector<char>>> owned_cells_;
  // Partitioned assembly: the whole mesh's facts kept when each rank dropped the other
  // ranks' cells (share_out_cells): each body's nodes, sorted, and the nodes in no cell.
  std::vector<std::vector<Index>> body_nodes_;
  std::vector<Index> cellless_nodes_;
  std::vector<char> is_multiplier_;  // per unknown
  bool has_multipliers_ = false;
  bool symmetric_ = true;
  bool body_symmetric_ = true;        // symmetric apart from contact multipliers
  bool factor_assessed_ = false;      // rebuild_pattern: AlgebraBackend::assess_factor called
  // Stabilization: the stiffness scale D (set at the first tangent), the current increment
  // dl, and |f_v| / F at the last evaluation.
  Real stab_scale_ = 0, stab_dl_ = 0, stab_ratio_ = 0;
  Real ptc_shift_ = 0;  // pseudo-transient continuation: the shift on the free displacement rows' diagonal
  VecX u_predicted_;  // the increment's starting state (the predictor's)
  // SIGNORINI_CHECK_TANGENT=1: log the tangent against central differences along each Newton step.
  bool check_tangent_ = std::getenv("SIGNORINI_CHECK_TANGENT") != nullptr;
  VecX u_, u_converged_, reactions_;
  VecX last_du_;          // displacement change of the last converged increment of this step
  Real last_dl_ = 0;      // its size (0: no predictor available)
  Real dt_ = 0;           // the time of the increment being solved (its fraction times the step's time)
  std::vector<char> constrained_;
  std::vector<Prescribed> prescribed_;
  bool lift_pending_ = false;
  Real dirichlet_diagonal_ = 0;  // the diagonal of the prescribed DOFs' rows in the last tangent  // the last evaluate found prescribed DOFs short of their values
  std::vector<Load> previous_loads_;
  const std::vector<Load>* current_loads_ = nullptr;
  std::vector<FacetLoad> facet_loads_cache_;
  int step_ = 0;
  std::unique_ptr<RankExchange> rank_exchange_;  // several MPI ranks: their exchange (null: one process)
  std::vector<std::unique_ptr<ContactInterface>> contacts_;
  std::unique_ptr<BoundaryTraction> boundary_traction_;  // Nitsche's method: the bodies' stress at their boundary
  std::vector<QuadratureHistory> history_;  // per body: the material's internal variables
  std::vector<const ElementBlock*> cells_;
  std::vector<std::vector<Index>> couplings_;

  AnalysisSummary summary_;
  std::function<void(const Analysis&, const IncrementRecord&)> observer_;
  std::function<void(const Analysis&, int)> step_observer_;
  int first_step_ = 0;  // set by read_restart
};

// A small-strain answer whose displacements are larger than the model itself is meaningless
// (a load in the wrong units: 5e30 for 5). Returns the warning, naming the node, or "".
std::string oversized_displacement(const Analysis& a);

}  // namespace signorini
