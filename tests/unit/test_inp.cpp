// The CalculiX / Abaqus .inp reader (issue 17, item 1): element node orders and face numbers
// of every element type against the Abaqus conventions (Abaqus Analysis User's Guide, "Solid
// (continuum) elements": node ordering and face numbering figures; the CalculiX manual, section
// 6.2, repeats them), the translation of boundary conditions, loads, steps and materials, and
// clear errors naming file, line and keyword.
#include <gtest/gtest.h>

#include <tuple>

#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/io/deck.hpp"
#include "signorini/io/inp_reader.hpp"

using namespace signorini;
namespace fs = std::filesystem;

namespace {

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("signorini_inp_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

struct AbaqusElement {
  std::string name;
  ElementType type;
  std::vector<std::array<int, 2>> mid_edges;       // Abaqus order of the mid-edge nodes (0-based corners)
  std::vector<std::vector<int>> faces;              // S1, S2, ...: corner nodes (1-based), Abaqus
};

std::vector<AbaqusElement> catalogue() {
  using T = ElementType;
  const std::vector<std::vector<int>> tri{{1, 2}, {2, 3}, {3, 1}}, quad{{1, 2}, {2, 3}, {3, 4}, {4, 1}},
      tet{{1, 2, 3}, {1, 4, 2}, {2, 4, 3}, {3, 4, 1}},
      hex{{1, 2, 3, 4}, {5, 8, 7, 6}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 8, 4}, {4, 8, 5, 1}};
  return {{"CPE3", T::tri3, {}, tri},
          {"CPS6", T::tri6, {{0, 1}, {1, 2}, {2, 0}}, tri},
          {"CAX4", T::quad4, {}, quad},
          {"CPE8R", T::quad8, {{0, 1}, {1, 2}, {2, 3}, {3, 0}}, quad},
          {"C3D4", T::tet4, {}, tet},
          {"C3D10", T::tet10, {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}, tet},
          {"C3D8", T::hex8, {}, hex},
          {"C3D20R", T::hex20, {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}},
           hex}};
}

}  // namespace

// One element of each type, its corners at Signorini's reference corners and its mid-edge
// nodes at the midpoints of the Abaqus edges: after reading, local node k must sit at the
// reference coordinates of node k, and face S<j> must hold the Abaqus corners of S<j>, with
// its normal pointing out of the element.
TEST(Inp, ElementNodeOrderAndFaceNumbersFollowAbaqus) {
  log::set_level(log::Level::warning);
  for (const AbaqusElement& a : catalogue()) {
    const ElementInfo& info = element_info(a.type);
    std::vector<Vec3> x(info.ref_coords.begin(), info.ref_coords.begin() + info.num_corners);
    for (auto& e : a.mid_edges) x.push_back(0.5 * (x[e[0]] + x[e[1]]));
    ASSERT_EQ(static_cast<int>(x.size()), info.num_nodes) << a.name;
    std::string inp = "*NODE\n";
    for (size_t i = 0; i < x.size(); ++i) inp += fmt::format("{}, {}, {}, {}\n", i + 1, x[i](0), x[i](1), x[i](2));
    inp += "*ELEMENT, TYPE=" + a.name + ", ELSET=E\n7";
    for (size_t i = 0; i < x.size(); ++i) inp += (i == 15 ? ",\n" : ", ") + std::to_string(i + 1);  // C3D20: continued
    inp += "\n";
    for (size_t f = 0; f < a.faces.size(); ++f) inp += fmt::format("*SURFACE, NAME=F{}\nE, S{}\n", f + 1, f + 1);
    const fs::path p = write_temp(a.name + ".inp", inp);
    Mesh m = read_inp_mesh(p.string());
    fs::remove(p);
    ASSERT_EQ(m.regions.count("E"), 1u) << a.name;
    const ElementBlock& b = m.regions.at("E").front();
    ASSERT_EQ(b.type, a.type) << a.name;
    EXPECT_EQ(b.ids[0], 7);
    for (int k = 0; k < info.num_nodes; ++k)
      EXPECT_LT((m.nodes[b.element(0)[k]] - info.ref_coords[k]).norm(), 1e-12) << a.name << " node " << k;
    MeshCheck chk = check_and_orient(m);
    EXPECT_EQ(chk.reoriented, 0) << a.name;
    EXPECT_TRUE(chk.inverted.empty() && chk.degenerate.empty()) << a.name;
    Vec3 centre = Vec3::Zero();
    for (int k = 0; k < info.num_corners; ++k) centre += m.nodes[b.element(0)[k]] / info.num_corners;
    for (size_t f = 0; f < a.faces.size(); ++f) {
      const auto& blocks = m.facet_sets.at("F" + std::to_string(f + 1));
      ASSERT_EQ(blocks.size(), 1u);
      const ElementBlock& fb = blocks[0];
      ASSERT_EQ(fb.size(), 1);
      const int nc = element_info(fb.type).num_corners;
      std::set<Index> got, want;
      for (int k = 0; k < nc; ++k) got.insert(m.node_ids[fb.element(0)[k]]);
      for (int n : a.faces[f]) want.insert(n);
      EXPECT_EQ(got, want) << a.name << " S" << f + 1;
      // every node of the facet lies on it (mid-side nodes included) and the normal points out
      const Vec3 p0 = m.nodes[fb.element(0)[0]], p1 = m.nodes[fb.element(0)[1]];
      Vec3 n = info.dim == 2 ? Vec3((p1 - p0)(1), -(p1 - p0)(0), 0)
                             : Vec3((p1 - p0).cross(m.nodes[fb.element(0)[2]] - p0));
      Vec3 fc = Vec3::Zero();
      for (int k = 0; k < nc; ++k) fc += m.nodes[fb.element(0)[k]] / nc;
      EXPECT_GT(n.dot(fc - centre), 0) << a.name << " S" << f + 1 << ": normal not outward";
      for (int k = 0; k < fb.nodes_per_element(); ++k)
        EXPECT_NEAR(n.normalized().dot(m.nodes[fb.element(0)[k]] - p0), 0, 1e-12) << a.name << " S" << f + 1;
    }
  }
}

namespace {
const char* kPlate = R"(*HEADING
plate in two steps
** a comment
*NODE, NSET=ALLN
1, 0, 0
2, 1, 0
3, 2, 0
4, 0, 1
5, 1, 1
6, 2, 1
*ELEMENT, TYPE=CPS4, ELSET=PLATE
1, 1, 2, 5, 4
2, 2, 3, 6, 5
*NSET, NSET=LEFT
1, 4
*NSET, NSET=RIGHT
3, 6
*ELSET, ELSET=E2, GENERATE
2, 2, 1
*MATERIAL, NAME=ST
*ELASTIC
210000., 0.3
*PLASTIC
240., 0.
340., 0.1
*SOLID SECTION, ELSET=PLATE, MATERIAL=ST
2.
*BOUNDARY
LEFT, ENCASTRE
*STEP, INC=50
*STATIC
0.1, 1., 1e-4, 0.5
*CLOAD
RIGHT, 1, 10.
*DLOAD
E2, P2, 5.
*END STEP
*STEP
*STATIC
*BOUNDARY, OP=NEW
LEFT, 1, 1
1, 2, 2
*CLOAD
RIGHT, 2, -3.
*NODE PRINT, NSET=RIGHT
U
*CONTROLS, PARAMETERS=FIELD
0.1, 0.2
*END STEP
)";
}  // namespace

// Boundary conditions and loads carry over from step to step as in Abaqus (OP=MOD), OP=NEW
// removes them; a *CLOAD acts on every node of its set (Signorini's force is shared by the
// nodes: the total is written); *DLOAD P<k> becomes a pressure on a facet set of face S<k>;
// *STATIC's times become fractions of the step; a two-point *PLASTIC table is linear hardening.
TEST(Inp, TranslatesStepsLoadsAndMaterials) {
  log::set_level(log::Level::warning);
  const fs::path p = write_temp("plate.inp", kPlate);
  InpDeck d = read_inp(p.string());
  EXPECT_NE(d.yaml.find("model: j2_plasticity, E: 210000, nu: 0.29999999999999999, yield_stress: 240, hardening: "
                        "{isotropic: {type: linear, H: 1000}}"),
            std::string::npos)
      << d.yaml;
  Registry r = default_registry();
  Model m = read_deck(p.string(), r);
  fs::remove(p);
  EXPECT_EQ(m.title, "plate in two steps");
  EXPECT_EQ(m.settings.dimension, Dimension::plane_stress);
  EXPECT_DOUBLE_EQ(m.settings.thickness, 2.0);
  ASSERT_EQ(m.steps.size(), 2u);
  const Step& s1 = m.steps[0];
  EXPECT_DOUBLE_EQ(s1.initial_increment, 0.1);
  EXPECT_DOUBLE_EQ(s1.min_increment, 1e-4);
  EXPECT_DOUBLE_EQ(s1.max_increment, 0.5);
  EXPECT_EQ(s1.max_increments, 50);
  ASSERT_EQ(s1.dirichlet.size(), 2u);
  for (auto& dc : s1.dirichlet) EXPECT_EQ(dc.set, "LEFT");
  ASSERT_EQ(s1.loads.size(), 2u);
  EXPECT_EQ(s1.loads[0].kind, LoadKind::nodal_force);
  EXPECT_EQ(s1.loads[0].set, "RIGHT");
  EXPECT_DOUBLE_EQ(s1.loads[0].vector(0), 20.0);  // 10 on each of its 2 nodes
  EXPECT_EQ(s1.loads[1].kind, LoadKind::pressure);
  EXPECT_DOUBLE_EQ(s1.loads[1].pressure, 5.0);
  const auto& facets = m.mesh.facet_sets.at(s1.loads[1].set);  // face S2 of element 2: nodes 3 and 6
  ASSERT_EQ(facets.size(), 1u);
  std::set<Index> ids{m.mesh.node_ids[facets[0].element(0)[0]], m.mesh.node_ids[facets[0].element(0)[1]]};
  EXPECT_EQ(ids, (std::set<Index>{3, 6}));
  const Step& s2 = m.steps[1];
  EXPECT_DOUBLE_EQ(s2.initial_increment, 1.0);
  ASSERT_EQ(s2.dirichlet.size(), 2u);  // OP=NEW: LEFT ux and node 1 uy only
  std::set<std::pair<std::string, int>> bcs;
  for (auto& dc : s2.dirichlet) bcs.insert({dc.set, dc.component});
  EXPECT_EQ(bcs, (std::set<std::pair<std::string, int>>{{"LEFT", 0}, {"node:1", 1}}));
  ASSERT_EQ(s2.loads.size(), 2u);  // the force modified in y, the pressure carried over
  EXPECT_DOUBLE_EQ(s2.loads[0].vector(0), 20.0);
  EXPECT_DOUBLE_EQ(s2.loads[0].vector(1), -6.0);
  EXPECT_DOUBLE_EQ(s2.loads[1].pressure, 5.0);
}

// *CONTACT PAIR with the same surface on both sides is self-contact (surface: S, self: true).
TEST(Inp, SameSurfaceOnBothSidesIsSelfContact) {
  log::set_level(log::Level::warning);
  std::string text = kPlate;
  const std::string at = "*BOUNDARY\nLEFT, ENCASTRE\n";
  ASSERT_NE(text.find(at), std::string::npos);
  text.insert(text.find(at), "*SURFACE, NAME=EDGE\nPLATE, S3\n*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, "
                             "PRESSURE-OVERCLOSURE=HARD\n*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE\nEDGE, EDGE\n");
  const fs::path p = write_temp("self.inp", text);
  Registry r = default_registry();
  Model m = read_deck(p.string(), r);
  fs::remove(p);
  ASSERT_EQ(m.contacts.size(), 1u);
  EXPECT_TRUE(m.contacts[0].self);
  EXPECT_EQ(m.contacts[0].slave, "EDGE");
  EXPECT_EQ(m.contacts[0].master, "EDGE");
  EXPECT_EQ(m.contacts[0].discretization, "node_to_segment");
  // Mortar on one surface: HARD (Lagrange multipliers) and LINEAR (penalty) both read.
  std::string mortar = text;
  mortar.replace(mortar.find("TYPE=NODE TO SURFACE"), 20, "TYPE=MORTAR");
  std::string linear = mortar;
  linear.replace(linear.find("PRESSURE-OVERCLOSURE=HARD"), 25, "PRESSURE-OVERCLOSURE=LINEAR\n1e5");
  for (const auto& [name, deck, method] : {std::tuple{"self_mortar_hard.inp", mortar, "lagrange"},
                                           std::tuple{"self_mortar_linear.inp", linear, "penalty"}}) {
    const fs::path pm = write_temp(name, deck);
    Model mm = read_deck(pm.string(), r);
    fs::remove(pm);
    ASSERT_EQ(mm.contacts.size(), 1u) << name;
    EXPECT_TRUE(mm.contacts[0].self) << name;
    EXPECT_EQ(mm.contacts[0].discretization, "mortar") << name;
    EXPECT_EQ(mm.contacts[0].method, method) << name;
  }
}

// Every bad input gets one message naming the file, the line and the keyword.
TEST(Inp, ErrorsNameFileLineAndKeyword) {
  log::set_level(log::Level::quiet);
  const std::string mesh = "*NODE\n1, 0, 0\n2, 1, 0\n3, 1, 1\n4, 0, 1\n*ELEMENT, TYPE=CPE4, ELSET=B\n1, 1, 2, 3, 4\n";
  const std::string model = "*MATERIAL, NAME=M\n*ELASTIC\n1000, 0.3\n*SOLID SECTION, ELSET=B, MATERIAL=M\n";
  const std::string step = "*STEP\n*STATIC\n*BOUNDARY\n1, 1, 2\n*END STEP\n";
  struct Case {
    std::string text, where, key, what;
  };
  std::vector<Case> cases{
      {mesh + "*FOO, BAR=1\n" + model + step, ":8", "*FOO", "not available"},
      {"*NODE\n1, 0, inf\n", ":2", "*NODE", "finite"},
      {"*NODE\n1, 0, .nan\n", ":2", "*NODE", "got '.nan'"},
      {"*NODE\n1, 0, 1e999\n", ":2", "*NODE", "finite"},
      {"*NODE\n1, 0, 0\n*ELEMENT, TYPE=CPE4\n1, 1, 2, 3, 4\n", ":4", "*ELEMENT", "node 2"},
      {"*NODE\n1, 0, 0\n*ELEMENT, TYPE=S4R\n1, 1, 1, 1, 1\n", ":3", "*ELEMENT", "S4R is not available"},
      {mesh + model + "*STEP\n*DYNAMIC\n*END STEP\n", ":13", "*DYNAMIC", "procedure"},
      {mesh + model + "*STEP\n*STATIC\n", ":12", "*STEP", "not closed"},
      {mesh + model + "*STEP\n*STATIC\n*BOUNDARY\nNOPE, 1, 1\n*END STEP\n", ":15", "*BOUNDARY", "no node set named 'NOPE'"},
      {mesh + model + "*STEP\n*STATIC\n*BOUNDARY\n1, 4, 6\n*END STEP\n", ":15", "*BOUNDARY", "degree of freedom 4"},
      {mesh + model + "*STEP\n*STATIC\n*BOUNDARY\n1, ZSYMM\n*END STEP\n", ":15", "*BOUNDARY", "no meaning in a 2D"},
      {mesh + model + "*STEP\n*STATIC\n*BOUNDARY\n1, CLAMPED\n*END STEP\n", ":15", "*BOUNDARY", "got 'CLAMPED'"},
      {mesh + "*MATERIAL, NAME=M\n*ELASTIC\n1000, 0.3, 20\n" + model.substr(model.find("*SOLID")) + step, ":10",
       "*ELASTIC", "temperature"},
      {mesh + model + "*SURFACE, NAME=S\nB, S9\n" + step, ":13", "*SURFACE", "no face S9"},
      {mesh + "*MATERIAL, NAME=M\n*ELASTIC\n1000, 0.3\n*SOLID SECTION, ELSET=B, MATERIAL=Q\n" + step, ":11",
       "*SOLID SECTION", "no *MATERIAL named Q"},
      // A rule of the translated deck (Poisson's ratio out of range) points at the .inp line.
      {mesh + "*MATERIAL, NAME=M\n*ELASTIC\n1000, 0.7\n" + model.substr(model.find("*SOLID")) + step, ":9",
       "*ELASTIC", "nu"},
      {mesh + model + "*STEP\n*STATIC\n0.1, 1\n*BOUNDARY, AMPLITUDE=A\n1, 1, 2\n*END STEP\n", ":15", "*BOUNDARY",
       "AMPLITUDE"},
      {"*INCLUDE, INPUT=does_not_exist.inp\n", ":1", "*INCLUDE", "is not a readable file"},
      {"*INCLUDE, INPUT=/dev/zero\n", ":1", "*INCLUDE", "is not a readable file"},
      {"*INCLUDE, INPUT=" + std::string(300, 'a') + "\n", ":1", "*INCLUDE", "is not a readable file"},
      // Found in review: ids beyond 2^31, a face on a surface's second card, a set naming itself.
      {"*NODE\n9223372036854775807, 0, 0\n", ":2", "*NODE", "from 1 to 2147483647"},
      {mesh + "*NSET, NSET=A, GENERATE\n1, 9223372036854775800, 5\n", ":9", "*NSET", "from 1 to 2147483647"},
      {mesh + model + "*SURFACE, NAME=S\nB, S1\nB, S2\n*SURFACE, NAME=S\nB, S9\n" + step, ":16", "*SURFACE", "no face S9"},
  };
  Registry r = default_registry();
  int i = 0;
  for (const Case& c : cases) {
    const fs::path p = write_temp("bad" + std::to_string(i++) + ".inp", c.text);
    try {
      read_deck(p.string(), r);
      ADD_FAILURE() << "accepted:\n" << c.text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), p.string() + c.where) << e.what();
      EXPECT_EQ(e.key(), c.key) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.what), std::string::npos) << e.what();
    }
    fs::remove(p);
  }
}

// A YAML deck may take its mesh from an .inp: element sets are regions (EALL all elements),
// node sets and NALL node sets, element-face surfaces facet sets, and a node surface also the
// exterior facets its nodes cover.
TEST(Inp, MeshForAYamlDeck) {
  log::set_level(log::Level::warning);
  const fs::path p = write_temp("m.inp", "*NODE\n1, 0, 0\n2, 1, 0\n3, 1, 1\n4, 0, 1\n5, 2, 0\n6, 2, 1\n"
                                         "*ELEMENT, TYPE=CPE4, ELSET=B\n1, 1, 2, 3, 4\n2, 2, 5, 6, 3\n"
                                         "*NSET, NSET=TOP\n3, 4, 6\n*SURFACE, NAME=TOPS, TYPE=NODE\nTOP\n"
                                         "*SURFACE, NAME=ALLSIDES\nB\n");
  Mesh m = read_inp_mesh(p.string());
  // A YAML deck on it; order and parameters belong to .geo meshes and are refused here.
  const fs::path y = write_temp("on_inp.yaml", "analysis: {dimension: plane_strain}\nmesh: {file: " + p.string() +
                                                   ", order: 2}\nmaterials: {s: {model: linear_elastic, E: 1, nu: 0.3}}\n"
                                                   "bodies: [{name: b, region: B, material: s}]\nsteps: [{name: s}]\n");
  Registry r = default_registry();
  try {
    read_deck(y.string(), r);
    ADD_FAILURE() << "order on an .inp mesh accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "mesh.order") << e.what();
  }
  fs::remove(y);
  fs::remove(p);
  EXPECT_EQ(m.regions.at("EALL")[0].size(), 2);
  EXPECT_EQ(m.node_sets.at("NALL").size(), 6u);
  EXPECT_EQ(m.node_sets.at("TOP").size(), 3u);
  EXPECT_EQ(m.facet_sets.at("TOPS")[0].size(), 2);      // the two top edges
  EXPECT_EQ(m.facet_sets.at("ALLSIDES")[0].size(), 6);  // the boundary of the 2 x 1 strip
}

// Found in review: a set that names itself doubles at each card (now a set, not a list), and
// CalculiX's predefined NALL and EALL may be named before any deck defines them.
TEST(Inp, SetsNamingThemselvesAndPredefinedSets) {
  log::set_level(log::Level::warning);
  std::string text = "*NODE\n1, 0, 0\n2, 1, 0\n3, 1, 1\n4, 0, 1\n*ELEMENT, TYPE=CPE4, ELSET=B\n1, 1, 2, 3, 4\n"
                     "*NSET, NSET=A\n1, 2\n";
  for (int i = 0; i < 40; ++i) text += "*NSET, NSET=A\nA, A\n";
  text += "*NSET, NSET=BOTH\nNALL\n*ELSET, ELSET=E\nEALL\n*SURFACE, NAME=OUT\nEALL\n";
  const fs::path p = write_temp("selfsets.inp", text);
  Mesh m = read_inp_mesh(p.string());
  fs::remove(p);
  EXPECT_EQ(m.node_sets.at("A").size(), 2u);
  EXPECT_EQ(m.node_sets.at("BOTH").size(), 4u);
  EXPECT_EQ(m.regions.at("E")[0].size(), 1);
  EXPECT_EQ(m.facet_sets.at("OUT")[0].size(), 4);
}
