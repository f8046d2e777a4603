#include "signorini/mesh/mesh.hpp"

#include <algorithm>
#include <array>
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
  // A mark per node, not the sets' connectivity sorted: a region's cells list each node
  // about 20 times (tetrahedra), 90 MB for the 2.8M tetrahedra of the 1.4M-DOF Hertz model.
  std::vector<char> mark;
  auto add = [&](const std::string& name, const std::vector<ElementBlock>& blocks) {
    if (node_sets.count(name)) return;
    mark.assign(nodes.size(), 0);
    for (auto& b : blocks)
      for (Index n : b.conn) {
        if (n >= static_cast<Index>(mark.size())) mark.resize(static_cast<size_t>(n) + 1, 0);
        mark[static_cast<size_t>(n)] = 1;
      }
    std::vector<Index> ns;
    for (size_t n = 0; n < mark.size(); ++n)
      if (mark[n]) ns.push_back(static_cast<Index>(n));
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
  // The facets of the facet sets, keyed by their sorted corners (at most 4), are matched to
  // the first cell facet with the same corners, in the order of the regions, blocks, cells
  // and the catalogue's facets. Only the facet sets' facets are held: until session 51 every
  // facet of every cell went into the map (its corners and its nodes as two vectors per
  // entry), about 150 bytes per facet, 0.85 GB for the 2.8M tetrahedra of the 1.4M-DOF Hertz
  // model: the peak of reading the deck, on every MPI rank.
  using Key = std::array<Index, 4>;
  struct Hash {
    size_t operator()(const Key& v) const {
      size_t h = 1469598103934665603ull;
      for (Index x : v) h = (h ^ static_cast<size_t>(x)) * 1099511628211ull;
      return h;
    }
  };
  auto key_of = [](const Index* corners, int nc) {
    Key k;
    k.fill(-1);
    std::copy(corners, corners + nc, k.begin());
    std::sort(k.begin(), k.begin() + nc);
    return k;
  };
  if (mesh.facet_sets.empty()) return 0;
  // Each distinct facet of the sets: its key -> its slot, whose owner's node list (outward
  // order) is filled by the first cell facet found with those corners.
  std::unordered_map<Key, Index, Hash> slot_of;
  for (auto& [name, blocks] : mesh.facet_sets)
    for (auto& b : blocks) {
      const int nc = element_info(b.type).num_corners;
      for (Index e = 0; e < b.size(); ++e) slot_of.emplace(key_of(b.element(e), nc), static_cast<Index>(slot_of.size()));
    }
  std::vector<std::vector<Index>> owner(slot_of.size());
  Index found = 0;
  Index corners[4];
  for (auto& [name, blocks] : mesh.regions)
    for (auto& b : blocks) {
      const ElementInfo& info = element_info(b.type);
      for (Index e = 0; e < b.size() && found < static_cast<Index>(owner.size()); ++e) {
        const Index* c = b.element(e);
        for (auto& f : info.facets) {
          const int nc = element_info(f.type).num_corners;
          for (int k = 0; k < nc; ++k) corners[k] = c[f.nodes[k]];
          auto it = slot_of.find(key_of(corners, nc));
          if (it == slot_of.end() || !owner[it->second].empty()) continue;
          for (int node : f.nodes) owner[it->second].push_back(c[node]);
          ++found;
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
        const std::vector<Index>& own = owner[slot_of.at(key_of(c, info.num_corners))];
        if (static_cast<int>(own.size()) != nn) {
          ++orphans;
          continue;
        }
        std::copy(own.begin(), own.end(), c);
      }
    }
  return orphans;
}

}  // namespace signorini
