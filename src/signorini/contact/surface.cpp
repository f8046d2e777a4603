#include "signorini/contact/surface.hpp"

#include <algorithm>
#include <numbers>

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

FacetBasis MasterSurface::basis(Index f) const {
  if (!smooth()) return FacetBasis(type[f]);
  return FacetBasis::hermite(prev[f] >= 0, next[f] >= 0);
}

std::vector<Index> MasterSurface::basis_nodes(Index f) const {
  if (!smooth()) return facets[f];
  std::vector<Index> v;
  if (prev[f] >= 0) v.push_back(prev[f]);
  v.push_back(facets[f][0]);
  v.push_back(facets[f][1]);
  if (next[f] >= 0) v.push_back(next[f]);
  return v;
}

void smooth_master_surface(MasterSurface& m, const std::vector<Vec3>& x) {
  for (ElementType t : m.type)
    if (t != ElementType::line2)
      throw Error("smoothing: hermite needs a 2D master surface of line2 facets (found " + element_info(t).name + ")");
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

SlaveSurface make_slave_surface(const Mesh& mesh, const std::string& set, const AnalysisSettings& settings) {
  const int dim = settings.spatial_dim();
  std::vector<Real> w(mesh.num_nodes(), 0.0);
  std::vector<char> used(mesh.num_nodes(), 0);
  for (const ElementBlock& b : mesh.facet_sets.at(set)) {
    const ElementInfo& info = element_info(b.type);
    const QuadratureRule rule = quadrature_rule(b.type, 2 * info.order + 1);
    for (Index e = 0; e < b.size(); ++e) {
      const Index* c = b.element(e);
      for (auto& q : rule) {
        VecX N;
        MatX dN;
        shape_functions(b.type, q.xi, N, dN);
        Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero(), x = Vec3::Zero();
        for (int i = 0; i < info.num_nodes; ++i) {
          x += N(i) * mesh.nodes[c[i]];
          a1 += dN(i, 0) * mesh.nodes[c[i]];
          if (dim == 3) a2 += dN(i, 1) * mesh.nodes[c[i]];
        }
        Real da = (dim == 2 ? a1.norm() : a1.cross(a2).norm()) * q.weight;
        if (settings.dimension == Dimension::axisymmetric) da *= 2 * std::numbers::pi * x(0);
        else if (dim == 2) da *= settings.thickness;
        for (int i = 0; i < info.num_nodes; ++i) w[c[i]] += N(i) * da;
      }
      for (int i = 0; i < info.num_nodes; ++i) used[c[i]] = 1;
    }
  }
  SlaveSurface s;
  for (Index n = 0; n < mesh.num_nodes(); ++n)
    if (used[n]) {
      if (!(w[n] > 0) && !(settings.dimension == Dimension::axisymmetric && std::abs(mesh.nodes[n](0)) < 1e-12))
        throw Error("slave surface '" + set + "': node " + std::to_string(mesh.node_ids[n]) +
                    " gets a non-positive contact area from its facets (tri6 and quad8 corner nodes do): "
                    "node-to-segment needs linear facets (line2, tri3, quad4) or line3/quad9 on the slave side");
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
