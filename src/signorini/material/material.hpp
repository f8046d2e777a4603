// The material interface: stress and tangent at a quadrature point, with history variables
// read from the last converged state and written to a trial state (committed by the
// analysis only when an increment converges).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"

namespace signorini {

struct MaterialInput {
  Mat3 F = Mat3::Identity();  // deformation gradient (finite strain)
  Vec6 strain = Vec6::Zero(); // small strain (Voigt, engineering shears) or Green-Lagrange E
  bool finite = false;        // finite strain: return PK2 S and dS/dE; else sigma and dsigma/deps
  Real dt = 0;                // the increment's time (the step's `time` times its fraction); 0 when the
                              // state is only evaluated (output): a rate-dependent material then does not flow
  const Real* history_old = nullptr;  // history_size() values of the last converged state
  Real* history_new = nullptr;        // trial values to write
};

class Material {
 public:
  virtual ~Material() = default;
  virtual std::string model() const = 0;
  virtual int history_size() const { return 0; }
  // The history of a point before any load (history_size() values): zero by default; a
  // multiplicative plastic F_p starts at I.
  virtual void initialize_history(Real* h) const {
    for (int i = 0; i < history_size(); ++i) h[i] = 0;
  }
  // Names of the history values, for output (default: history_1, history_2, ...).
  virtual std::vector<std::string> history_names() const {
    std::vector<std::string> n;
    for (int i = 0; i < history_size(); ++i) n.push_back("history_" + std::to_string(i + 1));
    return n;
  }
  // Stress (Voigt) and tangent (6x6, consistent with the strain measure) at one point.
  virtual void compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const = 0;
  // A stiffness scale (Young's modulus or equivalent), used for automatic scalings.
  virtual Real stiffness_scale() const = 0;
  // Small strain: the stress is a fixed linear map of the strain (no history), so that a
  // body's internal force is K u with K assembled once (Analysis::evaluate).
  virtual bool linear_at_small_strain() const { return false; }
};

// Isotropic elasticity matrix in Voigt form (engineering shears) from Lame constants.
Mat6 isotropic_elasticity(Real lambda, Real mu);

// Isotropic linear elasticity. In finite strain it is the Saint Venant-Kirchhoff model
// (S = C : E), which is what "linear elastic" means for a total Lagrangian formulation.
class LinearElastic final : public Material {
 public:
  LinearElastic(Real E, Real nu);
  std::string model() const override { return "linear_elastic"; }
  bool linear_at_small_strain() const override { return true; }
  void compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const override;
  Real stiffness_scale() const override { return E_; }

 private:
  Real E_, nu_;
  Mat6 D_;
};

// Compressible Neo-Hookean (Bonet & Wood, Nonlinear Continuum Mechanics for FEA, 2nd ed.,
// eqs. 6.27-6.28): S = mu (I - C^-1) + lambda ln(J) C^-1. Small strain: its linearization.
class NeoHookean final : public Material {
 public:
  NeoHookean(Real E, Real nu);
  std::string model() const override { return "neo_hookean"; }
  bool linear_at_small_strain() const override { return true; }
  void compute(const MaterialInput& in, Vec6& stress, Mat6& tangent) const override;
  Real stiffness_scale() const override { return E_; }

 private:
  Real E_, nu_, lambda_, mu_;
  Mat6 D_;
};

}  // namespace signorini
