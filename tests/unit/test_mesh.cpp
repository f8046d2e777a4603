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
