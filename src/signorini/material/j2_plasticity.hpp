// J2 (von Mises) plasticity at small strain with isotropic hardening (linear or Voce) and
// linear kinematic hardening: the radial return map and its consistent tangent (Simo &
// Hughes, Computational Inelasticity, 1998, sec. 3.3, Box 3.2). Rate independent.
#pragma once
#include "signorini/material/material.hpp"

namespace signorini {

struct J2Hardening {
  Real H = 0;           // linear isotropic modulus: sigma_y(alpha) = sigma_y0 + H alpha + ...
  bool voce = false;    // ... + (saturation - sigma_y0) (1 - exp(-rate alpha))
  Real saturation = 0;  // Voce: the yield stress approached at large alpha (without H)
  Real rate = 0;        // Voce: 1 / the equivalent plastic strain of saturation
  Real kinematic = 0;   // linear kinematic modulus H_k: d(beta) = 2/3 H_k d(eps_p)
};

class J2Plasticity final : public Material {
 public:
  J2Plasticity(Real E, Real nu, Real yield_stress, J2Hardening hardening);
  std::string model() const override { return "j2_plasticity"; }
  // Per point: plastic strain (6, Voigt with engineering shears), equivalent plastic strain
  // alpha, back stress (6, tensor components), plastic work, plastic dissipation, and
  // whether the point yielded in its last increment (1) or not (0).
  int history_size() const override { return 16; }
  std::vector<std::string> history_names() const override;
  void compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const override;
  Real stiffness_scale() const override { return E_; }

  // The yield stress at equivalent plastic strain alpha, and its slope.
  Real yield_stress(Real alpha) const;
  Real yield_slope(Real alpha) const;

  enum Slot { kPlasticStrain = 0, kAlpha = 6, kBackStress = 7, kWork = 13, kDissipation = 14, kYielding = 15 };

 private:
  Real E_, nu_, sy0_, kappa_, mu_;
  J2Hardening h_;
  Mat6 D_;
};

}  // namespace signorini
