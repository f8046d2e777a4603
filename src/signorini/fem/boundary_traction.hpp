// The bodies' normal pressure at points of their boundary, from the stress of the cells that
// own the boundary facets: what Nitsche's method needs (Chouly, Hild & Renard 2015): the
// contact pressure p = -n.sigma(u).n of the slave body at a point of a slave facet and its
// gradient over the cell's displacements. Materials without history; at small strain sigma is
// the material's stress at the point (its strain from the cell's shape functions, which the
// point's facet coordinates give in the cell's reference element), dp/du = -m^T D B with m the
// Voigt form of n (x) n; its traction t = sigma.n for friction, dt/du = T D B. At finite strain
// (total Lagrangian) the nominal traction t = P n = F S n per reference area, n the reference
// normal, and dt/du = dF S n + F (D dE) n.
#pragma once
#include <memory>
#include <vector>

#include "signorini/fem/analysis_settings.hpp"
#include "signorini/material/material.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

class BoundaryTraction {
 public:
  // The cells (blocks with their material) whose facets may be asked for.
  struct Cells {
    const ElementBlock* block;
    const Material* material;
  };
  BoundaryTraction(std::vector<Cells> cells, const std::vector<Vec3>& X, AnalysisSettings settings);

  // The cell that owns each facet (node lists in the facet's order): a handle, -1 for a facet
  // no cell owns. It adds the owners to this object's table (so two threads must not locate on
  // one object, nor read handles while another locates: until session 70 this was a const
  // method over a mutable table, and a unit test's two thread-ranks sharing one object failed
  // once in a while, "a facet node is not a node of its cell").
  std::vector<Index> locate(const std::vector<std::vector<Index>>& facets);
  // Marks in `keep` (one flag per cell of `block`) the cells that own a facet located so far
  // (Body::keep_cells must keep them).
  void mark_needed(const ElementBlock* block, std::vector<char>& keep) const;
  // The block's cells renumbered (Body::keep_cells): cell e is now `index[e]` (-1: dropped,
  // which a cell that owns a located facet must not be).
  void renumber(const ElementBlock* block, const std::vector<Index>& index);
  // The owning cell's nodes and its material's stiffness scale (Young's modulus).
  std::vector<Index> cell_nodes(Index handle) const;
  Real stiffness(Index handle) const;
  // The owning cell's height over the facet (reference): its measure over the facet's (area
  // over length in 2D, volume over area in 3D): the length in the trace inequality that
  // Nitsche's parameter scales with.
  Real height(Index handle, const std::vector<Index>& facet, ElementType facet_type) const;
  // At the facet's point with facet shape functions N (facet nodes `facet`, owned by `handle`)
  // and unit normal n, the displacement u = x - X: p = -n.sigma.n and dp/du over cell_nodes
  // (dim per node).
  void normal_pressure(Index handle, const std::vector<Index>& facet, const VecX& N, const Vec3& n,
                       const std::vector<Vec3>& x, Real& p, VecX& grad) const;
  // The whole traction t = sigma.n at that point (friction's tangential part) and dt/du (dim
  // rows, columns as normal_pressure's gradient).
  void traction(Index handle, const std::vector<Index>& facet, const VecX& N, const Vec3& n,
                const std::vector<Vec3>& x, Vec3& t, MatX& grad) const;

 private:
  struct Owner {
    size_t cells;  // index into cells_
    Index element;
  };
  std::vector<Cells> cells_;
  const std::vector<Vec3>* X_;
  AnalysisSettings settings_;
  std::vector<Owner> owners_;
};

}  // namespace signorini
