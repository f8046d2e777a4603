#include "signorini/contact/geometry/facet_projection.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>

#include "signorini/fem/shape.hpp"

namespace signorini {

namespace {

// Second derivatives of the facet's shape functions: central differences of the analytic
// first derivatives, exact (to round-off, for any step) because every facet shape function
// has degree <= 2 in each parameter (the Hermite segment: 3, in one parameter), so its first
// derivatives are at most quadratic in each, and central differences are exact on those.
constexpr Real kShapeStep = 0.25;

void second_derivatives(const FacetBasis& t, const Vec3& xi, int params, std::vector<Mat2>& d2) {
  if (t.patch) return t.eval_second(xi, d2);
  const int nn = t.num_nodes();
  d2.assign(nn, Mat2::Zero());
  const Real h = kShapeStep;
  VecX N;
  MatX dp, dm;
  for (int b = 0; b < params; ++b) {
    Vec3 xp = xi, xm = xi;
    xp(b) += h;
    xm(b) -= h;
    t.eval(xp, N, dp);
    t.eval(xm, N, dm);
    for (int i = 0; i < nn; ++i)
      for (int a = 0; a < params; ++a) d2[i](a, b) = (dp(i, a) - dm(i, a)) / (2 * h);
  }
  for (auto& m : d2) m = 0.5 * (m + m.transpose()).eval();
}

// Third derivatives d3[i][c](a, b) = N_i,abc: central differences of the second derivatives,
// exact for the same reason (N_i,ab has degree <= 2 in each parameter).
void third_derivatives(const FacetBasis& t, const Vec3& xi, int params, std::vector<std::array<Mat2, 2>>& d3) {
  if (t.patch) return t.eval_third(xi, d3);
  const int nn = t.num_nodes();
  d3.assign(nn, {Mat2::Zero(), Mat2::Zero()});
  std::vector<Mat2> dp, dm;
  for (int c = 0; c < params; ++c) {
    Vec3 xp = xi, xm = xi;
    xp(c) += kShapeStep;
    xm(c) -= kShapeStep;
    second_derivatives(t, xp, params, dp);
    second_derivatives(t, xm, params, dm);
    for (int i = 0; i < nn; ++i) d3[i][c] = (dp[i] - dm[i]) / (2 * kShapeStep);
  }
}

Vec3 normal_from_basis(const Vec3* a, int params) {
  if (params == 1) return Vec3(a[0](1), -a[0](0), 0).normalized();
  return a[0].cross(a[1]).normalized();
}

// Fills point, basis, metric, normal, curvature at fp.xi.
void evaluate(const FacetBasis& t, const std::vector<Vec3>& x, int params, FacetProjection& fp, const Vec3& p) {
  VecX N;
  MatX dN;
  t.eval(fp.xi, N, dN);
  fp.point.setZero();
  fp.a[0].setZero();
  fp.a[1].setZero();
  for (size_t i = 0; i < x.size(); ++i) {
    fp.point += N(i) * x[i];
    for (int a = 0; a < params; ++a) fp.a[a] += dN(i, a) * x[i];
  }
  fp.A = Mat2::Identity();
  for (int a = 0; a < params; ++a)
    for (int b = 0; b < params; ++b) fp.A(a, b) = fp.a[a].dot(fp.a[b]);
  fp.normal = normal_from_basis(fp.a, params);
  fp.gap = (p - fp.point).dot(fp.normal);
  std::vector<Mat2> d2;
  second_derivatives(t, fp.xi, params, d2);
  fp.H.setZero();
  for (size_t i = 0; i < x.size(); ++i)
    for (int a = 0; a < params; ++a)
      for (int b = 0; b < params; ++b) fp.H(a, b) += d2[i](a, b) * x[i].dot(fp.normal);
}

}  // namespace

int FacetBasis::num_nodes() const {
  if (patch) return static_cast<int>(patch->cols());
  return smooth ? 2 + has_prev + has_next : element_info(type).num_nodes;
}

namespace {

// Catmull-Rom weights of the points p_-1, p_0, p_1, p_2 of a curve at t in [0, 1] (the curve
// of FacetBasis::hermite without ghosts) and their k-th derivatives in t, k = 0..3.
std::array<Real, 4> catmull_rom(Real t, int k) {
  const Real t2 = t * t, t3 = t2 * t;
  Real h00, h10, h01, h11;
  switch (k) {
    case 0: h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2; break;
    case 1: h00 = 6 * t2 - 6 * t, h10 = 3 * t2 - 4 * t + 1, h01 = -6 * t2 + 6 * t, h11 = 3 * t2 - 2 * t; break;
    case 2: h00 = 12 * t - 6, h10 = 6 * t - 4, h01 = -12 * t + 6, h11 = 6 * t - 2; break;
    default: h00 = 12, h10 = 6, h01 = -12, h11 = 6; break;
  }
  return {-0.5 * h10, h00 - 0.5 * h11, h01 + 0.5 * h10, 0.5 * h11};
}

// Weights of the patch's nodes for the derivative of order (kx, ky) in (xi, eta):
// the grid weights w_i^(kx)(s) w_j^(ky)(t) (1/2 per derivative: d/dxi = d/ds / 2) mapped to
// the nodes through the patch's combinations.
VecX patch_weights(const MatX& patch, const Vec3& xi, int kx, int ky) {
  const auto wx = catmull_rom(0.5 * (xi(0) + 1), kx), wy = catmull_rom(0.5 * (xi(1) + 1), ky);
  const Real scale = std::pow(0.5, kx + ky);
  Eigen::Matrix<Real, 16, 1> g;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) g(i + 4 * j) = scale * wx[i] * wy[j];
  return patch.transpose() * g;
}

}  // namespace

void FacetBasis::eval_second(const Vec3& xi, std::vector<Mat2>& d2) const {
  const VecX w20 = patch_weights(*patch, xi, 2, 0), w11 = patch_weights(*patch, xi, 1, 1),
             w02 = patch_weights(*patch, xi, 0, 2);
  d2.assign(num_nodes(), Mat2::Zero());
  for (int i = 0; i < num_nodes(); ++i) d2[i] << w20(i), w11(i), w11(i), w02(i);
}

void FacetBasis::eval_third(const Vec3& xi, std::vector<std::array<Mat2, 2>>& d3) const {
  const VecX w30 = patch_weights(*patch, xi, 3, 0), w21 = patch_weights(*patch, xi, 2, 1),
             w12 = patch_weights(*patch, xi, 1, 2), w03 = patch_weights(*patch, xi, 0, 3);
  d3.assign(num_nodes(), {Mat2::Zero(), Mat2::Zero()});
  for (int i = 0; i < num_nodes(); ++i) {
    d3[i][0] << w30(i), w21(i), w21(i), w12(i);  // N_,ab0
    d3[i][1] << w21(i), w12(i), w12(i), w03(i);  // N_,ab1
  }
}

bool FacetBasis::simplex() const { return element_info(type).family == ShapeFamily::simplex; }

void FacetBasis::eval(const Vec3& xi, VecX& N, MatX& dN) const {
  if (patch) {
    N = patch_weights(*patch, xi, 0, 0);
    dN.resize(N.size(), 2);
    dN.col(0) = patch_weights(*patch, xi, 1, 0);
    dN.col(1) = patch_weights(*patch, xi, 0, 1);
    return;
  }
  if (!smooth) {
    shape_functions(type, xi, N, dN);
    return;
  }
  // Weights of x_prev, x_a, x_b, x_next (see the header), then the ghosts folded in:
  // x_prev = 2 x_a - x_b, x_next = 2 x_b - x_a.
  const Real t = 0.5 * (xi(0) + 1), t2 = t * t, t3 = t2 * t;
  const Real h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  const Real d00 = 6 * t2 - 6 * t, d10 = 3 * t2 - 4 * t + 1, d01 = -6 * t2 + 6 * t, d11 = 3 * t2 - 2 * t;
  Real w[4] = {-0.5 * h10, h00 - 0.5 * h11, h01 + 0.5 * h10, 0.5 * h11};
  Real dw[4] = {-0.5 * d10, d00 - 0.5 * d11, d01 + 0.5 * d10, 0.5 * d11};
  for (Real* v : {w, dw}) {
    if (!has_prev) v[1] += 2 * v[0], v[2] -= v[0], v[0] = 0;
    if (!has_next) v[2] += 2 * v[3], v[1] -= v[3], v[3] = 0;
  }
  const int n = num_nodes();
  N.resize(n);
  dN.setZero(n, 1);
  int k = 0;
  for (int i = 0; i < 4; ++i) {
    if ((i == 0 && !has_prev) || (i == 3 && !has_next)) continue;
    N(k) = w[i];
    dN(k, 0) = 0.5 * dw[i];  // dt/dxi = 1/2
    ++k;
  }
}

bool inside_reference(const FacetBasis& facet, const Vec3& xi, Real tol) {
  const ElementInfo& e = element_info(facet.type);
  if (e.family == ShapeFamily::simplex) return xi(0) >= -tol && xi(1) >= -tol && xi(0) + xi(1) <= 1 + tol;
  for (int d = 0; d < e.dim; ++d)
    if (std::abs(xi(d)) > 1 + tol) return false;
  return true;
}

Real outside_reference(const FacetBasis& facet, const Vec3& xi) {
  const ElementInfo& e = element_info(facet.type);
  if (e.family == ShapeFamily::simplex) return std::max({Real(0), -xi(0), -xi(1), xi(0) + xi(1) - 1});
  Real out = 0;
  for (int d = 0; d < e.dim; ++d) out = std::max(out, std::abs(xi(d)) - 1);
  return out;
}

Vec3 facet_normal(const FacetBasis& facet, const std::vector<Vec3>& x, const Vec3& xi, int dim) {
  FacetProjection fp;
  fp.xi = xi;
  evaluate(facet, x, dim - 1, fp, Vec3::Zero());
  return fp.normal;
}

FacetProjection project_on_facet(const FacetBasis& facet, const std::vector<Vec3>& x, const Vec3& p, int dim,
                                 Real inside_tolerance) {
  FacetProjection fp;
  fp.params = dim - 1;
  const int np = fp.params;
  // Start from the facet centre.
  fp.xi = facet.simplex() ? Vec3(1.0 / 3, 1.0 / 3, 0) : Vec3::Zero();
  // Newton on F_alpha = a_alpha . (p - x(xi)) = 0 with Jacobian -(A - g H).
  for (int it = 0; it < 30; ++it) {
    evaluate(facet, x, np, fp, p);
    const Vec3 r = p - fp.point;
    Eigen::Vector2d F = Eigen::Vector2d::Zero();
    for (int a = 0; a < np; ++a) F(a) = fp.a[a].dot(r);
    const Mat2 M = (fp.A - fp.gap * fp.H).topLeftCorner(2, 2);
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    if (np == 1) d(0) = F(0) / M(0, 0);
    else d = M.lu().solve(F);
    fp.iterations = it + 1;
    const Real scale = std::sqrt(fp.A.trace());
    if (!std::isfinite(d.norm()) || fp.xi.cwiseAbs().maxCoeff() > 1e3) break;
    for (int a = 0; a < np; ++a) fp.xi(a) += d(a);
    if (d.norm() < 1e-13 || F.norm() < 1e-14 * scale * (r.norm() + scale)) {
      evaluate(facet, x, np, fp, p);
      fp.converged = true;
      break;
    }
  }
  fp.inside = fp.converged && inside_reference(facet, fp.xi, inside_tolerance);
  return fp;
}

void gap_variations(const FacetBasis& facet, const std::vector<Vec3>& x, const FacetProjection& fp, int dim, VecX& grad,
                    MatX& hess, MatX* dxi) {
  // Notation (derivation in docs/contact.md): y = x_s - sum N_i x_i at fixed xi,
  //   Y_g = d(a_g . y), Q_a = d(n . sum N_i,a x_i), M = A - g H,
  //   Xi_b = d(xi_b) = M^-1 (Y + g Q), grad g = d(n . y) = [n, -N_1 n, ...],
  //   hess g = -A^{ag} Y_g (x) (Q_a + H_ab Xi_b) - Q_a (x) Xi_a.
  const int nn = facet.num_nodes(), np = fp.params, n = (nn + 1) * dim;
  VecX N;
  MatX dN;
  facet.eval(fp.xi, N, dN);
  grad.setZero(n);
  std::vector<VecX> Y(np, VecX::Zero(n)), Q(np, VecX::Zero(n)), Xi(np, VecX::Zero(n));
  for (int d = 0; d < dim; ++d) {
    grad(d) = fp.normal(d);
    for (int a = 0; a < np; ++a) Y[a](d) = fp.a[a](d);
  }
  for (int i = 0; i < nn; ++i)
    for (int d = 0; d < dim; ++d) {
      const int k = (i + 1) * dim + d;
      grad(k) = -N(i) * fp.normal(d);
      for (int a = 0; a < np; ++a) {
        Y[a](k) = -N(i) * fp.a[a](d);
        Q[a](k) = dN(i, a) * fp.normal(d);
      }
    }
  const Mat2 M = fp.A - fp.gap * fp.H;
  Mat2 Minv = Mat2::Zero(), Ainv = Mat2::Zero();
  if (np == 1) {
    Minv(0, 0) = 1 / M(0, 0);
    Ainv(0, 0) = 1 / fp.A(0, 0);
  } else {
    Minv = M.inverse();
    Ainv = fp.A.inverse();
  }
  for (int b = 0; b < np; ++b)
    for (int g = 0; g < np; ++g) Xi[b] += Minv(b, g) * (Y[g] + fp.gap * Q[g]);
  hess.setZero(n, n);
  for (int a = 0; a < np; ++a) {
    VecX qh = Q[a];
    for (int b = 0; b < np; ++b) qh += fp.H(a, b) * Xi[b];
    for (int g = 0; g < np; ++g) hess.noalias() -= Ainv(a, g) * Y[g] * qh.transpose();
    hess.noalias() -= Q[a] * Xi[a].transpose();
  }
  if (dxi) {
    dxi->resize(n, np);
    for (int a = 0; a < np; ++a) dxi->col(a) = Xi[a];
  }
}

void parameter_variations(const FacetBasis& facet, const std::vector<Vec3>& x, const FacetProjection& fp, int dim,
                          MatX& dxi, std::vector<MatX>& d2xi) {
  // F_a(u, xi) = a_a(xi; u) . r(xi; u), r = x_s - x(xi), is bilinear in the nodal positions at
  // fixed xi. With the linear maps d a_a = Aa[a] du, d r = R du, d a_ab = Aab[a][b] du:
  //   F_a,u     = Aa[a]^T r + R^T a_a
  //   F_a,uu    = Aa[a]^T R + R^T Aa[a]
  //   F_a,u xi_c = Aab[a][c]^T r - Aa[a]^T a_c - Aa[c]^T a_a + R^T a_ac
  //   F_a,xi_c  = a_ac . r - a_a . a_c = -M_ac  (M = A - g H, as r = g n)
  //   F_a,xi_c xi_d = a_acd . r - a_ac . a_d - a_ad . a_c - a_a . a_cd.
  // Differentiating F_a(u, xi(u)) = 0 once gives M dxi = F_u, twice
  //   M_ab d2xi_b = F_a,uu + sum_c (F_a,uxi_c (x) dxi_c + dxi_c (x) F_a,uxi_c)
  //                 + sum_cd F_a,xi_c xi_d dxi_c (x) dxi_d.
  const int nn = facet.num_nodes(), np = fp.params, n = (nn + 1) * dim;
  VecX N;
  MatX dN;
  facet.eval(fp.xi, N, dN);
  std::vector<Mat2> d2;
  second_derivatives(facet, fp.xi, np, d2);
  std::vector<std::array<Mat2, 2>> d3;
  third_derivatives(facet, fp.xi, np, d3);
  const Vec3 r = fp.gap * fp.normal;
  MatX R = MatX::Zero(dim, n);
  std::vector<MatX> Aa(np, MatX::Zero(dim, n));
  std::vector<std::vector<MatX>> Aab(np, std::vector<MatX>(np, MatX::Zero(dim, n)));
  std::vector<std::vector<Vec3>> aab(np, std::vector<Vec3>(np, Vec3::Zero()));
  std::vector<std::vector<std::vector<Vec3>>> aabc(
      np, std::vector<std::vector<Vec3>>(np, std::vector<Vec3>(np, Vec3::Zero())));
  for (int d = 0; d < dim; ++d) R(d, d) = 1;
  for (int i = 0; i < nn; ++i) {
    for (int d = 0; d < dim; ++d) {
      const int k = (i + 1) * dim + d;
      R(d, k) = -N(i);
      for (int a = 0; a < np; ++a) {
        Aa[a](d, k) = dN(i, a);
        for (int b = 0; b < np; ++b) Aab[a][b](d, k) = d2[i](a, b);
      }
    }
    for (int a = 0; a < np; ++a)
      for (int b = 0; b < np; ++b) {
        aab[a][b] += d2[i](a, b) * x[i];
        for (int c = 0; c < np; ++c) aabc[a][b][c] += d3[i][c](a, b) * x[i];
      }
  }
  auto head = [&](const Vec3& v) -> VecX { return v.head(dim); };
  // dxi = M^-1 F_u.
  const Mat2 M = fp.A - fp.gap * fp.H;
  Mat2 Minv = Mat2::Zero();
  if (np == 1) Minv(0, 0) = 1 / M(0, 0);
  else Minv = M.inverse();
  std::vector<VecX> Fu(np);
  for (int a = 0; a < np; ++a) Fu[a] = Aa[a].transpose() * head(r) + R.transpose() * head(fp.a[a]);
  dxi.setZero(n, np);
  for (int b = 0; b < np; ++b)
    for (int a = 0; a < np; ++a) dxi.col(b) += Minv(b, a) * Fu[a];
  // Right-hand sides of the second variation, one per condition a.
  std::vector<MatX> rhs(np);
  for (int a = 0; a < np; ++a) {
    MatX Fuu = Aa[a].transpose() * R;
    rhs[a] = Fuu + Fuu.transpose();
    for (int c = 0; c < np; ++c) {
      const VecX Fuxi = Aab[a][c].transpose() * head(r) - Aa[a].transpose() * head(fp.a[c]) -
                        Aa[c].transpose() * head(fp.a[a]) + R.transpose() * head(aab[a][c]);
      rhs[a].noalias() += Fuxi * dxi.col(c).transpose() + dxi.col(c) * Fuxi.transpose();
      for (int d = 0; d < np; ++d) {
        const Real Fxixi =
            aabc[a][c][d].dot(r) - aab[a][c].dot(fp.a[d]) - aab[a][d].dot(fp.a[c]) - fp.a[a].dot(aab[c][d]);
        rhs[a].noalias() += Fxixi * dxi.col(c) * dxi.col(d).transpose();
      }
    }
  }
  d2xi.assign(np, MatX::Zero(n, n));
  for (int b = 0; b < np; ++b)
    for (int a = 0; a < np; ++a) d2xi[b] += Minv(b, a) * rhs[a];
}

PointGap point_gap(const Vec3& slave, const Vec3& vertex, const Vec3& reference_normal, int dim, VecX* grad,
                   MatX* hess) {
  PointGap pg;
  const Vec3 d = slave - vertex;
  const Real len = d.norm();
  const Real s = d.dot(reference_normal) >= 0 ? 1.0 : -1.0;
  pg.gap = s * len;
  pg.normal = len > 0 ? Vec3(s * d / len) : reference_normal;
  if (grad) {
    grad->setZero(2 * dim);
    for (int k = 0; k < dim; ++k) {
      (*grad)(k) = pg.normal(k);
      (*grad)(dim + k) = -pg.normal(k);
    }
  }
  if (hess) {
    hess->setZero(2 * dim, 2 * dim);
    if (len > 0) {
      // d2(s |d|)/dd2 = s (I - m m)/|d| with m = d/|d|.
      const Vec3 m = d / len;
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          const Real v = s * ((i == j ? 1.0 : 0.0) - m(i) * m(j)) / len;
          (*hess)(i, j) = v;
          (*hess)(dim + i, dim + j) = v;
          (*hess)(i, dim + j) = -v;
          (*hess)(dim + i, j) = -v;
        }
    }
  }
  return pg;
}

EdgeGap edge_gap(const Vec3& slave, const Vec3& xa, const Vec3& xb, const Vec3& reference_normal, int dim, VecX* grad,
                 MatX* hess) {
  // phi(X, eta) = |d|, d = x_s - (1 - eta) x_a - eta x_b, minimised over eta: t . d = 0 with
  // t = x_b - x_a. With D = d d/dX = [I, -(1 - eta) I, -eta I], m = d/|d|, P = I - m m:
  //   grad g = s D^T m,
  //   hess g = s (D^T P D / |d| - b b^T / phi_ee),  b = phi_X,eta = [0, m, -m] - D^T t / |d|,
  //   phi_ee = |t|^2 / |d|  (second-order envelope theorem).
  EdgeGap eg;
  const Vec3 t = xb - xa;
  const Real tt = t.squaredNorm();
  eg.eta = tt > 0 ? t.dot(slave - xa) / tt : 0.0;
  const Vec3 d = slave - xa - eg.eta * t;
  const Real len = d.norm();
  const Real s = d.dot(reference_normal) >= 0 ? 1.0 : -1.0;
  eg.gap = s * len;
  eg.normal = len > 0 ? Vec3(s * d / len) : reference_normal;
  const int n = 3 * dim;
  MatX D = MatX::Zero(dim, n);
  for (int k = 0; k < dim; ++k) {
    D(k, k) = 1;
    D(k, dim + k) = -(1 - eg.eta);
    D(k, 2 * dim + k) = -eg.eta;
  }
  if (grad) *grad = D.transpose() * eg.normal.head(dim);
  if (hess) {
    hess->setZero(n, n);
    if (len > 0 && tt > 0) {
      const Vec3 m = d / len;
      const MatX P = MatX::Identity(dim, dim) - m.head(dim) * m.head(dim).transpose();
      VecX b = VecX::Zero(n);
      for (int k = 0; k < dim; ++k) {
        b(dim + k) = m(k);
        b(2 * dim + k) = -m(k);
      }
      b -= D.transpose() * t.head(dim) / len;
      *hess = s * (D.transpose() * P * D / len - b * b.transpose() * (len / tt));
    }
  }
  return eg;
}

}  // namespace signorini
