// Contact geometry on a master facet: closest-point projection of a slave point by Newton
// iterations in the facet parameters, normal gap, covariant basis, metric and curvature,
// and the first and second variations of the gap with respect to the slave and facet nodes
// (Wriggers, Computational Contact Mechanics, 2nd ed., 2006, sec. 4.3; course eqs. 4-6).
// Sign convention: g > 0 open, g < 0 penetration; the normal is the master's outward one.
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/mesh/element_type.hpp"

namespace signorini {

using Mat2 = Eigen::Matrix<Real, 2, 2>;

// The parameterisation x(xi) = sum_i N_i(xi) x_i of a master facet: the mesh facet's own
// shape functions, or (2D, `smooth`) a cubic Hermite segment between the facet's two nodes
// whose end tangents are the chords of the neighbouring segments, Catmull-Rom style:
//   x(t) = h00 x_a + h10 m_a + h01 x_b + h11 m_b,  t = (xi + 1)/2,
//   m_a = (x_b - x_prev)/2, m_b = (x_next - x_a)/2  (tangents per unit t),
// with the cubic Hermite polynomials h00 = 2t^3 - 3t^2 + 1, h10 = t^3 - 2t^2 + t,
// h01 = -2t^3 + 3t^2, h11 = t^3 - t^2. Neighbouring segments share the end point and the
// tangent direction, so the normal is continuous across nodes (G1); where a neighbour is
// missing (the end of the surface, or a corner kept sharp) a ghost node 2 x_a - x_b stands
// in for it, which makes the end tangent the segment's chord. Nodes: [prev], a, b, [next].
// The positions enter linearly, so the gap variations hold unchanged (Wriggers 2006,
// sec. 9.4 discusses Hermite and Bezier smoothing of 2D master surfaces).
//
// 3D (quad4 facets, `patch`): the tensor product of the same curves, a bicubic patch over the
// 4 x 4 grid of nodes around the facet (the facet is the grid's central cell),
//   x(xi, eta) = sum_ij w_i(s) w_j(t) X_ij,  s = (xi + 1)/2, t = (eta + 1)/2,
// with w the Catmull-Rom weights of the curve above. On a regular grid (four facets at every
// node) neighbouring patches share their edge curves and the cross-boundary tangents, so the
// surface is C1 and its normal continuous. Grid points that are not mesh nodes (the edge of
// the surface, a kink kept sharp, a node with other than four facets) are linear
// combinations of nodes (a ghost 2 X_1j - X_2j beyond an edge, a parallelogram completion
// X_01 + X_10 - X_11 at a corner); `patch` holds those combinations, one row per grid point
// (i + 4 j) and one column per node the patch depends on, so the positions still enter
// linearly. (Bicubic spline patches for contact: Wriggers 2006, sec. 9.4; Puso & Laursen
// 2002 smooth 3D masters with similar patches.)
struct FacetBasis {
  ElementType type = ElementType::line2;  // reference domain; the shape functions unless smooth
  bool smooth = false;
  bool has_prev = false, has_next = false;  // smooth: neighbour nodes present
  const MatX* patch = nullptr;            // 3D smooth: 16 x nodes, grid points from nodes
  FacetBasis() = default;
  FacetBasis(ElementType t) : type(t) {}  // NOLINT: a mesh facet is its own basis
  static FacetBasis hermite(bool prev, bool next) {
    FacetBasis b(ElementType::line2);
    b.smooth = true;
    b.has_prev = prev;
    b.has_next = next;
    return b;
  }
  static FacetBasis bicubic(const MatX* grid) {
    FacetBasis b(ElementType::quad4);
    b.smooth = true;
    b.patch = grid;
    return b;
  }
  int num_nodes() const;
  bool simplex() const;
  // N (num_nodes) and dN (num_nodes x parameters) at xi.
  void eval(const Vec3& xi, VecX& N, MatX& dN) const;
  // Bicubic patch only: the exact second derivatives d2[i](a, b) = N_i,ab and third
  // derivatives d3[i][c](a, b) = N_i,abc (the mesh facets and the Hermite curve get theirs
  // from exact central differences of eval).
  void eval_second(const Vec3& xi, std::vector<Mat2>& d2) const;
  void eval_third(const Vec3& xi, std::vector<std::array<Mat2, 2>>& d3) const;
};

struct FacetProjection {
  int params = 1;            // facet parameters: 1 (2D: line2, line3) or 2 (3D surfaces)
  Vec3 xi = Vec3::Zero();    // parameters of the closest point
  Vec3 point = Vec3::Zero(); // the closest point x(xi)
  Vec3 normal = Vec3::Zero();
  Real gap = 0;              // (slave - point) . normal
  Vec3 a[2];                 // covariant basis a_alpha = dx/dxi_alpha
  Mat2 A = Mat2::Identity(); // metric a_alpha . a_beta
  Mat2 H = Mat2::Zero();     // curvature n . x_{,alpha beta}
  bool converged = false;
  bool inside = false;       // xi inside the reference facet (with tolerance)
  int iterations = 0;
};

// The outward normal of a facet at parameters xi; `dim` is the space dimension (2 or 3).
Vec3 facet_normal(const FacetBasis& facet, const std::vector<Vec3>& x, const Vec3& xi, int dim);

// Closest-point projection of `p` on the facet with current nodal positions `x`.
FacetProjection project_on_facet(const FacetBasis& facet, const std::vector<Vec3>& x, const Vec3& p, int dim,
                                 Real inside_tolerance = 1e-9);

// Whether xi lies in the facet's reference domain, up to tol.
bool inside_reference(const FacetBasis& facet, const Vec3& xi, Real tol);

// How far xi lies outside the facet's reference domain, in reference parameters (0 inside):
// the largest violated bound.
Real outside_reference(const FacetBasis& facet, const Vec3& xi);

// Gradient and Hessian of the gap with respect to the DOFs [x_slave, x_1, ..., x_N]
// (dim components per node) at a converged projection; `dxi` (optional) gets the gradient of
// each facet parameter (one column per parameter).
void gap_variations(const FacetBasis& facet, const std::vector<Vec3>& x, const FacetProjection& fp, int dim, VecX& grad,
                    MatX& hess, MatX* dxi = nullptr);

// First and second variations of the facet parameters xi_b of the closest point with respect
// to [x_slave, x_1, ..., x_N] at a converged projection: `dxi` gets one column per parameter,
// `d2xi[b]` the Hessian of xi_b. Needed by the tangent of the tangential slip (friction).
// Derivation in docs/contact.md: the implicit function theorem applied twice to the
// projection condition F_a = a_a . (x_s - x(xi)) = 0 (Wriggers 2006, sec. 4.3, eq. 4.51 ff.).
void parameter_variations(const FacetBasis& facet, const std::vector<Vec3>& x, const FacetProjection& fp, int dim,
                          MatX& dxi, std::vector<MatX>& d2xi);

// Node-to-vertex: gap s |x_s - x_v| with s = sign((x_s - x_v) . n_ref) for a reference
// normal n_ref (the average normal of the facets at the vertex); gradient and Hessian with
// respect to [x_s, x_v].
struct PointGap {
  Real gap = 0;
  Vec3 normal = Vec3::Zero();
};
PointGap point_gap(const Vec3& slave, const Vec3& vertex, const Vec3& reference_normal, int dim, VecX* grad,
                   MatX* hess);

// Node-to-edge (3D): gap s |x_s - x_e| to the closest point x_e = (1 - eta) x_a + eta x_b of
// the straight edge [x_a, x_b], with s = sign((x_s - x_e) . n_ref) for a reference normal
// n_ref (the average normal of the facets along the edge); gradient and Hessian with respect
// to [x_s, x_a, x_b]. Valid for eta strictly inside (0, 1) (else node-to-vertex); derivation
// in docs/contact.md.
struct EdgeGap {
  Real gap = 0;
  Real eta = 0;
  Vec3 normal = Vec3::Zero();
};
EdgeGap edge_gap(const Vec3& slave, const Vec3& xa, const Vec3& xb, const Vec3& reference_normal, int dim, VecX* grad,
                 MatX* hess);

}  // namespace signorini
