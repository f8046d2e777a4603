#include "signorini/contact/discretization/discretization.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "signorini/contact/discretization/mortar.hpp"
#include "signorini/contact/discretization/node_to_segment.hpp"
#include "signorini/contact/discretization/segment_to_segment.hpp"
#include "signorini/contact/discretization/rigid_obstacle.hpp"
#include "signorini/contact/search/search.hpp"
#include "signorini/core/binary_io.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/first_error.hpp"
#include "signorini/core/log.hpp"
#include "signorini/core/rank_exchange.hpp"
#include "signorini/fem/boundary_traction.hpp"

namespace signorini {

namespace {

// Appends a node to c with zero derivatives of the gap and the normal (a deformable master: no
// extra DOFs after the nodes').
void append_node(Constraint& c, Index node, int dim) {
  const Index old = c.grad.size();
  c.nodes.push_back(node);
  c.grad.conservativeResize(old + dim);
  c.grad.tail(dim).setZero();
  c.hess.conservativeResize(old + dim, old + dim);
  c.hess.rightCols(dim).setZero();
  c.hess.bottomRows(dim).setZero();
  c.normal_jacobian.conservativeResize(dim, old + dim);
  c.normal_jacobian.rightCols(dim).setZero();
}

// A uniform grid of axis-aligned boxes (self-contact's searches): cells about a box wide (the
// mean of the boxes' largest extents), coarsened while there would be more than 8 cells per
// box; each box is listed in the cells it spans. A query visits the boxes listed in the cells a
// point or a box touches (a box may be visited more than once).
class BoxGrid {
 public:
  BoxGrid(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi, int dim) : dim_(dim) {
    const Index n = static_cast<Index>(lo.size());
    glo_ = Vec3::Constant(std::numeric_limits<Real>::infinity());
    Vec3 ghi = -glo_;
    Real extent = 0;
    for (Index b = 0; b < n; ++b) {
      glo_ = glo_.cwiseMin(lo[b]);
      ghi = ghi.cwiseMax(hi[b]);
      extent += (hi[b] - lo[b]).head(dim).maxCoeff();
    }
    cell_ = n > 0 ? extent / static_cast<Real>(n) : 1;
    if (!(cell_ > 0)) cell_ = 1;  // every box a point: one cell will do
    for (;;) {
      Real total = 1;
      for (int d = 0; d < dim; ++d) {
        count_[d] = n > 0 ? static_cast<Index>(std::floor((ghi(d) - glo_(d)) / cell_)) + 1 : 1;
        total *= static_cast<Real>(count_[d]);
      }
      if (total <= 8.0 * static_cast<Real>(n) + 64) break;
      cell_ *= 1.5;
    }
    start_.assign(static_cast<size_t>(count_[0] * count_[1] * count_[2]) + 1, 0);
    for (Index b = 0; b < n; ++b) cells(lo[b], hi[b], [&](Index c) { ++start_[c + 1]; });
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    item_.resize(start_.back());
    std::vector<Index> fill(start_.begin(), start_.end() - 1);
    for (Index b = 0; b < n; ++b) cells(lo[b], hi[b], [&](Index c) { item_[fill[c]++] = b; });
  }
  // fn(b) for the boxes listed in the cells that [a, b] touches.
  template <class F>
  void visit(const Vec3& a, const Vec3& b, F&& fn) const {
    cells(a, b, [&](Index c) {
      for (Index k = start_[c]; k < start_[c + 1]; ++k) fn(item_[k]);
    });
  }
  template <class F>
  void visit(const Vec3& p, F&& fn) const {
    visit(p, p, fn);
  }

 private:
  Index cell_of(Real v, int d) const {
    const Real c = std::floor((v - glo_(d)) / cell_);
    return static_cast<Index>(std::clamp<Real>(c, 0, static_cast<Real>(count_[d] - 1)));
  }
  template <class F>
  void cells(const Vec3& a, const Vec3& b, F&& fn) const {
    std::array<Index, 3> lo{0, 0, 0}, hi{0, 0, 0};
    for (int d = 0; d < dim_; ++d) lo[d] = cell_of(a(d), d), hi[d] = cell_of(b(d), d);
    for (Index k = lo[2]; k <= hi[2]; ++k)
      for (Index j = lo[1]; j <= hi[1]; ++j)
        for (Index i = lo[0]; i <= hi[0]; ++i) fn((k * count_[1] + j) * count_[0] + i);
  }
  int dim_;
  Vec3 glo_;
  Real cell_ = 1;
  std::array<Index, 3> count_{1, 1, 1};
  std::vector<Index> start_, item_;  // boxes per cell (compressed rows)
};

}  // namespace

void Discretization::set_boundary_traction(BoundaryTraction*) {
  throw Error(name() + " does not use the bodies' boundary traction (Nitsche's method needs segment_to_segment)");
}

SlipOrigin Discretization::origin(const Constraint& c, const Vec3&, const VecX&) const {
  // A deformable master: the master point as the combination of master nodes that c found.
  SlipOrigin o;
  o.valid = c.kind != ConstraintKind::none;
  for (size_t k = 0; k < c.master_weights.size() && o.valid; ++k) o.nodes.emplace_back(c.nodes[k + 1], c.master_weights[k]);
  if (o.valid && c.slave_coefficient != 1) o.nodes.emplace_back(c.slave, 1 - c.slave_coefficient);
  return o;
}

void Discretization::add_slip(const SlipOrigin& o, const std::vector<Vec3>& x, const VecX&, Constraint& c) const {
  // d = x_s - sum_k w_k x_k over the origin's nodes; nodes c does not hold yet are appended
  // (with zero gap derivatives).
  const int dim = static_cast<int>(c.normal_jacobian.rows());
  for (auto [node, w] : o.nodes)
    if (std::find(c.nodes.begin(), c.nodes.end(), node) == c.nodes.end()) append_node(c, node, dim);
  c.slip_jacobian.setZero(dim, c.grad.size());
  c.slip = x[c.slave];
  for (int d = 0; d < dim; ++d) c.slip_jacobian(d, d) = 1;
  for (auto [node, w] : o.nodes) {
    c.slip -= w * x[node];
    const Index k = std::find(c.nodes.begin(), c.nodes.end(), node) - c.nodes.begin();
    for (int d = 0; d < dim; ++d) c.slip_jacobian(d, k * dim + d) -= w;
  }
  c.has_slip = true;
}

namespace {

// A deformable master surface and its global search: the closest master facet of each slave
// node (the candidate) within dmax.
class DeformableMaster : public Discretization {
 public:
  DeformableMaster(const ContactPairSettings& s, const Mesh& mesh, const SlaveSurface& slave, int dim)
      : slave_(slave), dim_(dim), search_(make_search(s.search)) {
    master_ = make_master_surface(mesh, s.master);
    if (s.smoothing == "hermite") smooth_master_surface(master_, mesh.nodes);
    facets_.corners = dim == 2 ? 2 : element_info(master_.type.empty() ? ElementType::tri3 : master_.type[0]).num_corners;
    for (ElementType t : master_.type)
      if (element_info(t).num_corners != facets_.corners)
        throw Error("contact '" + s.name + "': the master surface '" + s.master +
                    "' mixes triangles and quadrilaterals, which the search does not support yet");
    candidate_.assign(slave_.nodes.size(), -1);
  }

 protected:
  // The closest facet of each slave node within dmax (-1: none).
  void search(const std::vector<Vec3>& x, Real dmax, std::vector<Index>& facet, std::vector<Real>* distance = nullptr) {
    const int nc = facets_.corners;
    facets_.points.resize(master_.size() * nc);
    for (Index f = 0; f < master_.size(); ++f)
      for (int k = 0; k < nc; ++k) facets_.points[f * nc + k] = x[master_.facets[f][k]];
    search_->build(facets_);
    std::vector<Vec3> pts(slave_.nodes.size());
    for (size_t j = 0; j < pts.size(); ++j) pts[j] = x[slave_.nodes[j]];
    std::vector<SearchHit> hits;
    search_->closest(pts, dmax, hits);
    facet.resize(pts.size());
    for (size_t j = 0; j < pts.size(); ++j) facet[j] = hits[j].facet;
    if (distance) {
      distance->resize(pts.size());
      for (size_t j = 0; j < pts.size(); ++j) (*distance)[j] = hits[j].distance;
    }
  }

  // Per slave facet of `sf`: the master facets whose bounding box meets the facet's, grown by
  // a margin, reached from the closest master facets of its nodes through shared nodes (a facet
  // whose nodes found none keeps its list while one of them is tracked). The margin is dmax;
  // with motion >= 0 it is min(dmax, d + l + motion), d the largest distance of the facet's
  // nodes from the master (flat facets through the corners), l the facet's largest extent:
  // every point of the facet is within d + l of the master, its closest master point within
  // that distance of it (segment_to_segment: in 3D, dmax's margin of twice the mean master facet
  // size gave a slave facet of a refined contact zone 470 candidates on the Cattaneo sphere).
  void facet_candidates(const MasterSurface& sf, const std::vector<Index>& index, const std::vector<Vec3>& x,
                        Real dmax, const std::vector<char>& tracked, std::vector<std::vector<Index>>& out,
                        Real motion = -1) {
    std::vector<Index> closest;
    std::vector<Real> distance;
    search(x, dmax, closest, &distance);
    auto box = [&](const std::vector<Index>& nodes, Vec3& lo, Vec3& hi) {
      lo = hi = x[nodes[0]];
      for (Index n : nodes) lo = lo.cwiseMin(x[n]), hi = hi.cwiseMax(x[n]);
    };
    out.resize(sf.size());
    for (Index e = 0; e < sf.size(); ++e) {
      const auto& nodes = sf.facets[e];
      std::vector<Index> queue;
      bool was_tracked = false;
      for (Index n : nodes) {
        const Index j = index[n];
        if (j < 0) continue;
        if (closest[j] >= 0) queue.push_back(closest[j]);
        was_tracked = was_tracked || tracked[j];
      }
      if (queue.empty()) {
        if (!was_tracked) out[e].clear();
        continue;
      }
      Vec3 lo, hi;
      box(nodes, lo, hi);
      Real margin = dmax;
      if (motion >= 0) {
        Real d = 0;
        for (Index n : nodes) {
          const Index j = index[n];
          if (j >= 0) d = std::max(d, closest[j] >= 0 ? distance[j] : dmax);
        }
        margin = std::min(dmax, d + (hi - lo).maxCoeff() + motion);
      }
      lo.array() -= margin;
      hi.array() += margin;
      std::set<Index> seen(queue.begin(), queue.end()), accepted;
      while (!queue.empty()) {
        const Index f = queue.back();
        queue.pop_back();
        Vec3 flo, fhi;
        box(master_.facets[f], flo, fhi);
        if ((flo.array() > hi.array()).any() || (fhi.array() < lo.array()).any()) continue;
        accepted.insert(f);
        for (Index g : master_.neighbourhood(f))
          if (seen.insert(g).second) queue.push_back(g);
      }
      out[e].assign(accepted.begin(), accepted.end());
    }
  }

  // The nodes slave node j's weighted gap may involve: the nodes of the slave facets around
  // it (with `ring`, also of the facets around those nodes: averaged normals) and of their
  // candidate master facets.
  void facet_coupled_nodes(const MasterSurface& sf, const std::vector<std::vector<Index>>& candidates, Index node,
                           bool ring, std::vector<Index>& nodes) const {
    std::set<Index> around;
    for (Index e : sf.node_facets[node]) {
      for (Index n : sf.facets[e]) {
        around.insert(n);
        if (ring)
          for (Index f : sf.node_facets[n])
            for (Index m : sf.facets[f]) around.insert(m);
      }
      for (Index f : candidates[e])
        for (Index m : master_.basis_nodes(f)) around.insert(m);
    }
    around.erase(node);
    nodes.assign(1, node);
    nodes.insert(nodes.end(), around.begin(), around.end());
  }

  // Adds per-facet shares of weighted gaps (R: nodes, gap[k], grad[k], hess[k] per facet node
  // k over `nodes`) into the constraints of the facets' slave nodes; a constraint that got a
  // share becomes a segment constraint against `facet[e]`.
  template <class R>
  void gather(const MasterSurface& sf, const std::vector<Index>& index, const std::vector<std::vector<R>>& results,
              const std::vector<std::vector<Index>>& facet, ConstraintSet& out) const {
    const int dim = dim_;
    auto column = [](Constraint& c, Index node) {
      auto it = std::find(c.nodes.begin(), c.nodes.end(), node);
      if (it != c.nodes.end()) return static_cast<Index>(it - c.nodes.begin());
      c.nodes.push_back(node);
      return static_cast<Index>(c.nodes.size() - 1);
    };
    std::vector<Index> at;
    for (int pass = 0; pass < 2; ++pass) {
      for (Index e = 0; e < sf.size(); ++e)
        for (size_t r = 0; r < results[e].size(); ++r) {
          const R& res = results[e][r];
          for (size_t k = 0; k < res.gap.size(); ++k) {
            const Index j = index[sf.facets[e][k]];
            if (j < 0) continue;
            Constraint& c = out[j];
            if (pass == 0) {
              if (c.kind == ConstraintKind::none) {
                c.kind = ConstraintKind::segment;
                c.facet = facet[e][r];
                c.nodes.assign(1, c.slave);
              }
              for (Index n : res.nodes) column(c, n);
              continue;
            }
            at.clear();
            for (Index n : res.nodes) at.push_back(column(c, n));
            c.gap += res.gap[k];
            for (size_t a = 0; a < at.size(); ++a) {
              c.grad.segment(at[a] * dim, dim) += res.grad[k].segment(static_cast<Index>(a) * dim, dim);
              if (res.hess.empty()) continue;  // gradients only (Discretization::set_second_variation)
              for (size_t b = 0; b < at.size(); ++b)
                c.hess.block(at[a] * dim, at[b] * dim, dim, dim) +=
                    res.hess[k].block(static_cast<Index>(a) * dim, static_cast<Index>(b) * dim, dim, dim);
            }
          }
        }
      if (pass == 0)
        for (Constraint& c : out)
          if (c.kind != ConstraintKind::none) {
            const Index n = static_cast<Index>(c.nodes.size()) * dim;
            c.gap = 0;
            c.grad.setZero(n);
            c.hess.setZero(n, n);
          }
    }
  }

  // Friction's slip origin (mortar, segment-to-segment): the per-facet shares of each slave
  // node's weighted relative position (R::relative[k], coefficients of R::nodes) summed into the
  // order of its constraint's nodes.
  template <class R>
  static std::vector<VecX> gather_relative(const MasterSurface& sf, const std::vector<Index>& index,
                                           const std::vector<std::vector<R>>& results, const ConstraintSet& out) {
    std::vector<VecX> relative(out.size());
    for (size_t j = 0; j < out.size(); ++j)
      if (out[j].kind != ConstraintKind::none) relative[j].setZero(static_cast<Index>(out[j].nodes.size()));
    for (Index e = 0; e < sf.size(); ++e)
      for (const R& r : results[e])
        for (size_t k = 0; k < r.relative.size(); ++k) {
          const Index j = index[sf.facets[e][k]];
          if (j < 0) continue;
          const std::vector<Index>& cn = out[j].nodes;
          for (size_t a = 0; a < r.nodes.size() && a < static_cast<size_t>(r.relative[k].size()); ++a) {
            const auto it = std::find(cn.begin(), cn.end(), r.nodes[a]);
            if (it != cn.end()) relative[j](it - cn.begin()) += r.relative[k](static_cast<Index>(a));
          }
        }
    return relative;
  }

  // The weighted-gap constraint's normal: the slave surface's averaged normal at c's slave node
  // (2D: mortar's nodal normal; 3D: MasterSurface::node_normal_jacobian_3d), turned to point
  // from the master towards the slave, with its variation. A node of a facet around the slave
  // node that c does not hold yet (its points found no master: the normal depends on it, the
  // gap does not) is appended.
  void set_slave_normal(const MasterSurface& sf, const std::vector<Vec3>& x, Constraint& c) const {
    const int dim = dim_;
    Vec3 n;
    std::vector<Index> nn;
    MatX dn;
    if (dim == 2) mortar_nodal_normal_2d(sf, c.slave, x, n, nn, dn);
    else sf.node_normal_jacobian_3d(c.slave, x, n, nn, dn);
    c.normal = -n;
    c.normal_jacobian.setZero(dim, c.grad.size());
    for (size_t a = 0; a < nn.size(); ++a) {
      const Index k = std::find(c.nodes.begin(), c.nodes.end(), nn[a]) - c.nodes.begin();
      if (k == static_cast<Index>(c.nodes.size())) append_node(c, nn[a], dim);
      c.normal_jacobian.middleCols(k * dim, dim) = -dn.middleCols(static_cast<Index>(a) * dim, dim);
    }
  }

  SlaveSurface slave_;
  int dim_;
  MasterSurface master_;
  std::unique_ptr<ContactSearch> search_;
  SearchFacets facets_;
  std::vector<Index> candidate_;  // per slave node: master facet (node-to-segment) or node (node-to-node)
};

class NodeToSegment : public DeformableMaster {
 public:
  using DeformableMaster::DeformableMaster;
  std::string name() const override { return "node_to_segment"; }
  void detect(const std::vector<Vec3>& x, Real dmax, Real motion, const std::vector<char>& tracked) override {
    std::vector<Index> facet;
    search(x, dmax, facet);
    // A node in contact keeps being tracked even if it moved beyond d_max.
    for (size_t j = 0; j < facet.size(); ++j)
      if (facet[j] >= 0 || !(tracked[j] && candidate_[j] >= 0)) candidate_[j] = facet[j];
  }
  void coupled_nodes(size_t j, std::vector<Index>& nodes) const override {
    nodes.assign(1, slave_.nodes[j]);
    if (candidate_[j] < 0) return;
    std::set<Index> around;
    for (Index f : master_.neighbourhood(candidate_[j]))
      for (Index n : master_.basis_nodes(f)) around.insert(n);
    nodes.insert(nodes.end(), around.begin(), around.end());
  }
  void build(const std::vector<Vec3>& x, const VecX&, Real, ConstraintSet& out) const override {
    node_to_segment(master_, slave_, x, dim_, candidate_, out, nullptr, held_.empty() ? nullptr : &held_);
  }
  void hold_facets(std::vector<Index> facet) override { held_ = std::move(facet); }

 protected:
  std::vector<Index> held_;  // per slave node, the facet it is held on (-1: none); empty: none
};

// Self-contact: node-to-segment on one surface (ContactPairSettings::self). Every node of the
// surface is constrained against the surface's own facets, except the facets around it (those
// sharing a node with one of its facets: the "two-ring", where a node is always within reach)
// and facets that do not face it (the facet's outward normal must point against the node's
// averaged one: the two sides of a fold meet face to face; a facet seen from behind or across
// a thin wall is no partner). Both sides of a fold are slave and master at once, as the two
// passes of a pair would be. Search: a uniform grid of the facets' boxes grown by d_max (the
// pair's bucket grid and tree return one closest facet, always the node's own here).
class SelfNodeToSegment final : public NodeToSegment {
 public:
  SelfNodeToSegment(const ContactPairSettings& s, const Mesh& mesh, const SlaveSurface& slave, int dim)
      : NodeToSegment(s, mesh, slave, dim), excluded_(slave.nodes.size()) {
    for (size_t j = 0; j < slave_.nodes.size(); ++j) {
      std::set<Index> ex;
      for (Index f : master_.node_facets[slave_.nodes[j]])
        for (Index m : master_.facets[f])
          for (Index g : master_.node_facets[m]) ex.insert(g);
      excluded_[j].assign(ex.begin(), ex.end());
      sorted_.emplace_back(slave_.nodes[j], static_cast<Index>(j));
    }
    std::sort(sorted_.begin(), sorted_.end());
  }
  std::string name() const override { return "self_node_to_segment"; }
  void detect(const std::vector<Vec3>& x, Real dmax, Real motion, const std::vector<char>& tracked) override {
    const std::vector<Index> facet = closest_facing(x, dmax);
    for (size_t j = 0; j < facet.size(); ++j)
      if (facet[j] >= 0 || !(tracked[j] && candidate_[j] >= 0)) candidate_[j] = facet[j];
  }
  void build(const std::vector<Vec3>& x, const VecX&, Real, ConstraintSet& out) const override {
    node_to_segment(master_, slave_, x, dim_, candidate_, out, &excluded_, held_.empty() ? nullptr : &held_);
    // Two nodes that meet each other (each one's closest master point the other node: mirror
    // images on a symmetry plane, or the nodes of two symmetric halves) carry the same
    // constraint twice, which makes the multiplier system singular: the second is dropped.
    std::vector<Index> vertex(out.size(), -1);
    for (size_t j = 0; j < out.size(); ++j)
      for (size_t k = 0; k < out[j].master_weights.size(); ++k)
        if (out[j].kind != ConstraintKind::none && out[j].master_weights[k] >= 1 - kVertexWeight)
          vertex[j] = out[j].nodes[k + 1];
    for (size_t j = 0; j < out.size(); ++j) {
      if (vertex[j] < 0) continue;
      const Index k = index_of(vertex[j]);
      if (k >= 0 && static_cast<size_t>(k) < j && vertex[k] == out[j].slave) {
        Constraint open;
        open.slave = out[j].slave;
        open.weight = out[j].weight;
        out[j] = std::move(open);
      }
    }
  }

 private:
  static constexpr Real kVertexWeight = 1e-9;  // a master point this close to a node (in weights) is the node
  Index index_of(Index node) const {
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(node, Index(-1)));
    return it != sorted_.end() && it->first == node ? it->second : -1;
  }
  std::vector<std::pair<Index, Index>> sorted_;  // (mesh node, slave index), by mesh node

  // Per slave node: the closest facet within dmax that is not excluded and faces the node.
  std::vector<Index> closest_facing(const std::vector<Vec3>& x, Real dmax) const {
    const Index nf = master_.size();
    std::vector<Index> best(slave_.nodes.size(), -1);
    if (nf == 0) return best;
    const int nc = dim_ == 2 ? 2 : master_.corners(0);
    std::vector<Vec3> corners(static_cast<size_t>(nf) * nc), normal(nf), lo(nf), hi(nf);
    std::vector<Vec3> xf;
    for (Index f = 0; f < nf; ++f) {
      xf.clear();
      for (Index n : master_.facets[f]) xf.push_back(x[n]);
      lo[f] = hi[f] = xf[0];
      for (int k = 0; k < nc; ++k) {
        corners[f * nc + k] = x[master_.facets[f][k]];
        lo[f] = lo[f].cwiseMin(xf[k]);
        hi[f] = hi[f].cwiseMax(xf[k]);
      }
      if (!lo[f].allFinite() || !hi[f].allFinite())
        throw SolverError("self-contact: a facet has a non-finite corner (a diverging iterate)");
      const Vec3 centre = element_info(master_.type[f]).family == ShapeFamily::simplex ? Vec3(1.0 / 3, 1.0 / 3, 0)
                                                                                      : Vec3::Zero();
      normal[f] = facet_normal(master_.type[f], xf, centre, dim_);
      lo[f].array() -= dmax;
      hi[f].array() += dmax;
    }
    const BoxGrid grid(lo, hi, dim_);  // the facets' boxes grown by d_max
    const Index ns = static_cast<Index>(slave_.nodes.size());
#pragma omp parallel for schedule(dynamic, 64)
    for (Index j = 0; j < ns; ++j) {
      const Index node = slave_.nodes[j];
      const Vec3& p = x[node];
      if (!p.allFinite()) continue;
      const Vec3 nn = master_.node_normal(node, x, dim_);
      Real bd = dmax;
      const std::vector<Index>& ex = excluded_[j];
      grid.visit(p, [&](Index f) {
        if (normal[f].dot(nn) >= 0 || std::binary_search(ex.begin(), ex.end(), f)) return;
        const Real dist = point_facet_distance(corners.data() + f * nc, nc, p);
        if (dist <= bd) bd = dist, best[j] = f;
      });
    }
    return best;
  }

  std::vector<std::vector<Index>> excluded_;  // per slave node: sorted facets it is never constrained against
};

class NodeToNode final : public DeformableMaster {
 public:
  NodeToNode(const ContactPairSettings& s, const Mesh& mesh, const SlaveSurface& slave, int dim)
      : DeformableMaster(s, mesh, slave, dim), normal_(slave.nodes.size(), Vec3::Zero()) {}
  std::string name() const override { return "node_to_node"; }
  void detect(const std::vector<Vec3>& x, Real dmax, Real motion, const std::vector<char>& tracked) override {
    std::vector<Index> facet;
    search(x, dmax, facet);
    for (size_t j = 0; j < facet.size(); ++j) {
      const Index f = facet[j];
      if (f < 0) {
        if (!(tracked[j] && candidate_[j] >= 0)) candidate_[j] = -1;
        continue;
      }
      // The nearest corner of the closest facet, with its normal frozen until the next search.
      const Vec3& p = x[slave_.nodes[j]];
      Index best = -1;
      Real bd = 1e300;
      for (int k = 0; k < master_.corners(f); ++k) {
        const Index m = master_.facets[f][k];
        const Real d = (x[m] - p).norm();
        if (d < bd) bd = d, best = m;
      }
      candidate_[j] = best;
      normal_[j] = master_.node_normal(best, x, dim_);
    }
  }
  void coupled_nodes(size_t j, std::vector<Index>& nodes) const override {
    nodes.assign(1, slave_.nodes[j]);
    if (candidate_[j] >= 0) nodes.push_back(candidate_[j]);
  }
  void build(const std::vector<Vec3>& x, const VecX&, Real, ConstraintSet& out) const override {
    node_to_node(slave_, candidate_, normal_, x, dim_, out);
  }

 private:
  std::vector<Vec3> normal_;  // per slave node: the master node's normal, frozen at detection
};


// Dual mortar (2D and 3D, every facet type: mortar.hpp): one weighted gap per
// slave node, integrated over the segments
// of its slave facets against the master facets they overlap. The constraint's gap is
// g~_j / w_j (w_j the node's reference weight int N~_j dA0, the constraint's weight; N~ = N but
// on quadratic slave facets in 3D, whose transformed basis the dual one is built on), so that
// enforcement's force p w_j grad(g~_j / w_j) = p grad g~_j is the mortar virtual work with
// the nodal pressure p as the dual multiplier.
//
// Self-contact (ContactPairSettings::self): the surface's facets are slave or master facets.
// Two facets are partners when they are within d_max (boxes), face each other and neither is
// in the other's two-ring (the facets sharing a node with a facet that shares a node with it:
// always within reach, never a partner), as in SelfNodeToSegment. The partner graph is
// two-coloured, slave and master, at each detection (keeping each contact zone's colours), so
// that every pair is integrated once, from its slave side, as one pass (the dynamic slave and
// master assignment of mortar self-contact; integrating both sides, as Yang and Laursen 2008,
// CMAME 197, do with half the pressure each, makes the two sides' constraints redundant where
// the walls close, which Lagrange multipliers cannot take). Only the slave side's nodes carry
// constraints and pressures. Where a master covers a slave facet only
// in part (the fold's ends, the facets beyond d_max) the dual basis is built on the covered
// part (mortar.hpp); line3 facets use the transformed basis whose functions are non-negative,
// and a node's weighted gap is scaled by that basis' weight (the constraint's gap is then the
// coefficient of the gap in that basis).
class Mortar final : public DeformableMaster {
 public:
  Mortar(const ContactPairSettings& s, const Mesh& mesh, const SlaveSurface& slave, const AnalysisSettings& as)
      : DeformableMaster(s, mesh, slave, as.spatial_dim()), self_(s.self) {
    measure_.axisymmetric = as.dimension == Dimension::axisymmetric;
    measure_.thickness = as.thickness;
    slave_facets_ = make_master_surface(mesh, s.slave);
    index_.assign(mesh.num_nodes(), -1);
    for (size_t j = 0; j < slave_.nodes.size(); ++j) index_[slave_.nodes[j]] = static_cast<Index>(j);
    candidates_.assign(slave_facets_.size(), {});
    for (ElementType t : slave_facets_.type) quadratic_slave_ = quadratic_slave_ || (dim_ == 3 && element_info(t).order > 1);
    if (self_) {
      // 2D: the weights of line3's transformed basis; 3D (tri3, quad4 facets, non-negative
      // functions): the slave's own weights int N_j dA0 (slave_basis: positive).
      if (dim_ == 2) {
        std::vector<Real> w;
        mortar_slave_weights(slave_facets_, mesh.nodes, measure_, true, w);
        gap_scale_.resize(slave_.nodes.size());
        for (size_t j = 0; j < slave_.nodes.size(); ++j) gap_scale_[j] = w[slave_.nodes[j]];
      } else {
        gap_scale_ = slave_.weights;
      }
      excluded_.resize(slave_facets_.size());
      for (Index e = 0; e < slave_facets_.size(); ++e) {
        std::set<Index> ex;
        for (Index n : slave_facets_.facets[e])
          for (Index f : slave_facets_.node_facets[n])
            for (Index m : slave_facets_.facets[f])
              for (Index g : slave_facets_.node_facets[m]) ex.insert(g);
        excluded_[e].assign(ex.begin(), ex.end());
      }
    }
  }
  std::string name() const override { return self_ ? "self_mortar" : "mortar"; }
  bool shares_out() const override { return true; }
  // On quadratic slave facets in 3D a uniform pressure gives the corner nodes of tri6 and quad8
  // no or negative nodal force (int N_corner dA <= 0): the reported pressure is then the
  // multiplier, the dual pressure's nodal value (the coefficient of N~_j, as the gap), per
  // reference area (Constraint::pressure_factor).
  bool pressure_is_multiplier() const override { return quadratic_slave_; }
  bool weighted_slip() const override { return true; }

  void detect(const std::vector<Vec3>& x, Real dmax, Real motion, const std::vector<char>& tracked) override {
    if (self_) self_candidates(x, dmax);
    // 3D: the margin bounded by the facet's distance, size and the motion expected, as for
    // segment_to_segment (each candidate pair costs a clipping on hyper-dual numbers).
    else facet_candidates(slave_facets_, index_, x, dmax, tracked, candidates_, dim_ == 3 ? motion : -1);
    // 3D: the candidates that overlap (clipped in plain numbers), for coupled_nodes.
    if (dim_ == 3 && !self_) {
      const Index ne = slave_facets_.size();
      coupled_masters_.assign(ne, {});
      FirstError first;
#pragma omp parallel for schedule(dynamic, 8)
      for (Index e = 0; e < ne; ++e)
        if (!candidates_[e].empty())
          first.run([&] { set_coupled_masters(e, mortar_element_3d(slave_facets_, e, master_, candidates_[e], x, false).masters); });
      first.rethrow();
    }
  }

  void coupled_nodes(size_t j, std::vector<Index>& nodes) const override {
    // 2D: the ring of facets around (the averaged normals along the facet); 3D: the gap is
    // measured along the facet's own normal, and the slip normal is the node's. In 3D the
    // masters are those that overlapped at the last evaluation (the search's clipping, then
    // each assembly's): a slave facet of the tet10 Hertz sphere has some 20 candidates, 4 to 6 of
    // which overlap, and the candidates' couplings took the fine mesh's matrix from 19 to 26
    // million entries (5.8 GB to factorize). A master that starts to overlap during the
    // iterations puts its entries outside the pattern, which Analysis rebuilds then.
    const bool overlaps = dim_ == 3 && !self_;
    facet_coupled_nodes(slave_facets_, overlaps ? coupled_masters_ : candidates_, slave_.nodes[j], dim_ == 2, nodes);
  }

  void build(const std::vector<Vec3>& x, const VecX&, Real, ConstraintSet& out) const override {
    out = open_constraints(slave_);
    const Index ne = slave_facets_.size();
    std::vector<std::vector<MortarFacetResult>> results(ne);
    std::vector<std::vector<Index>> facet(ne);
    const bool overlaps = dim_ == 3 && !self_;
    if (overlaps) coupled_masters_.resize(ne);
    // Under MPI the facets with candidates are dealt out to the ranks in turn (a contact zone's
    // facets are neighbours: dealing keeps the shares even where blocks would not), each rank
    // integrates its own, and the results are exchanged (collective: every rank calls build
    // alike).
    const int ranks = ranks_ ? ranks_->size() : 1, rank = ranks_ ? ranks_->rank() : 0;
    std::vector<char> mine(ne, ranks == 1);
    if (ranks > 1)
      for (Index e = 0, k = 0; e < ne; ++e)
        if (!candidates_[e].empty()) mine[e] = (k++ % ranks) == rank;
    FirstError first;
#pragma omp parallel for schedule(dynamic, 8)
    for (Index e = 0; e < ne; ++e) {
      if (overlaps) coupled_masters_[e].clear();
      if (candidates_[e].empty() || !mine[e]) continue;
      first.run([&] {
        MortarFacetResult r = dim_ == 2 ? mortar_element_2d(slave_facets_, e, master_, candidates_[e], x, measure_, true, self_)
                                        : mortar_element_3d(slave_facets_, e, master_, candidates_[e], x, true, second_variation_);
        if (overlaps) set_coupled_masters(e, r.masters);
        if (!r.overlap) return;
        facet[e].push_back(r.facet);
        results[e].push_back(std::move(r));
      });
    }
    // Shared out over ranks, a failure on one rank is thrown by all of them (the lowest rank's),
    // before the exchange that the others would wait in.
    if (ranks > 1) first.rethrow_agreed(*ranks_);
    first.rethrow();
    if (ranks > 1) exchange_results(mine, results, facet);
    gather(slave_facets_, index_, results, facet, out);
    // Friction's slip origin: each node's weighted relative position gathered over its facets'
    // segments, divided by its weight there (an average of x_s - x_m(chi) with N~_j), as a
    // combination of the constraint's nodes (master_weights, slave_coefficient).
    const std::vector<VecX> relative = gather_relative(slave_facets_, index_, results, out);
    std::vector<Real> slip_weight(out.size(), 0.0);
    for (Index e = 0; e < ne; ++e)
      for (const MortarFacetResult& r : results[e])
        for (size_t k = 0; k < r.slip_weight.size(); ++k)
          if (const Index j = index_[slave_facets_.facets[e][k]]; j >= 0) slip_weight[j] += r.slip_weight[k];
    // Scaled by the reference tributary area; the normal is the slave's averaged one, turned
    // to point from the master towards the slave (as a master normal does).
    // Self-contact: by the weight of the transformed basis (the gap is then its coefficient), the
    // constraint keeping the node's weight int N_j dA0, which its nodal force is divided by for the
    // reported pressure.
    for (size_t j = 0; j < out.size(); ++j) {
      Constraint& c = out[j];
      if (c.kind == ConstraintKind::none) continue;
      const Real scale = self_ ? gap_scale_[j] : c.weight;
      if (!(c.weight > 0) || !(scale > 0)) {
        Constraint open;
        open.slave = c.slave;
        open.weight = c.weight;
        c = std::move(open);
        continue;
      }
      c.gap /= scale;
      c.grad /= scale;
      c.hess /= scale;
      if (quadratic_slave_) c.pressure_factor = slip_weight[j] / c.weight;
      set_slave_normal(slave_facets_, x, c);
      // The slip origin (after the normal, which may append nodes the slip does not involve);
      // the weight is positive wherever a segment covers the node's facets (N~ >= 0).
      if (slip_weight[j] > 0) {
        c.slave_coefficient = relative[j](0) / slip_weight[j];
        c.master_weights.assign(c.nodes.size() - 1, 0.0);
        for (Index k = 1; k < relative[j].size(); ++k) c.master_weights[k - 1] = -relative[j](k) / slip_weight[j];
      }
    }
  }

 private:
  // Self-contact: the partner graph (the facets whose boxes, one grown by dmax, meet, that face
  // each other and are outside each other's two-ring; a uniform grid of the grown boxes finds
  // them), two-coloured into slave and master facets; a slave facet's candidates are its master
  // partners. No node is tracked beyond d_max: a contact zone is within it.
  void self_candidates(const std::vector<Vec3>& x, Real dmax) {
    const MasterSurface& sf = slave_facets_;
    const Index nf = sf.size();
    if (nf == 0) return;
    std::vector<Vec3> lo(nf), hi(nf), normal(nf);
    std::vector<Vec3> xf;
    for (Index f = 0; f < nf; ++f) {
      xf.clear();
      for (Index n : sf.facets[f]) xf.push_back(x[n]);
      lo[f] = hi[f] = xf[0];
      for (const Vec3& p : xf) lo[f] = lo[f].cwiseMin(p), hi[f] = hi[f].cwiseMax(p);
      if (!lo[f].allFinite() || !hi[f].allFinite())
        throw SolverError("self-contact: a facet has a non-finite node (a diverging iterate)");
      normal[f] = facet_normal(sf.type[f], xf, Vec3::Zero(), dim_);
    }
    const Vec3 grow = Vec3::Constant(dmax);
    std::vector<Vec3> glo(nf), ghi(nf);
    for (Index f = 0; f < nf; ++f) glo[f] = lo[f] - grow, ghi[f] = hi[f] + grow;
    const BoxGrid grid(glo, ghi, dim_);  // the facets' boxes grown by d_max
    // The facets near each other (either's box within the other's grown box), facing, outside
    // the two-rings: an undirected graph.
    std::vector<std::vector<Index>> near(nf);
    for (Index e = 0; e < nf; ++e)
      grid.visit(lo[e], hi[e], [&](Index f) {
        if (normal[f].dot(normal[e]) >= 0 || std::binary_search(excluded_[e].begin(), excluded_[e].end(), f)) return;
        if ((glo[f].head(dim_).array() > hi[e].head(dim_).array()).any() ||
            (ghi[f].head(dim_).array() < lo[e].head(dim_).array()).any())
          return;
        near[e].push_back(f);
        near[f].push_back(e);
      });
    for (auto& v : near) {
      std::sort(v.begin(), v.end());
      v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    // One pass: the graph's facets two-coloured, slave (0) and master (1), so that each pair is
    // integrated once, from its slave side. A component keeps the colours it had at the last
    // detection (its seed is a facet that had one, with it), so that contact zones do not swap
    // sides as they grow; an edge whose ends get the same colour (an odd cycle: three walls
    // meeting) is not integrated.
    std::vector<int> color(static_cast<size_t>(nf), -1);
    std::vector<Index> component, queue;
    for (Index e0 = 0; e0 < nf; ++e0) {
      if (color[e0] >= 0 || near[e0].empty()) continue;
      component.clear();
      queue.assign(1, e0);
      color[e0] = 0;  // provisional: marks the component
      while (!queue.empty()) {
        const Index e = queue.back();
        queue.pop_back();
        component.push_back(e);
        for (Index f : near[e])
          if (color[f] < 0) color[f] = 0, queue.push_back(f);
      }
      std::sort(component.begin(), component.end());
      Index seed = component.front();
      int seed_color = 0;
      for (Index e : component)
        if (e < static_cast<Index>(color_.size()) && color_[e] >= 0) {
          seed = e;
          seed_color = color_[e];
          break;
        }
      for (Index e : component) color[e] = -1;
      color[seed] = seed_color;
      queue.assign(1, seed);
      while (!queue.empty()) {
        const Index e = queue.back();
        queue.pop_back();
        for (Index f : near[e])
          if (color[f] < 0) color[f] = 1 - color[e], queue.push_back(f);
      }
    }
    color_ = color;
    for (Index e = 0; e < nf; ++e) {
      candidates_[e].clear();
      if (color[e] != 0) continue;
      for (Index f : near[e])
        if (color[f] == 1) candidates_[e].push_back(f);
    }
  }

  bool self_;
  bool quadratic_slave_ = false;  // 3D, a tri6, quad8 or quad9 slave facet
  MortarMeasure measure_;
  MasterSurface slave_facets_;
  std::vector<Index> index_;                     // mesh node -> slave node (-1: not a slave node)
  std::vector<std::vector<Index>> candidates_;   // per slave facet: master facets it may overlap
  // 3D, per slave facet: the candidates that overlapped it at the last evaluation and their
  // neighbours (a master that starts to overlap is most often next to one that does), the
  // masters coupled_nodes couples to; written by detect and build (const: a cache of its
  // result, one facet per thread).
  mutable std::vector<std::vector<Index>> coupled_masters_;
  // A shared-out build: each rank's facets (`mine`: their coupled masters and results) sent to
  // every rank, and the other ranks' received into `results`, `facet` and coupled_masters_, as
  // the facets' loop would have filled them.
  void exchange_results(const std::vector<char>& mine, std::vector<std::vector<MortarFacetResult>>& results,
                        std::vector<std::vector<Index>>& facet) const {
    const bool overlaps = dim_ == 3 && !self_;
    std::ostringstream os;
    const Index ne = slave_facets_.size();
    for (Index e = 0; e < ne; ++e) {
      if (!mine[e]) continue;
      binary::put<std::int64_t>(os, e);
      binary::put_vector(os, overlaps ? coupled_masters_[e] : std::vector<Index>{});
      binary::put<std::int64_t>(os, static_cast<std::int64_t>(results[e].size()));
      for (const MortarFacetResult& r : results[e]) write_facet_result(os, r);
    }
    const std::vector<std::string> all = ranks_->allgather(os.str());
    for (int q = 0; q < ranks_->size(); ++q) {
      if (q == ranks_->rank()) continue;
      std::istringstream is(all[q]);
      while (is.peek() != std::char_traits<char>::eof()) {
        const auto e = binary::get<std::int64_t>(is);
        if (e < 0 || e >= ne || mine[e]) throw SolverError(fmt::format("mortar: rank {} sent slave facet {} of {}", q, e, ne));
        std::vector<Index> coupled = binary::get_vector<Index>(is, -1, "mortar facet masters");
        if (overlaps) coupled_masters_[e] = std::move(coupled);
        const auto n = binary::get<std::int64_t>(is);
        for (std::int64_t i = 0; i < n; ++i) {
          MortarFacetResult r = read_facet_result(is);
          facet[e].push_back(r.facet);
          results[e].push_back(std::move(r));
        }
      }
    }
  }
  void set_coupled_masters(Index e, const std::vector<Index>& overlap) const {
    std::set<Index> near;
    for (Index f : overlap)
      for (Index g : master_.neighbourhood(f)) near.insert(g);
    coupled_masters_[e].clear();
    for (Index f : candidates_[e])
      if (near.count(f)) coupled_masters_[e].push_back(f);
  }
  std::vector<std::vector<Index>> excluded_;     // self-contact, per facet: its two-ring (sorted)
  std::vector<Real> gap_scale_;                  // self-contact, per slave node: int N~_j dA0
  std::vector<int> color_;                       // self-contact, per facet: 0 slave, 1 master, -1 neither
};

// Segment-to-segment by integration points (segment_to_segment.hpp): each slave facet's Gauss
// points projected onto the master, their gaps gathered per slave node with the dual shape
// functions (on the modified basis for tri6 and quad8). The constraint's gap is g~_j / w_j,
// w_j = int N~_j dA0 (the slave surface's weights, computed on the modified basis).
class SegmentToSegment final : public DeformableMaster {
 public:
  SegmentToSegment(const ContactPairSettings& s, const Mesh& mesh, const SlaveSurface& slave, const AnalysisSettings& as)
      : DeformableMaster(s, mesh, slave, as.spatial_dim()) {
    slave_facets_ = make_master_surface(mesh, s.slave);
    index_.assign(mesh.num_nodes(), -1);
    for (size_t j = 0; j < slave_.nodes.size(); ++j) index_[slave_.nodes[j]] = static_cast<Index>(j);
    candidates_.assign(slave_facets_.size(), {});
    hits_.assign(slave_facets_.size(), {});
    for (Index e = 0; e < slave_facets_.size(); ++e)
      integration_.push_back(make_integration_facet(slave_facets_.type[e], slave_facets_.facets[e], mesh.nodes, dim_,
                                                    as.dimension == Dimension::axisymmetric, as.thickness));
    gamma0_ = s.nitsche_gamma > 0 ? s.nitsche_gamma : kNitscheGamma;
    node_ids_ = &mesh.node_ids;
    cells_ = s.discretization == "mortar";
    finite_ = as.finite_strain;
    if (cells_) {
      rule_ = integration_;
      X_ = &mesh.nodes;
      axisymmetric_ = as.dimension == Dimension::axisymmetric;
      thickness_ = as.thickness;
    }
  }
  // Nitsche on mortar integration (cells_) is this class on mortar's segments.
  std::string name() const override { return cells_ ? "mortar" : "segment_to_segment"; }
  bool pressure_is_multiplier() const override { return true; }
  bool weighted_slip() const override { return true; }

  // Nitsche on mortar integration: each slave facet's points are those of mortar's segmentation
  // against its candidates (mortar_cell_points), each held on its cell's master facet; a facet
  // the master does not cover keeps its own rule. The cells are cut at the increment's start and
  // again at every build that assembles the Newton matrix (set_second_variation), i.e. at every
  // Newton iterate, and held for the residual-only builds that follow from it (a line search's
  // trial points, finite differences): the Newton matrix and its residual belong to one fixed
  // set of points, whose tangent is exact, and the converged state is integrated on its own
  // cells (Taylor's patch test exact after sliding). The tangent leaves out the cells' motion:
  // for an integrand continuous across the cells' edges (the gap and the master's shape
  // functions are, on a C0 master) the motion of the edges adds nothing to the integral's
  // derivative (the boundary terms of neighbouring cells cancel), and with a rule exact on each
  // cell neither does the motion of the points; otherwise the tangent is off by the derivative
  // of the rule's error.
  void begin_increment(const std::vector<Vec3>& x) override {
    if (!cells_) return;
    start_ = x;
    origins_.clear();  // set_point_origins, after the increment's first build
    segment(x);
  }

  void set_boundary_traction(BoundaryTraction* t) override {
    traction_ = t;
    cell_ = t->locate(slave_facets_.facets);
    cell_nodes_.assign(cell_.size(), {});
    for (size_t e = 0; e < cell_.size(); ++e) {
      if (cell_[e] < 0) {
        std::string nodes;
        for (Index n : slave_facets_.facets[e]) nodes += (nodes.empty() ? "" : ", ") + std::to_string((*node_ids_)[n]);
        throw Error("Nitsche's method needs the slave body's stress, but the slave facet of mesh nodes " + nodes +
                    " belongs to no cell of a deformable body (a rigid body, or a facet set that is not a body's boundary)");
      }
      cell_nodes_[e] = t->cell_nodes(cell_[e]);
    }
    // Nitsche's parameter per slave facet: gamma0 E / h, h the owning cell's height over the
    // facet (its volume over the facet's area) over the order (the trace inequality's constant
    // grows with the cell's aspect and the order).
    facet_size_.assign(cell_.size(), 0);
    for (size_t e = 0; e < cell_.size(); ++e)
      facet_size_[e] = t->height(cell_[e], slave_facets_.facets[e], slave_facets_.type[e]) /
                       element_info(slave_facets_.type[e]).order;
    positive_weights();
  }
  const std::vector<PointConstraint>* integration_points() const override { return traction_ ? &points_ : nullptr; }
  // A facet's points belong to rank e % ranks: a fixed owner, so that the slip origins a rank
  // records at an increment's start (set_point_origins, from its own points) are those of the
  // points it builds later, whatever the search finds in between.
  bool share_points(int rank, int ranks) override {
    if (!traction_ || ranks < 2) return false;
    point_rank_ = rank;
    point_ranks_ = ranks;
    return true;
  }
  void set_point_origins() override {
    if (!traction_) return;
    origins_.assign(integration_.size(), {});
    for (size_t e = 0; e < integration_.size(); ++e) origins_[e].assign(integration_[e].N.size(), {});
    for (const PointConstraint& pc : points_) origins_[pc.facet][pc.q] = pc.master_point;
  }

  void detect(const std::vector<Vec3>& x, Real dmax, Real motion, const std::vector<char>& tracked) override {
    facet_candidates(slave_facets_, index_, x, dmax, tracked, candidates_, motion);
    // The facets the points project on now, for the sparse pattern (coupled_nodes).
    const Index ne = slave_facets_.size();
    hits_.assign(ne, {});
    held_.resize(ne);
    FirstError first;
#pragma omp parallel for schedule(dynamic, 8)
    for (Index e = 0; e < ne; ++e) {
      if (candidates_[e].empty()) continue;
      first.run([&] {
        IntegrationResult r;
        integration_point_gaps(integration_[e], master_, candidates_[e], x, dim_, r, nullptr, &held_[e]);
        hits_[e] = std::move(r.hit);
      });
    }
    first.rethrow();
    if (log::level() <= log::Level::debug) {
      size_t with = 0, cand = 0, hit = 0;
      for (Index e = 0; e < ne; ++e)
        if (!candidates_[e].empty()) ++with, cand += candidates_[e].size(), hit += hits_[e].size();
      log::debug("segment_to_segment: {} slave facets within reach, {:.1f} candidate and {:.1f} hit master facets each",
                 with, double(cand) / std::max<size_t>(with, 1), double(hit) / std::max<size_t>(with, 1));
    }
  }

  // The nodes of the slave facets around the node (its normal's), and of the master facets
  // around those its facets' points projected on at the last detection or build (one ring of
  // master facets: room to slide before the pattern must grow). A point that moves beyond it
  // makes the assembly miss the pattern, which is then rebuilt from the build's own hits
  // (Analysis::assemble); the candidates alone (every master facet within reach of a slave
  // facet, some 50 in 3D) would make the pattern, and the factorization, several times denser.
  void coupled_nodes(size_t j, std::vector<Index>& nodes) const override {
    const Index node = slave_.nodes[j];
    std::set<Index> around;
    for (Index e : slave_facets_.node_facets[node]) {
      for (Index n : slave_facets_.facets[e]) around.insert(n);
      const std::vector<Index>& hit = hits_[e].empty() ? candidates_[e] : hits_[e];
      std::set<Index> ring;
      for (Index f : hit)
        for (Index g : master_.neighbourhood(f)) ring.insert(g);
      for (Index f : ring)
        for (Index m : master_.basis_nodes(f)) around.insert(m);
      // Nitsche: the point's traction couples the cell's nodes with the master's.
      if (traction_)
        for (Index n : cell_nodes_[e]) around.insert(n);
    }
    around.erase(node);
    nodes.assign(1, node);
    nodes.insert(nodes.end(), around.begin(), around.end());
  }

  void build(const std::vector<Vec3>& x, const VecX&, Real, ConstraintSet& out) const override {
    out = open_constraints(slave_);
    if (cells_ && second_variation_) segment(x);  // a Newton iterate: its own cells
    const Index ne = slave_facets_.size();
    std::vector<std::vector<IntegrationResult>> results(ne);
    std::vector<std::vector<Index>> facet(ne);
    std::vector<std::vector<PointConstraint>> points(traction_ ? ne : 0);
    held_.resize(ne);
    // An exception may not leave an OpenMP region (std::terminate): the first one thrown in the
    // loop (Nitsche's slave stress at an inverted cell, a SolverError the Newton iteration
    // answers by shortening its step) is kept and rethrown after it.
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 8)
    for (Index e = 0; e < ne; ++e) {
      if (candidates_[e].empty()) continue;
      try {
        IntegrationResult r;
        std::vector<IntegrationPointGap> pg;
        integration_point_gaps(integration_[e], master_, candidates_[e], x, dim_, r, traction_ ? &pg : nullptr,
                               &held_[e]);
        hits_[e] = r.hit;
        if (r.points == 0) continue;
        if (traction_ && e % point_ranks_ == point_rank_) nitsche_points(e, r, pg, x, points[e]);
        facet[e].push_back(r.first_facet);
        results[e].push_back(std::move(r));
      } catch (...) {
#pragma omp critical(segment_to_segment_error)
        if (!error) error = std::current_exception();
      }
    }
    if (error) std::rethrow_exception(error);
    if (traction_) {
      points_.clear();
      for (auto& v : points)
        for (auto& p : v) points_.push_back(std::move(p));
    }
    gather(slave_facets_, index_, results, facet, out);
    // Friction's slip origin: the weighted relative positions gathered over each constraint's
    // nodes (slip_j = sum of the facets' shares / w_j, in master_weights and slave_coefficient).
    const std::vector<VecX> relative = gather_relative(slave_facets_, index_, results, out);
    for (size_t j = 0; j < out.size(); ++j) {
      Constraint& c = out[j];
      if (c.kind == ConstraintKind::none) continue;
      if (!(c.weight > 0)) {
        Constraint open;
        open.slave = c.slave;
        open.weight = c.weight;
        c = std::move(open);
        continue;
      }
      c.gap /= c.weight;
      c.grad /= c.weight;
      c.hess /= c.weight;
      // The slave's averaged normal, turned to point from the master to the slave, with its
      // variation (friction's tangent reads it).
      set_slave_normal(slave_facets_, x, c);
      // The slip origin (after the normal, which may append nodes the slip does not involve).
      c.slave_coefficient = relative[j](0) / c.weight;
      c.master_weights.assign(c.nodes.size() - 1, 0.0);
      for (Index k = 1; k < relative[j].size(); ++k) c.master_weights[k - 1] = -relative[j](k) / c.weight;
    }
  }

 private:
  // Nitsche's integration points of slave facet e: the points' gaps (over r.nodes) with the
  // cell's other nodes appended, the slave body's normal pressure and its gradient, the
  // parameter and the shares of the nodal pressures.
  void nitsche_points(Index e, const IntegrationResult& r, const std::vector<IntegrationPointGap>& pg, const std::vector<Vec3>& x,
                      std::vector<PointConstraint>& out) const {
    const IntegrationFacet& f = integration_[e];
    const int ns = static_cast<int>(f.nodes.size());
    std::vector<Index> nodes = r.nodes;
    for (Index n : cell_nodes_[e])
      if (std::find(nodes.begin(), nodes.end(), n) == nodes.end()) nodes.push_back(n);
    // Friction: the master nodes of the points' slip origins (one list for the facet's points).
    const bool friction = !origins_.empty();
    if (friction)
      for (const IntegrationPointGap& g : pg)
        for (auto [n, w] : origins_[e][g.q])
          if (std::find(nodes.begin(), nodes.end(), n) == nodes.end()) nodes.push_back(n);
    const Index m = static_cast<Index>(nodes.size()) * dim_;
    const Index mr = static_cast<Index>(r.nodes.size()) * dim_;
    // Where each cell node sits in `nodes`.
    std::vector<Index> at;
    for (Index n : cell_nodes_[e]) at.push_back(std::find(nodes.begin(), nodes.end(), n) - nodes.begin());
    const Real eps = gamma0_ * traction_->stiffness(cell_[e]) / facet_size_[e];
    MatX tcell;
    for (const IntegrationPointGap& g : pg) {
      PointConstraint pc;
      pc.facet = e;
      pc.q = g.q;
      pc.master_point = g.master_point;
      pc.weight = f.weight[g.q];
      pc.gap = g.gap;
      pc.nodes = nodes;
      pc.facet_nodes = ns;
      pc.grad = VecX::Zero(m);
      pc.grad.head(mr) = g.grad;
      pc.hess = g.hess;
      pc.gap_nodes = static_cast<int>(r.nodes.size());
      // The slave body's traction t = sigma.nu (nu the facet's reference normal) and its
      // normal pressure p = -nu.t, with their gradients over `nodes`. Finite strain: t the
      // nominal traction F S nu, and p = -n.t with n the facet's current unit normal at the
      // point, dp = -n.dt - t.dn.
      const Vec3& nu = f.normal[g.q];
      traction_->traction(cell_[e], f.nodes, f.N[g.q], nu, x, pc.traction, tcell);
      pc.traction_grad = MatX::Zero(dim_, m);
      for (size_t a = 0; a < at.size(); ++a)
        pc.traction_grad.middleCols(at[a] * dim_, dim_) = tcell.middleCols(static_cast<Index>(a) * dim_, dim_);
      if (finite_) {
        current_normal(f, g.q, x, m, pc.normal, pc.normal_jacobian);
        pc.pressure = -pc.normal.head(dim_).dot(pc.traction.head(dim_));
        pc.pressure_grad = -(pc.traction_grad.transpose() * pc.normal.head(dim_)) -
                           pc.normal_jacobian.transpose() * pc.traction.head(dim_);
      } else {
        pc.pressure = -nu.head(dim_).dot(pc.traction.head(dim_));
        pc.pressure_grad = -(pc.traction_grad.transpose() * nu.head(dim_));
        pc.normal = nu;
      }
      pc.stiffness = eps;
      // The slip of the increment from the point's origin: d = sum_i N_i x_i - sum_b w_b x_b.
      if (friction && !origins_[e][g.q].empty()) {
        pc.has_slip = true;
        pc.slip_jacobian = MatX::Zero(dim_, m);
        pc.slip.setZero();
        for (int i = 0; i < ns; ++i) {
          const Real Ni = f.N[g.q](i);
          pc.slip += Ni * x[f.nodes[i]];
          pc.slip_jacobian.middleCols(static_cast<Index>(i) * dim_, dim_) += Ni * MatX::Identity(dim_, dim_);
        }
        for (auto [n, w] : origins_[e][g.q]) {
          const Index k = std::find(nodes.begin(), nodes.end(), n) - nodes.begin();
          pc.slip -= w * x[n];
          pc.slip_jacobian.middleCols(k * dim_, dim_) -= w * MatX::Identity(dim_, dim_);
        }
        if (dim_ == 2) pc.slip(2) = 0;
      }
      for (int j = 0; j < ns; ++j) {
        const Index sj = index_[f.nodes[j]];
        const Real np = std::max<Real>(f.Nt[g.q](j), 0);
        if (sj >= 0 && np > 0 && positive_weight_[sj] > 0)
          pc.shares.push_back({sj, np * f.weight[g.q] / positive_weight_[sj]});
      }
      out.push_back(std::move(pc));
    }
  }

  // The unit normal n = m / |m| of slave facet f at its point q at positions x (m = a1 x a2 in
  // 3D, (a1_y, -a1_x) in 2D: the reference normal's orientation, outward) and dn/dx over the
  // facet's nodes, the first of `m` columns: dn = (I - n n^T) dm / |m|, with dm/dx_i =
  // dN_i,1 [a1]x - dN_i,0 [a2]x in 3D ([v]x w = v x w) and dN_i,0 [[0, 1], [-1, 0]] in 2D.
  void current_normal(const IntegrationFacet& f, int q, const std::vector<Vec3>& x, Index m, Vec3& n,
                      MatX& jacobian) const {
    const MatX& dN = f.dN[q];
    const int ns = static_cast<int>(f.nodes.size());
    Vec3 a1 = Vec3::Zero(), a2 = Vec3::Zero();
    for (int i = 0; i < ns; ++i) {
      a1 += dN(i, 0) * x[f.nodes[i]];
      if (dim_ == 3) a2 += dN(i, 1) * x[f.nodes[i]];
    }
    const Vec3 mv = dim_ == 3 ? Vec3(a1.cross(a2)) : Vec3(a1(1), -a1(0), 0);
    const Real len = mv.norm();
    n = mv / len;
    const Mat3 P = (Mat3::Identity() - n * n.transpose()) / len;
    auto skew = [](const Vec3& v) {
      Mat3 s;
      s << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
      return s;
    };
    jacobian = MatX::Zero(dim_, m);
    for (int i = 0; i < ns; ++i) {
      Mat3 dm = Mat3::Zero();
      if (dim_ == 3) {
        dm = dN(i, 1) * skew(a1) - dN(i, 0) * skew(a2);
      } else {
        dm(0, 1) = dN(i, 0);
        dm(1, 0) = -dN(i, 0);
      }
      jacobian.middleCols(static_cast<Index>(i) * dim_, dim_) = (P * dm).topLeftCorner(dim_, dim_);
    }
  }

  // Nitsche on mortar integration: the cells at positions x (begin_increment). With friction,
  // each new point's slip origin is the master point it projected on at the increment's start.
  void segment(const std::vector<Vec3>& x) const {
    const Index ne = slave_facets_.size();
    held_.resize(ne);
    hits_.resize(ne);
    const bool friction = !origins_.empty();
    FirstError first;
#pragma omp parallel for schedule(dynamic, 8)
    for (Index e = 0; e < ne; ++e) {
      first.run([&] {
        std::vector<MortarCellPoint> cells;
        if (!candidates_[e].empty()) mortar_cell_points(slave_facets_, e, master_, candidates_[e], x, dim_, cells);
        if (cells.empty()) {
          integration_[e] = rule_[e];
          held_[e].assign(rule_[e].N.size(), -1);
        } else {
          std::vector<Vec2> xi(cells.size());
          std::vector<Real> w(cells.size());
          held_[e].resize(cells.size());
          hits_[e].clear();
          for (size_t q = 0; q < cells.size(); ++q) {
            xi[q] = Vec2(cells[q].xi[0], cells[q].xi[1]);
            w[q] = cells[q].weight;
            held_[e][q] = cells[q].master;
            hits_[e].push_back(cells[q].master);
          }
          std::sort(hits_[e].begin(), hits_[e].end());
          hits_[e].erase(std::unique(hits_[e].begin(), hits_[e].end()), hits_[e].end());
          integration_[e] = integration_facet_at(rule_[e], *X_, dim_, axisymmetric_, thickness_, xi, w);
        }
        if (friction) {
          origins_[e].assign(integration_[e].N.size(), {});
          if (candidates_[e].empty()) return;
          IntegrationResult r;
          std::vector<IntegrationPointGap> pg;
          std::vector<Index> held = held_[e];
          integration_point_gaps(integration_[e], master_, candidates_[e], start_, dim_, r, &pg, &held);
          for (IntegrationPointGap& g : pg) origins_[e][g.q] = std::move(g.master_point);
        }
      });
    }
    first.rethrow();
    if (traction_) positive_weights();
  }

  // The reported nodal pressure: the points' [P]_+ averaged with the positive part of the
  // modified basis, N+_j = max(N~_j, 0) (N~ itself is negative in places on tri6 and quad8).
  void positive_weights() const {
    positive_weight_.assign(slave_.nodes.size(), 0.0);
    for (size_t e = 0; e < integration_.size(); ++e) {
      const IntegrationFacet& f = integration_[e];
      for (size_t q = 0; q < f.Nt.size(); ++q)
        for (size_t j = 0; j < f.nodes.size(); ++j)
          if (index_[f.nodes[j]] >= 0)
            positive_weight_[index_[f.nodes[j]]] += std::max<Real>(f.Nt[q](static_cast<Index>(j)), 0) * f.weight[q];
    }
  }

  MasterSurface slave_facets_;
  std::vector<Index> index_;                     // mesh node -> slave node (-1: not a slave node)
  // Nitsche on mortar integration: the slave facets' own rules (integration_ holds the cells'
  // points of the increment), the reference positions and the measure.
  // (segment() is a cache of the cells: it runs in build).
  bool finite_ = false;  // Nitsche at finite strain: the current normal (current_normal)
  bool cells_ = false;
  std::vector<IntegrationFacet> rule_;
  const std::vector<Vec3>* X_ = nullptr;
  bool axisymmetric_ = false;
  Real thickness_ = 1;
  std::vector<Vec3> start_;  // the positions at the increment's start (the slip origins')
  // Nitsche's method: the boundary traction, per slave facet the owning cell (handle), its
  // nodes and the facet's size h, gamma0, and the integration points of the last build.
  const BoundaryTraction* traction_ = nullptr;
  const std::vector<Index>* node_ids_ = nullptr;  // mesh node ids, for messages
  std::vector<Index> cell_;
  std::vector<std::vector<Index>> cell_nodes_;
  std::vector<Real> facet_size_;
  mutable std::vector<Real> positive_weight_;  // per slave node: int max(N~_j, 0) dA0 (the reported pressure's average)
  Real gamma0_ = 0;
  // The points this process builds: slave facet e's when e % point_ranks_ == point_rank_
  // (share_points; one process: all of them).
  int point_rank_ = 0, point_ranks_ = 1;
  mutable std::vector<PointConstraint> points_;
  // Friction: per slave facet and integration point, the master point of its slip origin
  // (empty: none; the whole vector empty: no friction).
  mutable std::vector<std::vector<std::vector<std::pair<Index, Real>>>> origins_;
  std::vector<std::vector<Index>> candidates_;   // per slave facet: master facets it may meet
  mutable std::vector<IntegrationFacet> integration_;  // per slave facet: points, shape and dual functions
  // Per slave facet: the master facets its points projected on at the last detect or build
  // (the sparse pattern's; build updates it, so a rebuilt pattern follows the sliding).
  mutable std::vector<std::vector<Index>> hits_;
  // Per slave facet and point: the master facet the point is held on (integration_point_gaps).
  mutable std::vector<std::vector<Index>> held_;
};

// A rigid analytic obstacle, moved by its own unknowns: dim translations and, when a step turns
// it, the angles it turns by about its point (one about z in plane problems, a rotation vector
// in 3D; geometry/rotation.hpp). No search, no master nodes.
class RigidObstacleContact final : public Discretization {
 public:
  RigidObstacleContact(const RigidObstacle& ob, const SlaveSurface& slave, int dim, int angles)
      : ob_(ob), slave_(slave), dim_(dim), angles_(angles) {}
  std::string name() const override { return "rigid_obstacle"; }
  void detect(const std::vector<Vec3>&, Real, Real, const std::vector<char>&) override {}
  void coupled_nodes(size_t j, std::vector<Index>& nodes) const override { nodes.assign(1, slave_.nodes[j]); }
  int num_extra_dofs() const override { return dim_ + angles_; }
  void set_extra_dofs(Index first) override { first_ = first; }
  Index extra_dofs() const override { return first_; }
  void build(const std::vector<Vec3>& x, const VecX& z, Real dmax, ConstraintSet& out) const override {
    const Rotation rot = rotation_of(z);
    rigid_obstacle_constraints(ob_, offset(z), turns() ? &rot : nullptr, first_, slave_, x, dim_,
                               std::max(dmax, 1e-300), out);
  }
  SlipOrigin origin(const Constraint& c, const Vec3& x_s, const VecX& z) const override {
    // The closest point of the obstacle, in the obstacle's frame: relative to its point (the
    // centre it turns about) and turned back (it moves and turns with the obstacle).
    SlipOrigin o;
    o.valid = c.kind != ConstraintKind::none;
    o.point = x_s - c.gap * c.normal - ob_.point - offset(z);
    if (turns()) o.point = rotation_of(z).R.transpose() * o.point;
    return o;
  }
  void add_slip(const SlipOrigin& o, const std::vector<Vec3>& x, const VecX& z, Constraint& c) const override {
    // d = x_s - (p0 + offset + R(theta) q): dd/dtheta_i = -R_,i q, d2d/dtheta_i dtheta_j = -R_,ij q.
    const Rotation rot = rotation_of(z);
    const Vec3 rq = turns() ? Vec3(rot.R * o.point) : o.point;
    c.slip = x[c.slave] - (ob_.point + offset(z) + rq);
    c.slip_jacobian.setZero(dim_, c.grad.size());
    const Index first = static_cast<Index>(c.nodes.size()) * dim_;
    for (int d = 0; d < dim_; ++d) {
      c.slip_jacobian(d, d) = 1;
      if (first_ >= 0) c.slip_jacobian(d, first + d) = -1;
    }
    c.slip_hessian.clear();
    if (first_ >= 0 && turns()) {
      c.slip_hessian.assign(dim_, MatX::Zero(c.grad.size(), c.grad.size()));
      for (int i = 0; i < angles_; ++i) {
        const Vec3 di = -(rot.dR[i] * o.point);
        for (int d = 0; d < dim_; ++d) c.slip_jacobian(d, first + dim_ + i) = di(d);
        for (int k = 0; k < angles_; ++k) {
          const Vec3 dik = -(rot.d2R[i][k] * o.point);
          for (int d = 0; d < dim_; ++d) c.slip_hessian[d](first + dim_ + i, first + dim_ + k) = dik(d);
        }
      }
    }
    c.has_slip = true;
  }

 private:
  bool turns() const { return angles_ > 0 && first_ >= 0; }
  Vec3 offset(const VecX& z) const {
    Vec3 o = Vec3::Zero();
    if (first_ >= 0)
      for (int d = 0; d < dim_; ++d) o(d) = z(first_ + d);
    return o;
  }
  Rotation rotation_of(const VecX& z) const {
    Real a[3] = {0, 0, 0};
    if (turns())
      for (int i = 0; i < angles_; ++i) a[i] = z(first_ + dim_ + i);
    return rotation(a, angles_ > 0 ? angles_ : 1);
  }
  RigidObstacle ob_;
  SlaveSurface slave_;
  int dim_;
  int angles_;  // 0 (the obstacle only moves), 1 (about z) or 3 (rotation vector)
  Index first_ = -1;
};

}  // namespace

std::unique_ptr<Discretization> make_discretization(const ContactPairSettings& s, const Mesh& mesh,
                                                    const SlaveSurface& slave, const AnalysisSettings& as) {
  const int dim = as.spatial_dim();
  // The obstacle turns when a step turns it: about z in plane problems, by a rotation vector in
  // 3D (axisymmetry: it only moves along the axis).
  const int angles = !s.turns || as.dimension == Dimension::axisymmetric ? 0 : (dim == 3 ? 3 : 1);
  if (s.rigid) return std::make_unique<RigidObstacleContact>(s.obstacle, slave, dim, angles);
  if (s.self && s.discretization == "node_to_segment") return std::make_unique<SelfNodeToSegment>(s, mesh, slave, dim);
  if (s.discretization == "node_to_segment") return std::make_unique<NodeToSegment>(s, mesh, slave, dim);
  if (s.discretization == "node_to_node") return std::make_unique<NodeToNode>(s, mesh, slave, dim);
  // Nitsche on mortar integration: segment_to_segment's points on mortar's segments.
  if (s.discretization == "mortar" && s.method == "nitsche") return std::make_unique<SegmentToSegment>(s, mesh, slave, as);
  if (s.discretization == "mortar") return std::make_unique<Mortar>(s, mesh, slave, as);  // self-contact too
  if (s.discretization == "segment_to_segment") return std::make_unique<SegmentToSegment>(s, mesh, slave, as);
  throw Error("contact '" + s.name + "': unknown discretization '" + s.discretization + "'");
}

}  // namespace signorini
