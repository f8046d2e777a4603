// Helpers shared by the tests: a dense GlobalMatrix for tangent checks and a direct linear
// solve with per-node prescribed displacements (patch tests, manufactured solutions).
#pragma once
#include <functional>

#include "signorini/fem/body.hpp"
#include "signorini/fem/global_system.hpp"
#include "signorini/solver/linear_solver.hpp"

namespace signorini::test {

class DenseMatrix final : public GlobalMatrix {
 public:
  explicit DenseMatrix(Index n) : k(MatX::Zero(n, n)) {}
  void add(const Index* dofs, int n, const MatX& ke) override {
    // add() is called from the assembly's threads: serialize.
#pragma omp critical(signorini_dense_matrix)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (dofs[i] >= 0 && dofs[j] >= 0) k(dofs[i], dofs[j]) += ke(i, j);
  }
  MatX k;
};

// Largest difference between the columns of K and -dR/dz by central differences, where
// `residual(z)` returns R; K is the tangent -dR/dz.
template <typename Residual>
Real central_difference_error(const Residual& residual, const VecX& z, const MatX& K, Real h) {
  Real err = 0;
  for (Index j = 0; j < z.size(); ++j) {
    VecX zp = z, zm = z;
    zp(j) += h;
    zm(j) -= h;
    const VecX d = -(residual(zp) - residual(zm)) / (2 * h);
    err = std::max(err, (d - K.col(j)).cwiseAbs().maxCoeff());
  }
  return err;
}

inline std::vector<const ElementBlock*> cells_of(const Body& b) {
  std::vector<const ElementBlock*> v;
  for (auto& blk : b.blocks()) v.push_back(&blk);
  return v;
}

// Solves the linear problem fint(u) = fext with u = g(X) on the nodes flagged in `fixed`.
// One Newton step from `start` (zero if null); returns the full DOF vector.
inline VecX solve_with_prescribed(Body& body, const Mesh& mesh, const DofMap& dofs, const std::vector<char>& fixed,
                                  const std::function<Vec3(const Vec3&)>& g, const VecX& fext,
                                  const VecX* start = nullptr) {
  SparseSystem sys;
  sys.build_pattern(dofs, cells_of(body));
  VecX u = start ? *start : VecX::Zero(dofs.num_dofs());
  std::vector<char> constrained(dofs.num_dofs(), 0);
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if (fixed[n] && dofs.has_dofs(n)) {
      Vec3 v = g(mesh.nodes[n]);
      for (int i = 0; i < dofs.dofs_per_node(); ++i) {
        u(dofs.dof(n, i)) = v(i);
        constrained[dofs.dof(n, i)] = 1;
      }
    }
  VecX fint = VecX::Zero(dofs.num_dofs());
  sys.zero();
  body.assemble(mesh.nodes, u, dofs, fint, &sys);
  VecX r = fext - fint;
  for (Index i = 0; i < r.size(); ++i)
    if (constrained[i]) r(i) = 0;
  sys.apply_dirichlet(constrained, sys.mean_abs_diagonal());
  AutoLinearSolver solver("auto");
  VecX du;
  solver.solve(sys.matrix(), true, r, du);
  return u + du;
}

}  // namespace signorini::test

#include "signorini/fem/model.hpp"

namespace signorini::test {

// A one-body model on a mesh whose region is "domain" (structured meshes).
inline Model model_on(Mesh mesh, AnalysisSettings s, std::shared_ptr<Material> mat) {
  Model m;
  m.title = "test";
  m.settings = s;
  m.mesh = std::move(mesh);
  orient_facets(m.mesh);
  m.mesh.complete_node_sets();
  m.bodies.push_back(std::make_unique<Body>("body", m.mesh.regions["domain"], std::move(mat), s));
  return m;
}

inline DirichletCondition fix(const std::string& set, int comp, Real value = 0) {
  return DirichletCondition{set, comp, std::nullopt, value, ""};
}

}  // namespace signorini::test

#include "signorini/mesh/structured.hpp"

namespace signorini::test {

// Two blocks in one mesh: `lower` (regions/sets prefixed "lower_") on [0, w] x [0, h] and
// `upper` ("upper_") shifted by `offset`. Non-matching when the cell counts differ.
// `upper_type`: the upper block's cell type when it differs from the lower one's; `upper_w`:
// its width when it differs (0: w).
inline Mesh two_blocks(ElementType type, int nl, int nu, Real w, Real h, const Vec3& offset, bool three_d = false,
                       ElementType upper_type = ElementType::point1, int layers = 2, Real upper_w = 0) {
  const ElementType ut = upper_type == ElementType::point1 ? type : upper_type;
  const Real wu = upper_w > 0 ? upper_w : w;
  Mesh a = three_d ? structured_box(type, nl, nl, layers, w, w, h) : structured_rectangle(type, nl, layers, w, h);
  StructuredOptions o;
  o.origin = offset;
  Mesh b = three_d ? structured_box(ut, nu, nu, layers, wu, wu, h, o) : structured_rectangle(ut, nu, layers, wu, h, o);
  Mesh m;
  m.dim = a.dim;
  m.nodes = a.nodes;
  m.nodes.insert(m.nodes.end(), b.nodes.begin(), b.nodes.end());
  for (Index i = 0; i < m.num_nodes(); ++i) m.node_ids.push_back(i + 1);
  const Index shift = a.num_nodes();
  auto add = [&](const Mesh& src, const std::string& prefix, Index sh) {
    for (auto& [name, blocks] : src.regions) {
      auto copy = blocks;
      for (auto& blk : copy)
        for (auto& c : blk.conn) c += sh;
      m.regions[prefix + name] = copy;
    }
    for (auto& [name, blocks] : src.facet_sets) {
      auto copy = blocks;
      for (auto& blk : copy)
        for (auto& c : blk.conn) c += sh;
      m.facet_sets[prefix + name] = copy;
    }
    for (auto& [name, nodes] : src.node_sets) {
      auto copy = nodes;
      for (auto& c : copy) c += sh;
      m.node_sets[prefix + name] = copy;
    }
  };
  add(a, "lower_", 0);
  add(b, "upper_", shift);
  return m;
}

// Two plane-strain quad4 blocks 1 x 0.5 (lower 3, upper 4 cells wide), the upper one on top of
// the lower one: bodies "lower" and "upper" with their own materials (null: rigid).
inline Model two_block_model(std::shared_ptr<Material> lower, std::shared_ptr<Material> upper) {
  AnalysisSettings s;
  Model m;
  m.settings = s;
  m.mesh = two_blocks(ElementType::quad4, 3, 4, 1.0, 0.5, Vec3(0, 0.5, 0));
  orient_facets(m.mesh);
  m.bodies.push_back(std::make_unique<Body>("lower", m.mesh.regions["lower_domain"], std::move(lower), s));
  m.bodies.push_back(std::make_unique<Body>("upper", m.mesh.regions["upper_domain"], std::move(upper), s));
  return m;
}

}  // namespace signorini::test

namespace signorini::test {
// Current positions X + u for the displacement part of z.
inline std::vector<Vec3> cells_of_positions(const Mesh& mesh, const DofMap& dofs, const VecX& z) {
  std::vector<Vec3> x = mesh.nodes;
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if (dofs.has_dofs(n))
      for (int d = 0; d < dofs.dofs_per_node(); ++d) x[n](d) += z(dofs.dof(n, d));
  return x;
}
}  // namespace signorini::test
