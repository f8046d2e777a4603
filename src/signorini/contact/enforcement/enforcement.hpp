// Enforcement of the contact constraints (Signorini conditions g >= 0, p >= 0,
// p g = 0), reading only the ConstraintSet. Penalty: p = eps <-g>. Lagrange multipliers with a
// semi-smooth Newton method: one multiplier (pressure) per slave node and the complementarity
// function C = lambda - max(0, lambda - c g) = 0 (Alart & Curnier 1991; Hüeber & Wohlmuth 2005),
// which makes the active set change inside Newton's iterations and gives exact
// non-penetration. Augmented Lagrangian: p = <lambda-bar - eps g> with lambda-bar updated
// between Newton solves (Uzawa) until the penetration is below a tolerance
// (Simo & Laursen 1992; Wriggers 2006, sec. 6.3). Friction, with penalty: the trial traction
// t_tr = P(n) (t_old + eps_T d) returned onto the friction law's disc (Wriggers 2006, sec. 5.2);
// with Lagrange multipliers the traction is dim more multipliers per node, and the same return
// map makes the tangential complementarity function (Alart & Curnier 1991).
// Nitsche (Chouly, Hild & Renard 2015), on the integration points of segment_to_segment: no
// new unknowns; at each point P = p(u) - eps g with p = -n.sigma.n the slave body's normal
// pressure from its stress and eps = gamma0 E / h, and the contact term
//   R_c = w [P]_+ grad g - (theta / eps) w ([P]_+ - p) grad p
// (docs/contact.md): theta = 1 is the symmetric variant (the derivative of a potential),
// 0 the incomplete and -1 the skew-symmetric one. The exact solution satisfies it (p is the
// contact pressure, g = 0 where it is positive): no penetration beyond the discretization's.
// With friction, each point's tangential traction is the slave body's sigma_T, returned with
// Q = sigma_T - eps s onto the friction disc (docs/contact.md (N2)).
// Residual convention: R = f_ext - f_int + f_contact, tangent -dR/dz.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/friction/friction_law.hpp"
#include "signorini/contact/pair_state.hpp"
#include "signorini/core/rank_exchange.hpp"
#include "signorini/fem/dof_map.hpp"
#include "signorini/fem/global_system.hpp"

namespace signorini {

struct EnforcementInput {
  const ConstraintSet* constraints = nullptr;
  const DofMap* dofs = nullptr;
  int dim = 2;
  // Per constraint (the pair's slave nodes): penalty or complementarity constants, the
  // augmented Lagrangian's lambda-bar, the committed friction traction, the chattering guard's
  // holds (pair_state.hpp).
  const std::vector<NodeRecord>* nodes = nullptr;
  Index multiplier_offset = -1;             // first multiplier unknown (Lagrange; with friction the
                                            // dim tangential ones of each constraint follow the normal ones)
  // Friction: the law; constraints with has_slip get the frictional force.
  const FrictionLaw* friction = nullptr;
  const std::vector<char>* fixed = nullptr;  // per unknown: 1 if a Dirichlet condition prescribes it
  // Friction with a weighted slip (Discretization::weighted_slip: mortar, segment_to_segment):
  // per mesh node, 1 for the pair's slave nodes, which tells a constraint's slave columns from
  // its master ones (symmetry planes: enforcement.cpp, prescribed_slip_directions). Null: the
  // slip is the node's own (x_s - x_0).
  const std::vector<char>* slave_nodes = nullptr;
  // Friction, penalty and augmented Lagrangian: the stick predictor is on (ContactInterface;
  // only in an increment that starts with every node open): a closed node sticks, whatever its
  // trial.
  bool stick_predictor = false;
  // Friction, any node-status enforcement: the bodies stand where the last increment
  // converged (no slip yet, d = 0), so a closed node's trial is its committed traction, inside
  // its disc or on the rim, the return map's kink, where either branch is a valid Newton
  // derivative: it takes the stick branch (ContactInterface::begin_increment). Per node: only
  // where the constraint's tangential slip is round-off (enforcement.cpp, at_kink).
  bool stick_at_kink = false;
  // Nitsche: the integration points (the discretization's; `constraints` then serve output).
  const std::vector<PointConstraint>* points = nullptr;
  // Nitsche, partitioned assembly (issue 15; null: one process, or every rank holding every
  // point): `points` are this rank's share (Discretization::share_points). It adds its points'
  // matrix entries, whichever rank owns their rows (the caller has the backend carry them), and
  // the per-node output, the contact force and the residual's entries are summed over the ranks
  // through this exchange (collective), in rank order: the same bits on every rank.
  const RankExchange* share = nullptr;
};

struct EnforcementOutput {
  std::vector<Real> pressure;  // per constraint, positive in compression
  std::vector<char> active;
  std::vector<Vec3> traction;  // friction: tangential traction on the master (slave: minus it)
  std::vector<char> slip;      // friction: 1 slip, 0 stick
  std::vector<Real> cone_excess;  // friction: |t_trial| - bound (> 0: outside the disc)
  // Nitsche: the contact force on the slave side, summed over the points (the nodal pressures
  // are a projection of the points' and do not give it exactly).
  // Nitsche with friction, per integration point (of this rank's share, EnforcementInput::share):
  // -1 open or without a slip origin, 0 stick, 1 slip.
  std::vector<signed char> point_slip;
  bool has_slave_force = false;
  Vec3 slave_force = Vec3::Zero();
};

// What an augmentation (Uzawa update) did.
struct Augmentation {
  bool converged = true;            // within the gap tolerance: no update, the increment is done
  Real max_penetration = 0;
  std::vector<Index> restart_slip;  // friction: constraints whose slip origin moves to the current contact point
};

// The enforcement lifecycle, on the pair's node records: begin_increment (from the committed
// state), assemble at every Newton iteration, augment after a converged Newton solve (the
// augmented Lagrangian's Uzawa update; Newton goes on if it updated), end_increment once the
// increment is accepted.
class Enforcement {
 public:
  virtual ~Enforcement() = default;
  virtual std::string name() const = 0;
  virtual bool uses_multipliers() const = 0;
  virtual bool symmetric() const = 0;
  // Whether the open/closed status is decided per slave node (the chattering guard may hold
  // it); Nitsche decides it per integration point.
  virtual bool node_statuses() const { return true; }
  // Whether the enforcement needs the integration points of the discretization (Nitsche).
  virtual bool needs_points() const { return false; }
  // Whether Newton takes the semi-smooth method's full steps (no line search on the residual
  // norm, which is no merit function for it) with elastic bodies: the multipliers, and
  // Nitsche (measured on CalculiX's 2D Hertz mesh: 5-9 iterations with full steps, 9-25 with
  // the line search, which held back its active-set updates).
  virtual bool full_steps() const { return uses_multipliers(); }
  virtual void begin_increment(std::vector<NodeRecord>& nodes) const;
  virtual void assemble(const EnforcementInput& in, const VecX& z, VecX& residual, GlobalMatrix* K,
                        EnforcementOutput& out) const = 0;
  // gap_tolerance: the largest accepted penetration (0: 1e-3 of each node's facet size).
  virtual Augmentation augment(const ConstraintSet&, const EnforcementOutput&, bool /*friction*/, Real /*gap_tolerance*/,
                               std::vector<NodeRecord>&) const {
    return {};
  }
  virtual void end_increment(const ConstraintSet& cs, const EnforcementOutput& out, std::vector<NodeRecord>& nodes) const;
};

// theta: Nitsche's variant (1, 0, -1); exact_tangent: Nitsche's Newton matrix with the gap's
// whole second variation (enforcement.cpp; the finite-difference tests).
std::unique_ptr<Enforcement> make_enforcement(const std::string& method, int theta = 1, bool exact_tangent = false);

}  // namespace signorini
