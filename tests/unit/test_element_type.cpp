// The element catalogue against Gmsh's own definitions, facet orientation, VTK order.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "signorini/fem/shape.hpp"
#include "signorini/mesh/element_type.hpp"

using namespace signorini;

TEST(ElementType, NodeCoordinatesMatchGmsh) {
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
  for (ElementType t : all_element_types()) {
    const ElementInfo& e = element_info(t);
    if (e.dim == 0) continue;
    std::string name;
    int dim, order, nn, npv;
    std::vector<double> coords;
    gmsh::model::mesh::getElementProperties(e.gmsh_type, name, dim, order, nn, coords, npv);
    ASSERT_EQ(dim, e.dim) << e.name;
    ASSERT_EQ(order, e.order) << e.name;
    ASSERT_EQ(nn, e.num_nodes) << e.name;
    for (int i = 0; i < nn; ++i)
      for (int d = 0; d < dim; ++d)
        EXPECT_NEAR(coords[i * dim + d], e.ref_coords[i](d), 1e-12) << e.name << " node " << i << " dir " << d;
  }
  gmsh::finalize();
}

static Real ref_jacobian(ElementType t, const std::vector<Vec3>& x) {
  VecX N;
  MatX dN;
  const ElementInfo& e = element_info(t);
  Vec3 c = Vec3::Zero();
  for (auto& p : e.ref_coords) c += p / e.num_nodes;
  shape_functions(t, c, N, dN);
  Mat3 J = Mat3::Identity();
  J.topLeftCorner(e.dim, e.dim).setZero();
  for (int a = 0; a < e.num_nodes; ++a)
    for (int i = 0; i < e.dim; ++i)
      for (int d = 0; d < e.dim; ++d) J(i, d) += x[a](i) * dN(a, d);
  return J.determinant();
}

TEST(ElementType, FacetsPointOutward) {
  for (ElementType t : all_element_types()) {
    const ElementInfo& e = element_info(t);
    if (e.dim < 2) continue;
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < e.num_corners; ++k) centroid += e.ref_coords[k] / e.num_corners;
    ASSERT_EQ(e.facets.size(), e.dim == 2 ? size_t(e.num_corners) : (e.num_corners == 4 ? 4u : 6u));
    for (auto& f : e.facets) {
      const ElementInfo& fi = element_info(f.type);
      ASSERT_EQ(static_cast<int>(f.nodes.size()), fi.num_nodes) << e.name;
      for (int n : f.nodes) ASSERT_GE(n, 0) << e.name;
      // Facet nodes sit where the facet's reference coordinates map to (affine map from corners).
      const Vec3 c0 = e.ref_coords[f.nodes[0]], c1 = e.ref_coords[f.nodes[1]];
      Vec3 normal;
      if (e.dim == 2) {
        Vec3 tng = c1 - c0;
        normal = Vec3(tng(1), -tng(0), 0);
      } else {
        normal = (c1 - c0).cross(e.ref_coords[f.nodes[fi.num_corners - 1]] - c0);
      }
      Vec3 fc = Vec3::Zero();
      for (int k = 0; k < fi.num_corners; ++k) fc += e.ref_coords[f.nodes[k]] / fi.num_corners;
      EXPECT_GT(normal.dot(fc - centroid), 0) << e.name << ": facet normal points inward";
      // Higher-order facet nodes are where the facet's own shape functions put them.
      for (int k = fi.num_corners; k < fi.num_nodes; ++k) {
        VecX N;
        MatX dN;
        shape_functions(f.type, fi.ref_coords[k], N, dN);
        Vec3 x = Vec3::Zero();
        for (int m = 0; m < fi.num_nodes; ++m) x += N(m) * e.ref_coords[f.nodes[m]];
        EXPECT_NEAR((x - e.ref_coords[f.nodes[k]]).norm(), 0, 1e-12) << e.name << " facet node " << k;
      }
    }
  }
}

TEST(ElementType, MirrorReversesOrientationAndVtkOrderIsPermutation) {
  for (ElementType t : all_element_types()) {
    const ElementInfo& e = element_info(t);
    if (e.dim < 2) continue;
    std::vector<Vec3> x = e.ref_coords, m(e.num_nodes);
    for (int i = 0; i < e.num_nodes; ++i) m[i] = x[e.mirror[i]];
    EXPECT_GT(ref_jacobian(t, x), 0) << e.name;
    EXPECT_LT(ref_jacobian(t, m), 0) << e.name;
    std::vector<int> v = e.vtk_order;
    std::sort(v.begin(), v.end());
    for (int i = 0; i < e.num_nodes; ++i) EXPECT_EQ(v[i], i) << e.name;
  }
}
