// One contact pair at run time: search (global, at each increment or iteration), the
// discretization's constraints, the enforcement and its state (multipliers, active set),
// the chattering guard, and what the output needs. Two-pass node-to-segment is two
// interfaces, the second with master and slave swapped.
#pragma once
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/discretization/discretization.hpp"
#include "signorini/contact/pair_state.hpp"
#include "signorini/contact/enforcement/enforcement.hpp"
#include "signorini/contact/surface.hpp"
#include "signorini/fem/analysis_settings.hpp"

namespace signorini {

// Meshed rigid bodies that turn: a node of such a body sits at
// x = X_ref + u_ref + R(theta) (X - X_ref), its translation the body's shared DOFs and theta
// unknowns of its own (one angle about z in plane problems, a rotation vector in 3D;
// geometry/rotation.hpp). The contact constraints' derivatives in theta follow by the chain
// rule (ContactInterface::add_rigid_rotations).
struct RigidRotations {
  int angles = 1;                 // per body: 1 (plane problems) or 3 (3D)
  std::vector<int> body_of_node;  // per mesh node: the turning body (index below), or -1
  std::vector<Index> dof;         // per turning body: its first angle's unknown (then the others)
  std::vector<Vec3> ref;          // per turning body: the point it turns about (reference configuration)
  const std::vector<Vec3>* reference = nullptr;  // the mesh's reference coordinates
};

struct ContactStats {
  std::string label;
  Index active = 0;       // closed slave nodes
  Index changes = 0;      // status changes against the previous increment
  Index frozen = 0;       // nodes held closed by the chattering guard
  Real max_penetration = 0;
  Vec3 force = Vec3::Zero();  // total contact force on the slave side
  Index sticking = 0, slipping = 0;  // friction: closed nodes that stick, that slip
  Index stick_slip_changes = 0;      // friction: closed nodes that went from stick to slip or back
  std::vector<Index> changed_nodes;  // slave nodes (mesh indices) whose status changed
};

class ContactInterface {
 public:
  // `stiffness_scale`: Young's modulus of the stiffer body, for the automatic penalty.
  ContactInterface(const ContactPairSettings& s, const Mesh& mesh, const AnalysisSettings& as, Real stiffness_scale,
                   bool second_pass);

  const std::string& label() const { return label_; }
  const ContactPairSettings& settings() const { return s_; }
  bool uses_multipliers() const { return enforcement_->uses_multipliers(); }
  // Statuses per slave node (multipliers, penalty, the augmented Lagrangian; not Nitsche's points).
  bool node_statuses() const { return enforcement_->node_statuses(); }
  bool symmetric() const { return enforcement_->symmetric() && !frictional(); }
  // A friction law other than frictionless.
  bool frictional() const { return friction_ != nullptr; }
  // Lagrange: one normal multiplier per slave node, and with friction dim tangential ones
  // after all the normal ones.
  Index num_multipliers() const {
    return uses_multipliers() ? static_cast<Index>(slave_.nodes.size()) * (frictional() ? 1 + dim_ : 1) : 0;
  }
  void set_multiplier_offset(Index o) { offset_ = o; }
  Index multiplier_offset() const { return offset_; }
  bool update_each_iteration() const { return s_.update == "iteration"; }
  bool rigid() const { return s_.rigid; }
  // A rigid obstacle's displacement from its deck position is `dim` unknowns of their own,
  // numbered from `first` (prescribed, loaded by a force, or held by the analysis).
  Index num_obstacle_dofs() const { return discretization_->num_extra_dofs(); }
  void set_obstacle_dofs(Index first) { discretization_->set_extra_dofs(first); }
  Index obstacle_dofs() const { return discretization_->extra_dofs(); }

  // Meshed rigid bodies that turn (may be null: none); the analysis owns it.
  void set_rigid_rotations(const RigidRotations* r) { rotations_ = r; }
  // Nitsche's method: the enforcement needs the bodies' boundary traction, which the analysis
  // gives before the first detect (fem/boundary_traction.hpp).
  bool needs_boundary_traction() const { return enforcement_->needs_points(); }
  // Whether Newton takes full steps (Enforcement::full_steps), but Nitsche's with friction: its
  // points' friction force follows the body's own shear traction (Q = sigma_T - eps s), and full
  // steps can run away from the solution. Measured on the 3D sliding patch, tet10 punch on hex8
  // (ContactPatch3dFrictionNitsche): with full steps the press's points went from stick to slip
  // a few more at each iteration and the residual grew by 1.35 per iteration at every increment
  // size (the press is homogeneous in the load: cutbacks to 1.5e-5 changed nothing); with the
  // line search 7 iterations. The 2D press-then-shear family: 28 and 19 iterations against 25 and 22.
  bool full_newton_steps() const {
    return enforcement_->full_steps() && (enforcement_->uses_multipliers() || !frictional());
  }
  void set_boundary_traction(BoundaryTraction* t) { discretization_->set_boundary_traction(t); }
  // Several MPI ranks (null: one process): the discretization may share its evaluation out
  // (Discretization::set_rank_exchange); the exchange outlives the pair.
  void set_rank_exchange(const RankExchange* r) {
    ranks_ = r;
    discretization_->set_rank_exchange(r);
  }
  bool shares_evaluation() const { return discretization_->shares_out(); }
  // Partitioned assembly over several ranks (the Analysis calls it once, with the distributed
  // backend): Nitsche's integration points are then built and assembled by one rank each
  // (Discretization::share_points, EnforcementInput::share), the other work staying whole on
  // every rank. Returns whether this pair does so (Nitsche's method with a set exchange of two
  // ranks or more); its assemble() then adds matrix entries into rows other ranks own, which
  // the caller's backend must carry (AlgebraBackend::begin_cells), and it, build included, is
  // collective.
  bool share_points();
  bool shares_points() const { return points_shared_; }
  // Nitsche: the integration points of the last assembly (null for other methods).
  const std::vector<PointConstraint>* integration_points() const { return discretization_->integration_points(); }
  // Global search at positions x; max_step bounds the motion expected before the next search.
  void detect(const std::vector<Vec3>& x, Real max_step);
  // DOF groups the constraints may couple (for the sparse pattern).
  void couplings(const DofMap& dofs, std::vector<std::vector<Index>>& out) const;
  // At the start of an increment, at the converged state (x, z): resets the chattering guard
  // and, with friction, records each slave node's closest master material point (the origin
  // of its slip in this increment). `unmoved`: the increment's first Newton matrix is
  // assembled at (x, z) itself (no predictor moved the bodies): its friction takes the stick
  // branch at the return map's kink (EnforcementInput::stick_at_kink).
  void begin_increment(const std::vector<Vec3>& x, const VecX& z, bool unmoved = false);
  // Builds the constraints at x and adds the contact forces (and tangent) to the system.
  // fixed: per unknown, 1 if a Dirichlet condition prescribes it (may be null).
  void assemble(const std::vector<Vec3>& x, const VecX& z, const DofMap& dofs, VecX& residual, GlobalMatrix* K,
                const std::vector<char>* fixed = nullptr);
  bool augmented() const { return s_.method == "augmented_lagrangian"; }
  // Largest accepted penetration of the augmented Lagrangian (the smallest over the nodes).
  Real gap_tolerance() const;
  // After Newton converged at (x, z): true if the enforcement is satisfied; else (augmented
  // Lagrangian beyond its gap tolerance) it updates its multipliers (Uzawa), restarts the slip
  // of the sticking nodes from their contact points, and returns false.
  bool augment(const std::vector<Vec3>& x, const VecX& z, Real& max_penetration);
  // Augmented Lagrangian: Uzawa updates allowed per increment.
  int max_augmentations() const { return augmented() ? s_.max_uzawa : 0; }
  // Each open slave node's penetration max(0, -gap) at the last assembly (0 where no master
  // is within reach, NaN for a closed node): the state a Newton step starts from, for
  // penetration_growth.
  std::vector<Real> penetrations() const;
  // The largest growth of an open slave node's penetration since `before` (penetrations() at
  // the step's start), in units of the node's facet size h, and the mesh id of that node.
  std::pair<Real, Index> penetration_growth(const std::vector<Real>& before) const;
  // After an accepted Newton iterate: count status changes (chattering guard).
  void count_status_changes();
  // Friction with the penalty or the augmented Lagrangian: ends the stick predictor (nodes that
  // close in this increment stick while the normal statuses change) after an accepted iterate
  // whose normal statuses held, whose line-search `step` was kStickPredictorStep or less (not
  // at the `first_iteration`), or whose residual has `converged`; returns how many nodes it
  // held in stick outside their friction disc (their residual changes when it ends).
  Index end_stick_predictor(bool converged, Real step, bool first_iteration);
  // At the last accepted iterate: closed slave nodes, and how many closed and opened in it;
  // with friction and node statuses (multipliers, penalty, the augmented Lagrangian), the
  // closed nodes that slip, and how many of the nodes closed before and after turned to slip
  // and to stick in it (the Newton log's "[N closed +a -b, S slip +c -d]").
  struct IterateStatus {
    Index closed = 0, newly_closed = 0, newly_opened = 0;
    Index slipping = 0, to_slip = 0, to_stick = 0;
  };
  const IterateStatus& iterate_status() const { return iterate_status_; }
  // After convergence: a node held closed that ends in tension is held open instead
  // (returns how many; Newton must go on then).
  Index fix_held_nodes();
  // Holds closed the slave nodes whose gap is in (0, 1e-6 h] (h: their facet size) at
  // positions x, for the increment: "touching" whose sign is the discretization's, not the
  // geometry's (mortar's weighted gap of a node at the contact point of a curved body is of
  // that size, either sign). Node-based statuses only (multipliers, penalty, the augmented
  // Lagrangian; not Nitsche's points). Penalty and the augmented Lagrangian: only when no
  // constraint has g <= 0, and closed without adhesion while touching (Hold::touching).
  // Returns how many.
  Index hold_touching(const std::vector<Vec3>& x, const VecX& z);
  // After convergence with nodes held by the chattering guard: releases the holds the state
  // does not satisfy exactly (returns how many); a released node is held again at its next
  // status change.
  Index release_holds();
  // Held nodes whose final state violates the contact conditions (the increment is then not
  // a solution and is cut back): closed in tension, open and penetrating, or held in stick
  // (slip) with the trial traction outside (inside) the friction disc by more than 2 % of
  // its radius.
  Index frozen_in_tension() const;
  // After a converged increment: statistics against the previous increment.
  ContactStats commit();
  // The total contact force on the slave side at the last assembly.
  Vec3 slave_force() const;

  // The state of each slave node for output (the numbers are the output's status codes).
  enum Status : int { far = 0, open = 1, closed = 2, slipping = 3 };  // closed: sticking, with friction
  struct SlaveState {
    Index node;
    int status;     // Status
    Real gap;       // NaN when no master is within reach
    Real pressure;  // positive in compression
    Vec3 traction = Vec3::Zero();   // friction: tangential traction on the slave
    Real slip_increment = 0;        // friction: |tangential slip| in the last increment
    Real slip_accumulated = 0;      // friction: sum of the slip increments
  };
  std::vector<SlaveState> slave_states() const;
  // Adds the force each constraint puts on its nodes (its multiplier, or penalty force, times
  // the gap gradient) to f, indexed by mesh node.
  void add_nodal_forces(std::vector<Vec3>& f) const;
  // The pressure reported for output: the normal contact force on each slave node from all the
  // constraints of its pair (both passes of a two-pass pair), per unit tributary area. With one
  // pass this is the multiplier per area; with two passes a node also carries the other pass's
  // constraints as a master node, and the multipliers alone split the pressure between passes.
  void set_reported_pressure(const std::vector<Vec3>& nodal_force);

  // Restart files: the per-node records (committed statuses, multiplier shifts, friction
  // tractions, slip origins and records) written and read back; load throws Error when the
  // file's pair does not match this one.
  void save(std::ostream& os) const;
  void load(std::istream& is);

  const SlaveSurface& slave() const { return slave_; }
  const ConstraintSet& constraints() const { return constraints_; }
  const EnforcementOutput& state() const { return state_; }

 private:
  ContactPairSettings s_;
  std::string label_;
  int dim_;
  const std::vector<Index>* node_ids_;  // the mesh's node ids, for messages (the mesh outlives the pair)
  SlaveSurface slave_;
  std::unique_ptr<Discretization> discretization_;
  std::unique_ptr<Enforcement> enforcement_;
  std::unique_ptr<FrictionLaw> friction_;
  Real mean_master_edge_ = 0;
  Real dmax_ = 0;
  Index offset_ = -1;
  ConstraintSet constraints_;
  EnforcementOutput state_;       // of the last assembly
  std::vector<NodeRecord> nodes_;  // per slave node
  IterateStatus iterate_status_;
  Index frozen_reported_ = 0;
  std::vector<char> is_slave_;  // per mesh node: a slave node of this pair (pass)
  bool pressure_reported_ = false;  // set_reported_pressure was called (else the multipliers are reported)
  static constexpr Real kHeldFrictionTolerance = 0.02;     // of the bound
  // Lagrange friction, the automatic c_T = this x E / h: for a node open at the increment's start
  // (closing: the stick/slip decision follows the traction), for one closed at it (sliding: the
  // slip weighs as much as the traction it makes); begin_increment.
  static constexpr Real kTangentialComplementarity = 0.1;
  static constexpr Real kTangentialComplementaritySliding = 1.0;
  // The stick predictor ends after a step the line search cut to this or less, beyond the
  // first iteration (measured: Klang's pin has 1/16 at its second iteration and needs it
  // ended; the friction grid's press has full steps there and needs it; end_stick_predictor).
  static constexpr Real kStickPredictorStep = 0.125;
  Real friction_violation(size_t j) const;
  void build_constraints(const std::vector<Vec3>& x, const VecX& z);
  const RigidRotations* rotations_ = nullptr;
  // Appends to c the angle of each turning rigid body among its nodes: grad, hess,
  // normal_jacobian and (friction) slip_jacobian and slip_hessian by the chain rule through
  // x_k(theta): dx/dtheta = J R d, d2x/dtheta2 = -R d, d = X_k - X_ref.
  void add_rigid_rotations(Constraint& c, const VecX& z) const;
  bool stick_predictor_ = false;  // friction: the stick predictor is on (end_stick_predictor)
  bool stick_at_kink_ = false;    // friction: the next Newton matrix is the first of an unmoved increment
  const RankExchange* ranks_ = nullptr;  // several MPI ranks (null: one process)
  bool points_shared_ = false;           // share_points()
};

}  // namespace signorini
