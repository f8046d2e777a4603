// Reading meshes: .msh 2.2 and 4.1 give the same model, mixed element types in one region,
// inverted elements reported by id, clockwise elements re-ordered, facets oriented outward.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "signorini/core/error.hpp"
#include "signorini/mesh/gmsh_reader.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;
namespace fs = std::filesystem;

static const std::string kData = SIGNORINI_TEST_DATA;

TEST(Mesh, Msh22And41AreReadAlike) {
  const fs::path dir = fs::temp_directory_path() / "signorini_mesh_tests";
  fs::create_directories(dir);
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open(kData + "/mixed.geo");
  gmsh::model::mesh::generate(2);
  gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
  gmsh::write((dir / "m22.msh").string());
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::write((dir / "m41.msh").string());
  gmsh::finalize();
  Mesh a = read_gmsh((dir / "m22.msh").string()), b = read_gmsh((dir / "m41.msh").string());
  Mesh c = read_gmsh(kData + "/mixed.geo");
  for (const Mesh* m : {&a, &b, &c}) {
    EXPECT_EQ(m->dim, 2);
    ASSERT_EQ(m->regions.count("Plate"), 1u);
    EXPECT_EQ(m->regions.at("Plate").size(), 2u) << "quads and triangles in one region";
    EXPECT_EQ(m->facet_sets.count("Bottom"), 1u);
    EXPECT_EQ(m->node_sets.at("Left").size(), 5u);
  }
  EXPECT_EQ(a.num_nodes(), b.num_nodes());
  EXPECT_EQ(a.num_cells(), b.num_cells());
  EXPECT_EQ(a.num_cells(), c.num_cells());
  // Node numbering may differ between formats: compare the coordinates of a set.
  auto coords = [](const Mesh& m, const std::string& set) {
    std::vector<std::array<Real, 2>> v;
    for (Index n : m.node_sets.at(set)) v.push_back({m.nodes[n](0), m.nodes[n](1)});
    std::sort(v.begin(), v.end());
    return v;
  };
  for (const Mesh* other : {&b, &c}) {
    auto p = coords(a, "Bottom"), q = coords(*other, "Bottom");
    ASSERT_EQ(p.size(), q.size());
    for (size_t i = 0; i < p.size(); ++i)
      for (int d = 0; d < 2; ++d) EXPECT_NEAR(p[i][d], q[i][d], 1e-12);
  }
}

TEST(Mesh, InvertedElementsAreReportedByIdAndClockwiseOnesReordered) {
  Mesh m = read_gmsh(kData + "/inverted.msh");
  MeshCheck chk = check_and_orient(m);
  // Element 12 is a bow-tie (Jacobian changes sign); 13 is clockwise (re-ordered); 11, 14 fine.
  ASSERT_EQ(chk.inverted.size(), 1u);
  EXPECT_EQ(chk.inverted[0], 12);
  EXPECT_EQ(chk.reoriented, 1);
  EXPECT_TRUE(chk.degenerate.empty());
}

TEST(Mesh, FacetsAreOrientedOutward) {
  Mesh m = structured_rectangle(ElementType::quad8, 3, 2, 3, 2);
  // Reverse every facet of "xmax", then let orient_facets repair them.
  for (auto& b : m.facet_sets["xmax"])
    for (Index e = 0; e < b.size(); ++e) std::swap(b.conn[e * 3], b.conn[e * 3 + 1]);
  EXPECT_EQ(orient_facets(m), 0);
  for (auto& b : m.facet_sets["xmax"])
    for (Index e = 0; e < b.size(); ++e) {
      const Vec3 t = m.nodes[b.element(e)[1]] - m.nodes[b.element(e)[0]];
      EXPECT_GT(t(1), 0) << "outward normal (t_y, -t_x) must point to +x";
    }
}

// 3D: every facet of a set mirrored, on linear and quadratic cells, is given back the node
// list of the cell facet it lies on (the first orientation pass's result); a facet on no cell,
// and a tri3 facet on tet10 cells (node counts differ), are counted as orphans and left alone.
TEST(Mesh, FacetsAreOrientedOutwardIn3D) {
  for (ElementType type : {ElementType::tet4, ElementType::tet10, ElementType::hex8, ElementType::hex20}) {
    SCOPED_TRACE(element_info(type).name);
    Mesh m = structured_box(type, 2, 3, 2, 1.0, 1.5, 1.0);
    ASSERT_EQ(orient_facets(m), 0);
    const std::vector<ElementBlock> outward = m.facet_sets.at("xmax");
    for (auto& b : m.facet_sets["xmax"]) {
      const ElementInfo& info = element_info(b.type);
      const int nn = info.num_nodes;
      for (Index e = 0; e < b.size(); ++e) {
        std::vector<Index> old(b.conn.begin() + e * nn, b.conn.begin() + (e + 1) * nn);
        for (int i = 0; i < nn; ++i) b.conn[e * nn + i] = old[info.mirror[i]];
      }
    }
    ElementBlock stray = m.facet_sets["xmax"].front();
    const Index nn = stray.nodes_per_element();
    stray.conn.resize(nn);
    stray.ids.resize(1);
    stray.conn[0] = m.node_sets.at("xmin").front();  // a corner on x = 0, the others on x = 1: no cell spans 2 cells
    const std::vector<Index> stray_nodes = stray.conn;
    m.facet_sets["stray"] = {stray};
    EXPECT_EQ(orient_facets(m), 1);
    EXPECT_EQ(m.facet_sets["stray"].front().conn, stray_nodes);
    const auto& fixed = m.facet_sets.at("xmax");
    ASSERT_EQ(fixed.size(), outward.size());
    for (size_t k = 0; k < fixed.size(); ++k) EXPECT_EQ(fixed[k].conn, outward[k].conn);
    for (auto& b : fixed)
      for (Index e = 0; e < b.size(); ++e) {
        const Index* c = b.element(e);
        const Vec3 normal = (m.nodes[c[1]] - m.nodes[c[0]]).cross(m.nodes[c[2]] - m.nodes[c[0]]);
        EXPECT_GT(normal(0), 0) << "the facet's normal must point out of the box, to +x";
      }
  }
  // tri3 facets on tet10 cells: the corners match, the node counts do not.
  Mesh q = structured_box(ElementType::tet10, 1, 1, 1, 1.0, 1.0, 1.0);
  ElementBlock linear{ElementType::tri3, {}, {}};
  for (const ElementBlock& b : q.facet_sets.at("xmax"))
    for (Index e = 0; e < b.size(); ++e) linear.add({b.element(e)[0], b.element(e)[1], b.element(e)[2]}, b.ids[e]);
  const Index count = linear.size();
  q.facet_sets["xmax_linear"] = {linear};
  EXPECT_EQ(orient_facets(q), count);
}

// A region's or facet set's node set, made when the mesh has none of that name: its nodes,
// sorted, each once.
TEST(Mesh, NodeSetsAreCompletedFromRegionsAndFacetSets) {
  Mesh m = structured_box(ElementType::hex20, 2, 2, 3, 1.0, 1.0, 1.5);
  for (const std::string name : {"domain", "zmax"}) {
    const auto& blocks = name == "domain" ? m.regions.at(name) : m.facet_sets.at(name);
    std::vector<Index> expected;
    for (const ElementBlock& b : blocks) expected.insert(expected.end(), b.conn.begin(), b.conn.end());
    std::sort(expected.begin(), expected.end());
    expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
    m.node_sets.erase(name);
    m.complete_node_sets();
    EXPECT_EQ(m.node_sets.at(name), expected) << name;
  }
  EXPECT_EQ(static_cast<Index>(m.node_sets.at("domain").size()), m.num_nodes());
  for (Index n : m.node_sets.at("zmax")) EXPECT_NEAR(m.nodes[n](2), 1.5, 1e-12);
}

TEST(Mesh, MissingAndBrokenFilesGiveClearErrors) {
  EXPECT_THROW(read_gmsh("/nonexistent.msh"), InputError);
  const fs::path bad = fs::temp_directory_path() / "signorini_broken.geo";
  { std::ofstream(bad) << "Point(1) = {0,0,0;\n"; }
  try {
    read_gmsh(bad.string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("syntax error"), std::string::npos) << e.what();
  }
}

// Issue 17: a non-finite coordinate in a .msh (inf, nan, 1e999) stops the read with the
// file, the line and the node.
TEST(Mesh, NonFiniteCoordinatesAreRefusedWithTheLine) {
  std::ifstream in(kData + "/inverted.msh");
  std::stringstream ss;
  ss << in.rdbuf();
  for (const char* bad : {"inf", "nan", "1e999"}) {
    std::string text = ss.str();
    text.replace(text.find("\n7 1.5 0.5 0"), 12, std::string("\n7 1.5 ") + bad + " 0");
    const std::string path = (std::filesystem::temp_directory_path() / "signorini_nonfinite.msh").string();
    std::ofstream(path) << text;
    try {
      read_gmsh(path);
      ADD_FAILURE() << bad << ": accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("signorini_nonfinite.msh:16"), std::string::npos) << m;
      EXPECT_NE(m.find("node 7"), std::string::npos) << m;
      EXPECT_NE(m.find("non-finite"), std::string::npos) << m;
    }
    std::filesystem::remove(path);
  }
}

// A region's cells handed to a body leave the mesh (held once), counted still; a region taken
// twice or not in the mesh is an error, not an empty body.
TEST(Mesh, TakeRegionMovesTheCellsOut) {
  Mesh m = structured_rectangle(ElementType::quad4, 3, 2, 1.0, 1.0);
  ASSERT_EQ(m.regions.count("domain"), 1u);
  const Index cells = m.num_cells();
  ASSERT_EQ(cells, 6);
  const std::vector<Index> first(m.regions.at("domain")[0].conn.begin(), m.regions.at("domain")[0].conn.begin() + 4);
  std::vector<ElementBlock> taken = m.take_region("domain");
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].size(), 6);
  EXPECT_TRUE(std::equal(first.begin(), first.end(), taken[0].conn.begin()));
  EXPECT_TRUE(m.regions.at("domain").empty());
  EXPECT_EQ(m.num_cells(), cells);
  EXPECT_THROW(m.take_region("domain"), Error);
  EXPECT_THROW(m.take_region("nowhere"), Error);
}
