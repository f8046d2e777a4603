// What kind of continuum problem is solved: dimension (plane strain, plane stress,
// axisymmetric, 3D) and kinematics (small or finite strain, total Lagrangian).
#pragma once
#include <string>

#include "signorini/core/types.hpp"

namespace signorini {

enum class Dimension { plane_strain, plane_stress, axisymmetric, three_d };

struct AnalysisSettings {
  Dimension dimension = Dimension::plane_strain;
  bool finite_strain = false;
  Real thickness = 1.0;  // plane strain and plane stress; axisymmetric integrates 2 pi r
  int spatial_dim() const { return dimension == Dimension::three_d ? 3 : 2; }
};

inline std::string to_string(Dimension d) {
  switch (d) {
    case Dimension::plane_strain: return "plane_strain";
    case Dimension::plane_stress: return "plane_stress";
    case Dimension::axisymmetric: return "axisymmetric";
    case Dimension::three_d: return "3d";
  }
  return "?";
}

}  // namespace signorini
