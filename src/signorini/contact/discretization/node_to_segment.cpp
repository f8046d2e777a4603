#include "signorini/contact/discretization/node_to_segment.hpp"

#include <algorithm>
#include <limits>

#include "signorini/contact/geometry/facet_projection.hpp"
#include "signorini/core/first_error.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

namespace {
constexpr Real kEdgeTolerance = 1e-2;  // in facet parameters
}  // namespace

void node_to_segment(const MasterSurface& master, const SlaveSurface& slave, const std::vector<Vec3>& x, int dim,
                     const std::vector<Index>& candidate, ConstraintSet& out,
                     const std::vector<std::vector<Index>>* excluded, const std::vector<Index>* held) {
  const Index ns = static_cast<Index>(slave.nodes.size());
  out = open_constraints(slave);
  FirstError first;  // an exception must not leave the OpenMP loop (std::terminate)
#pragma omp parallel for schedule(dynamic, 32)
  for (Index j = 0; j < ns; ++j) {
    try {
      Constraint& c = out[j];
      if (candidate[j] < 0 || !(c.weight > 0)) continue;
      const Vec3& p = x[c.slave];
      std::vector<Index> around = master.neighbourhood(candidate[j]);
      if (excluded) {
        const std::vector<Index>& ex = (*excluded)[j];
        around.erase(std::remove_if(around.begin(), around.end(),
                                    [&](Index f) { return std::binary_search(ex.begin(), ex.end(), f); }),
                     around.end());
      }
      // The facet closest to the node, measured as about the distance to the facet itself: the
      // gap on the facet's plane combined with how far the projection lies beyond the facet's
      // edge (its excess in reference parameters times the longer covariant base vector;
      // projections up to 1 % of the facet beyond its edge are accepted, on the facet's
      // extended surface: a slave node on a symmetry plane projects orthogonally onto a tilted
      // boundary facet of a deforming master slightly outside it, and the vertex fallback there
      // would switch its gap to another function and stall Newton). The measure is continuous
      // as the node moves, so the choice switches facet where both are about as close (the
      // planes' gaps still differ there: docs/contact.md, Limits). With a
      // rule "inside first, then the smallest |gap|", a penetrated node near a master vertex on
      // a symmetry plane jumped between a facet it lay over and a neighbour's extension whose
      // plane was 3 % nearer, every few Newton iterations (penalty on CalculiX's tet4 Hertz mesh:
      // the residual stalled at 5e-7).
      Index best = -1;
      FacetProjection best_fp;
      std::vector<Vec3> xf, best_x;
      Real best_dist = std::numeric_limits<Real>::infinity();
      // A node held on a facet (it went back and forth between two) keeps it while it projects
      // onto it, the facet extended by kHeldFacetTolerance beyond its edges.
      if (held && static_cast<Index>(held->size()) == ns && (*held)[j] >= 0) {
        const Index f = (*held)[j];
        for (Index n : master.basis_nodes(f)) xf.push_back(x[n]);
        const FacetProjection fp = project_on_facet(master.basis(f), xf, p, dim, kHeldFacetTolerance);
        if (fp.inside) {
          best = f;
          best_fp = fp;
          best_x = xf;
        }
      }
      if (best < 0)
        for (Index f : around) {
          xf.clear();
          for (Index n : master.basis_nodes(f)) xf.push_back(x[n]);
          const FacetBasis basis = master.basis(f);
          FacetProjection fp = project_on_facet(basis, xf, p, dim, kEdgeTolerance);
          if (!fp.inside) continue;
          Real metric = fp.A(0, 0);
          if (fp.params == 2) metric = std::max(metric, fp.A(1, 1));
          const Real beyond = outside_reference(basis, fp.xi) * std::sqrt(metric);
          // Distances equal to 1e-10 of the facet's edge are a tie, broken by the lower facet
          // index: a slave node over a master vertex or edge (the pole of a sphere over the
          // corner of a symmetric block) has the same gap on every facet around it up to
          // round-off, and round-off picked the facet, whose normal then set the force's
          // direction: the choice flipped from one Newton iteration to the next and the residual
          // stalled once at 2.7e-8 (examples/hertz_sphere_3d at hc 0.035; in units x 1e-3 it did
          // not).
          const Real tie = 1e-10 * (xf[1] - xf[0]).norm();
          const Real d = std::hypot(fp.gap, beyond);
          if (d < best_dist - tie || (d <= best_dist + tie && f < best)) {
            best_dist = d;
            best = f;
            best_fp = fp;
            best_x = xf;
          }
        }
      if (best >= 0) {
        c.kind = ConstraintKind::segment;
        c.facet = best;
        c.gap = best_fp.gap;
        c.normal = best_fp.normal;
        c.nodes.assign(1, c.slave);
        const std::vector<Index> bn = master.basis_nodes(best);
        c.nodes.insert(c.nodes.end(), bn.begin(), bn.end());
        const FacetBasis basis = master.basis(best);
        gap_variations(basis, best_x, best_fp, dim, c.grad, c.hess);
        VecX N;
        MatX dN;
        basis.eval(best_fp.xi, N, dN);
        c.master_weights.assign(N.data(), N.data() + N.size());
        c.normal_jacobian = c.hess.topRows(dim);  // n = d gap / d x_s
        continue;
      }
      // Node-to-edge (3D, straight edges of linear facets): the closest point on the edges of
      // the facets around the candidate, if it lies strictly inside an edge (the closest point
      // of the faceted surface is then on that edge: a convex ridge, or a blind spot).
      if (dim == 3) {
        Index ea = -1, eb = -1, ef = -1;
        Real ed = std::numeric_limits<Real>::infinity();
        for (Index f : around) {
          if (element_info(master.type[f]).order != 1) continue;
          const int nc = master.corners(f);
          for (int k = 0; k < nc; ++k) {
            const Index a = master.facets[f][k], b = master.facets[f][(k + 1) % nc];
            const Vec3 t = x[b] - x[a];
            const Real eta = t.dot(p - x[a]) / t.squaredNorm();
            if (!(eta > 1e-9 && eta < 1 - 1e-9)) continue;
            const Real dist = (p - x[a] - eta * t).norm();
            if (dist < ed) ed = dist, ea = a, eb = b, ef = f;
          }
        }
        Real vmin = std::numeric_limits<Real>::infinity();
        for (Index f : around)
          for (int k = 0; k < master.corners(f); ++k) vmin = std::min(vmin, (x[master.facets[f][k]] - p).norm());
        if (ea >= 0 && ed < vmin) {
          // Reference normal: the average of the normals of the facets along the edge.
          Vec3 nref = Vec3::Zero();
          for (Index f : around) {
            const auto& fn = master.facets[f];
            if (std::find(fn.begin(), fn.end(), ea) == fn.end() || std::find(fn.begin(), fn.end(), eb) == fn.end())
              continue;
            xf.clear();
            for (Index nd : fn) xf.push_back(x[nd]);
            const ElementInfo& info = element_info(master.type[f]);
            nref += facet_normal(master.type[f], xf, info.family == ShapeFamily::simplex ? Vec3(1.0 / 3, 1.0 / 3, 0) : Vec3::Zero(), 3);
          }
          nref.normalize();
          const Vec3 de = p - x[ea] - ((x[eb] - x[ea]).dot(p - x[ea]) / (x[eb] - x[ea]).squaredNorm()) * (x[eb] - x[ea]);
          // As for vertices: only a node facing the edge (within 60 degrees of its normal).
          if (de.norm() > 1e-12 * (1 + p.norm()) && std::abs(de.dot(nref)) < 0.5 * de.norm()) continue;
          EdgeGap eg = edge_gap(p, x[ea], x[eb], nref, dim, &c.grad, &c.hess);
          c.kind = ConstraintKind::edge;
          c.facet = ef;
          c.gap = eg.gap;
          c.normal = eg.normal;
          c.nodes = {c.slave, ea, eb};
          c.master_weights = {1 - eg.eta, eg.eta};
          c.normal_jacobian = c.hess.topRows(dim);
          continue;
        }
      }
      // Node-to-vertex: the nearest corner of the facets around the candidate.
      Index vertex = -1;
      Real vd = std::numeric_limits<Real>::infinity();
      for (Index f : around)
        for (int k = 0; k < master.corners(f); ++k) {
          const Index n = master.facets[f][k];
          const Real d = (x[n] - p).norm();
          if (d < vd) vd = d, vertex = n;
        }
      if (vertex < 0) continue;
      const Vec3 nref = master.node_normal(vertex, x, dim);
      // Only a node facing the vertex (within 60 degrees of its averaged normal, either side:
      // a convex corner or a blind spot) is constrained; one beside the end of the master
      // surface is not in contact with it, and its gap sign would be meaningless.
      const Vec3 d = p - x[vertex];
      if (d.norm() > 1e-12 * (1 + p.norm()) && std::abs(d.dot(nref)) < 0.5 * d.norm()) continue;
      PointGap pg = point_gap(p, x[vertex], nref, dim, &c.grad, &c.hess);
      c.kind = ConstraintKind::vertex;
      c.facet = vertex;
      c.gap = pg.gap;
      c.normal = pg.normal;
      c.nodes = {c.slave, vertex};
      c.master_weights = {1.0};
      c.normal_jacobian = c.hess.topRows(dim);
    } catch (...) {
      first.capture();
    }
  }
  first.rethrow();
}

void node_to_node(const SlaveSurface& slave, const std::vector<Index>& master_node, const std::vector<Vec3>& normal,
                  const std::vector<Vec3>& x, int dim, ConstraintSet& out) {
  const Index ns = static_cast<Index>(slave.nodes.size());
  out = open_constraints(slave);
  for (Index j = 0; j < ns; ++j) {
    Constraint& c = out[j];
    if (master_node[j] < 0 || !(c.weight > 0)) continue;
    c.kind = ConstraintKind::node;
    c.facet = master_node[j];
    c.normal = normal[j];
    c.gap = (x[c.slave] - x[master_node[j]]).dot(normal[j]);
    c.nodes = {c.slave, master_node[j]};
    c.master_weights = {1.0};
    c.grad.setZero(2 * dim);
    for (int d = 0; d < dim; ++d) {
      c.grad(d) = normal[j](d);
      c.grad(dim + d) = -normal[j](d);
    }
    c.hess.setZero(2 * dim, 2 * dim);  // the normal is frozen during the increment
    c.normal_jacobian.setZero(dim, 2 * dim);
  }
}

}  // namespace signorini
