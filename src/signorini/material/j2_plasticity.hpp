// J2 (von Mises) plasticity with isotropic hardening (linear or Voce) and, at small strain,
// linear kinematic hardening. Rate independent.
//  - Small strain: the radial return map and its consistent tangent (Simo & Hughes,
//    Computational Inelasticity, 1998, sec. 3.3, Box 3.2).
//  - Finite strain: the multiplicative split F = F_e F_p with a Hencky (logarithmic) elastic
//    law, the same radial return on the logarithmic elastic strain of the trial state, and F_p
//    updated with the exponential map, so that det F_p stays 1 (Simo, CMAME 99, 1992; Eterovic
//    & Bathe, IJNME 30, 1990; Weber & Anand, CMAME 79, 1990). For an isotropic material without
//    back stress the trial elastic stretch, the stress and the flow direction share their
//    principal axes, and the return is exact in those axes; the tangent is the derivative of an
//    isotropic tensor function of the trial elastic right Cauchy-Green tensor (the principal
//    values' derivatives plus the divided differences that rotate the axes; see
//    j2_plasticity.cpp). Kinematic hardening is not offered at finite strain.
#pragma once
#include "signorini/material/material.hpp"

namespace signorini {

struct J2Hardening {
  Real H = 0;           // linear isotropic modulus: sigma_y(alpha) = sigma_y0 + H alpha + ...
  bool voce = false;    // ... + (saturation - sigma_y0) (1 - exp(-rate alpha))
  Real saturation = 0;  // Voce: the yield stress approached at large alpha (without H)
  Real rate = 0;        // Voce: 1 / the equivalent plastic strain of saturation
  Real kinematic = 0;   // linear kinematic modulus H_k: d(beta) = 2/3 H_k d(eps_p) (small strain only)
};

// Perzyna viscoplasticity: d(alpha)/dt = (1 / viscosity) <q / sigma_y(alpha) - 1>^rate_exponent
// (q the von Mises stress, of s - beta with kinematic hardening); viscosity 0 is the
// rate-independent model, and the response tends to it as the viscosity goes to 0.
struct J2Viscosity {
  Real viscosity = 0;      // eta, in time units (the steps' `time`)
  Real rate_exponent = 1;  // m
};

class J2Plasticity final : public Material {
 public:
  // finite: the multiplicative finite-strain model (kinematics: finite_strain); throws an
  // Error for kinematic hardening there.
  J2Plasticity(Real E, Real nu, Real yield_stress, J2Hardening hardening, bool finite = false,
               J2Viscosity viscosity = {});
  std::string model() const override { return "j2_plasticity"; }
  // Per point, small strain: plastic strain (6, Voigt with engineering shears), equivalent
  // plastic strain alpha, back stress (6, tensor components), plastic work, plastic
  // dissipation, and whether the point yielded in its last increment (1) or not (0).
  // Finite strain: the plastic deformation gradient F_p (9, row by row; I before any load),
  // alpha, plastic work, plastic dissipation (per unit reference volume), yielding.
  int history_size() const override { return finite_ ? 13 : 16; }
  void initialize_history(Real* h) const override;
  std::vector<std::string> history_names() const override;
  void compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const override;
  Real stiffness_scale() const override { return E_; }
  bool finite() const { return finite_; }

  // The yield stress at equivalent plastic strain alpha, and its slope.
  Real yield_stress(Real alpha) const;
  Real yield_slope(Real alpha) const;

  // History slots. Small strain:
  enum Slot { kPlasticStrain = 0, kAlpha = 6, kBackStress = 7, kWork = 13, kDissipation = 14, kYielding = 15 };
  // Finite strain:
  enum FiniteSlot { kPlasticDeformation = 0, kFiniteAlpha = 9, kFiniteWork = 10, kFiniteDissipation = 11, kFiniteYielding = 12 };
  int alpha_slot() const { return finite_ ? int(kFiniteAlpha) : int(kAlpha); }
  int yielding_slot() const { return finite_ ? int(kFiniteYielding) : int(kYielding); }

 private:
  // The return map for a trial |dev stress - back stress| = norm at alpha over a time dt:
  // whether it flows, the plastic multiplier dg, the slope d(k)/d(dg) of the hardening and
  // viscous resistance k(dg) (the consistent tangent's k'), and the viscous overstress ratio
  // y (|xi| = sqrt(2/3) sigma_y (1 + y); 0 when rate independent).
  struct Return {
    bool plastic = false;
    Real dg = 0, slope = 0, overstress = 0;
  };
  Return radial_return(Real norm, Real alpha, Real dt) const;
  // The dissipation of a return ending at alpha_new: sigma_y0 d(alpha), plus the overstress's.
  Real dissipation(Real alpha_new, const Return& r) const;
  void compute_small(const MaterialInput& in, Vec6& stress, Mat6& tangent) const;
  void compute_finite(const MaterialInput& in, Vec6& stress, Mat6& tangent) const;

  Real E_, nu_, sy0_, kappa_, mu_;
  J2Hardening h_;
  J2Viscosity visc_;
  bool finite_;
  Mat6 D_;
};

}  // namespace signorini
