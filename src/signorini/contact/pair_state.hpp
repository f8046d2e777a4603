// The state a contact pair keeps per slave node between Newton iterations and increments, as
// named records (one per slave node, in the slave surface's order): the enforcement's
// parameters and multipliers (penalty, complementarity constants, the augmented Lagrangian's
// lambda-bar, the committed friction traction), the chattering guard's holds, and friction's
// slip origin and slip record. Enforcement reads and updates it through its lifecycle
// (enforcement.hpp); ContactInterface owns one per pair.
#pragma once
#include <vector>

#include "signorini/contact/discretization/discretization.hpp"
#include "signorini/contact/friction/friction_law.hpp"
#include "signorini/core/types.hpp"

namespace signorini {

// The chattering guard's hold on a node's open/closed status within an increment.
enum class Hold : signed char {
  none,      // free: the enforcement decides
  closed,    // held closed (changed status more than max_flips times)
  open,      // held open
  released,  // was held closed, ended in tension: held open for the rest of the increment
  // Penalty and the augmented Lagrangian, from the undeformed state (hold_touching): closed,
  // with p = <lambda-bar - eps g> >= 0, while the gap is within kTouching of the facet size; free
  // otherwise. Not a hold of the guard: the node gets the stiffness a body held only by contact
  // needs at its first solve and no adhesion, and leaves the branch as soon as it separates.
  touching,
};
inline bool held_closed(Hold h) { return h == Hold::closed; }
inline bool held_open(Hold h) { return h == Hold::open || h == Hold::released; }
// Whether the chattering guard holds the node (touching is not the guard's).
inline bool guard_hold(Hold h) { return h != Hold::none && h != Hold::touching; }
// "Touching": a gap in (0, kTouching h], h the node's facet size (ContactInterface::hold_touching).
constexpr double kTouching = 1e-6;

struct NodeRecord {
  // Set once, from the mesh and the settings.
  Real size = 0;                  // local slave facet size h (mean edge of the node's facets)
  Real stiffness = 0;             // penalty, or the normal complementarity constant c
  Real tangential_stiffness = 0;  // tangential penalty, or the tangential complementarity constant c_T
  // Lagrange friction with the automatic c_T: its value for a node open at the increment's start
  // (tangential_stiffness is set from it at each begin_increment; 0: not automatic).
  Real tangential_closing = 0;
  // Augmented Lagrangian: the multiplier lambda-bar, current and at the last converged increment.
  Real shift = 0, shift_committed = 0;
  // Chattering guard, reset at each increment: open/closed changes, the status at the last
  // accepted iterate and at the last converged increment, the hold.
  int flips = 0;
  bool last_closed = false, committed_closed = false;
  Hold hold = Hold::none;
  // The same for stick/slip of a closed node; `swapped`: a hold already turned once to the
  // other status (fix_held_nodes).
  int friction_flips = 0;
  bool last_slip = false, swapped = false;
  StickSlip friction_hold = StickSlip::none;
  StickSlip committed_friction = StickSlip::none;
  // The master feature (the constraint's kind and facet) a closed node met at the last
  // accepted iterate and the one before its last change, how often it changed and how often
  // it went back to the one before, in this increment; the master facet it is held on (-1:
  // none). A node on the edge between two master facets can go to and fro between them at
  // every Newton iteration (the normal, and with it the force, jumps there): after two returns
  // it is held on its facet for the rest of the increment (ContactInterface::count_status_changes).
  int last_kind = -1, before_kind = -1;
  Index last_facet = -1, before_facet = -1;
  int feature_changes = 0, feature_returns = 0;
  Index held_facet = -1;
  // Friction: where the slip of the increment is measured from, the tangential traction the
  // return map starts from (penalty; the committed one, or the augmented Lagrangian's last
  // update) and the committed one, and the slip record for output.
  SlipOrigin origin;
  Vec3 traction_old = Vec3::Zero(), traction_committed = Vec3::Zero();
  Real slip_increment = 0, slip_accumulated = 0;
  // The pressure reported for output (ContactInterface::set_reported_pressure).
  Real reported_pressure = 0;
  // The augmented Lagrangian's accepted penetration (and elastic slip) at this node: `given`
  // (enforcement.gap_tolerance), or 1e-3 of its facet size.
  Real gap_tolerance(Real given) const { return given > 0 ? given : 1e-3 * size; }
};

}  // namespace signorini
