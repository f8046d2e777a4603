#include "signorini/contact/enforcement/enforcement.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <cstdlib>
#include <sstream>

#include "signorini/core/binary_io.hpp"
#include "signorini/core/error.hpp"
#include "signorini/fem/coloring.hpp"

namespace signorini {

namespace {

// DOFs of a constraint's nodes, node after node.
void constraint_dofs(const Constraint& c, const DofMap& dofs, int dim, std::vector<Index>& out) {
  out.clear();
  for (Index n : c.nodes)
    for (int d = 0; d < dim; ++d) out.push_back(dofs.dof(n, d));
  out.insert(out.end(), c.extra_dofs.begin(), c.extra_dofs.end());
}

// Constraints that share a node's DOFs (or an obstacle's unknowns) get different colours, so
// the assembly adds into each entry in one fixed order (fem/coloring.hpp). A constraint's own
// multiplier rows are its alone. Slots: DOF / dofs per node over every unknown.
Coloring color_constraints(const EnforcementInput& in, Index total_unknowns) {
  const ConstraintSet& cs = *in.constraints;
  const int dim = in.dim;
  return color_items(static_cast<Index>(cs.size()), total_unknowns / dim + 1, [&](Index j, std::vector<Index>& s) {
    if (cs[j].kind == ConstraintKind::none) return;
    constraint_dofs(cs[j], *in.dofs, dim, s);
    for (Index& d : s) d = d < 0 ? -1 : d / dim;
  });
}

// Tangential directions in which the free DOFs (nearly) cannot slip, e.g. a slave node on a
// symmetry plane over a master node on it, the plane's normal in the contact's tangent plane:
// the slip there is prescribed, the traction goes into the reactions, and the complementarity
// row of that component is empty or, with the master facet tilted by a few degrees, only
// sin(tilt) times the normal relative displacement, which the normal constraint already fixes
// (redundant constraints: the status flips on round-off). Those components of lambda_T are
// released (w lambda_T . e = 0): a direction e is released when the free DOFs move the slip
// along it by less than 0.1 of what all the constraint's DOFs do (within about 6 degrees of
// being prescribed). Returns the projector on the released directions. When it spans the
// tangent plane (always, in 2D) the node is treated as frictionless (rows w lambda_T = 0, an
// exact tangent); one direction of two in 3D is replaced in the rows with the projector held
// constant in the Jacobian (its rotation with the normal is left out of the tangent).
//
// A weighted slip (mortar, segment_to_segment: in.slave_nodes) averages x_s - x_m over the
// node's facets, its neighbours' DOFs included, so the test above does not see a symmetry
// plane: on it the slip of a node of the plane is the average over the half of its support
// that the model keeps. In the whole model the mirrored half cancels its component across the
// plane, and by symmetry that component of lambda_T is zero; the reduced model must release it,
// or the stick rows hold a combination of the neighbours' motions that the whole model leaves
// free (measured: on the tet10 Hertz quarter with mortar and mu 0.3 the plane's nodes carried
// tangential tractions of 0.8-1.0 mu p across the planes, alternating in sign with the next
// row of nodes, where the exact traction is about 0, and the stick/slip statuses cycled for
// 20 Newton iterations). The plane is read from the Dirichlet conditions: axis a is released
// where the slave node's own DOF a is prescribed, a Dirichlet condition also holds the master
// nodes of the constraint along a on at least 0.1 of their weight in the slip (the master's
// side of the plane), and a is tangential within about 6 degrees (|n . e_a| < 0.1). A slave
// node held along a over a master that slides along a keeps its friction (the master's side
// is free), as the test above decides for a node's own slip; so does a slave node held in
// every direction (a clamped edge, not a plane of symmetry, where the node moves normally).
MatX prescribed_slip_directions(const EnforcementInput& in, const Constraint& c, const std::vector<Index>& dofs,
                                int m) {
  const int dim = in.dim;
  if (!in.fixed) return MatX::Zero(dim, dim);
  const MatX& D = c.slip_jacobian;
  MatX Df = D;
  bool any_fixed = false;
  for (int col = 0; col < m && col < Df.cols(); ++col)
    if (dofs[col] >= 0 && (*in.fixed)[dofs[col]]) Df.col(col).setZero(), any_fixed = true;
  if (!any_fixed) return MatX::Zero(dim, dim);
  // Generalized eigenproblem of the tangential Gram matrices (free against all), the normal
  // added to both so that only tangential directions can be released.
  const VecX nv = c.normal.head(dim);
  const MatX N = nv * nv.transpose();
  const MatX P = MatX::Identity(dim, dim) - N;
  const MatX all = P * D * D.transpose() * P + N;
  const MatX free = P * Df * Df.transpose() * P + N;
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> es(free, all);
  std::vector<VecX> released;
  for (int i = 0; i < dim; ++i)
    if (es.eigenvalues()(i) < 1e-2) released.push_back(P * es.eigenvectors().col(i));
  bool clamped = in.slave_nodes != nullptr;  // a weighted slip's slave node held in every direction
  for (int a = 0; a < dim && clamped; ++a) clamped = dofs[a] < 0 || (*in.fixed)[dofs[a]];
  if (in.slave_nodes && !clamped) {
    const Index nodes = std::min<Index>(static_cast<Index>(c.nodes.size()), std::min<Index>(m, D.cols()) / dim);
    for (int a = 0; a < dim; ++a) {
      if (std::abs(nv(a)) >= 0.1 || dofs[a] < 0 || !(*in.fixed)[dofs[a]]) continue;
      Real held = 0, master = 0;
      for (Index k = 1; k < nodes; ++k) {
        if ((*in.slave_nodes)[c.nodes[k]]) continue;
        const Real w = std::abs(D(a, k * dim + a));
        master += w;
        if (const Index d = dofs[k * dim + a]; d < 0 || (*in.fixed)[d]) held += w;
      }
      if (master > 0 && held >= 0.1 * master) released.push_back(P.col(a));
    }
  }
  // The projector on their span (Gram-Schmidt; a direction within 1e-6 of the others' span adds
  // nothing).
  MatX Q = MatX::Zero(dim, dim);
  std::vector<VecX> basis;
  for (VecX e : released) {
    if (!(e.norm() > 0)) continue;
    e.normalize();
    for (const VecX& b : basis) e -= b * b.dot(e);
    if (e.norm() > 1e-6) e.normalize(), basis.push_back(e), Q += e * e.transpose();
  }
  return Q;
}

// EnforcementInput::stick_at_kink, per node: one that has not slipped, its tangential slip
// round-off of its facet size (kUnmovedSlip). Node-to-segment's slip is x_s - x_0 with the
// origin x_0 taken at these positions: zero but for round-off. Mortar's and
// segment-to-segment's nodal slips are weighted over facets and not zero at the unmoved state
// (1.4e-4 mm on examples/sphere_drag_3d's press, about 1e-3 of a facet, measured with mortar's
// slip weighted by N~ before session 61): their trial is not the committed traction, and the
// return map decides.
constexpr Real kUnmovedSlip = 1e-8;
bool at_kink(const EnforcementInput& in, const Constraint& c, const NodeRecord& node) {
  return in.stick_at_kink && c.tangential_slip().norm() <= kUnmovedSlip * node.size;
}

// r(dofs[k]) += scale v(k) for the entries of v (dofs may go on with multiplier rows that v
// does not cover). No atomics: the callers' colouring keeps concurrent constraints on
// disjoint rows.
// Called inside OpenMP regions, where an exception cannot escape (std::terminate): a vector
// longer than its DOFs is a programming error, asserted in debug builds; release builds add
// the entries that have DOFs only (no read past `dofs`).
void add_vector(VecX& r, const std::vector<Index>& dofs, const VecX& v, Real scale) {
  assert(static_cast<size_t>(v.size()) <= dofs.size() && "contact assembly: a vector longer than its DOFs");
  const Index n = std::min(v.size(), static_cast<Index>(dofs.size()));
  for (Index k = 0; k < n; ++k)
    if (dofs[k] >= 0) r(dofs[k]) += scale * v(k);
}

// Partitioned Nitsche (EnforcementInput::share), collective: `values` (the same length on every
// rank) summed over the ranks, and each rank's residual entries (the non-zero rows of `part`, its
// points' terms) added into `residual`, in rank order: the same bits on every rank.
void sum_shares(const RankExchange& ex, std::vector<Real>& values, const VecX& part, VecX& residual) {
  std::vector<Index> dofs;
  std::vector<Real> mine;
  for (Index i = 0; i < part.size(); ++i)
    if (part(i) != 0) dofs.push_back(i), mine.push_back(part(i));
  std::ostringstream os;
  binary::put_vector(os, values);
  binary::put_vector(os, dofs);
  binary::put_vector(os, mine);
  std::fill(values.begin(), values.end(), 0.0);
  for (const std::string& s : ex.allgather(os.str())) {
    std::istringstream is(s);
    const std::vector<Real> v = binary::get_vector<Real>(is, static_cast<std::int64_t>(values.size()), "nitsche's sums");
    const std::vector<Index> d = binary::get_vector<Index>(is, -1, "nitsche's residual rows");
    const std::vector<Real> r = binary::get_vector<Real>(is, static_cast<std::int64_t>(d.size()), "nitsche's residual");
    for (size_t k = 0; k < v.size(); ++k) values[k] += v[k];
    for (size_t k = 0; k < d.size(); ++k) {
      if (d[k] < 0 || d[k] >= residual.size()) throw Error("nitsche: a rank's residual row is out of range (internal error)");
      residual(d[k]) += r[k];
    }
  }
}

// The largest of every rank's values, entry by entry (collective).
std::vector<Real> max_over_ranks(const RankExchange& ex, const std::vector<Real>& values) {
  std::ostringstream os;
  binary::put_vector(os, values);
  std::vector<Real> m = values;
  for (const std::string& s : ex.allgather(os.str())) {
    std::istringstream is(s);
    const std::vector<Real> v = binary::get_vector<Real>(is, static_cast<std::int64_t>(values.size()), "nitsche's maxima");
    for (size_t k = 0; k < v.size(); ++k) m[k] = std::max(m[k], v[k]);
  }
  return m;
}

// Derivative of a trial traction P(n) v, v = v0 + c_T d (v0 fixed), over the constraint's
// DOFs: c_T P D - n (v^T dn/dz) - (n . v) dn/dz, with dn/dz the constraint's normal_jacobian
// (the discretization's; no assumption on how n relates to the gap's gradient). Shared by the penalty's trial
// traction and the multipliers' complementarity function.
MatX trial_derivative(const Constraint& c, int dim, const Vec3& v, Real ct) {
  const VecX n = c.normal.head(dim);
  const MatX& dn = c.normal_jacobian;
  const MatX P = MatX::Identity(dim, dim) - n * n.transpose();
  return ct * P * c.slip_jacobian - n * (v.head(dim).transpose() * dn) - n.dot(v.head(dim)) * dn;
}

class Penalty : public Enforcement {
 public:
  std::string name() const override { return "penalty"; }
  bool uses_multipliers() const override { return false; }
  bool symmetric() const override { return true; }
  void assemble(const EnforcementInput& in, const VecX&, VecX& residual, GlobalMatrix* K,
                EnforcementOutput& out) const override {
    const ConstraintSet& cs = *in.constraints;
    const Index n = static_cast<Index>(cs.size());
    out.pressure.assign(n, 0.0);
    out.active.assign(n, 0);
    out.traction.assign(n, Vec3::Zero());
    out.slip.assign(n, 0);
    out.cone_excess.assign(n, 0.0);
    const Coloring coloring = color_constraints(in, residual.size());
#pragma omp parallel
    {
      std::vector<Index> dofs;
      MatX k;
      for (int color = 0; color < coloring.colors(); ++color) {
#pragma omp for schedule(dynamic, 32)
        for (Index item = coloring.begin(color); item < coloring.end(color); ++item) {
          const Index j = coloring.items[item];
          const Constraint& c = cs[j];
          // g = 0 counts as closed (zero force, but its stiffness): a body held only by contact
          // can then start from touching; so does a gap within kTouching of the facet size
          // in the first increment (Hold::touching: mortar's weighted gap at a point contact is
          // of that size, either sign). Augmented Lagrangian: the shift lambda-bar. The
          // chattering guard's hold decides where it is set (ContactInterface): held open, no
          // force even if penetrating; held closed, p = lambda-bar - eps g whatever its sign
          // (a tensile p is released after convergence, fix_held_nodes), as the multipliers'
          // active set does.
          if (c.kind == ConstraintKind::none) continue;
          const NodeRecord& node = (*in.nodes)[j];
          const Real eps = node.stiffness;
          const Real shift = node.shift;
          if (held_open(node.hold)) continue;
          const bool touching = node.hold == Hold::touching && c.gap <= kTouching * node.size;
          if (!held_closed(node.hold) && !touching && (shift - eps * c.gap < 0 || (shift == 0 && c.gap > 0))) continue;
          const Real p = touching ? std::max(shift - eps * c.gap, Real(0)) : shift - eps * c.gap;
          out.pressure[j] = p;
          out.active[j] = 1;
          constraint_dofs(c, *in.dofs, in.dim, dofs);
          add_vector(residual, dofs, c.grad, p * c.weight);
          if (K) {
            // -d(p w grad g)/du = eps w grad g grad g^T - p w hess g
            k = eps * c.weight * c.grad * c.grad.transpose() - p * c.weight * c.hess;
          }
          if (in.friction && c.has_slip) add_friction(in, j, c, eps, p, dofs, residual, K ? &k : nullptr, out);
          if (K) K->add(dofs.data(), static_cast<int>(dofs.size()), k);
        }
      }
    }
  }

 private:
  // Regularized (penalty) Coulomb/Tresca friction on a closed node (Wriggers 2006, sec. 5.2):
  // t_tr = P(n) v with v = t_old + eps_T d, t = return map of t_tr onto |t| <= bound(p), force
  // on the DOFs f = -w D^T t. Tangent w D^T dt/dz with dt_tr/dz from trial_derivative and
  //   dt/dz = d_trial dt_tr/dz + d_bound bound'(p) dp/dz,  dp/dz = -eps grad g.
  static void add_friction(const EnforcementInput& in, Index j, const Constraint& c, Real eps, Real p,
                           const std::vector<Index>& dofs, VecX& residual, MatX* k, EnforcementOutput& out) {
    const int dim = in.dim;
    const NodeRecord& node = (*in.nodes)[j];
    const Real epst = node.tangential_stiffness;
    const Vec3 n = c.normal;
    const Vec3 v = node.traction_old + epst * c.slip;
    const Vec3 trial = v - n * n.dot(v);
    const Real bound = in.friction->bound(p);
    const ReturnMap rm =
        return_map(trial, bound, in.stick_predictor || at_kink(in, c, node) ? StickSlip::stick : node.friction_hold);
    out.traction[j] = rm.traction;
    out.slip[j] = rm.slip;
    out.cone_excess[j] = trial.norm() - bound;
    const MatX& D = c.slip_jacobian;
    add_vector(residual, dofs, -c.weight * (D.transpose() * rm.traction.head(dim)), 1.0);
    if (!k) return;
    MatX dt = rm.d_trial.topLeftCorner(dim, dim) * trial_derivative(c, dim, v, epst);
    const Real db = in.friction->bound_derivative(p);
    if (db != 0) dt -= (db * eps) * rm.d_bound.head(dim) * c.grad.transpose();
    *k += c.weight * D.transpose() * dt;
    for (size_t d = 0; d < c.slip_hessian.size(); ++d) *k += (c.weight * rm.traction(d)) * c.slip_hessian[d];
  }
};

// Penalty with multipliers lambda-bar updated between Newton solves (Uzawa; Simo & Laursen
// 1992, Wriggers 2006 sec. 6.3): p = <lambda-bar - eps g>.
class AugmentedLagrangian final : public Penalty {
 public:
  std::string name() const override { return "augmented_lagrangian"; }
  Augmentation augment(const ConstraintSet& cs, const EnforcementOutput& out, bool friction, Real gap_tolerance,
                       std::vector<NodeRecord>& nodes) const override {
    // Each node against its own tolerance: given, or 1e-3 of its local facet size.
    Augmentation a;
    auto tolerance = [&](size_t j) { return nodes[j].gap_tolerance(gap_tolerance); };
    for (size_t j = 0; j < cs.size(); ++j) {
      if (cs[j].kind == ConstraintKind::none || !out.active[j]) continue;
      const Real pen = -cs[j].gap;
      a.max_penetration = std::max(a.max_penetration, pen);
      a.converged = a.converged && pen <= tolerance(j);
      // Friction: a sticking node's elastic slip (the tangential part of d since the last
      // update) must be within the same tolerance.
      if (friction && cs[j].has_slip && !out.slip[j])
        a.converged = a.converged && cs[j].tangential_slip().norm() <= tolerance(j);
    }
    if (a.converged) return a;
    for (size_t j = 0; j < cs.size(); ++j) {
      NodeRecord& node = nodes[j];
      node.shift = cs[j].kind == ConstraintKind::none ? 0.0 : std::max(0.0, node.shift - node.stiffness * cs[j].gap);
      // Uzawa on the tangential multipliers: the traction becomes the new multiplier and the
      // slip restarts from the current contact point (Simo & Laursen 1992).
      if (friction && cs[j].kind != ConstraintKind::none && out.active[j] && cs[j].has_slip) {
        node.traction_old = out.traction[j];
        a.restart_slip.push_back(static_cast<Index>(j));
      }
    }
    return a;
  }
};

class LagrangeMultipliers final : public Enforcement {
 public:
  std::string name() const override { return "lagrange"; }
  bool uses_multipliers() const override { return true; }
  bool symmetric() const override { return false; }
  void assemble(const EnforcementInput& in, const VecX& z, VecX& residual, GlobalMatrix* K,
                EnforcementOutput& out) const override {
    const ConstraintSet& cs = *in.constraints;
    const Index n = static_cast<Index>(cs.size());
    const int dim = in.dim;
    const bool friction = in.friction != nullptr;
    out.pressure.assign(n, 0.0);
    out.active.assign(n, 0);
    out.traction.assign(friction ? n : 0, Vec3::Zero());
    out.slip.assign(friction ? n : 0, 0);
    out.cone_excess.assign(friction ? n : 0, 0.0);
    // Scale of the rows of nodes without a constraint (keeps the system regular).
    Real mean_w = 0;
    for (auto& c : cs) mean_w += c.weight;
    mean_w = n ? mean_w / n : 1.0;
    if (!(mean_w > 0)) mean_w = 1.0;
    const Coloring coloring = color_constraints(in, residual.size());
#pragma omp parallel
    {
      std::vector<Index> dofs;
      MatX k;
      for (int color = 0; color < coloring.colors(); ++color) {
#pragma omp for schedule(dynamic, 32)
        for (Index item = coloring.begin(color); item < coloring.end(color); ++item) {
          const Index j = coloring.items[item];
          const Constraint& c = cs[j];
          const Index ldof = in.multiplier_offset + j;
          const Real lambda = z(ldof);
          out.pressure[j] = lambda;
          // Friction: the tangential traction's multipliers, dim per constraint after the
          // normal ones (a vector in space; its normal component is driven to zero).
          Index tdof[3] = {-1, -1, -1};
          VecX lt = VecX::Zero(dim);
          if (friction)
            for (int d = 0; d < dim; ++d) {
              tdof[d] = in.multiplier_offset + n + j * dim + d;
              lt(d) = z(tdof[d]);
            }
          // Rows s lambda = 0 (no contact force).
          auto release = [&](Index row, Real value, Real s) {
            residual(row) -= s * value;
            if (K) {
              MatX one = MatX::Constant(1, 1, s);
              K->add(&row, 1, one);
            }
          };
          auto release_tangential = [&](Real s) {
            if (friction)
              for (int d = 0; d < dim; ++d) release(tdof[d], lt(d), s);
          };
          if (c.kind == ConstraintKind::none || !(c.weight > 0)) {
            // No master within reach: lambda = 0.
            const Real s = c.weight > 0 ? c.weight : mean_w;
            release(ldof, lambda, s);
            release_tangential(s);
            continue;
          }
          const Real c0 = (*in.nodes)[j].stiffness;
          const Hold hold = (*in.nodes)[j].hold;
          // At the kink (lambda = 0, g = 0: a node that just touches) either branch is a valid
          // Newton derivative; closed lets a body held only by contact start from touching.
          const bool active = held_closed(hold) || (hold == Hold::none && lambda - c0 * c.gap >= 0);
          out.active[j] = active;
          // Open: the multiplier row F = w lambda drives lambda to 0, and the node puts no force
          // on the bodies (the force is lambda on the active set only, as in the primal-dual
          // active set method, Hueber & Wohlmuth 2005): a node released in tension then adds
          // neither its force nor its -lambda w hess g to the tangent, which would make the
          // bodies' block indefinite.
          if (!active) {
            release(ldof, lambda, c.weight);
            release_tangential(c.weight);
            continue;
          }
          constraint_dofs(c, *in.dofs, dim, dofs);
          const int m = static_cast<int>(dofs.size());
          // Friction, unless every tangential direction of the node is prescribed (then as frictionless).
          MatX Q;
          if (friction && c.has_slip) Q = prescribed_slip_directions(in, c, dofs, m);
          const bool slips = friction && c.has_slip && Q.trace() < dim - 1.5;
          // Displacement rows: f_c = lambda w grad g.
          add_vector(residual, dofs, c.grad, lambda * c.weight);
          // Multiplier row: F = c w g; R = -F.
          residual(ldof) -= c0 * c.weight * c.gap;
          if (K) {
            k.setZero(m + 1 + (slips ? dim : 0), m + 1 + (slips ? dim : 0));
            k.topLeftCorner(m, m) = -lambda * c.weight * c.hess;
            k.block(0, m, m, 1) = -c.weight * c.grad;
            k.block(m, 0, 1, m) = c0 * c.weight * c.grad.transpose();
            dofs.push_back(ldof);
          }
          if (slips) add_friction(in, j, c, lambda, lt, Q, tdof, dofs, m, residual, K ? &k : nullptr, out);
          else release_tangential(c.weight);  // frictionless, no slip origin yet, or no free slip: no tangential traction
          if (K) K->add(dofs.data(), static_cast<int>(dofs.size()), k);
        }
      }
    }
  }

 private:
  // Coulomb/Tresca friction of a closed node with its traction as multipliers (semi-smooth
  // Newton; Alart & Curnier 1991, in the projected form of Hueber, Stadler & Wohlmuth 2008):
  //   E = w (lambda_T - proj_F(q)) = 0,  q = P(n) (lambda_T + c_T d),  F = bound(lambda - c g),
  // with d the slip of the increment (Constraint::slip). Inside the disc (stick) E = -w c_T P d:
  // no tangential slip; on the rim (slip) lambda_T has the radius F and the direction of q. Its
  // normal component is zero in either case (E's n-component is w n . lambda_T). The bodies get
  // the force -w D^T lambda_T (the penalty's, with the multipliers for the traction).
  // Tangent: dE/dlambda_T = w (I - A P), dE/dz = -w (A dq/dz + b dF/dz), dE/dlambda = -w b F',
  // with A, b the return map's derivatives in q and F, dF/dz = -F' c grad g and dq/dz from
  // trial_derivative with v = lambda_T + c_T d.
  // Q: the projector on the tangential directions whose slip is prescribed (released rows).
  static void add_friction(const EnforcementInput& in, Index j, const Constraint& c, Real lambda, const VecX& lt,
                           const MatX& Q, const Index* tdof, std::vector<Index>& dofs, int m, VecX& residual, MatX* k,
                           EnforcementOutput& out) {
    const int dim = in.dim;
    const NodeRecord& node = (*in.nodes)[j];
    const Real w = c.weight, c0 = node.stiffness, ct = node.tangential_stiffness;
    const VecX nv = c.normal.head(dim);
    const MatX& D = c.slip_jacobian;
    const MatX P = MatX::Identity(dim, dim) - nv * nv.transpose();
    Vec3 l3 = Vec3::Zero();
    l3.head(dim) = lt;
    const Vec3 v = l3 + ct * c.slip;
    const Vec3 q = v - c.normal * c.normal.dot(v);
    const Real p = lambda - c0 * c.gap;
    const Real bound = in.friction->bound(p), db = in.friction->bound_derivative(p);
    const ReturnMap rm = return_map(q, bound, at_kink(in, c, node) ? StickSlip::stick : node.friction_hold);
    out.traction[j] = l3;
    out.slip[j] = rm.slip;
    out.cone_excess[j] = q.norm() - bound;
    add_vector(residual, dofs, D.transpose() * lt, -w);
    const MatX keep = MatX::Identity(dim, dim) - Q;
    const VecX e = keep * (w * (lt - rm.traction.head(dim))) + Q * (w * lt);
    for (int d = 0; d < dim; ++d) residual(tdof[d]) -= e(d);
    if (!k) return;
    const MatX A = rm.d_trial.topLeftCorner(dim, dim);
    const VecX b = rm.d_bound.head(dim);
    k->block(0, m + 1, m, dim) = w * D.transpose();
    for (size_t d = 0; d < c.slip_hessian.size(); ++d) k->topLeftCorner(m, m) += (w * lt(d)) * c.slip_hessian[d];
    k->block(m + 1, 0, dim, m) = keep * (-w * A * trial_derivative(c, dim, v, ct) + (w * db * c0) * b * c.grad.transpose());
    k->block(m + 1, m, dim, 1) = keep * (-w * db * b);
    k->block(m + 1, m + 1, dim, dim) = keep * (w * (MatX::Identity(dim, dim) - A * P)) + w * Q;
    for (int d = 0; d < dim; ++d) dofs.push_back(tdof[d]);
  }
};

}  // namespace

void Enforcement::begin_increment(std::vector<NodeRecord>& nodes) const {
  // From the committed state: undoes what a failed attempt updated.
  for (NodeRecord& node : nodes) {
    node.shift = node.shift_committed;
    node.traction_old = node.traction_committed;
  }
}

void Enforcement::end_increment(const ConstraintSet& cs, const EnforcementOutput& out,
                                std::vector<NodeRecord>& nodes) const {
  for (size_t j = 0; j < nodes.size(); ++j) {
    NodeRecord& node = nodes[j];
    node.shift_committed = node.shift;
    const bool closed = j < out.active.size() && out.active[j] && j < cs.size() && cs[j].has_slip;
    node.traction_old = node.traction_committed = closed && j < out.traction.size() ? out.traction[j] : Vec3::Zero();
  }
}

// Nitsche's method on integration points (enforcement.hpp). Per point, active (P > 0):
//   R_c = w P grad g + theta w g grad p,
//   K_c = w (eps grad g grad g^T - grad g grad p^T - theta grad p grad g^T - P hess g);
// open: R_c = (theta / eps) w p grad p, K_c = -(theta / eps) w grad p grad p^T (small strain:
// p is linear in u, its Hessian is zero). The nodal pressure for output is an average of the
// points' [P]_+ with positive weights (segment_to_segment's shares).
// The gap's second variation enters the Newton matrix with P bounded by twice the largest
// pressure the slave body's stress gives at any point, unless `exact` (tests): after the first
// step of a press the bodies have moved rigidly into each other, P = p - eps g is the penalty
// of the whole penetration (10^3 times the contact pressure) while the stress is still zero,
// and w P hess g made the matrix indefinite: on CalculiX's coarse tet10 Hertz mesh the steps
// diverged (a master node moved by 1.6, the model's size), 18 iterations with the bound. Near
// the solution the bound is far above P: the tangent is exact there. It costs iterations in 2D
// (CalculiX's coarse 2D Hertz mesh: 17, against 6 with the whole term).
class Nitsche final : public Enforcement {
 public:
  Nitsche(int theta, bool exact) : theta_(theta), exact_(exact) {}
  std::string name() const override { return "nitsche"; }
  bool uses_multipliers() const override { return false; }
  bool symmetric() const override { return theta_ == 1; }
  bool node_statuses() const override { return false; }
  bool needs_points() const override { return true; }
  bool full_steps() const override { return true; }
  void assemble(const EnforcementInput& in, const VecX&, VecX& residual, GlobalMatrix* K,
                EnforcementOutput& out) const override {
    const Index n = static_cast<Index>(in.constraints->size());
    const int dim = in.dim;
    const bool friction = in.friction != nullptr;
    out.pressure.assign(n, 0.0);
    out.active.assign(n, 0);
    out.traction.assign(friction ? n : 0, Vec3::Zero());
    out.slip.assign(friction ? n : 0, 0);
    out.cone_excess.assign(friction ? n : 0, 0.0);
    out.point_slip.clear();
    out.has_slave_force = true;
    out.slave_force.setZero();
    if (!in.points) throw Error("nitsche: the discretization gave no integration points (segment_to_segment needed)");
    const std::vector<PointConstraint>& pts = *in.points;
    // The bound on P in the gap's second variation: twice the largest pressure the slave
    // body's stress gives at any point (see above the class). Partitioned, over every rank's
    // points, and so is whether the points are at finite strain (a rank may have none).
    Real bound = 0;
    for (const PointConstraint& pc : pts) bound = std::max(bound, 2 * pc.pressure);
    bool finite = !pts.empty() && pts.front().normal_jacobian.size() > 0;
    if (in.share) {
      const std::vector<Real> m = max_over_ranks(*in.share, {bound, finite ? 1.0 : 0.0});
      bound = m[0];
      finite = m[1] > 0;
    }
    // Finite strain (the points carry their current normal's variation): theta 0 only, whose
    // Newton matrix needs the pressure's first derivative only (docs/contact.md).
    if (theta_ != 0 && finite)
      throw Error("nitsche: at finite strain theta is 0 (the Newton matrix of theta 1 and -1 needs the second "
                  "derivative of the bodies' stress)");
    const DofMap& dm = *in.dofs;
    auto point_dofs = [&](const PointConstraint& pc, std::vector<Index>& d) {
      d.clear();
      for (Index nd : pc.nodes)
        for (int k = 0; k < dim; ++k) d.push_back(dm.dof(nd, k));
    };
    // The points of one slave facet share their nodes (the discretization builds them facet
    // after facet): their terms are summed per facet and added to the matrix once.
    std::vector<size_t> group{0};
    for (size_t q = 1; q <= pts.size(); ++q)
      if (q == pts.size() || pts[q].facet != pts[q - 1].facet || pts[q].nodes != pts[q - 1].nodes) group.push_back(q);
    if (pts.empty()) group.assign(1, 0);
    const Index groups = static_cast<Index>(group.size()) - 1;
    const Coloring coloring = color_items(groups, residual.size() / dim + 1, [&](Index g, std::vector<Index>& s) {
      point_dofs(pts[group[g]], s);
      for (Index& d : s) d = d < 0 ? -1 : d / dim;
    });
    const Real theta = theta_;
    std::vector<Real> positive(pts.size(), 0.0);  // [P]_+ per point
    // Friction, per point: the traction on the slave, tau_T = proj(Q), whether it slipped,
    // and |Q| - bound.
    std::vector<Vec3> tau(friction ? pts.size() : 0, Vec3::Zero());
    std::vector<char> slipped(friction ? pts.size() : 0, 0);
    std::vector<Real> excess(friction ? pts.size() : 0, 0.0);
    // Partitioned: this rank's points, whose residual entries go to `part` and are summed over
    // the ranks at the end.
    VecX part;
    if (in.share) part = VecX::Zero(residual.size());
    VecX& target = in.share ? part : residual;
#pragma omp parallel
    {
      std::vector<Index> dofs;
      MatX k;
      VecX r;
      Vec3 force = Vec3::Zero();
      for (int color = 0; color < coloring.colors(); ++color) {
#pragma omp for schedule(dynamic, 8)
        for (Index item = coloring.begin(color); item < coloring.end(color); ++item) {
          const Index g = coloring.items[item];
          point_dofs(pts[group[g]], dofs);
          const Index m = static_cast<Index>(dofs.size());
          r.setZero(m);
          if (K) k.setZero(m, m);
          for (size_t q = group[g]; q < group[g + 1]; ++q) {
            const PointConstraint& pc = pts[q];
            const Real eps = pc.stiffness, w = pc.weight;
            const Real P = pc.pressure - eps * pc.gap;
            // P = 0 at g = 0 (a point that just touches, no stress yet) counts as active: zero
            // force, but its stiffness (either branch is a valid Newton derivative at the kink),
            // so a body held only by contact can start from touching.
            const bool active = P > 0 || (P == 0 && pc.gap <= 0);
            if (friction && pc.has_slip)
              add_friction(*in.friction, pc, active, P, theta, dim, r, K ? &k : nullptr, tau[q], slipped[q], excess[q],
                           force);
            if (active) {
              r.noalias() += (w * P) * pc.grad + (theta * w * pc.gap) * pc.pressure_grad;
              if (K) {
                k.noalias() += (w * eps) * pc.grad * pc.grad.transpose();
                k.noalias() -= w * pc.grad * pc.pressure_grad.transpose();
                k.noalias() -= (theta * w) * pc.pressure_grad * pc.grad.transpose();
                const Index mg = static_cast<Index>(pc.gap_nodes) * dim;
                const Real Pg = exact_ ? P : std::min(P, bound);
                k.topLeftCorner(mg, mg) -= (w * Pg) * pc.hess;
              }
              for (int a = 0; a < pc.facet_nodes; ++a) force.head(dim) += w * P * pc.grad.segment(a * dim, dim);
              positive[q] = P;
            } else {
              r.noalias() += ((theta / eps) * w * pc.pressure) * pc.pressure_grad;
              if (K) k.noalias() -= ((theta / eps) * w) * pc.pressure_grad * pc.pressure_grad.transpose();
            }
          }
          add_vector(target, dofs, r, 1.0);
          if (K) K->add(dofs.data(), static_cast<int>(m), k);
        }
      }
#pragma omp critical
      out.slave_force += force;
    }
    for (size_t q = 0; q < pts.size(); ++q)
      if (positive[q] > 0)
        for (const auto& [j, share] : pts[q].shares) out.pressure[j] += share * positive[q];
    // Per node (output, the slip record): the traction on the master (minus the slave's) and
    // |Q| - bound averaged as the pressure is; slip when the shares of its active points that
    // slip outweigh those that stick.
    std::vector<Real> vote(friction ? n : 0, 0.0);
    if (friction)
      for (size_t q = 0; q < pts.size(); ++q)
        if (positive[q] > 0 && pts[q].has_slip)
          for (const auto& [j, share] : pts[q].shares) {
            out.traction[j] -= share * tau[q];
            out.cone_excess[j] += share * excess[q];
            vote[j] += slipped[q] ? share : -share;
          }
    if (in.share) share_sums(*in.share, part, residual, out, vote);
    for (Index j = 0; j < n; ++j) out.active[j] = out.pressure[j] > 0;
    if (!friction) return;
    for (Index j = 0; j < n; ++j) out.slip[j] = out.active[j] && vote[j] > 0;
    out.point_slip.assign(pts.size(), -1);
    for (size_t q = 0; q < pts.size(); ++q)
      if (positive[q] > 0 && pts[q].has_slip) out.point_slip[q] = slipped[q];
  }

 private:
  // Coulomb/Tresca friction at an integration point with Nitsche's method (Chouly 2014 for
  // Tresca; Renard 2013 and Chouly, Fabre, Hild, Mlika, Pousin & Renard 2017 for Coulomb; the
  // theta family as in Chouly, Hild & Renard 2015; docs/contact.md (N2)): with nu the slave
  // facet's normal, P_T = I - nu nu^T, sigma_T = P_T t the slave body's tangential traction,
  // s = P_T d the slip of the increment and eps Nitsche's parameter,
  //   Q = sigma_T - eps s,  tau = proj(Q) onto the disc |tau| <= bound([P]_+) (0 at an open point),
  //   R_T = w D_T^T tau + (theta / eps) w G^T (sigma_T - tau),   D_T = P_T D, G = P_T dt/du,
  // the tangential half of R_c = w (tau . delta(x_s - x_m)) + (theta / eps) w (sigma n - tau) . delta(sigma n)
  // whose normal half is (N1): the exact solution has sigma_T = tau (the traction is the
  // frictional one) and tau = 0 where the point is open. Tangent (small strain: D, G constant):
  //   K_T = -w D_T^T dtau - (theta / eps) w G^T (G - dtau),
  //   dtau = A (G - eps D_T) + b bound'(P) (grad p - eps grad g)^T  (active; 0 open),
  // A, b the return map's derivatives in Q and in the bound. The slave's force w tau
  // (sum_i N_i = 1) joins the normal one.
  static void add_friction(const FrictionLaw& law, const PointConstraint& pc, bool active, Real P, Real theta, int dim,
                           VecX& r, MatX* k, Vec3& tau, char& slipped, Real& excess, Vec3& force) {
    const Real w = pc.weight, eps = pc.stiffness;
    const VecX nu = pc.normal.head(dim);
    const MatX PT = MatX::Identity(dim, dim) - nu * nu.transpose();
    const MatX G = PT * pc.traction_grad;
    const MatX DT = PT * pc.slip_jacobian;
    const VecX sigma = PT * pc.traction.head(dim);
    Vec3 Q = Vec3::Zero();
    Q.head(dim) = sigma - eps * (PT * pc.slip.head(dim));
    VecX t = VecX::Zero(dim);
    MatX dtau = MatX::Zero(dim, pc.grad.size());
    // Finite strain (theta 0): nu is the current normal, and P_T varies: dQ = P_T (dt - eps dd)
    // + dP_T v with v = t - eps d and dP_T v = -dnu (nu.v) - nu (v.dnu).
    const bool finite = pc.normal_jacobian.size() > 0;
    MatX dQ = G - eps * DT;
    if (finite) {
      const VecX v = pc.traction.head(dim) - eps * pc.slip.head(dim);
      dQ -= pc.normal_jacobian * nu.dot(v) + nu * (v.transpose() * pc.normal_jacobian);
    }
    if (active) {
      const Real bound = law.bound(P);
      const ReturnMap rm = return_map(Q, bound);
      t = rm.traction.head(dim);
      slipped = rm.slip;
      excess = Q.norm() - bound;
      if (k) {
        dtau = rm.d_trial.topLeftCorner(dim, dim) * dQ;
        const Real db = law.bound_derivative(P);
        if (db != 0) dtau += (db * rm.d_bound.head(dim)) * (pc.pressure_grad - eps * pc.grad).transpose();
      }
    }
    tau.setZero();
    tau.head(dim) = t;
    r.noalias() += w * (DT.transpose() * t) + (theta * w / eps) * (G.transpose() * (sigma - t));
    if (k) {
      // d(D_T^T tau) = D^T d(P_T tau) = D^T dtau (tau stays tangential; at small strain P_T dtau = dtau).
      k->noalias() -= w * (pc.slip_jacobian.transpose() * dtau);
      k->noalias() -= (theta * w / eps) * (G.transpose() * (G - dtau));
    }
    force.head(dim) += w * t;
  }

  // Partitioned (EnforcementInput::share): every rank's per-node sums (pressure; with friction
  // the traction, |Q| - bound and the slip vote), contact force and residual entries (its
  // points' terms, `part`) summed over the ranks.
  static void share_sums(const RankExchange& ex, const VecX& part, VecX& residual, EnforcementOutput& out,
                         std::vector<Real>& vote) {
    const size_t n = out.pressure.size(), nf = vote.size();
    std::vector<Real> values;
    values.reserve(n + nf * 5 + 3);
    values.insert(values.end(), out.pressure.begin(), out.pressure.end());
    for (size_t j = 0; j < nf; ++j)
      for (int d = 0; d < 3; ++d) values.push_back(out.traction[j](d));
    values.insert(values.end(), out.cone_excess.begin(), out.cone_excess.end());
    values.insert(values.end(), vote.begin(), vote.end());
    for (int d = 0; d < 3; ++d) values.push_back(out.slave_force(d));
    sum_shares(ex, values, part, residual);
    size_t at = 0;
    for (size_t j = 0; j < n; ++j) out.pressure[j] = values[at++];
    for (size_t j = 0; j < nf; ++j)
      for (int d = 0; d < 3; ++d) out.traction[j](d) = values[at++];
    for (size_t j = 0; j < nf; ++j) out.cone_excess[j] = values[at++];
    for (size_t j = 0; j < nf; ++j) vote[j] = values[at++];
    for (int d = 0; d < 3; ++d) out.slave_force(d) = values[at++];
  }

  int theta_;
  bool exact_;
};

std::unique_ptr<Enforcement> make_enforcement(const std::string& method, int theta, bool exact_tangent) {
  if (method == "nitsche") {
    if (theta != 1 && theta != 0 && theta != -1) throw Error("nitsche: theta is 1, 0 or -1");
    return std::make_unique<Nitsche>(theta, exact_tangent);
  }
  if (method == "penalty") return std::make_unique<Penalty>();
  if (method == "lagrange") return std::make_unique<LagrangeMultipliers>();
  if (method == "augmented_lagrangian") return std::make_unique<AugmentedLagrangian>();
  throw Error("unknown contact enforcement method '" + method + "' (lagrange, augmented_lagrangian, penalty, nitsche)");
}

}  // namespace signorini
