// Master smoothing in 3D (smoothing: hermite on a quad4 master surface: bicubic patches):
// a shoe (2 x 2 hex8, 9 slave nodes) pressed by a constant vertical load onto a soft foundation
// whose top is a mound of coarse quads (8 x 4 facets of 0.5 x 0.25), then dragged 2.6 along
// x, frictionless, over five facet rows. The horizontal force needed to drag it is the load
// times the slope under it: on the faceted mound the slope jumps each time a slave node
// crosses a facet edge, so the force history is piecewise with kinks and jumps; on the
// smoothed mound it varies smoothly. Measured: the largest second difference of H along the
// path (uniform steps), relative to the largest |H|. Penalty enforcement (the geometry is what
// is compared).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>

#include "common.hpp"
#include "signorini/core/log.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

Real mound(Real x, Real y) { return 0.3 * std::sin(std::numbers::pi * x / 4) + 0.04 * std::cos(std::numbers::pi * (y - 0.5)); }

struct History {
  bool completed = false;
  std::vector<Real> ux, H, V;
  int iterations = 0;
};

History drag(const std::string& smoothing) {
  log::set_level(log::Level::warning);
  Mesh f = structured_box(ElementType::hex8, 8, 4, 2, 4, 1, 0.5);
  for (Vec3& X : f.nodes) X(2) += (X(2) / 0.5) * mound(X(0), X(1));
  // The shoe: [0.35, 0.65] x [0.3, 0.6], its bottom 1e-3 into the mound at its highest node.
  Real top = -1e300;
  for (Real x : {0.35, 0.5, 0.65})
    for (Real y : {0.3, 0.45, 0.6}) top = std::max(top, 0.5 + mound(x, y));
  StructuredOptions o;
  o.origin = Vec3(0.35, 0.3, top - 3e-2);
  Mesh s = structured_box(ElementType::hex8, 2, 2, 1, 0.3, 0.3, 0.2, o);
  Mesh m;
  m.dim = 3;
  m.nodes = f.nodes;
  m.nodes.insert(m.nodes.end(), s.nodes.begin(), s.nodes.end());
  for (Index i = 0; i < m.num_nodes(); ++i) m.node_ids.push_back(i + 1);
  const Index shift = f.num_nodes();
  auto shifted = [&](std::vector<ElementBlock> v) {
    for (auto& b : v)
      for (auto& c : b.conn) c += shift;
    return v;
  };
  m.regions["foundation"] = f.regions["domain"];
  m.regions["shoe"] = shifted(s.regions["domain"]);
  m.facet_sets["mound"] = f.facet_sets["zmax"];
  m.facet_sets["sole"] = shifted(s.facet_sets["zmin"]);
  m.facet_sets["shoe_top"] = shifted(s.facet_sets["zmax"]);
  m.node_sets["foundation_bottom"] = f.node_sets["zmin"];
  for (Index n : s.node_sets["zmax"]) m.node_sets["shoe_top_nodes"].push_back(n + shift);
  m.complete_node_sets();
  AnalysisSettings as;
  as.dimension = Dimension::three_d;
  as.finite_strain = true;
  Model model;
  model.settings = as;
  model.mesh = std::move(m);
  orient_facets(model.mesh);
  model.bodies.push_back(std::make_unique<Body>("foundation", model.mesh.regions["foundation"],
                                                std::make_shared<NeoHookean>(1000, 0.3), as));
  model.bodies.push_back(std::make_unique<Body>("shoe", model.mesh.regions["shoe"], std::make_shared<NeoHookean>(1000, 0.3), as));
  ContactPairSettings cs;
  cs.name = "mound";
  cs.master = "mound";
  cs.slave = "sole";
  cs.method = "penalty";
  cs.smoothing = smoothing;
  cs.update = "iteration";
  model.contacts = {cs};
  Load load;
  load.kind = LoadKind::nodal_force;  // a dead load (a pressure would tilt with the shoe)
  load.set = "shoe_top_nodes";
  load.vector = Vec3(0, 0, -9);
  Step press;
  press.name = "press";
  press.dirichlet = {test::fix("foundation_bottom", 0), test::fix("foundation_bottom", 1), test::fix("foundation_bottom", 2),
                     test::fix("shoe_top_nodes", 0), test::fix("shoe_top_nodes", 1)};
  press.loads = {load};
  Step slide = press;
  slide.name = "slide";
  slide.dirichlet[3] = DirichletCondition{"shoe_top_nodes", 0, std::nullopt, 2.6, ""};
  slide.initial_increment = slide.max_increment = 0.01;
  model.steps = {press, slide};
  Analysis a(model);
  History h;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    if (rec.step != 1) return;
    const Index probe = an.model().mesh.node_sets.at("shoe_top_nodes").front();
    h.ux.push_back(an.displacement()(an.dofs().dof(probe, 0)));
    h.H.push_back(an.reaction_sum("shoe_top_nodes")(0));
    h.V.push_back(rec.contact.at(0).force(2));  // on the shoe
    h.iterations += rec.iterations;
  });
  const AnalysisSummary sum = a.run();
  h.completed = sum.completed;
  if (!sum.completed) std::printf("smoothing %s: %s\n", smoothing.c_str(), sum.failure.c_str());
  return h;
}

Real roughness(const History& h) {
  Real d2 = 0, hmax = 0;
  for (size_t k = 1; k + 1 < h.H.size(); ++k) d2 = std::max(d2, std::abs(h.H[k + 1] - 2 * h.H[k] + h.H[k - 1]));
  for (Real v : h.H) hmax = std::max(hmax, std::abs(v));
  return hmax > 0 ? d2 / hmax : 0;
}

}  // namespace

TEST(Smoothing3D, BicubicMasterGivesASmoothDragForce) {
  const History faceted = drag("none"), smooth = drag("hermite");
  ASSERT_TRUE(faceted.completed);
  ASSERT_TRUE(smooth.completed);
  ASSERT_EQ(faceted.H.size(), 100u);
  ASSERT_EQ(smooth.H.size(), 100u);
  const Real rf = roughness(faceted), rs = roughness(smooth);
  std::printf("drag over a mound of coarse quads: max |second difference of H| / max |H|: faceted %.4f, smoothed %.4f; "
              "Newton iterations %d / %d\n",
              rf, rs, faceted.iterations, smooth.iterations);
  // The shoe goes uphill then downhill: H changes sign (the same on both surfaces), and the
  // load is carried throughout.
  EXPECT_LT(smooth.H.front() * smooth.H.back(), 0) << "uphill and downhill drag forces have opposite signs";
  // Vertical equilibrium of the shoe: the contact carries the load.
  for (Real v : smooth.V) EXPECT_NEAR(v, 9.0, 1e-6 * 9.0);
  EXPECT_LT(rs, 0.25 * rf) << "the smoothed mound's drag force should be much smoother than the faceted one's";
  // The histories for docs/figures/smoothing_3d.png (docs/plot_smoothing_3d.py).
  if (const char* out = std::getenv("SIGNORINI_SMOOTHING_CSV")) {
    std::ofstream f(out);
    f << "ux,H_faceted,H_smoothed\n";
    for (size_t k = 0; k < smooth.H.size(); ++k) f << smooth.ux[k] << "," << faceted.H[k] << "," << smooth.H[k] << "\n";
  }
}
