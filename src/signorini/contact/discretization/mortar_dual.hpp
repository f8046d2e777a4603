// Internal to the mortar discretization (mortar.cpp: 2D segments, mortar_3d.cpp: 3D clipped
// cells): the integrals a slave facet's weighted gaps are made of, the dual basis built from
// them on the covered part of the facet, and the chain rule that turns the integrals'
// derivatives into the weighted gaps' derivatives.
#pragma once
#include <algorithm>
#include <utility>
#include <vector>

#include "signorini/contact/discretization/mortar.hpp"
#include "signorini/core/types.hpp"

namespace signorini::mortar_detail {

// The integrals of one segment (2D) or of the cells of one clipped polygon (3D), the slave
// facet's overlap with one master facet, that the weighted gaps are made of, in the standard
// basis N_k of the slave facet:
//   G_k = int_seg N_k g dA,   M_ik = int_seg N_i N_k dA   (u = [G_0.., M_00, M_01, M_11, M_02, M_12, M_22, ...]).
constexpr int kMaxNs = 9;  // nodes of a slave facet: line2, line3 (2D), tri3, quad4, tri6, quad8, quad9 (3D)
constexpr int kMaxU = 54;  // G (9) and the upper triangle of M (45) for a quad9 slave facet
constexpr int kMaxU2d = 9;  // a line3 slave facet's
// The least share of a slave facet's parameter range that must be covered for its weighted gaps
// to count (see mortar_element_2d).
constexpr Real kMinCover = 1e-3;
inline int num_u(int ns) { return ns + ns * (ns + 1) / 2; }
inline int m_index(int ns, int i, int k) {  // the place of M_ik (i <= k) in u
  if (i > k) std::swap(i, k);
  return ns + k * (k + 1) / 2 + i;
}

// line3's transformed basis (self-contact in 2D, and the weights of friction's slip on line3):
//   N~_corner = N_corner + N_mid / 4,  N~_mid = N_mid / 2
// (Popp, Wohlmuth, Gee and Wall 2012, "Dual quadratic mortar finite element methods for 3D
// finite deformation contact", SIAM J. Sci. Comput. 34; 1/4 makes the corner functions
// (1 + xi)^2 / 4 non-negative): D_jj = int_c N~_j >= 0 on any covered part c (a line3 corner
// function is negative on half its facet, so D_jj of a partly covered corner may be negative and
// flip its gap's sign). See basis_transform for the other facets.
constexpr Real kTransform = 0.25;

// N~ from N (line3: the transformed basis above; line2: N itself).
inline void transformed_basis(int ns, const Real* N, Real* Nt) {
  for (int k = 0; k < ns; ++k) Nt[k] = N[k];
  if (ns == 3) {
    Nt[0] += kTransform * N[2];
    Nt[1] += kTransform * N[2];
    Nt[2] = (1 - 2 * kTransform) * N[2];
  }
}
// A slave facet's transformed basis N~_i = sum_k T_ik N_k (identity: N~ = N).
struct BasisTransform {
  bool identity = true;
  Real t[kMaxNs][kMaxNs] = {};
};
// The transformed basis of a slave facet of ns nodes in `dim` dimensions whose functions are
// non-negative, so that every node's weight int_c N~_j dA on any covered part c is >= 0 (Popp,
// Wohlmuth, Gee and Wall 2012: N~_corner = N_corner + alpha (the mid-side functions next to it),
// N~_mid = (1 - 2 alpha) N_mid; they take alpha = 1/5, which makes the weights on the whole
// facet positive but not the functions):
//  - line3 (only with `positive`, self-contact) and tri6: alpha = 1/4, which gives the Bernstein
//    polynomials ((1 + xi)^2 / 4 on line3; lambda_i^2 and 2 lambda_i lambda_j on tri6, with the
//    barycentric coordinates lambda);
//  - quad8: alpha = 3/8, the least alpha for which the corner function is non-negative (near the
//    opposite corner, N_corner ~ -3 e^2 / 4 and each mid-side function ~ e^2 at distance e);
//  - quad9: the tensor product of line3's (alpha = 1/4 in each direction: Bernstein again).
// Linear facets keep N.
BasisTransform basis_transform(int dim, int ns, bool positive);

// The weighted gaps from the element's summed segment integrals u: the dual basis built on the
// covered part of the slave facet (Cichosz and Bischoff 2011, "Consistent treatment of
// boundaries with mortar contact formulations using dual Lagrange multipliers", CMAME 200; used
// by Popp, Wohlmuth, Gee and Wall 2013, "Improved robustness and consistency of 3D contact
// algorithms based on a dual mortar approach", CMAME 264),
//   A = D M^-1,  D_jj = sum_k M_jk,  g~_j = sum_k A_jk G_k,
// biorthogonal on the covered part, so that a gap field the slave basis interpolates gives
// g~_j = D_jj g_j with D_jj = int_covered N_j > 0: a node whose support a master covers only in
// part gets a weighted gap of the sign of its gap (the basis built on the whole facet is negative
// on part of it, and read two walls 0.8 mm apart as a penetration). On a fully covered facet it
// is the usual dual basis. With a transformed basis (basis_transform) the same on N~:
// G~ = T G, M~ = T M T^T; the gaps are then those of the N~ coefficients, and the node weights
// int N~_j dA0.
// The dual basis's coefficients Phi_j = sum_k A_jk N~_k, A = D M~^-1 (row-major, ns x ns), and
// G~ = T G, from the summed integrals u (see dual_weighted_gaps).
template <class T>
void dual_matrix(int ns, const T* u_in, const BasisTransform& tr, T* A, T* Gt_out) {
  std::vector<T> G(u_in, u_in + ns), M(static_cast<size_t>(ns * ns)), inv(static_cast<size_t>(ns * ns), T(0)), D(ns, T(0));
  for (int i = 0; i < ns; ++i)
    for (int k = 0; k < ns; ++k) M[i * ns + k] = u_in[m_index(ns, i, k)];
  if (!tr.identity) {
    // G~ = T G, M~ = T M T^T (T is sparse: its zeros are skipped).
    std::vector<T> Gt(ns, T(0)), TM(static_cast<size_t>(ns * ns), T(0));
    for (int i = 0; i < ns; ++i)
      for (int l = 0; l < ns; ++l) {
        const Real t = tr.t[i][l];
        if (t == 0) continue;
        Gt[i] += t * G[l];
        for (int k = 0; k < ns; ++k) TM[i * ns + k] += t * M[l * ns + k];
      }
    for (int i = 0; i < ns; ++i)
      for (int k = i; k < ns; ++k) {
        T v = T(0);
        for (int l = 0; l < ns; ++l)
          if (tr.t[k][l] != 0) v += tr.t[k][l] * TM[i * ns + l];
        M[i * ns + k] = v;
        M[k * ns + i] = v;
      }
    G.swap(Gt);
  }
  for (int i = 0; i < ns; ++i) {
    inv[i * ns + i] = T(1.0);
    for (int k = 0; k < ns; ++k) D[i] += M[i * ns + k];
  }
  // M^-1 by Gauss-Jordan on [M | I] (M is a mass matrix: symmetric positive definite).
  for (int p = 0; p < ns; ++p) {
    const T piv = 1 / M[p * ns + p];
    for (int k = 0; k < ns; ++k) {
      M[p * ns + k] = M[p * ns + k] * piv;
      inv[p * ns + k] = inv[p * ns + k] * piv;
    }
    for (int r = 0; r < ns; ++r) {
      if (r == p) continue;
      const T f = M[r * ns + p];
      for (int k = 0; k < ns; ++k) {
        M[r * ns + k] -= f * M[p * ns + k];
        inv[r * ns + k] -= f * inv[p * ns + k];
      }
    }
  }
  for (int j = 0; j < ns; ++j)
    for (int k = 0; k < ns; ++k) A[j * ns + k] = D[j] * inv[j * ns + k];
  if (Gt_out)
    for (int k = 0; k < ns; ++k) Gt_out[k] = G[k];
}
// The weighted gaps g~_j = sum_k A_jk G~_k.
template <class T>
void dual_weighted_gaps(int ns, const T* u_in, const BasisTransform& tr, T* gap) {
  std::vector<T> A(static_cast<size_t>(ns * ns), T(0)), G(ns, T(0));
  dual_matrix(ns, u_in, tr, A.data(), G.data());
  for (int j = 0; j < ns; ++j) {
    T s = T(0);
    for (int k = 0; k < ns; ++k) s += A[j * ns + k] * G[k];
    gap[j] = s;
  }
}

// Friction's weighted relative positions in the dual basis: given, per node k of the slave
// facet, int N~_k (x_s - x_m) dA (`relative`, as coefficients of the nodes) and int N~_k dA
// (`weight`), summed over the facet's cells, they become int Phi_j (x_s - x_m) dA =
// sum_k A_jk int N~_k (x_s - x_m) dA and int Phi_j dA = D_jj, the test functions of the weighted
// gaps (Gitterle, Popp, Gee and Wall 2010, "Finite deformation frictional mortar contact using a
// semi-smooth Newton method with consistent linearization", IJNME 84, sec. 3: the weighted
// tangential slip with the dual shape functions, as the weighted gap). By biorthogonality the
// slave side is then D_jj times node j's own coefficient in the N~ basis (its own position on
// tri3 and quad4), not an average over the facet's other nodes; the tangential multiplier acts
// on the slave nodes as the normal one does (D diagonal), and the Coulomb cone compares two
// multipliers of one space. With the N~ weights instead (until session 61), the stick rows
// coupled each node to its facets' other nodes through a mass matrix, whose inverse put a noise
// of 0.16 (mu 0.3) to 0.24 (mu 0.8) times the pressure in the stick zone's tangential traction
// of the tet10 Hertz quarter, where the exact one is about 0 (0.02 and 0.014 with the dual
// weights), and stick/slip cycled at mu 0.1 (33 iterations and a cutback, now 8).
inline void dual_slip_weights(int ns, const Real* u, const BasisTransform& tr, std::vector<VecX>& relative,
                              std::vector<Real>& weight) {
  Real A[kMaxNs * kMaxNs];
  dual_matrix<Real>(ns, u, tr, A, nullptr);
  const Index n = relative.empty() ? 0 : relative[0].size();
  std::vector<VecX> rd(ns, VecX::Zero(n));
  std::vector<Real> wd(ns, 0.0);
  for (int j = 0; j < ns; ++j)
    for (int k = 0; k < ns; ++k) {
      rd[j] += A[j * ns + k] * relative[k];
      wd[j] += A[j * ns + k] * weight[k];
    }
  relative = std::move(rd);
  weight = std::move(wd);
}

// One segment's integrals u with their gradients and Hessians over the pair's nodes.
struct SegmentIntegrals {
  std::vector<Index> nodes;
  Real u[kMaxU] = {};
  std::vector<VecX> grad;  // per u, over `nodes` (dim per node)
  std::vector<MatX> hess;
};

// The weighted gaps of slave facet e's nodes (r.gap, r.grad, r.hess over r.nodes, `dim`
// coordinates each) from its summed integrals u and each segment's (or clipped polygon's)
// integrals with their derivatives: grad = sum_a f_a grad u_a, hess = sum_a f_a hess u_a +
// sum_ab f_ab grad u_a grad u_b^T, f = g~(u) differentiated by hyper-dual numbers over u.
void weighted_gap_derivatives(int dim, int ns, const Real* u, const BasisTransform& tr,
                              const std::vector<SegmentIntegrals>& segments, MortarFacetResult& r);

}  // namespace signorini::mortar_detail
