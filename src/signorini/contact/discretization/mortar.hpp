// Segment-based dual mortar contact in 2D (Popp, Gitterle, Gee, Wall 2010, "A dual mortar
// approach for 2D finite deformation frictional contact problems", CMAME 199; Wohlmuth 2000
// for the dual basis). Per slave node j the weighted gap
//   g~_j = int_{Gamma_s} Phi_j g dA,   g = (x_m(chi(xi)) - x_s(xi)) . n(xi) / |n(xi)|,
// with n(xi) = sum_k N_k(xi) n_k the interpolation of the slave's averaged nodal normals, chi
// the projection of the slave point along n onto the master, and Phi_j the dual basis
//   Phi_j = sum_k A_jk N_k,  A = D M^-1,  M_jk = int_e N_j N_k dA,  D_jj = int_e N_j dA
// (biorthogonal: int_e Phi_j N_k dA = delta_jk D_jj), so that the multipliers are nodal
// pressures and a uniform pressure is represented exactly (sum_j Phi_j = 1).
// Segmentation: the master facet's end nodes are projected onto the slave facet along the
// interpolated slave normal; the segment is the overlap of that interval with the slave facet,
// integrated with Gauss points in the slave parameter. Everything (normals, projections,
// segment ends, dual basis, Jacobians) is computed on hyper-dual numbers
// (geometry/hyper_dual.hpp), so the gradient and Hessian of g~_j are exact, including the
// variation of the segmentation and of the normals (Popp et al. 2010, sec. 4, derive them by
// hand). dA carries the thickness, or 2 pi r in an axisymmetric analysis.
#pragma once
#include <vector>

#include "signorini/contact/surface.hpp"
#include "signorini/core/types.hpp"

namespace signorini {

// The measure of the contact surface: per unit length of the 2D curve, `thickness`, or 2 pi r.
struct MortarMeasure {
  Real thickness = 1;
  bool axisymmetric = false;
};

// One slave facet against one master facet.
struct MortarFacetResult {
  bool overlap = false;
  Real segment_length = 0;    // length of the segment on the slave facet (current configuration)
  std::vector<Index> nodes;   // the nodes the weighted gaps depend on (mesh indices): the slave
                              // facet's, the other nodes of its neighbouring slave facets (normals), the master's
  std::vector<Real> gap;      // per node of the slave facet: its share of g~_j
  std::vector<VecX> grad;     // d/dx over `nodes` (2 per node)
  std::vector<MatX> hess;
};

// `slave`: the slave surface's facets (with node_facets, for the averaged normals); facet e of
// it against facet m of `master`, at positions x. Without `derivatives` only the overlap, the
// segment length and the gaps are computed.
MortarFacetResult mortar_facet_2d(const MasterSurface& slave, Index e, const MasterSurface& master, Index m,
                                  const std::vector<Vec3>& x, const MortarMeasure& measure, bool derivatives);

// The averaged outward normal of the slave surface at mesh node `node` and its derivative with
// respect to the nodes of the facets around it (`nodes`, 2 columns per node).
void mortar_nodal_normal_2d(const MasterSurface& slave, Index node, const std::vector<Vec3>& x, Vec3& normal,
                            std::vector<Index>& nodes, MatX& jacobian);

}  // namespace signorini
