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
constexpr int kMaxNs = 4;  // nodes of a slave facet: line2, line3 (2D), tri3, quad4 (3D)
constexpr int kMaxU = 14;  // G (4) and the upper triangle of M (10) for a quad4 slave facet
// The least share of a slave facet's parameter range that must be covered for its weighted gaps
// to count (see mortar_element_2d).
constexpr Real kMinCover = 1e-3;
inline int num_u(int ns) { return ns + ns * (ns + 1) / 2; }
inline int m_index(int ns, int i, int k) {  // the place of M_ik (i <= k) in u
  if (i > k) std::swap(i, k);
  return ns + k * (k + 1) / 2 + i;
}

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
// is the usual dual basis.
// With `positive` (self-contact), a line3 facet's basis is first transformed to
//   N~_corner = N_corner + N_mid / 4,  N~_mid = N_mid / 2
// (a transformed basis as in Popp, Wohlmuth, Gee and Wall 2012, "Dual quadratic mortar finite
// element methods for 3D finite deformation contact", SIAM J. Sci. Comput. 34; 1/4 is the
// value that makes the corner functions (1 + xi)^2 / 4 non-negative): then D_jj = int_c N~_j >= 0
// on any covered part c (a line3 corner function is negative on half its facet, so D_jj of a
// partly covered corner may be negative and flip its gap's sign). The gaps are then those of
// the N~ coefficients, and the node weights int N~_j dA0 (mortar_slave_weights).
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
template <class T>
void dual_weighted_gaps(int ns, const T* u_in, bool positive, T* gap) {
  T u[kMaxU];
  for (int i = 0; i < num_u(ns); ++i) u[i] = u_in[i];
  if (positive && ns == 3) {
    // G~ = T G, M~ = T M T^T with T = [1 0 a; 0 1 a; 0 0 1-2a].
    const Real a = kTransform, c = 1 - 2 * a;
    T G[3], M[3][3];
    for (int i = 0; i < 3; ++i) {
      G[i] = u_in[i];
      for (int k = 0; k < 3; ++k) M[i][k] = u_in[m_index(3, i, k)];
    }
    const Real Tm[3][3] = {{1, 0, a}, {0, 1, a}, {0, 0, c}};
    T TM[3][3];
    for (int i = 0; i < 3; ++i) {
      u[i] = T(0);
      for (int k = 0; k < 3; ++k) {
        if (Tm[i][k] != 0) u[i] += Tm[i][k] * G[k];
        TM[i][k] = T(0);
        for (int l = 0; l < 3; ++l)
          if (Tm[i][l] != 0) TM[i][k] += Tm[i][l] * M[l][k];
      }
    }
    for (int i = 0; i < 3; ++i)
      for (int k = i; k < 3; ++k) {
        T v = T(0);
        for (int l = 0; l < 3; ++l)
          if (Tm[k][l] != 0) v += TM[i][l] * Tm[k][l];
        u[m_index(3, i, k)] = v;
      }
  }
  T M[kMaxNs][kMaxNs], D[kMaxNs], inv[kMaxNs][kMaxNs];
  for (int i = 0; i < ns; ++i)
    for (int k = 0; k < ns; ++k) M[i][k] = u[m_index(ns, i, k)], inv[i][k] = T(i == k ? 1.0 : 0.0);
  for (int i = 0; i < ns; ++i) {
    D[i] = T(0);
    for (int k = 0; k < ns; ++k) D[i] += M[i][k];
  }
  // M^-1 by Gauss-Jordan on [M | I] (M is a mass matrix: symmetric positive definite).
  for (int p = 0; p < ns; ++p) {
    const T piv = 1 / M[p][p];
    for (int k = 0; k < ns; ++k) {
      M[p][k] = M[p][k] * piv;
      inv[p][k] = inv[p][k] * piv;
    }
    for (int r = 0; r < ns; ++r) {
      if (r == p) continue;
      const T f = M[r][p];
      for (int k = 0; k < ns; ++k) {
        M[r][k] -= f * M[p][k];
        inv[r][k] -= f * inv[p][k];
      }
    }
  }
  for (int j = 0; j < ns; ++j) {
    gap[j] = T(0);
    for (int k = 0; k < ns; ++k) gap[j] += D[j] * inv[j][k] * u[k];
  }
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
void weighted_gap_derivatives(int dim, int ns, const Real* u, bool positive_basis,
                              const std::vector<SegmentIntegrals>& segments, MortarFacetResult& r);

}  // namespace signorini::mortar_detail
