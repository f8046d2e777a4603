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
// Residual convention: R = f_ext - f_int + f_contact, tangent -dR/dz.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/friction/friction_law.hpp"
#include "signorini/contact/pair_state.hpp"
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
};

struct EnforcementOutput {
  std::vector<Real> pressure;  // per constraint, positive in compression
  std::vector<char> active;
  std::vector<Vec3> traction;  // friction: tangential traction on the master (slave: minus it)
  std::vector<char> slip;      // friction: 1 slip, 0 stick
  std::vector<Real> cone_excess;  // friction: |t_trial| - bound (> 0: outside the disc)
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

std::unique_ptr<Enforcement> make_enforcement(const std::string& method);

}  // namespace signorini
