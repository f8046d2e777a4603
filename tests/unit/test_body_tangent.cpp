// The global tangent of bodies (every analysis type, small and finite strain, several
// element types) and of follower pressure against central differences of the residual.
#include <gtest/gtest.h>

#include "common.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/history.hpp"
#include "signorini/fem/surface_load.hpp"
#include "signorini/material/j2_plasticity.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;
using signorini::test::DenseMatrix;

namespace {

struct Case {
  Dimension dim;
  bool finite;
  ElementType type;
  bool neo;
};

std::string describe(const Case& c) {
  return to_string(c.dim) + (c.finite ? "_finite_" : "_small_") + element_info(c.type).name + (c.neo ? "_NH" : "_LE");
}
std::string name_of(const ::testing::TestParamInfo<Case>& i) { return describe(i.param); }

Mesh make_mesh(const Case& c) {
  StructuredOptions o;
  o.distortion = 0.15;
  o.origin = Vec3(0.5, 0, 0);  // keeps r > 0 in axisymmetry
  return c.dim == Dimension::three_d ? structured_box(c.type, 2, 2, 1, 1.0, 1.0, 0.6, o)
                                     : structured_rectangle(c.type, 2, 2, 1.0, 0.8, o);
}

VecX random_displacement(Index n, Real amplitude, unsigned seed) {
  VecX u(n);
  unsigned s = seed;
  for (Index i = 0; i < n; ++i) {
    s = s * 1664525u + 1013904223u;
    u(i) = amplitude * (2.0 * (s >> 8) / static_cast<Real>(1u << 24) - 1.0);
  }
  return u;
}

// The largest difference between the body's tangent at u and central differences of its
// internal forces, relative to the tangent's largest entry (history read from its committed
// state, when given).
Real tangent_error(const Body& body, const Mesh& mesh, const DofMap& dofs, const VecX& u,
                   QuadratureHistory* hist = nullptr, DenseMatrix* tangent = nullptr) {
  DenseMatrix K(dofs.num_dofs());
  VecX f = VecX::Zero(dofs.num_dofs());
  body.assemble(mesh.nodes, u, dofs, f, &K, hist);
  const Real maxk = K.k.cwiseAbs().maxCoeff();
  // The tangent is d(fint)/du: the residual whose negative derivative it is, is -fint.
  const Real maxerr = test::central_difference_error(
      [&](const VecX& uu) {
        VecX fi = VecX::Zero(dofs.num_dofs());
        body.assemble(mesh.nodes, uu, dofs, fi, nullptr, hist);
        return VecX(-fi);
      },
      u, K.k, 1e-6);
  if (tangent) *tangent = K;
  return maxerr / maxk;
}

}  // namespace

class BodyTangent : public ::testing::TestWithParam<Case> {};

TEST_P(BodyTangent, MatchesCentralDifferences) {
  const Case c = GetParam();
  Mesh mesh = make_mesh(c);
  AnalysisSettings s;
  s.dimension = c.dim;
  s.finite_strain = c.finite;
  s.thickness = 0.7;
  std::shared_ptr<Material> mat =
      c.neo ? std::shared_ptr<Material>(std::make_shared<NeoHookean>(100, 0.3)) : std::make_shared<LinearElastic>(100, 0.3);
  Body body("b", mesh.regions["domain"], mat, s);
  DofMap dofs(mesh.num_nodes(), s.spatial_dim(), test::cells_of(body));
  const VecX u = random_displacement(dofs.num_dofs(), 0.05, 7);
  DenseMatrix K(dofs.num_dofs());
  EXPECT_LT(tangent_error(body, mesh, dofs, u, nullptr, &K), 1e-6) << describe(c);
  const Real maxk = K.k.cwiseAbs().maxCoeff();
  // The tangent of a hyperelastic body is symmetric.
  EXPECT_LT((K.k - K.k.transpose()).cwiseAbs().maxCoeff(), 1e-10 * maxk) << describe(c);
}

INSTANTIATE_TEST_SUITE_P(
    AllAnalysisTypes, BodyTangent,
    ::testing::Values(Case{Dimension::plane_strain, true, ElementType::quad4, true},
                      Case{Dimension::plane_strain, true, ElementType::tri6, true},
                      Case{Dimension::plane_strain, false, ElementType::quad8, false},
                      Case{Dimension::plane_stress, true, ElementType::quad4, true},
                      Case{Dimension::plane_stress, true, ElementType::quad9, false},
                      Case{Dimension::plane_stress, false, ElementType::tri3, false},
                      Case{Dimension::axisymmetric, true, ElementType::quad4, true},
                      Case{Dimension::axisymmetric, true, ElementType::tri6, true},
                      Case{Dimension::axisymmetric, false, ElementType::quad9, false},
                      Case{Dimension::three_d, true, ElementType::hex8, true},
                      Case{Dimension::three_d, true, ElementType::tet10, true},
                      Case{Dimension::three_d, true, ElementType::hex20, false},
                      Case{Dimension::three_d, false, ElementType::tet4, false},
                      Case{Dimension::three_d, true, ElementType::hex27, true}),
    name_of);

// J2 plasticity in a body: the tangent of a plastic state (strains about ten times the yield
// strain, history committed from a first plastic step) against central differences, small and
// finite strain (the finite-strain model's material tangent plus the geometric term).
class BodyTangentPlastic : public ::testing::TestWithParam<Case> {};

TEST_P(BodyTangentPlastic, MatchesCentralDifferences) {
  const Case c = GetParam();
  Mesh mesh = make_mesh(c);
  AnalysisSettings s;
  s.dimension = c.dim;
  s.finite_strain = c.finite;
  s.thickness = 0.7;
  J2Hardening h;
  h.H = 10;
  Body body("b", mesh.regions["domain"], std::make_shared<J2Plasticity>(100, 0.3, 0.5, h, c.finite), s);
  DofMap dofs(mesh.num_nodes(), s.spatial_dim(), test::cells_of(body));
  QuadratureHistory hist(body);
  // A first plastic step, committed; then the tangent at a further state.
  const VecX u1 = random_displacement(dofs.num_dofs(), 0.05, 7);
  VecX f = VecX::Zero(dofs.num_dofs());
  body.assemble(mesh.nodes, u1, dofs, f, nullptr, &hist);
  hist.commit();
  const VecX u = u1 + random_displacement(dofs.num_dofs(), 0.02, 11);
  EXPECT_LT(tangent_error(body, mesh, dofs, u, &hist), 1e-6) << describe(c);
  // The state checked is plastic: points yielded in the first step, and some yield at u (the
  // trial state of an assembly at u).
  const J2Plasticity& m = static_cast<const J2Plasticity&>(body.material());
  bool yielded = false, yielding = false;
  for (size_t i = m.alpha_slot(); i < hist.committed_values().size(); i += m.history_size())
    yielded = yielded || hist.committed_values()[i] > 0;
  f.setZero();
  body.assemble(mesh.nodes, u, dofs, f, nullptr, &hist);
  for (size_t bi = 0; bi < body.blocks().size(); ++bi)
    for (Index e = 0; e < body.blocks()[bi].size(); ++e)
      for (Index q = 0; q < body.points_per_element(bi); ++q)
        yielding = yielding || hist.trial(bi, e)[q * m.history_size() + m.yielding_slot()] > 0;
  EXPECT_TRUE(yielded) << describe(c);
  EXPECT_TRUE(yielding) << describe(c);
}

INSTANTIATE_TEST_SUITE_P(
    J2, BodyTangentPlastic,
    ::testing::Values(Case{Dimension::plane_strain, true, ElementType::quad4, false},
                      Case{Dimension::plane_strain, false, ElementType::tri6, false},
                      Case{Dimension::plane_stress, true, ElementType::quad4, false},
                      Case{Dimension::plane_stress, false, ElementType::quad8, false},
                      Case{Dimension::axisymmetric, true, ElementType::tri6, false},
                      Case{Dimension::three_d, true, ElementType::hex8, false},
                      Case{Dimension::three_d, true, ElementType::tet10, false},
                      Case{Dimension::three_d, false, ElementType::tet4, false}),
    [](const ::testing::TestParamInfo<Case>& i) {
      const Case& c = i.param;
      return to_string(c.dim) + (c.finite ? "_finite_" : "_small_") + element_info(c.type).name;
    });

class FollowerPressure : public ::testing::TestWithParam<Case> {};

TEST_P(FollowerPressure, LoadStiffnessMatchesCentralDifferences) {
  const Case c = GetParam();
  Mesh mesh = make_mesh(c);
  orient_facets(mesh);
  AnalysisSettings s;
  s.dimension = c.dim;
  s.finite_strain = true;
  s.thickness = 0.7;
  std::vector<const ElementBlock*> cells;
  for (auto& b : mesh.regions["domain"]) cells.push_back(&b);
  DofMap dofs(mesh.num_nodes(), s.spatial_dim(), cells);
  FacetLoad load{&mesh.facet_sets["xmax"], Vec3::Zero(), 3.0, true, true};
  const VecX u = random_displacement(dofs.num_dofs(), 0.05, 11);
  DenseMatrix K(dofs.num_dofs());
  VecX f = VecX::Zero(dofs.num_dofs());
  add_facet_load(load, s, mesh.nodes, u, dofs, 0.8, f, &K);
  ASSERT_GT(f.norm(), 0);
  // The matrix holds -d(fext)/du: fext is the residual.
  const Real maxerr = test::central_difference_error(
      [&](const VecX& uu) {
        VecX fe = VecX::Zero(dofs.num_dofs());
        add_facet_load(load, s, mesh.nodes, uu, dofs, 0.8, fe, nullptr);
        return fe;
      },
      u, K.k, 1e-6);
  EXPECT_LT(maxerr, 1e-7 * std::max(1.0, K.k.cwiseAbs().maxCoeff())) << describe(c);
  EXPECT_GT(K.k.cwiseAbs().maxCoeff(), 0) << describe(c);
}

INSTANTIATE_TEST_SUITE_P(Facets, FollowerPressure,
                         ::testing::Values(Case{Dimension::plane_strain, true, ElementType::quad4, true},
                                           Case{Dimension::plane_strain, true, ElementType::quad9, true},
                                           Case{Dimension::axisymmetric, true, ElementType::tri6, true},
                                           Case{Dimension::three_d, true, ElementType::hex8, true},
                                           Case{Dimension::three_d, true, ElementType::tet10, true},
                                           Case{Dimension::three_d, true, ElementType::hex27, true}),
    name_of);

TEST(SurfaceLoad, PressureResultantIsPressureTimesArea) {
  // Dead pressure p on the x = 1 face of a distorted box: resultant -p * area along x.
  StructuredOptions o;
  o.distortion = 0.1;
  Mesh mesh = structured_box(ElementType::tet10, 2, 3, 2, 1.0, 2.0, 0.5, o);
  orient_facets(mesh);
  AnalysisSettings s;
  s.dimension = Dimension::three_d;
  std::vector<const ElementBlock*> cells;
  for (auto& b : mesh.regions["domain"]) cells.push_back(&b);
  DofMap dofs(mesh.num_nodes(), 3, cells);
  VecX f = VecX::Zero(dofs.num_dofs()), u = f;
  FacetLoad load{&mesh.facet_sets["xmax"], Vec3::Zero(), 5.0, true, false};
  add_facet_load(load, s, mesh.nodes, u, dofs, 1.0, f, nullptr);
  Vec3 r = Vec3::Zero();
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    for (int i = 0; i < 3; ++i) r(i) += f(dofs.dof(n, i));
  EXPECT_NEAR(r(0), -5.0 * 2.0 * 0.5, 1e-12);
  EXPECT_NEAR(r(1), 0, 1e-12);
  EXPECT_NEAR(facet_set_area(mesh.facet_sets["xmax"], s, mesh.nodes), 1.0, 1e-12);
}

// A body force that depends on the position (the centrifugal load's rho omega^2 r), integrated
// exactly by the element rule: axisymmetric ring [0.5, 1.5] x [0, 0.8] about the y axis gives the
// radial resultant int rho omega^2 r 2 pi r dr dz = 2 pi rho omega^2 (1.5^3 - 0.5^3) / 3 * 0.8.
TEST(BodyForce, PositionDependentForceIsIntegratedExactly) {
  StructuredOptions o;
  o.distortion = 0.15;
  o.origin = Vec3(0.5, 0, 0);
  Mesh mesh = structured_rectangle(ElementType::quad9, 3, 2, 1.0, 0.8, o);
  AnalysisSettings s;
  s.dimension = Dimension::axisymmetric;
  Body body("b", mesh.regions["domain"], std::make_shared<LinearElastic>(100, 0.3), s);
  DofMap dofs(mesh.num_nodes(), 2, test::cells_of(body));
  VecX f = VecX::Zero(dofs.num_dofs());
  const Real k = 3.0;  // rho omega^2
  body.add_body_force(mesh.nodes, dofs, [&](const Vec3& x) { return Vec3(k * x(0), 0, 0); }, 1.0, f);
  Real fx = 0, fy = 0;
  for (Index n = 0; n < mesh.num_nodes(); ++n) fx += f(dofs.dof(n, 0)), fy += f(dofs.dof(n, 1));
  EXPECT_NEAR(fx, 2 * std::numbers::pi * k * (1.5 * 1.5 * 1.5 - 0.125) / 3 * 0.8, 1e-11);
  EXPECT_NEAR(fy, 0, 1e-12);
}

// An element that a state turns inside out is named, with its body, in the failure (which the
// analysis' line search passes on when no shortened step can be evaluated): a Neo-Hookean block
// whose right column of nodes is moved past its left one.
TEST(BodyFailure, InvertedElementIsNamedWithItsBody) {
  Mesh mesh = structured_rectangle(ElementType::quad4, 2, 1, 1.0, 1.0);
  AnalysisSettings s;
  s.dimension = Dimension::plane_strain;
  s.finite_strain = true;
  Body body("slab", mesh.regions["domain"], std::make_shared<NeoHookean>(100, 0.3), s);
  DofMap dofs(mesh.num_nodes(), 2, test::cells_of(body));
  VecX u = VecX::Zero(dofs.num_dofs());
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if (mesh.nodes[n].x() > 0.99) u(dofs.dof(n, 0)) = -0.9;  // x = 1 -> 0.1, left of x = 0.5
  VecX f = VecX::Zero(dofs.num_dofs());
  try {
    body.assemble(mesh.nodes, u, dofs, f, nullptr, nullptr);
    ADD_FAILURE() << "an inverted element was evaluated";
  } catch (const SolverError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("non-positive volume ratio"), std::string::npos) << what;
    EXPECT_NE(what.find("(element 2 of body slab)"), std::string::npos) << what;
  }
}

