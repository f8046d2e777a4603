// Segment-to-segment contact by integration points (2D and 3D, every facet type): the Gauss
// points of each slave facet are projected onto the master surface (the closest-point
// projection of node-to-segment, contact/geometry/facet_projection), and their gaps are
// gathered into one weighted gap per slave node with the dual shape functions of the facet
// (Wohlmuth 2000), built on the modified basis of Popp, Wohlmuth, Gee & Wall (2012) for tri6
// and quad8 so that every node's weight is positive:
//   g~_j = sum_e sum_q Phi_j(xi_q) g(x_s(xi_q)) w_q J0_q,   w_j = sum_e int_e N~_j dA0,
// with the integration weights and the dual coefficients in the reference configuration
// (the mortar integrals evaluated at the integration points, "element-based integration" in
// Popp's terms, instead of on segments). The constraint is g~_j / w_j, so enforcement's force
// p w_j grad(g~_j / w_j) = p grad g~_j is the virtual work of the nodal pressure p_j
// interpolated with the dual basis. Its variations are the gap's at each point (exact, from
// gap_variations) carried to the slave facet's nodes by x_s = sum_i N_i(xi_q) x_i.
#pragma once
#include <vector>

#include "signorini/contact/surface.hpp"
#include "signorini/core/types.hpp"

namespace signorini {

// Per slave facet, once (reference configuration).
struct IntegrationFacet {
  ElementType type = ElementType::line2;
  std::vector<Index> nodes;
  std::vector<VecX> N;      // per point: the facet's shape functions (geometry)
  std::vector<MatX> dN;     // per point: their parameter derivatives (the current normal at finite strain)
  std::vector<VecX> phi;    // per point: the dual shape functions
  std::vector<VecX> Nt;     // per point: the modified basis N~ (friction's averaging weights)
  std::vector<Real> weight; // per point: quadrature weight x reference area element (x thickness or 2 pi r)
  std::vector<Vec3> normal; // per point: the unit normal of the reference facet (Nitsche's traction)
  VecX area;                // per node: int N~_j dA0 (positive)
  MatX dual;                // the dual coefficients A (Phi = A N~), of the whole facet
};

// The modified basis N~ = N with, for tri6 and quad8, N~_corner = N_corner + (1/5) (the two
// mid-side functions next to it) and N~_mid = (3/5) N_mid (Popp et al. 2012, alpha = 1/5): a
// partition of unity with positive integrals. Other types: N~ = N.
void modified_shape_functions(ElementType type, const VecX& N, VecX& Nt);

IntegrationFacet make_integration_facet(ElementType type, const std::vector<Index>& nodes,
                                        const std::vector<Vec3>& X, int dim, bool axisymmetric, Real thickness);

// The facet f (made by make_integration_facet) with its points replaced by `xi` (facet
// parameters) of weights `weight` in the parameter measure (mortar's cells: Nitsche on mortar
// integration, mortar_cell_points): N, N~, the weights times the reference area element (and
// thickness or 2 pi r) and the reference normals at them; the dual functions keep the whole
// facet's coefficients (f.dual) and `area` the whole facet's integrals.
IntegrationFacet integration_facet_at(const IntegrationFacet& f, const std::vector<Vec3>& X, int dim,
                                      bool axisymmetric, Real thickness, const std::vector<Vec2>& xi,
                                      const std::vector<Real>& weight);

// The weighted gaps of the facet's nodes at positions x against the master facets
// `candidates`: `nodes` the facet's nodes then the master nodes met; per facet node its gap
// share, gradient and Hessian over `nodes`; `first_facet` a master facet met (-1: none).
struct IntegrationResult {
  std::vector<Index> nodes;
  std::vector<Real> gap;
  std::vector<VecX> grad;
  std::vector<MatX> hess;
  // Friction: per facet node j, the coefficients over `nodes` of its weighted relative
  // position sum_q N~_j(xi_q) w_q (x_s(xi_q) - x_m(xi_q^m)), the slave point minus the master
  // point it projects on (with the master parameters frozen at the start of the increment, the
  // slip origin's combination). Weighted with the positive (modified) basis N~, not with the
  // dual functions: divided by w_j = int N~_j dA0 it is an average of the points' relative
  // motion. The dual-weighted slip (the mortar form of Popp et al. 2010) converged as well with
  // Lagrange multipliers but made the penalty's stick/slip states cycle at mu = 0.3 on the
  // press-then-shear family (docs/contact.md): near the edge of the contact zone the dual
  // functions change sign and so does a partly covered node's weighted slip.
  std::vector<VecX> relative;
  Index first_facet = -1;
  int points = 0;  // integration points that found the master
  std::vector<Index> hit;  // the master facets they projected on (sorted, unique)
};
// One point's own gap and variations over IntegrationResult::nodes (Nitsche's method).
struct IntegrationPointGap {
  int q = 0;  // the facet's integration point
  Real gap = 0;
  VecX grad;
  MatX hess;
  std::vector<std::pair<Index, Real>> master_point;  // the master nodes and their shape functions at the projection
};
// `held` (optional, one entry per point): the master facet each point projected on at the last
// evaluation (-1: none), kept while the point's projection on it stays inside it within the
// edge tolerance, and updated. A point on the edge between two master facets that meet at an
// angle otherwise changes facet, and with it the direction of its force, from one Newton
// iterate to the next (the nearest of the two projections flips with round-off-sized motions),
// and Newton cycles between the two (the 3D patch with quad4 slave facets over triangle masters,
// whose diagonals run through the slave facets' Gauss points).
void integration_point_gaps(const IntegrationFacet& f, const MasterSurface& master, const std::vector<Index>& candidates,
                            const std::vector<Vec3>& x, int dim, IntegrationResult& out,
                            std::vector<IntegrationPointGap>* points = nullptr, std::vector<Index>* held = nullptr);

}  // namespace signorini
