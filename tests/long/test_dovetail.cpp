// The disk-blade dovetail (issue 16; the course's disk-blade frictional contact with an
// elasto-plastic material, T. Dick and G. Cailletaud): the example `long/dovetail`, plane strain,
// J2 plasticity (small strain), Coulomb friction (mu 0.3) on the 45-degree flanks, a centrifugal
// load ramped up to omega = 1000 rad/s and back down to an idle 300 rad/s (at rest the blade
// is loose in its slot). Quarter model (symmetry x = 0 and
// y = 0). References (exact, not fitted):
// - at speed, the blade is held radially by the flank contact alone: the contact force on the
//   blade balances its centrifugal force, rho omega^2 int y dA over the half blade (the
//   polygon's first moment, exact for its straight edges), to 1e-8; in x the flank force, the
//   blade's centrifugal x-resultant and the symmetry plane's reaction sum to zero (1e-8);
// - at idle the same balance with (300/1000)^2 of the load (1e-8);
// - the flank corners yield (plastic strain at speed) and keep their plastic strain at idle.
// It writes the flank pressure and accumulated slip at speed and at idle, and the plastic zone,
// for examples/long/dovetail/plot.py.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/solver/analysis.hpp"

using namespace signorini;

namespace {

// First moments of a polygon: (int x dA, int y dA).
Vec3 first_moments(const std::vector<Vec3>& p) {
  Vec3 m = Vec3::Zero();
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec3 &a = p[i], &b = p[(i + 1) % p.size()];
    const Real cr = a.x() * b.y() - b.x() * a.y();
    m.x() += cr * (a.x() + b.x()) / 6;
    m.y() += cr * (a.y() + b.y()) / 6;
  }
  return m;
}

// The largest committed equivalent plastic strain of the analysis's bodies.
Real max_plastic_strain(const Analysis& an) {
  Real ep = 0;
  for (size_t b = 0; b < an.model().bodies.size(); ++b) {
    const QuadratureHistory& h = an.history(b);
    const auto& names = h.names();
    const auto it = std::find(names.begin(), names.end(), "equivalent_plastic_strain");
    if (it == names.end()) continue;
    const size_t k = static_cast<size_t>(it - names.begin());
    for (size_t i = k; i < h.committed_values().size(); i += names.size()) ep = std::max(ep, h.committed_values()[i]);
  }
  return ep;
}

struct FlankState {
  std::vector<Real> s, pressure, slip;  // along the flank from its outer end, per slave node
};

}  // namespace

TEST(Dovetail, BladeHeldByItsFlanksThroughASpinUpAndDown) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  Registry r = default_registry();
  Model m = read_deck((fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "long" / "dovetail" / "dovetail.yaml").string(), r);
  m.output.vtu = "none";
  const Real omega = 1000, rho_blade = 4.5e-9;
  // The half blade of dovetail.geo.
  const Vec3 M = first_moments({Vec3(0, 252, 0), Vec3(20, 252, 0), Vec3(10, 262, 0), Vec3(10, 290, 0),
                                Vec3(25, 290, 0), Vec3(25, 350, 0), Vec3(0, 350, 0)});
  const Vec3 centrifugal = rho_blade * omega * omega * M;  // per unit thickness
  Analysis a(m);
  Real peak_fy = 0, peak_fx = 0, peak_sym = 0, rest_fy = 0, peak_ep = 0, rest_ep = 0;
  FlankState at_speed, at_rest;
  auto flank = [&](const Analysis& an) {
    FlankState f;
    const ContactInterface& c = *an.contacts()[0];
    const auto states = c.slave_states();
    for (const auto& st : states) {
      const Vec3& X = m.mesh.nodes[st.node];
      f.s.push_back((Vec3(20, 252, 0) - X).norm());
      f.pressure.push_back(st.pressure);
      f.slip.push_back(st.slip_accumulated);
    }
    return f;
  };
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    if (rec.fraction < 1) return;
    const ContactInterface& c = *an.contacts()[0];
    const Vec3 f = c.slave_force();  // on the blade (its flank is slave)
    if (rec.step == 0) {
      peak_fy = f.y(), peak_fx = f.x(), peak_sym = an.reaction_sum("BladeSymX").x();
      peak_ep = max_plastic_strain(an);
      at_speed = flank(an);
    } else {
      rest_fy = f.y();
      rest_ep = max_plastic_strain(an);
      at_rest = flank(an);
    }
  });
  const AnalysisSummary s = a.run();
  ASSERT_TRUE(s.completed) << s.failure;
  std::printf("at speed: flank force on the blade (%.3f, %.3f) N/mm, blade centrifugal (%.3f, %.3f), symmetry %.3f; "
              "y balance %.1e, x balance %.1e; largest plastic strain %.3e\n",
              peak_fx, peak_fy, centrifugal.x(), centrifugal.y(), peak_sym, std::abs(peak_fy + centrifugal.y()) / centrifugal.y(),
              std::abs(peak_fx + centrifugal.x() + peak_sym) / centrifugal.y(), peak_ep);
  std::printf("at idle: flank force y %.3f N/mm (balance %.1e of the force at speed); largest plastic strain %.3e; %d "
              "increments, %d Newton iterations, %d in cut-back attempts\n",
              rest_fy, std::abs(rest_fy + 0.09 * centrifugal.y()) / centrifugal.y(), rest_ep, static_cast<int>(s.increments.size()),
              s.total_iterations, s.failed_iterations);
  EXPECT_NEAR(peak_fy, -centrifugal.y(), 1e-8 * centrifugal.y());
  EXPECT_NEAR(peak_fx + centrifugal.x() + peak_sym, 0, 1e-8 * centrifugal.y());
  EXPECT_NEAR(rest_fy, -0.09 * centrifugal.y(), 1e-8 * centrifugal.y()) << "idle: (300 / 1000)^2 of the load";
  EXPECT_GT(peak_ep, 1e-4) << "the flank corners should yield at speed";
  EXPECT_GE(rest_ep, peak_ep) << "plastic strain does not go back";
  // The curves for docs/validation.md (examples/long/dovetail/plot.py).
  const fs::path dir = fs::path(SIGNORINI_BINARY_DIR) / "curves";
  fs::create_directories(dir);
  std::ofstream out(dir / "dovetail_flank.csv");
  out << "state,s,pressure,slip\n";
  for (const auto& [name, f] : {std::pair{"speed", &at_speed}, std::pair{"idle", &at_rest}})
    for (size_t i = 0; i < f->s.size(); ++i) out << name << "," << f->s[i] << "," << f->pressure[i] << "," << f->slip[i] << "\n";
  // The plastic zone at idle: cell centres (reference) and the cells' mean equivalent plastic
  // strain, within 15 mm of the flank's middle.
  std::ofstream zone(dir / "dovetail_plastic.csv");
  zone << "body,x,y,eps_p\n";
  const Vec3 middle(15, 257, 0);
  for (size_t b = 0; b < m.bodies.size(); ++b) {
    const Body& body = *m.bodies[b];
    const QuadratureHistory& h = a.history(b);
    const auto it = std::find(h.names().begin(), h.names().end(), "equivalent_plastic_strain");
    ASSERT_NE(it, h.names().end());
    const Index k = it - h.names().begin();
    for (size_t j = 0; j < body.blocks().size(); ++j) {
      const ElementBlock& blk = body.blocks()[j];
      const Index np = body.points_per_element(j);
      const int corners = element_info(blk.type).num_corners;
      for (Index e = 0; e < blk.size(); ++e) {
        Vec3 c = Vec3::Zero();
        for (int q = 0; q < corners; ++q) c += m.mesh.nodes[blk.element(e)[q]] / corners;
        if ((c - middle).norm() > 15) continue;
        const Real* hv = h.committed(j, e);
        Real ep = 0;
        for (Index q = 0; q < np; ++q) ep += hv[q * h.per_point() + k] / np;
        zone << body.name() << "," << c.x() << "," << c.y() << "," << ep << "\n";
      }
    }
  }
}

// The same dovetail as a 3D sector (examples/long/dovetail_3d): the quarter extruded along the
// spin axis by half the disk's thickness, h = 15 mm (symmetry at the mid-plane, the other face
// free), linear hexahedra. References (exact for the prismatic blade): at speed the flank
// force on the blade balances its centrifugal force, rho omega^2 h int y dA, to 1e-8; in x the
// flank force, the centrifugal x-resultant and the symmetry plane's reaction sum to zero, and
// in z the flank force and the mid-plane's reaction (1e-8); at idle (300/1000)^2 of the load;
// the flanks yield and keep their plastic strain. It reports the flank force per unit depth in
// the layer at the mid-plane and in the one at the free face: the root spreads at the free
// face, so the flank carries the load unevenly through the thickness (a 3D effect that plane
// strain cannot show).
TEST(Dovetail, ThreeDSectorHeldByItsFlanksThroughASpinUpAndDown) {
  namespace fs = std::filesystem;
  log::set_level(log::Level::warning);
  Registry r = default_registry();
  Model m = read_deck((fs::path(SIGNORINI_SOURCE_DIR) / "examples" / "long" / "dovetail_3d" / "dovetail_3d.yaml").string(), r);
  m.output.vtu = "none";
  const Real omega = 1000, rho_blade = 4.5e-9, h = 15;
  const Vec3 M = first_moments({Vec3(0, 252, 0), Vec3(20, 252, 0), Vec3(10, 262, 0), Vec3(10, 290, 0),
                                Vec3(25, 290, 0), Vec3(25, 350, 0), Vec3(0, 350, 0)});
  const Vec3 centrifugal = rho_blade * omega * omega * h * M;
  Analysis a(m);
  Vec3 peak_f = Vec3::Zero(), rest_f = Vec3::Zero();
  Real peak_sym = 0, peak_mid = 0, peak_ep = 0, rest_ep = 0, mid_layer = 0, face_layer = 0;
  a.on_increment([&](const Analysis& an, const IncrementRecord& rec) {
    if (rec.fraction < 1) return;
    const ContactInterface& c = *an.contacts()[0];
    if (rec.step == 0) {
      peak_f = c.slave_force();
      peak_sym = an.reaction_sum("BladeSymX").x();
      peak_mid = an.reaction_sum("BladeMid").z();
      peak_ep = max_plastic_strain(an);
      // The flank's normal force per unit depth in the first and last layers of slave nodes.
      std::vector<Vec3> f(m.mesh.num_nodes(), Vec3::Zero());
      c.add_nodal_forces(f);
      const Vec3 n(-std::sqrt(0.5), -std::sqrt(0.5), 0);
      for (Index node : m.mesh.node_sets.at("BladeFlank")) {
        const Real z = m.mesh.nodes[node].z();
        if (z < 1e-6) mid_layer += f[node].dot(n);
        if (z > h - 1e-6) face_layer += f[node].dot(n);
      }
    } else {
      rest_f = c.slave_force();
      rest_ep = max_plastic_strain(an);
    }
  });
  const AnalysisSummary s = a.run();
  ASSERT_TRUE(s.completed) << s.failure;
  const Real scale = centrifugal.y();
  std::printf("3D sector at speed: flank force on the blade (%.3f, %.3f, %.3f) N, blade centrifugal (%.3f, %.3f); y "
              "balance %.1e, x balance %.1e, z balance %.1e; flank's normal force on the mid-plane's nodes %.2f N, on the "
              "free face's %.2f N (ratio %.3f); largest plastic strain %.3e\n",
              peak_f.x(), peak_f.y(), peak_f.z(), centrifugal.x(), centrifugal.y(), std::abs(peak_f.y() + centrifugal.y()) / scale,
              std::abs(peak_f.x() + centrifugal.x() + peak_sym) / scale, std::abs(peak_f.z() + peak_mid) / scale, mid_layer,
              face_layer, face_layer / mid_layer, peak_ep);
  std::printf("3D sector at idle: flank force y %.3f N (balance %.1e); largest plastic strain %.3e; %d increments, %d "
              "Newton iterations, %d in cut-back attempts\n",
              rest_f.y(), std::abs(rest_f.y() + 0.09 * scale) / scale, rest_ep, static_cast<int>(s.increments.size()),
              s.total_iterations, s.failed_iterations);
  EXPECT_NEAR(peak_f.y(), -centrifugal.y(), 1e-8 * scale);
  EXPECT_NEAR(peak_f.x() + centrifugal.x() + peak_sym, 0, 1e-8 * scale);
  EXPECT_NEAR(peak_f.z() + peak_mid, 0, 1e-8 * scale);
  EXPECT_NEAR(rest_f.y(), -0.09 * scale, 1e-8 * scale) << "idle: (300 / 1000)^2 of the load";
  EXPECT_GT(peak_ep, 1e-4) << "the flank corners should yield at speed";
  EXPECT_GE(rest_ep, peak_ep) << "plastic strain does not go back";
  EXPECT_GT(mid_layer, 0);
  EXPECT_GT(face_layer, 0);
}
