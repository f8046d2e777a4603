// Element patch tests (Zienkiewicz & Taylor, The FEM vol. 1, ch. 10): on distorted meshes
// a linear displacement prescribed on the boundary must be reproduced exactly inside, with
// a constant stress, for every element type and every analysis type.
#include <gtest/gtest.h>

#include "common.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;

namespace {

struct PatchCase {
  ElementType type;
  Dimension dim;
  bool finite;  // finite strain with a small linear field: still exact (homogeneous deformation)
};

void run_patch(const PatchCase& pc) {
  StructuredOptions o;
  o.distortion = 0.25;
  o.origin = Vec3(1.0, 0.5, 0.2);
  const bool three = pc.dim == Dimension::three_d;
  Mesh mesh = three ? structured_box(pc.type, 3, 3, 3, 1.0, 1.2, 0.9, o) : structured_rectangle(pc.type, 4, 3, 1.0, 1.2, o);
  AnalysisSettings s;
  s.dimension = pc.dim;
  s.finite_strain = pc.finite;
  auto mat = std::make_shared<NeoHookean>(1000, 0.3);
  Body body("patch", mesh.regions["domain"], mat, s);
  DofMap dofs(mesh.num_nodes(), s.spatial_dim(), test::cells_of(body));
  std::vector<char> fixed(mesh.num_nodes(), 0);
  for (const char* set : {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"})
    if (mesh.node_sets.count(set))
      for (Index n : mesh.node_sets[set]) fixed[n] = 1;
  // A general linear field; in axisymmetry u_r = c r, u_z = a + b z (homogeneous strain).
  Mat3 B;
  B << 1e-3, 2e-3, -1e-3, -3e-3, 2e-3, 1.5e-3, 0.5e-3, -1e-3, 2.5e-3;
  const Vec3 a(1e-3, -2e-3, 0.5e-3);
  auto field = [&](const Vec3& x) -> Vec3 {
    if (pc.dim == Dimension::axisymmetric) return Vec3(2e-3 * x(0), 1e-3 - 3e-3 * x(1), 0);
    Vec3 u = a + B * x;
    if (!three) u(2) = 0;
    return u;
  };
  VecX fext = VecX::Zero(dofs.num_dofs());
  VecX u = test::solve_with_prescribed(body, mesh, dofs, fixed, field, fext);
  if (pc.finite) {
    // Newton corrections from there: the exact homogeneous state is reached to round-off.
    for (int it = 0; it < 5; ++it) u = test::solve_with_prescribed(body, mesh, dofs, fixed, field, fext, &u);
  }
  Real maxerr = 0;
  for (Index n = 0; n < mesh.num_nodes(); ++n) {
    Vec3 ue = field(mesh.nodes[n]);
    for (int i = 0; i < s.spatial_dim(); ++i) maxerr = std::max(maxerr, std::abs(u(dofs.dof(n, i)) - ue(i)));
  }
  const std::string what = element_info(pc.type).name + " " + to_string(pc.dim) + (pc.finite ? " finite" : " small");
  EXPECT_LT(maxerr, 1e-12) << what;
  CellResults r = body.results(mesh.nodes, u, dofs);
  Real spread = 0, scale = 0;
  for (auto& st : r.stress) {
    spread = std::max(spread, (st - r.stress[0]).cwiseAbs().maxCoeff());
    scale = std::max(scale, st.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(scale, 0.1) << what;
  EXPECT_LT(spread, 1e-9 * scale) << what << ": stress is not constant";
}

}  // namespace

class Patch : public ::testing::TestWithParam<PatchCase> {};
TEST_P(Patch, LinearFieldIsExact) { run_patch(GetParam()); }

static std::vector<PatchCase> all_cases() {
  std::vector<PatchCase> v;
  for (auto t : {ElementType::tri3, ElementType::tri6, ElementType::quad4, ElementType::quad8, ElementType::quad9})
    for (auto d : {Dimension::plane_strain, Dimension::plane_stress, Dimension::axisymmetric}) v.push_back({t, d, false});
  for (auto t : {ElementType::tet4, ElementType::tet10, ElementType::hex8, ElementType::hex20, ElementType::hex27})
    v.push_back({t, Dimension::three_d, false});
  for (auto t : {ElementType::quad4, ElementType::tri6}) v.push_back({t, Dimension::plane_strain, true});
  v.push_back({ElementType::quad8, Dimension::plane_stress, true});
  v.push_back({ElementType::hex8, Dimension::three_d, true});
  v.push_back({ElementType::tet10, Dimension::three_d, true});
  return v;
}
INSTANTIATE_TEST_SUITE_P(EveryElement, Patch, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<PatchCase>& i) {
                           return element_info(i.param.type).name + "_" + to_string(i.param.dim) +
                                  (i.param.finite ? "_finite" : "_small");
                         });
