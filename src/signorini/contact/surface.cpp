#include "signorini/contact/surface.hpp"

#include <algorithm>
#include <numbers>
#include <optional>
#include <map>

#include "signorini/contact/discretization/mortar.hpp"
#include "signorini/contact/discretization/segment_to_segment.hpp"
#include "signorini/contact/geometry/facet_projection.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

std::vector<Index> MasterSurface::neighbourhood(Index f) const {
  std::vector<Index> v;
  for (Index n : facets[f])
    for (Index g : node_facets[n]) v.push_back(g);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

Vec3 MasterSurface::node_normal(Index node, const std::vector<Vec3>& x, int dim) const {
  Vec3 n = Vec3::Zero();
  for (Index f : node_facets[node]) {
    std::vector<Vec3> xf;
    for (Index m : facets[f]) xf.push_back(x[m]);
    // Normal at the facet's parameter of this node.
    const auto& nodes = facets[f];
    const int k = static_cast<int>(std::find(nodes.begin(), nodes.end(), node) - nodes.begin());
    n += facet_normal(type[f], xf, element_info(type[f]).ref_coords[k], dim);
  }
  return n.norm() > 0 ? Vec3(n.normalized()) : n;
}

void MasterSurface::node_normal_jacobian_3d(Index node, const std::vector<Vec3>& x, Vec3& n, std::vector<Index>& nodes,
                                            MatX& jacobian) const {
  nodes.clear();
  for (Index f : node_facets[node])
    for (Index m : facets[f])
      if (std::find(nodes.begin(), nodes.end(), m) == nodes.end()) nodes.push_back(m);
  const Index cols = 3 * static_cast<Index>(nodes.size());
  MatX ds = MatX::Zero(3, cols);  // d s / dx
  Vec3 s = Vec3::Zero();
  VecX N;
  MatX dN;
  for (Index f : node_facets[node]) {
    const auto& fn = facets[f];
    const int k = static_cast<int>(std::find(fn.begin(), fn.end(), node) - fn.begin());
    shape_functions(type[f], element_info(type[f]).ref_coords[k], N, dN);
    Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero();
    for (size_t i = 0; i < fn.size(); ++i) a1 += dN(i, 0) * x[fn[i]], a2 += dN(i, 1) * x[fn[i]];
    const Vec3 m = a1.cross(a2);
    const Real len = m.norm();
    if (!(len > 0)) continue;
    const Vec3 nf = m / len;
    s += nf;
    const Mat3 P = (Mat3::Identity() - nf * nf.transpose()) / len;
    const Mat3 A1 = cross_matrix(a1), A2 = cross_matrix(a2);
    for (size_t i = 0; i < fn.size(); ++i) {
      const Index c = std::find(nodes.begin(), nodes.end(), fn[i]) - nodes.begin();
      // dm/dx_i = N_i,1 (-[a2]x) + N_i,2 [a1]x.
      ds.middleCols(3 * c, 3) += P * (dN(i, 1) * A1 - dN(i, 0) * A2);
    }
  }
  const Real sl = s.norm();
  if (!(sl > 0)) {
    n.setZero();
    jacobian.setZero(3, cols);
    return;
  }
  n = s / sl;
  jacobian = (Mat3::Identity() - n * n.transpose()) / sl * ds;
}

FacetBasis MasterSurface::basis(Index f) const {
  if (!patch.empty()) return FacetBasis::bicubic(&patch[f]);
  if (!smooth()) return FacetBasis(type[f]);
  return FacetBasis::hermite(prev[f] >= 0, next[f] >= 0);
}

std::vector<Index> MasterSurface::basis_nodes(Index f) const {
  if (!patch.empty()) return patch_nodes[f];
  if (!smooth()) return facets[f];
  std::vector<Index> v;
  if (prev[f] >= 0) v.push_back(prev[f]);
  v.push_back(facets[f][0]);
  v.push_back(facets[f][1]);
  if (next[f] >= 0) v.push_back(next[f]);
  return v;
}

namespace {

// A grid point of a bicubic patch as a linear combination of mesh nodes.
using Combination = std::map<Index, Real>;

Combination extrapolate(const Combination& a, const Combination& b) {  // 2 a - b
  Combination c;
  for (auto [n, w] : a) c[n] += 2 * w;
  for (auto [n, w] : b) c[n] -= w;
  return c;
}

Vec3 quad_normal(const MasterSurface& m, Index f, const std::vector<Vec3>& x) {
  const auto& q = m.facets[f];
  return (x[q[2]] - x[q[0]]).cross(x[q[3]] - x[q[1]]).normalized();
}

// The node of quad g next to `from` other than `not_this` (-1 if g has no such node).
Index beside(const MasterSurface& m, Index g, Index from, Index not_this) {
  const auto& q = m.facets[g];
  for (int k = 0; k < 4; ++k)
    if (q[k] == from) {
      const Index a = q[(k + 1) % 4], b = q[(k + 3) % 4];
      return a != not_this ? a : b;
    }
  return -1;
}

// The one other quad sharing nodes a and b with facet f, within the kink angle of f; -1 if
// none (or several: not a manifold edge).
Index across(const MasterSurface& m, Index f, Index a, Index b, const std::vector<Vec3>& x, Real cos_max) {
  Index found = -1;
  int count = 0;
  for (Index g : m.node_facets[a]) {
    if (g == f) continue;
    const auto& q = m.facets[g];
    if (std::find(q.begin(), q.end(), b) == q.end()) continue;
    ++count;
    if (m.type[g] == ElementType::quad4 && quad_normal(m, g, x).dot(quad_normal(m, f, x)) >= cos_max) found = g;
  }
  return count == 1 ? found : -1;
}

void bicubic_patches(MasterSurface& m, const std::vector<Vec3>& x, Real cos_max) {
  m.patch.assign(m.size(), MatX());
  m.patch_nodes.assign(m.size(), {});
  for (Index f = 0; f < m.size(); ++f) {
    const auto& q = m.facets[f];
    // G[i][j]: i along xi (node 0 -> 1), j along eta (node 0 -> 3); the facet is the cell
    // [1, 2] x [1, 2].
    std::optional<Combination> G[4][4];
    auto node = [](Index n) { return Combination{{n, 1.0}}; };
    G[1][1] = node(q[0]), G[2][1] = node(q[1]), G[2][2] = node(q[2]), G[1][2] = node(q[3]);
    // Across each edge: the neighbour's two other nodes, beside the edge's ends.
    struct Side {
      int a_i, a_j, b_i, b_j, out_a_i, out_a_j, out_b_i, out_b_j;
    };
    const Side sides[4] = {{1, 1, 2, 1, 1, 0, 2, 0},   // eta = -1: edge 0-1
                           {1, 2, 2, 2, 1, 3, 2, 3},   // eta = +1: edge 3-2
                           {1, 1, 1, 2, 0, 1, 0, 2},   // xi = -1: edge 0-3
                           {2, 1, 2, 2, 3, 1, 3, 2}};  // xi = +1: edge 1-2
    bool has[4] = {false, false, false, false};
    for (int s = 0; s < 4; ++s) {
      const Side& sd = sides[s];
      const Index a = G[sd.a_i][sd.a_j]->begin()->first, b = G[sd.b_i][sd.b_j]->begin()->first;
      const Index g = across(m, f, a, b, x, cos_max);
      if (g < 0) continue;
      const Index oa = beside(m, g, a, b), ob = beside(m, g, b, a);
      if (oa < 0 || ob < 0) continue;
      G[sd.out_a_i][sd.out_a_j] = node(oa);
      G[sd.out_b_i][sd.out_b_j] = node(ob);
      has[s] = true;
    }
    // Corners between two present sides: the diagonal quad's fourth node when the corner node
    // has exactly the four quads around it, else the parallelogram completion.
    const int corner[4][6] = {{0, 0, 1, 1, 0, 2},   // (i, j), the facet's node there (i, j), sides
                              {3, 0, 2, 1, 0, 3},
                              {0, 3, 1, 2, 1, 2},
                              {3, 3, 2, 2, 1, 3}};
    for (const auto& c : corner) {
      const int ci = c[0], cj = c[1], ni = c[2], nj = c[3];
      if (!has[c[4]] || !has[c[5]]) continue;
      const Index centre = G[ni][nj]->begin()->first;
      const Index u = G[ci][nj]->begin()->first, v = G[ni][cj]->begin()->first;  // along xi, along eta
      Index diag = -1;
      if (m.node_facets[centre].size() == 4)
        for (Index g : m.node_facets[centre]) {
          const auto& gq = m.facets[g];
          if (g == f || std::find(gq.begin(), gq.end(), u) == gq.end() || std::find(gq.begin(), gq.end(), v) == gq.end())
            continue;
          if (quad_normal(m, g, x).dot(quad_normal(m, f, x)) < cos_max) continue;
          for (Index n : gq)
            if (n != centre && n != u && n != v) diag = n;
        }
      if (diag >= 0) {
        G[ci][cj] = node(diag);
      } else {
        Combination p = *G[ci][nj];
        for (auto [n, w] : *G[ni][cj]) p[n] += w;
        p[centre] -= 1;
        G[ci][cj] = p;
      }
    }
    // Ghosts beyond missing sides: first along eta in the facet's columns, then along xi in
    // every row (which fills the remaining corners from points that now exist).
    for (int i = 1; i <= 2; ++i) {
      if (!G[i][0]) G[i][0] = extrapolate(*G[i][1], *G[i][2]);
      if (!G[i][3]) G[i][3] = extrapolate(*G[i][2], *G[i][1]);
    }
    for (int j = 0; j < 4; ++j) {
      if (!G[0][j]) G[0][j] = has[2] ? extrapolate(*G[0][j == 0 ? 1 : 2], *G[0][j == 0 ? 2 : 1])
                                     : extrapolate(*G[1][j], *G[2][j]);
      if (!G[3][j]) G[3][j] = has[3] ? extrapolate(*G[3][j == 0 ? 1 : 2], *G[3][j == 0 ? 2 : 1])
                                     : extrapolate(*G[2][j], *G[1][j]);
    }
    std::vector<Index>& nodes = m.patch_nodes[f];
    std::map<Index, int> col;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        for (auto [n, w] : *G[i][j])
          if (w != 0 && !col.count(n)) col[n] = static_cast<int>(nodes.size()), nodes.push_back(n);
    MatX& P = m.patch[f];
    P.setZero(16, static_cast<Index>(nodes.size()));
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i)
        for (auto [n, w] : *G[i][j])
          if (w != 0) P(i + 4 * j, col[n]) += w;
  }
}

}  // namespace

void smooth_master_surface(MasterSurface& m, const std::vector<Vec3>& x) {
  bool quads = m.size() > 0;
  for (ElementType t : m.type) quads = quads && t == ElementType::quad4;
  if (quads) {
    bicubic_patches(m, x, std::cos(kSmoothingMaxKink * std::numbers::pi / 180));
    return;
  }
  for (ElementType t : m.type)
    if (t != ElementType::line2)
      throw Error("smoothing: hermite needs a master surface of line2 facets (2D) or quad4 facets (3D) (found " +
                  element_info(t).name + ")");
  const Real cos_max = std::cos(kSmoothingMaxKink * std::numbers::pi / 180);
  m.prev.assign(m.size(), -1);
  m.next.assign(m.size(), -1);
  for (Index f = 0; f < m.size(); ++f) {
    const Index a = m.facets[f][0], b = m.facets[f][1];
    const Vec3 t = (x[b] - x[a]).normalized();
    // The neighbour across node a is the facet that ends at a (consistent orientation); one
    // across a kink sharper than kSmoothingMaxKink is left out.
    for (Index g : m.node_facets[a])
      if (g != f && m.facets[g][1] == a && (x[a] - x[m.facets[g][0]]).normalized().dot(t) >= cos_max)
        m.prev[f] = m.facets[g][0];
    for (Index g : m.node_facets[b])
      if (g != f && m.facets[g][0] == b && (x[m.facets[g][1]] - x[b]).normalized().dot(t) >= cos_max)
        m.next[f] = m.facets[g][1];
  }
}

MasterSurface make_master_surface(const Mesh& mesh, const std::string& set) {
  MasterSurface m;
  m.node_facets.resize(mesh.num_nodes());
  for (const ElementBlock& b : mesh.facet_sets.at(set))
    for (Index e = 0; e < b.size(); ++e) {
      const Index f = m.size();
      m.type.push_back(b.type);
      m.facets.emplace_back(b.element(e), b.element(e) + b.nodes_per_element());
      for (Index n : m.facets.back()) m.node_facets[n].push_back(f);
    }
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if (!m.node_facets[n].empty()) m.nodes.push_back(n);
  return m;
}

SlaveBasis slave_basis(const std::string& discretization, bool rigid_master, bool three_d, const std::string& method) {
  if (rigid_master) return SlaveBasis::standard;
  // segment_to_segment, and Nitsche on mortar integration (the same points' class).
  if (discretization == "segment_to_segment" || (discretization == "mortar" && method == "nitsche"))
    return SlaveBasis::modified;
  if (discretization == "mortar" && three_d) return SlaveBasis::positive;
  return SlaveBasis::standard;
}

SlaveSurface make_slave_surface(const Mesh& mesh, const std::string& set, const AnalysisSettings& settings,
                                SlaveBasis basis) {
  const int dim = settings.spatial_dim();
  std::vector<Real> w(mesh.num_nodes(), 0.0), area(mesh.num_nodes(), 0.0);
  std::vector<char> used(mesh.num_nodes(), 0), on_axis(mesh.num_nodes(), 0), axis_quadratic(mesh.num_nodes(), 0);
  for (const ElementBlock& b : mesh.facet_sets.at(set)) {
    const ElementInfo& info = element_info(b.type);
    const QuadratureRule rule = quadrature_rule(b.type, 2 * info.order + 1);
    for (Index e = 0; e < b.size(); ++e) {
      const Index* c = b.element(e);
      for (auto& q : rule) {
        VecX N;
        MatX dN;
        shape_functions(b.type, q.xi, N, dN);
        VecX Nw = N;
        if (basis == SlaveBasis::modified) modified_shape_functions(b.type, N, Nw);
        else if (basis == SlaveBasis::positive) mortar_positive_basis(N, Nw);
        Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero(), x = Vec3::Zero();
        for (int i = 0; i < info.num_nodes; ++i) {
          x += N(i) * mesh.nodes[c[i]];
          a1 += dN(i, 0) * mesh.nodes[c[i]];
          if (dim == 3) a2 += dN(i, 1) * mesh.nodes[c[i]];
        }
        Real da = (dim == 2 ? a1.norm() : a1.cross(a2).norm()) * q.weight;
        if (settings.dimension == Dimension::axisymmetric) da *= 2 * std::numbers::pi * x(0);
        else if (dim == 2) da *= settings.thickness;
        for (int i = 0; i < info.num_nodes; ++i) w[c[i]] += Nw(i) * da, area[c[i]] += std::abs(da);
      }
      for (int i = 0; i < info.num_nodes; ++i) {
        used[c[i]] = 1;
        // The axis node of a quadratic facet in axisymmetry: int N r dA is zero on a straight
        // facet and O(h/R) of the facet's area on a curved one, a pressure lambda / w without
        // meaning; it gets weight 0 (no constraint, no force), like the straight case.
        if (settings.dimension == Dimension::axisymmetric &&
            std::abs(mesh.nodes[c[i]](0)) <= 1e-12 * (mesh.nodes[c[0]] - mesh.nodes[c[1]]).norm()) {
          on_axis[c[i]] = 1;
          if (info.order >= 2) axis_quadratic[c[i]] = 1;
        }
      }
    }
  }
  SlaveSurface s;
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if (used[n]) {
      // A weight that is zero but for round-off is zero: such a node carries no contact force.
      if (std::abs(w[n]) <= 1e-12 * area[n] || axis_quadratic[n]) w[n] = 0;
      if (!(w[n] > 0) && !on_axis[n])
        throw Error("slave surface '" + set + "': node " + std::to_string(mesh.node_ids[n]) +
                    " gets a non-positive contact area from its facets (tri6 and quad8 corner nodes do): "
                    "node-to-segment needs linear facets (line2, tri3, quad4) or line3/quad9 on the slave side "
                    "(segment_to_segment takes every facet type, and mortar in 3D)");
      s.nodes.push_back(n);
      s.weights.push_back(w[n]);
    }
  return s;
}

ConstraintSet open_constraints(const SlaveSurface& slave) {
  ConstraintSet out(slave.nodes.size());
  for (size_t j = 0; j < out.size(); ++j) {
    out[j].slave = slave.nodes[j];
    out[j].weight = slave.weights[j];
  }
  return out;
}

}  // namespace signorini
