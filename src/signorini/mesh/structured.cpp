#include "signorini/mesh/structured.hpp"

#include <array>
#include <cmath>

#include "signorini/core/error.hpp"
#include "signorini/fem/shape.hpp"

namespace signorini {

namespace {

// Affine sub-cells of the unit cube: each maps reference coordinates to [0,1]^dim.
struct SubCell {
  std::array<Vec3, 4> vertices;  // simplices: vertices; tensor: unused
};

Mesh structured(ElementType type, int dim, std::array<int, 3> n, Vec3 len,
                const StructuredOptions& opt) {
  const ElementInfo& info = element_info(type);
  if (info.dim != dim) throw Error("structured mesh: " + info.name + " is not a " +
                                   std::to_string(dim) + "D cell type");
  const int p = info.order;
  std::array<Index, 3> np{n[0] * p + 1, n[1] * p + 1, dim == 3 ? n[2] * p + 1 : 1};
  auto grid = [&](Index i, Index j, Index k) { return (k * np[1] + j) * np[0] + i; };
  const Index ngrid = np[0] * np[1] * np[2];
  std::vector<Index> index_of(ngrid, -1);

  std::vector<std::vector<Vec3>> subcells;  // simplex vertices in cube coordinates
  if (info.family == ShapeFamily::simplex) {
    if (dim == 2) {
      subcells.push_back({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
      subcells.push_back({Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(1, 0, 0)});
    } else {
      const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
      for (auto& pm : perms) {
        Vec3 a = Vec3::Zero(), b = a, c = a, d = Vec3::Ones();
        b(pm[0]) = 1;
        c = b;
        c(pm[1]) = 1;
        subcells.push_back({a, b, c, d});
      }
    }
  }

  Mesh m;
  m.dim = dim;
  ElementBlock block{type, {}, {}};
  Index next_id = 1;
  std::vector<Index> cell_nodes(info.num_nodes);
  for (int k = 0; k < (dim == 3 ? n[2] : 1); ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        auto emit = [&](auto to_cube) {
          for (int a = 0; a < info.num_nodes; ++a) {
            Vec3 c = to_cube(info.ref_coords[a]);
            Index gi = i * p + std::lround(c(0) * p), gj = j * p + std::lround(c(1) * p),
                  gk = dim == 3 ? k * p + std::lround(c(2) * p) : 0;
            Index g = grid(gi, gj, gk);
            if (index_of[g] < 0) index_of[g] = 0;  // mark used
            cell_nodes[a] = g;
          }
          block.add(cell_nodes, next_id++);
        };
        if (info.family == ShapeFamily::simplex) {
          for (auto& s : subcells)
            emit([&](const Vec3& xi) {
              Vec3 r = s[0];
              for (int d = 0; d < dim; ++d) r += xi(d) * (s[d + 1] - s[0]);
              return r;
            });
        } else {
          emit([&](const Vec3& xi) {
            Vec3 r = 0.5 * (xi + Vec3::Ones());
            if (dim == 2) r(2) = 0;
            return r;
          });
        }
      }
  // Number the used grid points and place them.
  unsigned state = opt.seed;
  auto rnd = [&]() {  // uniform in [-1, 1], a plain LCG so results are reproducible
    state = state * 1664525u + 1013904223u;
    return 2.0 * (state >> 8) / static_cast<Real>(1u << 24) - 1.0;
  };
  for (Index k = 0; k < np[2]; ++k)
    for (Index j = 0; j < np[1]; ++j)
      for (Index i = 0; i < np[0]; ++i) {
        Index g = grid(i, j, k);
        if (index_of[g] < 0) continue;
        Vec3 x(len(0) * i / (np[0] - 1), len(1) * j / (np[1] - 1),
               dim == 3 ? len(2) * k / (np[2] - 1) : 0.0);
        // Only lattice vertices move; higher-order nodes are placed from the corners below.
        const bool vertex = i % p == 0 && j % p == 0 && k % p == 0;
        const bool interior = vertex && i > 0 && i < np[0] - 1 && j > 0 && j < np[1] - 1 &&
                              (dim == 2 || (k > 0 && k < np[2] - 1));
        if (interior && opt.distortion > 0)
          for (int d = 0; d < dim; ++d) x(d) += opt.distortion * rnd() * len(d) / (np[d] - 1);
        index_of[g] = m.num_nodes();
        m.nodes.push_back(x + opt.origin);
        m.node_ids.push_back(m.num_nodes());
      }
  for (auto& c : block.conn) c = index_of[c];
  if (p > 1 && opt.distortion > 0) {
    // Straight-sided cells: each higher-order node sits where the cell's linear map puts it.
    const ElementType linear = info.family == ShapeFamily::simplex
                                   ? (dim == 2 ? ElementType::tri3 : ElementType::tet4)
                                   : (dim == 2 ? ElementType::quad4 : ElementType::hex8);
    const int nc = info.num_corners;
    for (Index e = 0; e < block.size(); ++e) {
      const Index* c = block.element(e);
      for (int a = nc; a < info.num_nodes; ++a) {
        VecX N;
        MatX dN;
        shape_functions(linear, info.ref_coords[a], N, dN);
        Vec3 x = Vec3::Zero();
        for (int k = 0; k < nc; ++k) x += N(k) * m.nodes[c[k]];
        m.nodes[c[a]] = x;
      }
    }
  }
  m.regions["domain"].push_back(std::move(block));
  check_and_orient(m);

  // Boundary sets: facets whose nodes all lie on a face of the box.
  const char* names[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
  for (int d = 0; d < dim; ++d)
    for (int side = 0; side < 2; ++side) {
      const Real plane = opt.origin(d) + side * len(d);
      const Real tol = 1e-9 * len(d);
      std::vector<ElementBlock> facets;
      const ElementBlock& cells = m.regions["domain"][0];
      for (Index e = 0; e < cells.size(); ++e)
        for (auto& f : info.facets) {
          std::vector<Index> fn;
          bool on = true;
          for (int a : f.nodes) {
            Index nd = cells.element(e)[a];
            on = on && std::abs(m.nodes[nd](d) - plane) < tol;
            fn.push_back(nd);
          }
          if (!on) continue;
          if (facets.empty()) facets.push_back(ElementBlock{f.type, {}, {}});
          facets[0].add(fn, facets[0].size() + 1);
        }
      m.facet_sets[names[d][side]] = std::move(facets);
      std::vector<Index> ns;
      for (Index a = 0; a < m.num_nodes(); ++a)
        if (std::abs(m.nodes[a](d) - plane) < tol) ns.push_back(a);
      m.node_sets[names[d][side]] = std::move(ns);
    }
  m.complete_node_sets();
  return m;
}

}  // namespace

Mesh structured_rectangle(ElementType type, int nx, int ny, Real lx, Real ly,
                          const StructuredOptions& opt) {
  return structured(type, 2, {nx, ny, 1}, Vec3(lx, ly, 0), opt);
}

Mesh structured_box(ElementType type, int nx, int ny, int nz, Real lx, Real ly, Real lz,
                    const StructuredOptions& opt) {
  return structured(type, 3, {nx, ny, nz}, Vec3(lx, ly, lz), opt);
}

}  // namespace signorini
