// Output files: VTU structure (sizes and offsets consistent), PVD listing, atomic writes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>

#include "signorini/core/error.hpp"
#include "signorini/io/atomic_file.hpp"
#include "signorini/io/results_writer.hpp"
#include "signorini/io/vtu_writer.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;

TEST(Output, VtuArraysAreConsistent) {
  Mesh m = structured_box(ElementType::tet10, 1, 1, 1, 1, 1, 1);
  VtuData d;
  d.points = &m.nodes;
  for (auto& b : m.regions["domain"]) d.cells.push_back(&b);
  VtuField f{"displacement", 3, std::vector<Real>(3 * m.num_nodes(), 1.5), {}};
  d.point_fields.push_back(f);
  const std::string text = vtu_text(d);
  EXPECT_NE(text.find("NumberOfPoints=\"" + std::to_string(m.num_nodes()) + "\""), std::string::npos);
  EXPECT_NE(text.find("NumberOfCells=\"6\""), std::string::npos);
  // Walk the appended blocks: each starts with its byte count; offsets must match.
  const size_t start = text.find("<AppendedData encoding=\"raw\">\n_") + std::strlen("<AppendedData encoding=\"raw\">\n_");
  std::regex off_re("offset=\"(\\d+)\"");
  std::vector<size_t> offsets;
  for (std::sregex_iterator it(text.begin(), text.begin() + start, off_re), end; it != end; ++it)
    offsets.push_back(std::stoul((*it)[1]));
  ASSERT_EQ(offsets.size(), 5u);  // points, connectivity, offsets, types, displacement
  size_t pos = 0;
  const std::vector<size_t> expected_bytes{24 * size_t(m.num_nodes()), 8 * 60, 8 * 6, 6, 24 * size_t(m.num_nodes())};
  for (size_t k = 0; k < offsets.size(); ++k) {
    EXPECT_EQ(offsets[k], pos);
    std::uint64_t n;
    std::memcpy(&n, text.data() + start + pos, 8);
    EXPECT_EQ(n, expected_bytes[k]) << "array " << k;
    pos += 8 + n;
  }
  // The last array holds our values.
  double v;
  std::memcpy(&v, text.data() + start + offsets[4] + 8, 8);
  EXPECT_EQ(v, 1.5);
  // VTK's quadratic tetra type.
  std::uint8_t type;
  std::memcpy(&type, text.data() + start + offsets[3] + 8, 1);
  EXPECT_EQ(type, 24);
  // Connectivity in VTK's node order, and each cell's end offset (the arrays are streamed
  // value by value, so check values, not only sizes).
  const ElementBlock& blk = *d.cells[0];
  const ElementInfo& info = element_info(blk.type);
  for (Index e = 0; e < blk.size(); ++e) {
    for (int k = 0; k < info.num_nodes; ++k) {
      std::int64_t c;
      std::memcpy(&c, text.data() + start + offsets[1] + 8 + 8 * (e * info.num_nodes + k), 8);
      EXPECT_EQ(c, blk.element(e)[info.vtk_order[k]]) << "cell " << e << " node " << k;
    }
    std::int64_t end;
    std::memcpy(&end, text.data() + start + offsets[2] + 8 + 8 * e, 8);
    EXPECT_EQ(end, (e + 1) * info.num_nodes);
  }
  double z;  // the last point's z
  std::memcpy(&z, text.data() + start + offsets[0] + 8 + 24 * (m.num_nodes() - 1) + 16, 8);
  EXPECT_EQ(z, m.nodes.back()(2));
  EXPECT_EQ(text.substr(text.size() - 28), "\n</AppendedData>\n</VTKFile>\n");
  // The file streamed to disk is the same bytes.
  const auto path = (std::filesystem::temp_directory_path() / "signorini_streamed.vtu").string();
  write_vtu_file(path, d);
  std::ifstream in(path, std::ios::binary);
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(file, text);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::filesystem::remove(path);
}

TEST(Output, AtomicWriteReplacesWholeFile) {
  auto p = (std::filesystem::temp_directory_path() / "signorini_atomic.txt").string();
  write_file_atomically(p, "first version, longer\n");
  write_file_atomically(p, "second\n");
  std::ifstream in(p);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(s, "second\n");
  EXPECT_FALSE(std::filesystem::exists(p + ".tmp"));
  EXPECT_THROW(write_file_atomically("/nonexistent-dir/x.txt", "x"), Error);
  // A write that fails (the stream's error, as a full disk sets it) or throws half way: the
  // error names the file, the old version stays whole and no partial .tmp is left behind.
  try {
    write_file_atomically(p, [](std::ostream& out) {
      out << "half of a third version";
      out.setstate(std::ios::badbit);
    });
    ADD_FAILURE() << "a failed write was not reported";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("signorini_atomic.txt.tmp' failed"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_file_atomically(p, [](std::ostream& out) {
                 out << "half";
                 throw Error("the writer failed");
               }),
               Error);
  std::ifstream again(p);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(again)), std::istreambuf_iterator<char>()), "second\n");
  EXPECT_FALSE(std::filesystem::exists(p + ".tmp"));
  std::filesystem::remove(p);
}

TEST(Output, PvdListsFilesWithTimes) {
  std::string s = pvd_text({{0.5, "a.vtu"}, {1.0, "b.vtu"}});
  EXPECT_NE(s.find("timestep=\"0.5\" part=\"0\" file=\"a.vtu\""), std::string::npos);
  EXPECT_NE(s.find("timestep=\"1\" part=\"0\" file=\"b.vtu\""), std::string::npos);
}

#include <fstream>

#include "common.hpp"
#include "signorini/io/results_writer.hpp"
#include "signorini/solver/analysis.hpp"

namespace {
// The two blocks of test::two_block_model, the upper pressed 0.01 down onto the lower, with the
// contact pairs `pairs`, run in one increment with a ResultsWriter into a fresh temporary
// directory `name`.
struct PressedBlocks {
  Model m;
  std::string dir;
  std::unique_ptr<Analysis> a;
  bool completed = false;
};
std::unique_ptr<PressedBlocks> press_blocks(const std::vector<ContactPairSettings>& pairs, const std::string& name) {
  auto mat = std::make_shared<LinearElastic>(100, 0.3);
  auto run = std::make_unique<PressedBlocks>();
  run->m = test::two_block_model(mat, mat);
  run->m.contacts = pairs;
  Step st;
  st.dirichlet = {test::fix("lower_ymin", 0), test::fix("lower_ymin", 1), test::fix("upper_ymax", 0),
                  test::fix("upper_ymax", 1, -0.01)};
  run->m.steps = {st};
  run->dir = (std::filesystem::temp_directory_path() / name).string();
  std::filesystem::remove_all(run->dir);
  ResultsWriter w(run->m, run->dir);
  run->a = std::make_unique<Analysis>(run->m);
  w.write_initial(*run->a);
  run->a->on_increment([&](const Analysis& an, const IncrementRecord& r) { w.write_increment(an, r); });
  run->completed = run->a->run().completed;
  return run;
}
}  // namespace

TEST(Output, ContactSurfaceFilesPerPairAndIncrement) {
  // Two blocks pressed together: a contact CSV per increment with the documented header and
  // one row per slave node, and the slave surface as its own VTU (its facets as cells).
  ContactPairSettings cs;
  cs.name = "pair one";
  cs.master = "lower_ymax";
  cs.slave = "upper_ymin";
  const auto run = press_blocks({cs}, "signorini_contact_output");
  ASSERT_TRUE(run->completed);
  const std::string& dir = run->dir;
  std::ifstream csv(dir + "/contact_pair_one_01_0001.csv");
  ASSERT_TRUE(csv) << "no contact CSV";
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "node,x,y,z,gap,pressure,status");
  int rows = 0, closed = 0;
  while (std::getline(csv, line)) {
    ++rows;
    closed += line.find(",closed") != std::string::npos;
  }
  EXPECT_EQ(rows, 5);  // 4 slave facets, 5 nodes
  EXPECT_EQ(closed, 5);
  std::ifstream vtu(dir + "/contact_pair_one_01_0001.vtu");
  const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("NumberOfPoints=\"5\" NumberOfCells=\"4\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"pressure\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir + "/contact_pair_one.pvd"));
}

namespace {
// A Float64 point array of a VTU file written by write_vtu_file (raw appended data, each array
// behind its UInt64 byte count), by name.
std::vector<double> vtu_array(const std::string& text, const std::string& name) {
  const std::regex re("Name=\"" + name + "\"[^>]*offset=\"(\\d+)\"");
  std::smatch m;
  if (!std::regex_search(text, m, re)) return {};
  const std::string tag = "<AppendedData encoding=\"raw\">\n_";
  const size_t at = text.find(tag) + tag.size() + std::stoul(m[1]);
  std::uint64_t bytes;
  std::memcpy(&bytes, text.data() + at, 8);
  std::vector<double> v(bytes / 8);
  std::memcpy(v.data(), text.data() + at + 8, bytes);
  return v;
}
}  // namespace

// A slave node of several pairs shows, in the whole mesh's contact fields, the pair where it is
// most engaged (until session 69 the last pair's: the tube crush example's nodes closed on its
// first plate showed the second plate's "far", with no pressure).
TEST(Output, ANodeOfSeveralPairsShowsThePairWhereItIsMostEngaged) {
  using S = ContactInterface::SlaveState;
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const S far{0, ContactInterface::far, nan, 0}, open_near{0, ContactInterface::open, 0.1, 0},
      open_away{0, ContactInterface::open, 0.5, 0}, closed_light{0, ContactInterface::closed, 0, 1},
      slipping_hard{0, ContactInterface::slipping, 0, 3};
  EXPECT_TRUE(more_engaged(open_away, far));
  EXPECT_FALSE(more_engaged(far, open_away));
  EXPECT_TRUE(more_engaged(open_near, open_away));
  EXPECT_FALSE(more_engaged(open_away, open_near));
  EXPECT_TRUE(more_engaged(closed_light, open_near));
  EXPECT_TRUE(more_engaged(slipping_hard, closed_light));
  EXPECT_FALSE(more_engaged(closed_light, slipping_hard));
  EXPECT_FALSE(more_engaged(far, far));

  // The upper block pressed on the lower one (pair "pressed", first) and, as the slave of a
  // second pair, above a rigid plane 0.3 below its bottom face, open or out of reach (pair
  // "beyond", last): the slave nodes show the first pair's closed state and pressure.
  ContactPairSettings pressed, beyond;
  pressed.name = "pressed";
  pressed.master = "lower_ymax";
  pressed.slave = "upper_ymin";
  beyond.name = "beyond";
  beyond.rigid = true;
  beyond.obstacle.shape = "plane";
  beyond.obstacle.point = Vec3(0, 0.2, 0);
  beyond.slave = "upper_ymin";
  const auto run = press_blocks({pressed, beyond}, "signorini_two_pair_output");
  ASSERT_TRUE(run->completed);
  std::ifstream vtu(run->dir + "/increment_01_0001.vtu");
  const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
  const std::vector<double> status = vtu_array(text, "contact_status"), pressure = vtu_array(text, "contact_pressure"),
                            gap = vtu_array(text, "contact_gap");
  ASSERT_EQ(status.size(), static_cast<size_t>(run->m.mesh.num_nodes()));
  ASSERT_EQ(pressure.size(), status.size());
  ASSERT_EQ(gap.size(), status.size());
  // A node of no pair has no gap (NaN; until session 69 a 0, a touching node's).
  for (Index n = 0; n < run->m.mesh.num_nodes(); ++n) {
    if (status[n] < 0) {
      EXPECT_TRUE(std::isnan(gap[n])) << "node " << n << " of no pair: gap " << gap[n];
    }
  }
  const auto& pairs = run->a->contacts();
  ASSERT_EQ(pairs.size(), 2u);
  int closed = 0;
  for (const S& ns : pairs[0]->slave_states()) {
    ASSERT_EQ(ns.status, ContactInterface::closed) << "node " << ns.node;
    EXPECT_EQ(status[ns.node], ContactInterface::closed) << "node " << ns.node;
    EXPECT_EQ(pressure[ns.node], ns.pressure) << "node " << ns.node;
    EXPECT_EQ(gap[ns.node], ns.gap) << "node " << ns.node;
    EXPECT_GT(pressure[ns.node], 0) << "node " << ns.node;
    ++closed;
  }
  EXPECT_EQ(closed, 5);
  for (const S& ns : pairs[1]->slave_states()) EXPECT_NE(ns.status, ContactInterface::closed) << "node " << ns.node;
}

namespace {
// Elastic, with one history value that starts at 2 (the material's initial state) and counts
// the converged increments: the analysis owns, initialises and commits it, the VTU names it.
class IncrementCounter final : public Material {
 public:
  std::string model() const override { return "increment_counter"; }
  int history_size() const override { return 1; }
  void initialize_history(Real* h) const override { h[0] = 2; }
  std::vector<std::string> history_names() const override { return {"increments_seen"}; }
  void compute(const MaterialInput& in, Vec6& s, Mat6& d) const override {
    d = isotropic_elasticity(50, 40);
    s = d * in.strain;
    in.history_new[0] = in.history_old[0] + 1;  // every evaluation of the trial state: old + 1
  }
  Real stiffness_scale() const override { return 100; }
};
}  // namespace

TEST(Output, HistoryFieldsByTheMaterialsNames) {
  Model m = test::two_block_model(std::make_shared<IncrementCounter>(), std::make_shared<LinearElastic>(100, 0.3));
  Step st;
  st.dirichlet = {test::fix("lower_ymin", 0), test::fix("lower_ymin", 1), test::fix("upper_ymax", 0),
                  test::fix("upper_ymax", 1, -0.01), test::fix("upper_ymin", 0), test::fix("upper_ymin", 1)};
  st.initial_increment = st.max_increment = 0.5;  // two increments
  m.steps = {st};
  const std::string dir = (std::filesystem::temp_directory_path() / "signorini_history_output").string();
  std::filesystem::remove_all(dir);
  ResultsWriter w(m, dir);
  Analysis a(m);
  EXPECT_EQ(a.history(0).committed_values().front(), 2) << "not initialised by the material";
  w.write_initial(a);
  a.on_increment([&](const Analysis& an, const IncrementRecord& r) { w.write_increment(an, r); });
  ASSERT_TRUE(a.run().completed);
  ASSERT_EQ(a.summary().increments.size(), 2u);
  // Committed twice, each time old + 1 from the committed value: 2 + 2.
  EXPECT_EQ(a.history(0).committed_values().front(), 4);
  EXPECT_TRUE(a.history(1).empty());
  std::ifstream vtu(dir + "/increment_01_0002.vtu");
  const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("Name=\"increments_seen\""), std::string::npos);
}

// The radius of a 3D contact or stick zone (check component r): the threshold with the
// fewest nodes on the wrong side.
TEST(Checks, SeparatingRadiusIsTheBestThreshold) {
  // Clean separation: midway between the outermost inside point and the next outside one.
  EXPECT_DOUBLE_EQ(separating_radius({{0.1, true}, {0.3, true}, {0.2, true}, {0.6, false}, {0.5, false}}), 0.4);
  // One outside point among the inside ones: two thresholds leave one point on the wrong
  // side (0.225 and 0.4); their mean.
  EXPECT_DOUBLE_EQ(separating_radius({{0.1, true}, {0.2, true}, {0.25, false}, {0.3, true}, {0.5, false}, {0.6, false}}),
                   0.3125);
  EXPECT_EQ(separating_radius({{0.1, false}, {0.2, false}}), 0.0);
  EXPECT_DOUBLE_EQ(separating_radius({{0.1, true}, {0.2, true}}), 0.2);  // no outside point: the outermost
  // Points scattered over a disc, inside below r = 0.7: the radius is found within the
  // spacing of the points around the rim.
  std::vector<std::pair<Real, bool>> pts;
  unsigned seed = 12345;
  for (int k = 0; k < 2000; ++k) {
    seed = seed * 1103515245u + 12345u;
    const Real r = std::sqrt(((seed >> 8) & 0xffff) / 65535.0);
    pts.push_back({r, r < 0.7});
  }
  EXPECT_NEAR(separating_radius(pts), 0.7, 2e-3);
}
