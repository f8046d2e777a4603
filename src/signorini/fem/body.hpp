// A body: the cells of one region with one material. It computes internal forces, the
// tangent and per-cell results for a given displacement, for every analysis type
// (plane strain, plane stress, axisymmetric, 3D) and both small and finite strain. A rigid
// body has no material: its nodes share the DOFs of its reference node (see DofMap) and it
// adds no internal forces.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "signorini/fem/analysis_settings.hpp"
#include "signorini/fem/dof_map.hpp"
#include "signorini/fem/global_system.hpp"
#include "signorini/fem/history.hpp"
#include "signorini/fem/quadrature.hpp"
#include "signorini/material/material.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

// Per-cell averages over the quadrature points, for output.
struct CellResults {
  std::vector<Vec6> stress;   // Cauchy stress (Voigt, no engineering factor)
  std::vector<Vec6> strain;   // small strain or Green-Lagrange (tensor components)
  std::vector<Real> von_mises;
};

// One column of the strain-displacement matrix (Voigt, engineering shears) for the DOF of a
// node along direction i: delta E = sym(F^T delta H), with (f0, f1, f2) row i of F (I in
// small strain) and (g0, g1, g2) the node's shape function gradient.
template <class Column>
inline void strain_column(Column&& b, Real f0, Real f1, Real f2, Real g0, Real g1, Real g2) {
  b(0) = f0 * g0;
  b(1) = f1 * g1;
  b(2) = f2 * g2;
  b(3) = f1 * g2 + f2 * g1;
  b(4) = f0 * g2 + f2 * g0;
  b(5) = f0 * g1 + f1 * g0;
}

class Body {
 public:
  // A null material makes the body rigid.
  Body(std::string name, std::vector<ElementBlock> blocks, std::shared_ptr<const Material> material,
       AnalysisSettings settings);

  const std::string& name() const { return name_; }
  const std::vector<ElementBlock>& blocks() const { return blocks_; }
  const Material& material() const { return *material_; }
  bool rigid() const { return !material_; }
  // Its internal force is K u, K independent of u (small strain, a linear material).
  bool linear() const { return material_ && !settings_.finite_strain && material_->linear_at_small_strain(); }
  // Nodes that follow the body as a rigid body: the reference node set (nodes outside the
  // mesh's cells allowed). Only for rigid bodies.
  const std::vector<Index>& reference_nodes() const { return reference_; }
  void set_reference_nodes(std::vector<Index> nodes) { reference_ = std::move(nodes); }
  // A rigid body that turns (plane problems): its angle about its first reference node is an
  // unknown of its own (set when a step prescribes the angle or loads it by a moment).
  bool turns() const { return turns_; }
  void set_turns(bool t) { turns_ = t; }
  // The cells held here (after keep_cells, this MPI rank's share of the body).
  Index num_cells() const;
  // Partitioned over MPI ranks: keep only the cells marked (per block), the others dropped
  // (their connectivity and ids freed). The kept cells stay in their order; where each sat
  // in the whole body is remembered (whole_index), for the layouts that span the whole body
  // (a restart file's history).
  void keep_cells(const std::vector<std::vector<char>>& keep);
  // Block b's cell count in the whole body, and the whole body's index of its held cell e.
  Index whole_cells(size_t b) const { return whole_index_.empty() ? blocks_[b].size() : whole_cells_[b]; }
  Index whole_index(size_t b, Index e) const { return whole_index_.empty() ? e : whole_index_[b][static_cast<size_t>(e)]; }

  // Adds internal forces to `fint` (full DOF vector) and, if `matrix` is not null, the
  // tangent. Reads the committed history and writes the trial one of `history` (the body's,
  // owned by the analysis; may be null for a material without history); throws SolverError
  // on a non-physical state. dt: the increment's time (rate-dependent materials).
  // `owned` (partitioned assembly over MPI ranks): per block, the cells to assemble (null: all).
  void assemble(const std::vector<Vec3>& X, const VecX& u, const DofMap& dofs, VecX& fint, GlobalMatrix* matrix,
                QuadratureHistory* history = nullptr, Real dt = 0,
                const std::vector<std::vector<char>>* owned = nullptr) const;
  // Adds the consistent nodal forces of a dead body force b (per unit reference volume),
  // uniform or a function of the reference position. `owned`: as in assemble.
  void add_body_force(const std::vector<Vec3>& X, const DofMap& dofs, const Vec3& b, Real scale, VecX& fext,
                      const std::vector<std::vector<char>>* owned = nullptr) const;
  void add_body_force(const std::vector<Vec3>& X, const DofMap& dofs, const std::function<Vec3(const Vec3&)>& b,
                      Real scale, VecX& fext, const std::vector<std::vector<char>>* owned = nullptr) const;
  // Per-cell averages of stress and strain at the state `u` (from the committed history).
  // `owned` (an MPI rank's piece of the output): per block, the cells to evaluate (null: all);
  // the results then hold those cells only, block by block in cell order.
  CellResults results(const std::vector<Vec3>& X, const VecX& u, const DofMap& dofs,
                      const QuadratureHistory* history = nullptr,
                      const std::vector<std::vector<char>>* owned = nullptr) const;
  // Quadrature points per element of block b (the history's layout).
  Index points_per_element(size_t b) const { return static_cast<Index>(caches_[b].rule.size()); }
  // Reference volume (area times thickness, or with 2 pi r in axisymmetry).
  Real volume(const std::vector<Vec3>& X) const;

  // Element kernel: residual and tangent of one cell, exposed for tangent tests.
  // Xe: nodal reference coordinates, ue: nodal displacements (ndpn per node, node-major).
  void element(ElementType type, const std::vector<Vec3>& Xe, const VecX& ue, const Real* hist_old,
               Real* hist_new, VecX& fe, MatX* ke, Vec6* mean_stress = nullptr,
               Vec6* mean_strain = nullptr, Real dt = 0) const;

 private:
  struct BlockCache {
    QuadratureRule rule;
    std::vector<VecX> N;
    std::vector<MatX> dN;
  };
  const BlockCache& cache(ElementType t) const;

  std::string name_;
  std::vector<ElementBlock> blocks_;
  std::shared_ptr<const Material> material_;
  AnalysisSettings settings_;
  std::vector<BlockCache> caches_;  // one per block
  std::vector<Index> reference_;
  bool turns_ = false;
  std::vector<Index> whole_cells_;               // after keep_cells: each block's whole count
  std::vector<std::vector<Index>> whole_index_;  // after keep_cells: each held cell's whole index
};

}  // namespace signorini
