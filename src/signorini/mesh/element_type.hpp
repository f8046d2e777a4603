// Catalogue of the element types Signorini knows: reference node coordinates in Gmsh's
// local order (which is also ours), facets, Gmsh and VTK type ids and the VTK node order.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "signorini/core/types.hpp"

namespace signorini {

enum class ElementType { point1, line2, line3, tri3, tri6, quad4, quad8, quad9, tet4, tet10, hex8, hex20, hex27 };

enum class ShapeFamily { point, simplex, tensor, serendipity };

struct Facet {
  ElementType type;          // facet type (line2, tri6, quad9, ...)
  std::vector<int> nodes;    // local node indices of the parent, in the facet's own order
};

struct ElementInfo {
  ElementType type;
  std::string name;
  int dim;
  int order;
  int num_nodes;
  int num_corners;
  ShapeFamily family;
  int gmsh_type;
  int vtk_type;
  std::vector<Vec3> ref_coords;   // reference coordinates of the nodes (unused dims are 0)
  std::vector<int> vtk_order;     // vtk_order[k] = our local index of VTK's k-th node
  std::vector<Facet> facets;      // boundary facets, numbered so the normal points outward
  std::vector<int> mirror;        // node permutation that reverses the orientation
};

const ElementInfo& element_info(ElementType type);
// Type for a Gmsh element type id; throws Error for an unsupported id.
ElementType element_type_from_gmsh(int gmsh_type);
ElementType element_type_from_name(const std::string& name);
std::vector<ElementType> all_element_types();

}  // namespace signorini
