// Structured meshes of rectangles and boxes in any supported element type, for tests and
// benchmarks. Sets: region "domain"; node and facet sets xmin, xmax, ymin, ymax (zmin, zmax).
#pragma once
#include "signorini/mesh/mesh.hpp"

namespace signorini {

struct StructuredOptions {
  Real distortion = 0;      // random interior node shift, as a fraction of the node spacing
  unsigned seed = 12345;    // for the distortion
  Vec3 origin = Vec3::Zero();
};

// nx x ny cells on [0, lx] x [0, ly] (triangles: two per cell).
Mesh structured_rectangle(ElementType type, int nx, int ny, Real lx, Real ly,
                          const StructuredOptions& opt = {});
// nx x ny x nz cells on [0, lx] x [0, ly] x [0, lz] (tetrahedra: six per cell).
Mesh structured_box(ElementType type, int nx, int ny, int nz, Real lx, Real ly, Real lz,
                    const StructuredOptions& opt = {});

}  // namespace signorini
