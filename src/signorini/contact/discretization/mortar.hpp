// Segment-based dual mortar contact in 2D and 3D (mortar_3d.cpp). 2D: (Popp, Gitterle, Gee, Wall 2010, "A dual mortar
// approach for 2D finite deformation frictional contact problems", CMAME 199; Wohlmuth 2000
// for the dual basis). Per slave node j the weighted gap
//   g~_j = int_{Gamma_s} Phi_j g dA,   g = (x_m(chi(xi)) - x_s(xi)) . n(xi) / |n(xi)|,
// with n(xi) = sum_k N_k(xi) n_k the interpolation of the slave's averaged nodal normals, chi
// the projection of the slave point along n onto the master, and Phi_j the dual basis
//   Phi_j = sum_k A_jk N_k,  A = D M^-1,  M_jk = int_c N_j N_k dA,  D_jj = int_c N_j dA
// over c, the part of the slave facet e the master covers (all of e inside a contact zone;
// Cichosz and Bischoff 2011 for partly covered facets); biorthogonal: int_c Phi_j N_k dA =
// delta_jk D_jj, so that the multipliers are nodal pressures and a uniform pressure is
// represented exactly (sum_j Phi_j = 1), and a partly covered node's weighted gap has the sign
// of its gap.
// Segmentation: the master facet's end nodes are projected onto the slave facet along the
// interpolated slave normal; the segment is the overlap of that interval with the slave facet,
// integrated with Gauss points in the slave parameter. Per segment, its integrals G_k =
// int N_k g dA and M_jk (normals, projections, segment ends, Jacobians) are computed on
// hyper-dual numbers (geometry/hyper_dual.hpp), and g~_j = sum_k A_jk(M) G_k through the chain
// rule, so the gradient and Hessian of g~_j are exact, including the variation of the
// segmentation, of the normals and of the covered part (Popp et al. 2010, sec. 4, derive them by
// hand). dA carries the thickness, or 2 pi r in an axisymmetric analysis.
#pragma once
#include <iosfwd>
#include <vector>

#include "signorini/contact/surface.hpp"
#include "signorini/core/types.hpp"

namespace signorini {

// The measure of the contact surface: per unit length of the 2D curve, `thickness`, or 2 pi r.
struct MortarMeasure {
  Real thickness = 1;
  bool axisymmetric = false;
};

// One slave facet against the master facets it overlaps.
struct MortarFacetResult {
  bool overlap = false;
  std::vector<Index> masters;  // the master facets whose segments were integrated
  Index facet = -1;            // the one of the longest segment
  Real segment_length = 0;    // length of the segment on the slave facet (current configuration)
  std::vector<Index> nodes;   // the nodes the weighted gaps depend on (mesh indices): the slave
                              // facet's, the other nodes of its neighbouring slave facets (normals), the master's
  std::vector<Real> gap;      // per node of the slave facet: its share of g~_j
                              // (the master nodes: of all the facets in `masters`)
  std::vector<VecX> grad;     // d/dx over `nodes` (2 per node)
  std::vector<MatX> hess;
  // Friction: per node k of the slave facet, its share of the weighted relative position
  // int_c N~_k (x_s - x_m(chi)) dA as coefficients of `nodes` (slave nodes positive, master
  // nodes negative), and of its weight int_c N~_k dA (N~ = N on line2, the transformed basis on
  // line3: non-negative). Values only.
  std::vector<VecX> relative;
  std::vector<Real> slip_weight;
};

// A facet's result as bytes and back (the ranks' exchange of a shared-out build, core/
// rank_exchange.hpp): read_facet_result gives back every field as written, bit for bit, and
// throws Error on bytes that end early.
void write_facet_result(std::ostream& os, const MortarFacetResult& r);
MortarFacetResult read_facet_result(std::istream& is);

// `slave`: the slave surface's facets (with node_facets, for the averaged normals); facet e of
// it against the facets `masters` of `master`, at positions x. The dual basis is built on the
// part of the facet the masters cover (mortar.cpp, dual_weighted_gaps); a facet covered on less
// than 1e-3 of its length has no overlap. Without `derivatives` only the overlap, the segment
// length and the gaps are computed. `positive_basis` (self-contact): on line3 facets the dual
// basis of a transformed basis whose functions are non-negative (mortar.cpp).
MortarFacetResult mortar_element_2d(const MasterSurface& slave, Index e, const MasterSurface& master,
                                    const std::vector<Index>& masters, const std::vector<Vec3>& x,
                                    const MortarMeasure& measure, bool derivatives, bool positive_basis = false);

// Slave facet e (tri3, tri6, quad4, quad8, quad9) against the facets `masters` (the same types)
// in 3D (mortar_3d.cpp): the master facets' corners projected along the slave facet's centre
// normal onto its parameter plane, clipped against its reference element, the clipped polygon
// integrated in triangles from its centroid; the dual basis on the covered part as in 2D, on
// quadratic slave facets of the transformed basis N~ (mortar_dual.hpp, basis_transform:
// non-negative functions; the gaps are then the N~ coefficients' weighted gaps).
// `segment_length` is the covered current area; `relative` and `slip_weight` from the cells'
// rule points with N~ (N itself on tri3 and quad4). Without `hessian` (a residual without its
// Newton matrix) the derivatives are gradients only (`hess` stays empty), on first-order dual
// numbers: a sixth of the time on the tet4 Hertz sphere.
MortarFacetResult mortar_element_3d(const MasterSurface& slave, Index e, const MasterSurface& master,
                                    const std::vector<Index>& masters, const std::vector<Vec3>& x, bool derivatives,
                                    bool hessian = true);

// Mortar's segmentation as integration points (Nitsche on mortar integration: the points of the
// segments, 2D, or of the clipped polygons' triangles, 3D, that mortar_element_2d and
// mortar_element_3d integrate on): slave facet e against each of `masters` at positions x, per
// point the master facet of its segment or cell, its slave facet parameters (2D: xi[0]) and its
// weight in the parameter measure (the rule's weight times the segment's or cell's extent in
// the parameters; a current or reference area element makes it an area). The segments and cells
// of different master facets tile the part of the slave facet the master covers, so a function
// that is smooth on each master facet (the gap, the master's shape functions) is integrated
// to the rule's degree across master edges and nodes, which a slave facet's own Gauss rule is
// not (segment_to_segment).
struct MortarCellPoint {
  Index master = -1;
  Real xi[2] = {0, 0};
  Real weight = 0;
};
void mortar_cell_points(const MasterSurface& slave, Index e, const MasterSurface& master,
                        const std::vector<Index>& masters, const std::vector<Vec3>& x, int dim,
                        std::vector<MortarCellPoint>& out);
void mortar_cell_points_3d(const MasterSurface& slave, Index e, const MasterSurface& master,
                           const std::vector<Index>& masters, const std::vector<Vec3>& x,
                           std::vector<MortarCellPoint>& out);

// N~ from N (the shape functions of a 3D slave facet, whose count tells its type) as in
// mortar_dual.hpp, basis_transform: non-negative functions, N itself on tri3 and quad4; the basis
// 3D mortar's dual basis and node weights are built on.
void mortar_positive_basis(const VecX& N, VecX& Nt);

// The reference weight int N_j dA0 of each slave node (indexed by mesh node, 0 elsewhere; X the
// reference positions); with `positive_basis`, of the transformed line3 basis (mortar.cpp).
void mortar_slave_weights(const MasterSurface& slave, const std::vector<Vec3>& X, const MortarMeasure& measure,
                          bool positive_basis, std::vector<Real>& weight);
// The averaged outward normal of the slave surface at mesh node `node` and its derivative with
// respect to the nodes of the facets around it (`nodes`, 2 columns per node).
void mortar_nodal_normal_2d(const MasterSurface& slave, Index node, const std::vector<Vec3>& x, Vec3& normal,
                            std::vector<Index>& nodes, MatX& jacobian);

}  // namespace signorini
