#include "signorini/contact/friction/friction_law.hpp"

#include "signorini/core/error.hpp"

namespace signorini {

namespace {

class Coulomb final : public FrictionLaw {
 public:
  explicit Coulomb(Real mu) : mu_(mu) {}
  std::string name() const override { return "coulomb"; }
  Real bound(Real p) const override { return mu_ * std::max(p, 0.0); }
  Real bound_derivative(Real p) const override { return p > 0 ? mu_ : 0.0; }

 private:
  Real mu_;
};

class Tresca final : public FrictionLaw {
 public:
  explicit Tresca(Real tau) : tau_(tau) {}
  std::string name() const override { return "tresca"; }
  Real bound(Real) const override { return tau_; }
  Real bound_derivative(Real) const override { return 0; }

 private:
  Real tau_;
};

class Frictionless final : public FrictionLaw {
 public:
  std::string name() const override { return "none"; }
  Real bound(Real) const override { return 0; }
  Real bound_derivative(Real) const override { return 0; }
};

}  // namespace

ReturnMap return_map(const Vec3& trial, Real bound, StickSlip hold) {
  ReturnMap r;
  const Real norm = trial.norm();
  if (hold == StickSlip::stick || (hold != StickSlip::slip && norm <= bound) || (hold == StickSlip::slip && norm == 0)) {  // stick
    r.traction = trial;
    r.d_trial = Mat3::Identity();
    return r;
  }
  r.slip = true;
  if (norm == 0) return r;  // bound = 0 and no trial: nothing to project
  const Vec3 dir = trial / norm;
  r.traction = bound * dir;
  r.d_trial = bound / norm * (Mat3::Identity() - dir * dir.transpose());
  r.d_bound = dir;
  return r;
}

std::unique_ptr<FrictionLaw> make_friction_law(const std::string& law, Real parameter) {
  if (law == "coulomb") return std::make_unique<Coulomb>(parameter);
  if (law == "tresca") return std::make_unique<Tresca>(parameter);
  if (law == "none") return std::make_unique<Frictionless>();
  throw Error("unknown friction law '" + law + "' (coulomb, tresca, none)");
}

}  // namespace signorini
