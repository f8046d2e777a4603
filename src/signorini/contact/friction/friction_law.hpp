// Friction laws behind one interface (DESIGN.md): the admissible set of tangential tractions
// is the disc |t| <= bound(p), with the bound given by the law (Coulomb: mu p; Tresca: a
// constant; frictionless: 0). The return map projects a trial traction onto that disc
// (Wriggers 2006, sec. 5.2; Laursen 2002, ch. 5) and gives its derivatives for the
// consistent tangent.
#pragma once
#include <memory>
#include <string>

#include "signorini/core/types.hpp"

namespace signorini {

using Mat3 = Eigen::Matrix<Real, 3, 3>;

// A closed node's friction status, or the branch a hold imposes (none: open, frictionless, or
// no hold).
enum class StickSlip : signed char { none, stick, slip };

struct ReturnMap {
  Vec3 traction = Vec3::Zero();   // the admissible traction
  bool slip = false;              // the trial traction was outside the disc
  Mat3 d_trial = Mat3::Zero();    // d traction / d trial traction
  Vec3 d_bound = Vec3::Zero();    // d traction / d bound
};

class FrictionLaw {
 public:
  virtual ~FrictionLaw() = default;
  virtual std::string name() const = 0;
  // Radius of the admissible disc at normal pressure p >= 0, and its derivative in p.
  virtual Real bound(Real p) const = 0;
  virtual Real bound_derivative(Real p) const = 0;
};

// Projection of `trial` onto the disc of radius `bound` (bound >= 0). At the cone apex
// (bound = 0) the traction is zero and counts as slip. `hold` (the chattering guard) imposes
// the branch: stick (traction = trial, even outside the disc), slip (traction on the rim in
// the trial's direction, even from inside); none chooses by |trial| <= bound.
ReturnMap return_map(const Vec3& trial, Real bound, StickSlip hold = StickSlip::none);

// law: "coulomb" (parameter mu), "tresca" (parameter: the bound), "none".
std::unique_ptr<FrictionLaw> make_friction_law(const std::string& law, Real parameter);

}  // namespace signorini
