#include "signorini/mesh/element_type.hpp"

#include <map>

#include "signorini/core/error.hpp"

namespace signorini {

namespace {

using C = std::vector<Vec3>;

Vec3 v(Real x, Real y = 0, Real z = 0) { return Vec3(x, y, z); }

// Index of the node at reference position p, or -1.
int find_node(const C& coords, const Vec3& p) {
  for (size_t i = 0; i < coords.size(); ++i)
    if ((coords[i] - p).norm() < 1e-12) return static_cast<int>(i);
  return -1;
}

// Builds a facet of the parent from the parent's corner indices: mid-edge and
// mid-face nodes are found by position, so the facet node order follows Gmsh's rules
// (corners, then edge midpoints in cyclic order, then the centre).
Facet make_facet(const C& coords, int order, bool quad_center, std::vector<int> corners,
                 ElementType linear, ElementType quadratic, ElementType quadratic_full) {
  Facet f{order == 1 ? linear : quadratic, corners};
  if (order == 1) return f;
  const size_t nc = corners.size();
  if (nc > 2) {
    for (size_t k = 0; k < nc; ++k) {
      Vec3 mid = 0.5 * (coords[corners[k]] + coords[corners[(k + 1) % nc]]);
      f.nodes.push_back(find_node(coords, mid));
    }
  } else {
    f.nodes.push_back(find_node(coords, 0.5 * (coords[corners[0]] + coords[corners[1]])));
  }
  if (quad_center) {
    Vec3 c = Vec3::Zero();
    for (int k : corners) c += coords[k];
    int center = find_node(coords, c / static_cast<Real>(nc));
    if (center >= 0) {
      f.nodes.push_back(center);
      f.type = quadratic_full;
    }
  }
  return f;
}

ElementInfo build(ElementType t, std::string name, int dim, int order, ShapeFamily fam,
                  int gmsh, int vtk, C coords, int ncorner, std::vector<int> vtk_order) {
  ElementInfo e;
  e.type = t;
  e.name = std::move(name);
  e.dim = dim;
  e.order = order;
  e.num_nodes = static_cast<int>(coords.size());
  e.num_corners = ncorner;
  e.family = fam;
  e.gmsh_type = gmsh;
  e.vtk_type = vtk;
  e.ref_coords = std::move(coords);
  if (vtk_order.empty())
    for (int i = 0; i < e.num_nodes; ++i) vtk_order.push_back(i);
  e.vtk_order = std::move(vtk_order);
  // Orientation reversal: swap the first two reference coordinates (maps each reference
  // element onto itself and flips the sign of the Jacobian). Points and lines: mirror x.
  e.mirror.resize(e.num_nodes);
  for (int i = 0; i < e.num_nodes; ++i) {
    Vec3 p = e.ref_coords[i];
    Vec3 q = dim >= 2 ? Vec3(p.y(), p.x(), p.z()) : Vec3(-p.x(), p.y(), p.z());
    e.mirror[i] = find_node(e.ref_coords, q);
  }
  return e;
}

std::map<ElementType, ElementInfo> make_catalogue() {
  std::map<ElementType, ElementInfo> m;
  using T = ElementType;
  using F = ShapeFamily;
  m[T::point1] = build(T::point1, "point1", 0, 0, F::point, 15, 1, {v(0)}, 1, {});
  m[T::line2] = build(T::line2, "line2", 1, 1, F::tensor, 1, 3, {v(-1), v(1)}, 2, {});
  m[T::line3] = build(T::line3, "line3", 1, 2, F::tensor, 8, 21, {v(-1), v(1), v(0)}, 2, {});
  C tri3{v(0, 0), v(1, 0), v(0, 1)};
  C tri6 = tri3;
  for (auto p : {v(.5, 0), v(.5, .5), v(0, .5)}) tri6.push_back(p);
  m[T::tri3] = build(T::tri3, "tri3", 2, 1, F::simplex, 2, 5, tri3, 3, {});
  m[T::tri6] = build(T::tri6, "tri6", 2, 2, F::simplex, 9, 22, tri6, 3, {});
  C quad4{v(-1, -1), v(1, -1), v(1, 1), v(-1, 1)};
  C quad8 = quad4;
  for (auto p : {v(0, -1), v(1, 0), v(0, 1), v(-1, 0)}) quad8.push_back(p);
  C quad9 = quad8;
  quad9.push_back(v(0, 0));
  m[T::quad4] = build(T::quad4, "quad4", 2, 1, F::tensor, 3, 9, quad4, 4, {});
  m[T::quad8] = build(T::quad8, "quad8", 2, 2, F::serendipity, 16, 23, quad8, 4, {});
  m[T::quad9] = build(T::quad9, "quad9", 2, 2, F::tensor, 10, 28, quad9, 4, {});
  C tet4{v(0, 0, 0), v(1, 0, 0), v(0, 1, 0), v(0, 0, 1)};
  C tet10 = tet4;
  // Gmsh: edges 01, 12, 20, 30, 32, 31 (VTK has 31 before 32).
  for (auto p : {v(.5, 0, 0), v(.5, .5, 0), v(0, .5, 0), v(0, 0, .5), v(0, .5, .5), v(.5, 0, .5)})
    tet10.push_back(p);
  m[T::tet4] = build(T::tet4, "tet4", 3, 1, F::simplex, 4, 10, tet4, 4, {});
  m[T::tet10] = build(T::tet10, "tet10", 3, 2, F::simplex, 11, 24, tet10, 4,
                      {0, 1, 2, 3, 4, 5, 6, 7, 9, 8});
  C hex8{v(-1, -1, -1), v(1, -1, -1), v(1, 1, -1), v(-1, 1, -1),
         v(-1, -1, 1),  v(1, -1, 1),  v(1, 1, 1),  v(-1, 1, 1)};
  C hex20 = hex8;
  // Gmsh edge order: 01 03 04 12 15 23 26 37 45 47 56 67.
  const int edges[12][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
                            {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
  for (auto& e : edges) hex20.push_back(0.5 * (hex8[e[0]] + hex8[e[1]]));
  C hex27 = hex20;
  // Gmsh face order: z-, y-, x-, x+, y+, z+, then the centre.
  for (auto p : {v(0, 0, -1), v(0, -1, 0), v(-1, 0, 0), v(1, 0, 0), v(0, 1, 0), v(0, 0, 1),
                 v(0, 0, 0)})
    hex27.push_back(p);
  std::vector<int> vtk20{0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15};
  std::vector<int> vtk27 = vtk20;
  for (int k : {22, 23, 21, 24, 20, 25, 26}) vtk27.push_back(k);
  m[T::hex8] = build(T::hex8, "hex8", 3, 1, F::tensor, 5, 12, hex8, 8, {});
  m[T::hex20] = build(T::hex20, "hex20", 3, 2, F::serendipity, 17, 25, hex20, 8, vtk20);
  m[T::hex27] = build(T::hex27, "hex27", 3, 2, F::tensor, 12, 29, hex27, 8, vtk27);

  // Facets with outward normals (counter-clockwise seen from outside; in 2D the interior
  // lies to the left of each edge).
  for (auto& [t, e] : m) {
    if (e.dim == 2) {
      const int nc = e.num_corners;
      for (int k = 0; k < nc; ++k)
        e.facets.push_back(make_facet(e.ref_coords, e.order, false, {k, (k + 1) % nc},
                                      T::line2, T::line3, T::line3));
    } else if (e.dim == 3 && e.num_corners == 4) {
      for (auto c : std::vector<std::vector<int>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}})
        e.facets.push_back(make_facet(e.ref_coords, e.order, false, c, T::tri3, T::tri6, T::tri6));
    } else if (e.dim == 3) {
      for (auto c : std::vector<std::vector<int>>{
               {0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}})
        e.facets.push_back(
            make_facet(e.ref_coords, e.order, true, c, T::quad4, T::quad8, T::quad9));
    }
  }
  return m;
}

const std::map<ElementType, ElementInfo>& catalogue() {
  static const std::map<ElementType, ElementInfo> c = make_catalogue();
  return c;
}

}  // namespace

const ElementInfo& element_info(ElementType type) { return catalogue().at(type); }

ElementType element_type_from_gmsh(int gmsh_type) {
  for (auto& [t, e] : catalogue())
    if (e.gmsh_type == gmsh_type) return t;
  throw Error("unsupported Gmsh element type " + std::to_string(gmsh_type) +
              " (supported: line2/3, tri3/6, quad4/8/9, tet4/10, hex8/20/27)");
}

ElementType element_type_from_name(const std::string& name) {
  for (auto& [t, e] : catalogue())
    if (e.name == name) return t;
  throw Error("unknown element type '" + name + "'");
}

std::vector<ElementType> all_element_types() {
  std::vector<ElementType> v;
  for (auto& [t, e] : catalogue()) v.push_back(t);
  return v;
}

}  // namespace signorini
