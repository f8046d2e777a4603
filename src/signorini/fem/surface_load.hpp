// Loads on facet sets: a dead traction (per unit reference area) or a pressure (positive in
// compression, acting against the outward normal). In finite strain a pressure follows the
// deformed surface and contributes an unsymmetric load stiffness.
#pragma once
#include <vector>

#include "signorini/fem/analysis_settings.hpp"
#include "signorini/fem/dof_map.hpp"
#include "signorini/fem/global_system.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

struct FacetLoad {
  const std::vector<ElementBlock>* facets = nullptr;
  Vec3 traction = Vec3::Zero();  // dead traction, if !is_pressure
  Real pressure = 0;
  bool is_pressure = false;
  bool follower = false;         // pressure on the current configuration
};

// Adds scale * (load) to fext; with a follower pressure and `matrix` given, subtracts the
// load stiffness d(fext)/du from the tangent (the tangent is d(fint - fext)/du).
void add_facet_load(const FacetLoad& load, const AnalysisSettings& settings, const std::vector<Vec3>& X,
                    const VecX& u, const DofMap& dofs, Real scale, VecX& fext, GlobalMatrix* matrix);

// The area of a facet set (reference configuration; with 2 pi r in axisymmetry).
Real facet_set_area(const std::vector<ElementBlock>& facets, const AnalysisSettings& settings,
                    const std::vector<Vec3>& X);

}  // namespace signorini
