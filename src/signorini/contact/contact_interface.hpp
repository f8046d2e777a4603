// One contact pair at run time: search (global, at each increment or iteration), the
// discretization's constraints, the enforcement and its state (multipliers, active set),
// the chattering guard, and what the output needs. Two-pass node-to-segment is two
// interfaces, the second with master and slave swapped.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/enforcement/enforcement.hpp"
#include "signorini/contact/search/search.hpp"
#include "signorini/contact/surface.hpp"
#include "signorini/fem/analysis_settings.hpp"

namespace signorini {

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
  // Penalty (or complementarity constant) of each slave node.
  const std::vector<Real>& stiffness() const { return stiffness_; }
  bool update_each_iteration() const { return s_.update == "iteration"; }
  bool rigid() const { return s_.rigid; }
  // A rigid obstacle's displacement from its deck position is `dim` unknowns of their own,
  // numbered from `first` (prescribed, loaded by a force, or held by the analysis).
  Index num_obstacle_dofs() const { return s_.rigid ? dim_ : 0; }
  void set_obstacle_dofs(Index first) { obstacle_dofs_ = first; }
  Index obstacle_dofs() const { return obstacle_dofs_; }

  // Global search at positions x; max_step bounds the motion expected before the next search.
  void detect(const std::vector<Vec3>& x, Real max_step);
  // DOF groups the constraints may couple (for the sparse pattern).
  void couplings(const DofMap& dofs, std::vector<std::vector<Index>>& out) const;
  // At the start of an increment, at the converged state (x, z): resets the chattering guard
  // and, with friction, records each slave node's closest master material point (the origin
  // of its slip in this increment).
  void begin_increment(const std::vector<Vec3>& x, const VecX& z);
  // Builds the constraints at x and adds the contact forces (and tangent) to the system.
  // fixed: per unknown, 1 if a Dirichlet condition prescribes it (may be null).
  void assemble(const std::vector<Vec3>& x, const VecX& z, const DofMap& dofs, VecX& residual, GlobalMatrix* K,
                const std::vector<char>* fixed = nullptr);
  bool augmented() const { return s_.method == "augmented_lagrangian"; }
  // Largest accepted penetration of the augmented Lagrangian (the smallest over the nodes).
  Real gap_tolerance() const;
  // Augmented Lagrangian, after Newton converged: true if the penetration is within the
  // tolerance; else the multipliers are updated (Uzawa) and false returned.
  bool uzawa_update(Real& max_penetration);
  // After an accepted Newton iterate: count status changes (chattering guard).
  void count_status_changes();
  // After convergence: a node held closed that ends in tension is held open instead
  // (returns how many; Newton must go on then).
  Index fix_held_nodes();
  // Held nodes whose final state violates the contact conditions (the increment is then not
  // a solution and is cut back): closed in tension, open and penetrating, or held in stick
  // (slip) with the trial traction outside (inside) the friction disc by more than 2 % of
  // its radius.
  Index frozen_in_tension() const;
  // After a converged increment: statistics against the previous increment.
  ContactStats commit();

  // The state of each slave node for output: 0 no master within reach, 1 open, 2 closed.
  struct SlaveState {
    Index node;
    int status;     // 0 far, 1 open, 2 closed (stick, with friction), 3 slip
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

  const SlaveSurface& slave() const { return slave_; }
  const ConstraintSet& constraints() const { return constraints_; }
  const EnforcementOutput& state() const { return state_; }

 private:
  ContactPairSettings s_;
  std::string label_;
  AnalysisSettings as_;
  int dim_;
  const std::vector<Index>* node_ids_;  // the mesh's node ids, for messages (the mesh outlives the pair)
  MasterSurface master_;
  SlaveSurface slave_;
  std::unique_ptr<ContactSearch> search_;
  std::unique_ptr<Enforcement> enforcement_;
  SearchFacets facets_;
  std::vector<Real> stiffness_, node_size_;  // per slave node: penalty, local facet size
  Real mean_master_edge_ = 0;
  Index offset_ = -1;
  std::vector<Index> candidate_;          // per slave node: master facet (NTS) or node (NTN)
  std::vector<Vec3> nts_normal_;          // NTN: frozen normals
  ConstraintSet constraints_;
  EnforcementOutput state_;
  std::vector<char> last_active_, committed_active_;
  std::vector<int> flips_;
  std::vector<signed char> forced_;
  Index frozen_reported_ = 0;
  Index obstacle_dofs_ = -1;
  std::vector<Real> shift_, shift_committed_;  // augmented Lagrangian multipliers
  std::vector<Real> reported_pressure_;        // per slave node, see set_reported_pressure
  // Friction: the law, the tangential penalty, and per slave node the slip origin (master
  // nodes and weights, or a point relative to a rigid obstacle's offset), the committed
  // traction and the slip record.
  std::unique_ptr<FrictionLaw> friction_;
  std::vector<Real> tangential_stiffness_;
  std::vector<std::vector<std::pair<Index, Real>>> origin_;
  std::vector<Vec3> origin_point_;
  std::vector<char> has_origin_;
  std::vector<Vec3> traction_old_, traction_committed_;
  std::vector<signed char> committed_friction_;  // per slave node: 0 open, 1 stick, 2 slip
  // Chattering guard of the stick/slip status (as flips_/forced_ for open/closed): flips of
  // a closed node's status in this increment, the status of the last iterate, and the hold
  // (0 none, 1 stick, 2 slip) passed to the return map.
  std::vector<int> friction_flips_;
  std::vector<char> last_slip_;
  std::vector<signed char> friction_hold_;
  static constexpr int kSwapped = 1 << 20;               // friction_flips_ of a hold swapped once
  static constexpr Real kHeldFrictionTolerance = 0.02;   // of the bound
  static constexpr Real kTangentialComplementarity = 0.1;  // Lagrange friction: c_T = this x E / h
  Real friction_violation(size_t j) const;
  std::vector<Real> slip_increment_, slip_accumulated_;
  void build_constraints(const std::vector<Vec3>& x, const VecX& z);
  void add_slip_kinematics(const std::vector<Vec3>& x, const VecX& z);
  void record_origin(size_t j, const Constraint& c, const Vec3& slave_from_obstacle);
  Vec3 obstacle_offset(const VecX& z) const;
  Real dmax_ = 0;
};

}  // namespace signorini
