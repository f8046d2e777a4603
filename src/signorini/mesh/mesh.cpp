#include "signorini/mesh/mesh.hpp"

#include <algorithm>
#include <unordered_map>

#include "signorini/core/error.hpp"
#include "signorini/fem/quadrature.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

void ElementBlock::add(const std::vector<Index>& nodes, Index id) {
  conn.insert(conn.end(), nodes.begin(), nodes.end());
  ids.push_back(id);
}

Index Mesh::num_cells() const {
  Index n = taken_cells_;
  for (auto& [name, blocks] : regions)
    for (auto& b : blocks) n += b.size();
  return n;
}

std::vector<ElementBlock> Mesh::take_region(const std::string& name) {
  auto it = regions.find(name);
  if (it == regions.end()) throw Error("no region named '" + name + "' in the mesh");
  if (taken_[name]) throw Error("the cells of region '" + name + "' were handed to a body already");
  taken_[name] = true;
  std::vector<ElementBlock> blocks = std::move(it->second);
  it->second.clear();
  for (auto& b : blocks) taken_cells_ += b.size();
  return blocks;
}

template <typename M>
static std::string join_keys(const M& m) {
  std::string s;
  for (auto& [k, v] : m) s += (s.empty() ? "" : ", ") + k;
  return s.empty() ? "(none)" : s;
}
std::string Mesh::region_names() const { return join_keys(regions); }
std::string Mesh::facet_set_names() const { return join_keys(facet_sets); }
std::string Mesh::node_set_names() const { return join_keys(node_sets); }

void Mesh::complete_node_sets() {
  auto add = [&](const std::string& name, const std::vector<ElementBlock>& blocks) {
    if (node_sets.count(name)) return;
    std::vector<Index> ns;
    for (auto& b : blocks) ns.insert(ns.end(), b.conn.begin(), b.conn.end());
    std::sort(ns.begin(), ns.end());
    ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
    node_sets[name] = std::move(ns);
  };
  for (auto& [n, b] : regions) add(n, b);
  for (auto& [n, b] : facet_sets) add(n, b);
}

std::vector<Real> facet_edge_lengths(const std::vector<ElementBlock>& facets, const std::vector<Vec3>& nodes) {
  std::vector<Real> out;
  for (const ElementBlock& b : facets) {
    const int nc = element_info(b.type).num_corners;
    for (Index e = 0; e < b.size(); ++e)
      for (int k = 0; k < (nc == 2 ? 1 : nc); ++k) out.push_back((nodes[b.element(e)[(k + 1) % nc]] - nodes[b.element(e)[k]]).norm());
  }
  return out;
}

namespace {

// Jacobian determinant of a cell at reference point xi (dim x dim block of dX/dxi).
Real jacobian_det(const ElementBlock& b, Index e, const std::vector<Vec3>& nodes, int dim,
                  const Vec3& xi) {
  VecX N;
  MatX dN;
  shape_functions(b.type, xi, N, dN);
  const Index* c = b.element(e);
  Mat3 J = Mat3::Identity();
  J.topLeftCorner(dim, dim).setZero();
  for (int i = 0; i < N.size(); ++i)
    for (int a = 0; a < dim; ++a)
      for (int d = 0; d < dim; ++d) J(a, d) += nodes[c[i]](a) * dN(i, d);
  return J.determinant();
}

}  // namespace

MeshCheck check_and_orient(Mesh& mesh) {
  MeshCheck report;
  for (auto& [name, blocks] : mesh.regions) {
    for (auto& b : blocks) {
      const ElementInfo& info = element_info(b.type);
      const QuadratureRule rule = quadrature_rule(b.type, default_quadrature_degree(b.type));
      std::vector<Vec3> points;
      for (auto& q : rule) points.push_back(q.xi);
      for (int k = 0; k < info.num_corners; ++k) points.push_back(info.ref_coords[k]);
      const int nn = info.num_nodes;
      for (Index e = 0; e < b.size(); ++e) {
        // Size scale: bounding box diagonal, for the degeneracy threshold.
        const Index* c = b.element(e);
        Vec3 lo = mesh.nodes[c[0]], hi = lo;
        for (int i = 1; i < nn; ++i) {
          lo = lo.cwiseMin(mesh.nodes[c[i]]);
          hi = hi.cwiseMax(mesh.nodes[c[i]]);
        }
        const Real scale = std::pow((hi - lo).norm(), info.dim);
        int neg = 0, pos = 0, tiny = 0;
        for (auto& p : points) {
          Real d = jacobian_det(b, e, mesh.nodes, info.dim, p);
          if (std::abs(d) <= 1e-12 * scale) ++tiny;
          else if (d < 0) ++neg;
          else ++pos;
        }
        if (tiny > 0 && pos + neg == 0) {
          report.degenerate.push_back(b.ids[e]);
        } else if (neg > 0 && pos == 0 && tiny == 0) {
          Index* cm = b.conn.data() + e * nn;
          std::vector<Index> old(cm, cm + nn);
          for (int i = 0; i < nn; ++i) cm[i] = old[info.mirror[i]];
          ++report.reoriented;
        } else if (neg > 0 || tiny > 0) {
          report.inverted.push_back(b.ids[e]);
        }
      }
    }
  }
  return report;
}

Index orient_facets(Mesh& mesh) {
  // Key of a facet: its sorted corner nodes.
  auto key_of = [](std::vector<Index> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  struct Hash {
    size_t operator()(const std::vector<Index>& v) const {
      size_t h = 1469598103934665603ull;
      for (Index x : v) h = (h ^ static_cast<size_t>(x)) * 1099511628211ull;
      return h;
    }
  };
  if (mesh.facet_sets.empty()) return 0;
  // Map every cell facet (by corners) to its node list in outward order.
  std::unordered_map<std::vector<Index>, std::vector<Index>, Hash> owner;
  for (auto& [name, blocks] : mesh.regions)
    for (auto& b : blocks) {
      const ElementInfo& info = element_info(b.type);
      for (Index e = 0; e < b.size(); ++e) {
        const Index* c = b.element(e);
        for (auto& f : info.facets) {
          const int nc = element_info(f.type).num_corners;
          std::vector<Index> corners, all;
          for (int k = 0; k < static_cast<int>(f.nodes.size()); ++k) {
            all.push_back(c[f.nodes[k]]);
            if (k < nc) corners.push_back(c[f.nodes[k]]);
          }
          owner.emplace(key_of(corners), std::move(all));
        }
      }
    }
  Index orphans = 0;
  for (auto& [name, blocks] : mesh.facet_sets)
    for (auto& b : blocks) {
      const ElementInfo& info = element_info(b.type);
      const int nn = info.num_nodes;
      for (Index e = 0; e < b.size(); ++e) {
        Index* c = b.conn.data() + e * nn;
        std::vector<Index> corners(c, c + info.num_corners);
        auto it = owner.find(key_of(corners));
        if (it == owner.end() || static_cast<int>(it->second.size()) != nn) {
          ++orphans;
          continue;
        }
        std::copy(it->second.begin(), it->second.end(), c);
      }
    }
  return orphans;
}

}  // namespace signorini
