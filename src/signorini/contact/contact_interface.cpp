#include "signorini/contact/contact_interface.hpp"

#include <algorithm>
#include <limits>
#include <set>

#include "signorini/contact/discretization/node_to_segment.hpp"
#include "signorini/contact/discretization/rigid_obstacle.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/log.hpp"

namespace signorini {

ContactInterface::ContactInterface(const ContactPairSettings& s, const Mesh& mesh, const AnalysisSettings& as,
                                   Real stiffness_scale, bool second_pass)
    : s_(s), as_(as), dim_(as.spatial_dim()), node_ids_(&mesh.node_ids) {
  if (second_pass) std::swap(s_.master, s_.slave);
  label_ = s_.name + (second_pass ? " (pass 2)" : "");
  if (!s_.rigid) {
    master_ = make_master_surface(mesh, s_.master);
    if (s_.smoothing == "hermite") smooth_master_surface(master_, mesh.nodes);
  }
  slave_ = make_slave_surface(mesh, s_.slave, as);
  if (second_pass) {
    // A node that coincides with a node of the other surface carries the same constraint in
    // both passes: keep it once (twice makes the multiplier system singular).
    Real h = 0;
    for (Index f = 0; f < master_.size(); ++f)
      h = std::max(h, (mesh.nodes[master_.facets[f][0]] - mesh.nodes[master_.facets[f][1]]).norm());
    SlaveSurface kept;
    for (size_t j = 0; j < slave_.nodes.size(); ++j) {
      bool duplicate = false;
      for (Index m : master_.nodes)
        duplicate = duplicate || (mesh.nodes[m] - mesh.nodes[slave_.nodes[j]]).norm() <= 1e-8 * h;
      if (duplicate) continue;
      kept.nodes.push_back(slave_.nodes[j]);
      kept.weights.push_back(slave_.weights[j]);
    }
    slave_ = std::move(kept);
  }
  search_ = make_search(s_.search);
  enforcement_ = make_enforcement(s_.method);
  // Mean edge of the slave and master surfaces (reference configuration).
  auto mean_edge = [&](const std::string& set) {
    const std::vector<Real> edges = facet_edge_lengths(mesh.facet_sets.at(set), mesh.nodes);
    Real sum = 0;
    for (Real l : edges) sum += l;
    return edges.empty() ? 1.0 : sum / static_cast<Real>(edges.size());
  };
  const Real h = mean_edge(s_.slave);
  mean_master_edge_ = s_.rigid ? h : mean_edge(s_.master);
  const Index n = static_cast<Index>(slave_.nodes.size());
  // Local facet size of each slave node (mean length of the edges of its facets): the
  // automatic penalty and gap tolerance follow the mesh where the node is, so graded meshes
  // get a stiff penalty where they are fine.
  {
    std::vector<Real> sum(mesh.num_nodes(), 0.0);
    std::vector<int> count(mesh.num_nodes(), 0);
    for (const ElementBlock& b : mesh.facet_sets.at(s_.slave)) {
      const int nc = element_info(b.type).num_corners;
      for (Index e = 0; e < b.size(); ++e) {
        Real len = 0;
        for (int k = 0; k < (nc == 2 ? 1 : nc); ++k)
          len += (mesh.nodes[b.element(e)[(k + 1) % nc]] - mesh.nodes[b.element(e)[k]]).norm();
        len /= (nc == 2 ? 1 : nc);
        for (int k = 0; k < b.nodes_per_element(); ++k) {
          sum[b.element(e)[k]] += len;
          ++count[b.element(e)[k]];
        }
      }
    }
    node_size_.resize(n);
    stiffness_.resize(n);
    for (Index j = 0; j < n; ++j) {
      const Index node = slave_.nodes[j];
      node_size_[j] = count[node] ? sum[node] / count[node] : h;
      stiffness_[j] = s_.penalty > 0 ? s_.penalty : s_.penalty_factor * stiffness_scale / node_size_[j];
    }
  }
  candidate_.assign(n, -1);
  nts_normal_.assign(n, Vec3::Zero());
  last_active_.assign(n, 0);
  committed_active_.assign(n, 0);
  flips_.assign(n, 0);
  forced_.assign(n, 0);
  shift_.assign(n, 0.0);
  shift_committed_.assign(n, 0.0);
  facets_.corners = dim_ == 2 ? 2 : element_info(master_.type.empty() ? ElementType::tri3 : master_.type[0]).num_corners;
  dmax_ = s_.max_distance > 0 ? s_.max_distance : 2 * mean_master_edge_;
  if (s_.friction != "none") {
    friction_ = make_friction_law(s_.friction, s_.friction_parameter);
    tangential_stiffness_.resize(n);
    // Automatic: the penalty, the normal one of the node (a regularization of stick); Lagrange
    // multipliers, the tangential complementarity constant kTangentialComplementarity E / h,
    // an order below the node's tangential stiffness (about E / h): the stick/slip decision
    // of the semi-smooth Newton method, |lambda_T + c_T d| <= F, then follows the traction
    // more than the unconverged slip of the iterate. The converged solution does not depend
    // on it; measured on the press-then-shear family (docs/contact.md), 0.01 to 0.3 E/h
    // converge in one increment per step, E/h and above cut back.
    for (Index j = 0; j < n; ++j)
      tangential_stiffness_[j] = s_.tangential_penalty > 0 ? s_.tangential_penalty
                                 : uses_multipliers()     ? kTangentialComplementarity * stiffness_scale / node_size_[j]
                                                          : stiffness_[j];
    origin_.assign(n, {});
    origin_point_.assign(n, Vec3::Zero());
    has_origin_.assign(n, 0);
    traction_old_.assign(n, Vec3::Zero());
    friction_flips_.assign(n, 0);
    last_slip_.assign(n, 0);
    friction_hold_.assign(n, 0);
    traction_committed_.assign(n, Vec3::Zero());
    committed_friction_.assign(n, 0);
    slip_increment_.assign(n, 0.0);
    slip_accumulated_.assign(n, 0.0);
  }
  for (ElementType t : master_.type)
    if (element_info(t).num_corners != facets_.corners)
      throw Error("contact '" + s_.name + "': the master surface '" + s_.master +
                  "' mixes triangles and quadrilaterals, which the search does not support yet");
}

void ContactInterface::detect(const std::vector<Vec3>& x, Real max_step) {
  dmax_ = s_.max_distance > 0 ? s_.max_distance : 2 * mean_master_edge_ + 2 * max_step;
  if (s_.rigid) return;  // an analytic obstacle needs no search
  // Linearized master facets at the current positions.
  const int nc = facets_.corners;
  facets_.points.resize(master_.size() * nc);
  for (Index f = 0; f < master_.size(); ++f)
    for (int k = 0; k < nc; ++k) facets_.points[f * nc + k] = x[master_.facets[f][k]];
  search_->build(facets_);
  // Maximal detection distance: given, or twice the master facet size plus twice the motion
  // expected before the next search.
  const Real dmax = s_.max_distance > 0 ? s_.max_distance : 2 * mean_master_edge_ + 2 * max_step;
  std::vector<Vec3> pts(slave_.nodes.size());
  for (size_t j = 0; j < pts.size(); ++j) pts[j] = x[slave_.nodes[j]];
  std::vector<SearchHit> hits;
  search_->closest(pts, dmax, hits);
  for (size_t j = 0; j < pts.size(); ++j) {
    Index f = hits[j].facet;
    // A node in contact keeps being tracked even if it moved beyond d_max.
    if (f < 0 && last_active_[j] && candidate_[j] >= 0 && s_.discretization == "node_to_segment") f = candidate_[j];
    if (s_.discretization == "node_to_node") {
      if (f < 0) {
        if (!(last_active_[j] && candidate_[j] >= 0)) candidate_[j] = -1;
        continue;
      }
      // The nearest corner of the closest facet, with its normal frozen for the increment.
      Index best = -1;
      Real bd = 1e300;
      for (int k = 0; k < master_.corners(f); ++k) {
        const Index m = master_.facets[f][k];
        const Real d = (x[m] - pts[j]).norm();
        if (d < bd) bd = d, best = m;
      }
      candidate_[j] = best;
      nts_normal_[j] = master_.node_normal(best, x, dim_);
    } else {
      candidate_[j] = f;
    }
  }
}

void ContactInterface::couplings(const DofMap& dofs, std::vector<std::vector<Index>>& out) const {
  for (size_t j = 0; j < candidate_.size(); ++j) {
    std::vector<Index> g;
    auto add_node = [&](Index n) {
      for (int d = 0; d < dim_; ++d) g.push_back(dofs.dof(n, d));
    };
    add_node(slave_.nodes[j]);
    if (!s_.rigid && candidate_[j] >= 0) {
      if (s_.discretization == "node_to_node") add_node(candidate_[j]);
      else {
        std::set<Index> nodes;
        for (Index f : master_.neighbourhood(candidate_[j]))
          for (Index n : master_.basis_nodes(f)) nodes.insert(n);
        for (Index n : nodes) add_node(n);
      }
    }
    if (frictional() && has_origin_[j])
      for (auto [node, w] : origin_[j]) add_node(node);
    if (uses_multipliers()) {
      g.push_back(offset_ + static_cast<Index>(j));
      if (frictional())
        for (int d = 0; d < dim_; ++d)
          g.push_back(offset_ + static_cast<Index>(candidate_.size() + j * dim_ + d));
    }
    for (int d = 0; d < num_obstacle_dofs(); ++d) g.push_back(obstacle_dofs_ + d);
    out.push_back(std::move(g));
  }
}

void ContactInterface::begin_increment(const std::vector<Vec3>& x, const VecX& z) {
  std::fill(flips_.begin(), flips_.end(), 0);
  std::fill(forced_.begin(), forced_.end(), 0);
  last_active_ = committed_active_;
  frozen_reported_ = 0;
  shift_ = shift_committed_;
  if (!frictional()) return;
  std::fill(friction_flips_.begin(), friction_flips_.end(), 0);
  std::fill(friction_hold_.begin(), friction_hold_.end(), 0);
  for (size_t j = 0; j < last_slip_.size(); ++j) last_slip_[j] = committed_friction_[j] == 2;
  traction_old_ = traction_committed_;  // undoes the augmented Lagrangian's updates of a failed attempt
  // The slip origins: where each slave node touches the master material now.
  build_constraints(x, z);
  const Vec3 offset = obstacle_offset(z);
  for (size_t j = 0; j < constraints_.size(); ++j) {
    const Constraint& c = constraints_[j];
    has_origin_[j] = c.kind != ConstraintKind::none;
    origin_[j].clear();
    if (has_origin_[j]) record_origin(j, c, x[c.slave] - offset);
  }
}

void ContactInterface::record_origin(size_t j, const Constraint& c, const Vec3& slave_from_obstacle) {
  // The closest master point of constraint c becomes node j's slip origin: the master nodes
  // with the discretization's weights, or (rigid obstacle) the point relative to the
  // obstacle's offset, from the slave position relative to that offset.
  if (s_.rigid) {
    origin_point_[j] = slave_from_obstacle - c.gap * c.normal;
    return;
  }
  origin_[j].clear();
  for (size_t k = 0; k < c.master_weights.size(); ++k) origin_[j].emplace_back(c.nodes[k + 1], c.master_weights[k]);
}

Vec3 ContactInterface::obstacle_offset(const VecX& z) const {
  Vec3 offset = Vec3::Zero();
  if (s_.rigid)
    for (int d = 0; d < dim_; ++d) offset(d) = z(obstacle_dofs_ + d);
  return offset;
}

void ContactInterface::build_constraints(const std::vector<Vec3>& x, const VecX& z) {
  if (s_.rigid)
    rigid_obstacle_constraints(s_.obstacle, obstacle_offset(z), obstacle_dofs_, slave_, x, dim_,
                               std::max(dmax_, 1e-300), constraints_);
  else if (s_.discretization == "node_to_node")
    node_to_node(slave_, candidate_, nts_normal_, x, dim_, constraints_);
  else
    node_to_segment(master_, slave_, x, dim_, candidate_, constraints_);
}

void ContactInterface::add_slip_kinematics(const std::vector<Vec3>& x, const VecX& z) {
  // d = x_s - x_0 over the constraint's DOFs; origin nodes the constraint does not hold yet
  // are appended to it (with zero gap derivatives).
  const Vec3 offset = obstacle_offset(z);
  for (size_t j = 0; j < constraints_.size(); ++j) {
    Constraint& c = constraints_[j];
    c.has_slip = false;
    if (c.kind == ConstraintKind::none || !has_origin_[j]) continue;
    if (!s_.rigid)
      for (auto [node, w] : origin_[j]) {
        if (std::find(c.nodes.begin(), c.nodes.end(), node) != c.nodes.end()) continue;
        const Index old = c.grad.size();  // no extra DOFs on a deformable master
        c.nodes.push_back(node);
        c.grad.conservativeResize(old + dim_);
        c.grad.tail(dim_).setZero();
        c.hess.conservativeResize(old + dim_, old + dim_);
        c.hess.rightCols(dim_).setZero();
        c.hess.bottomRows(dim_).setZero();
      }
    const Index cols = c.grad.size();
    c.slip_jacobian.setZero(dim_, cols);
    c.slip = x[c.slave];
    for (int d = 0; d < dim_; ++d) c.slip_jacobian(d, d) = 1;
    if (s_.rigid) {
      c.slip -= origin_point_[j] + offset;
      for (int d = 0; d < dim_; ++d) c.slip_jacobian(d, static_cast<Index>(c.nodes.size()) * dim_ + d) = -1;
    } else {
      for (auto [node, w] : origin_[j]) {
        c.slip -= w * x[node];
        const Index k = std::find(c.nodes.begin(), c.nodes.end(), node) - c.nodes.begin();
        for (int d = 0; d < dim_; ++d) c.slip_jacobian(d, k * dim_ + d) -= w;
      }
    }
    c.has_slip = true;
  }
}

void ContactInterface::assemble(const std::vector<Vec3>& x, const VecX& z, const DofMap& dofs, VecX& residual,
                                GlobalMatrix* K, const std::vector<char>* fixed) {
  build_constraints(x, z);
  if (frictional()) add_slip_kinematics(x, z);
  EnforcementInput in;
  in.constraints = &constraints_;
  in.dofs = &dofs;
  in.dim = dim_;
  in.stiffness = &stiffness_;
  in.multiplier_offset = offset_;
  in.forced = &forced_;
  if (augmented()) in.shift = &shift_;
  if (frictional()) {
    in.friction = friction_.get();
    in.tangential_stiffness = &tangential_stiffness_;
    in.traction_old = &traction_old_;
    in.friction_hold = &friction_hold_;
    in.fixed = fixed;
  }
  enforcement_->assemble(in, z, residual, K, state_);
}

void ContactInterface::count_status_changes() {
  // Chattering guard, on accepted iterates only: a node whose status keeps flipping within
  // the increment is held in its current status.
  std::vector<Index> newly_frozen;
  for (size_t j = 0; j < state_.active.size(); ++j) {
    if (state_.active[j] != last_active_[j]) ++flips_[j];
    last_active_[j] = state_.active[j];
    if (flips_[j] > s_.max_flips && !forced_[j]) {
      forced_[j] = state_.active[j] ? 1 : -1;
      newly_frozen.push_back(slave_.nodes[j]);
    }
    // Stick/slip of a closed node: held in its status after max_flips changes.
    if (frictional() && state_.active[j] && j < state_.slip.size()) {
      if (state_.slip[j] != last_slip_[j]) ++friction_flips_[j];
      last_slip_[j] = state_.slip[j];
      if (friction_flips_[j] > s_.max_flips && !friction_hold_[j]) {
        friction_hold_[j] = state_.slip[j] ? 2 : 1;
        newly_frozen.push_back(slave_.nodes[j]);
      }
    }
  }
  if (!newly_frozen.empty()) {
    std::string ids;
    for (size_t k = 0; k < newly_frozen.size() && k < 20; ++k)
      ids += (k ? ", " : "") + std::to_string((*node_ids_)[newly_frozen[k]]);
    log::warning("contact '{}': {} slave node(s) changed status (open/closed or stick/slip) more than {} times in this "
                 "increment and are held in their status until it ends (mesh nodes {}{})",
                 label_, newly_frozen.size(), s_.max_flips, ids, newly_frozen.size() > 20 ? ", ..." : "");
    frozen_reported_ += static_cast<Index>(newly_frozen.size());
  }
}

Index ContactInterface::fix_held_nodes() {
  // A node held closed that ends in tension is released (held open instead), once; a node
  // held open that penetrates beyond the tolerance cannot be fixed here.
  Index changed = 0;
  for (size_t j = 0; j < forced_.size() && j < state_.pressure.size(); ++j) {
    if (forced_[j] == 1 && state_.pressure[j] < 0) {
      forced_[j] = -2;
      ++changed;
    }
  }
  // A node held in stick (slip) whose trial traction ends outside (inside) the friction disc
  // beyond the tolerance takes the other status, once.
  for (size_t j = 0; j < friction_hold_.size() && j < state_.active.size(); ++j)
    if (state_.active[j] && friction_hold_[j] && friction_flips_[j] < kSwapped && friction_violation(j) > 0) {
      friction_hold_[j] = friction_hold_[j] == 1 ? 2 : 1;
      friction_flips_[j] = kSwapped;
      ++changed;
    }
  return changed;
}

Real ContactInterface::friction_violation(size_t j) const {
  // How far a held node's trial traction lies on the wrong side of the disc's rim, beyond
  // kHeldFrictionTolerance of the bound (<= 0: within the tolerance).
  const Real excess = state_.cone_excess[j];
  const Real bound = std::abs(state_.traction[j].norm() - (friction_hold_[j] == 1 ? excess : 0.0));
  const Real wrong = friction_hold_[j] == 1 ? excess : -excess;
  return wrong - kHeldFrictionTolerance * bound;
}

std::vector<ContactInterface::SlaveState> ContactInterface::slave_states() const {
  std::vector<SlaveState> out;
  for (size_t j = 0; j < constraints_.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.slave < 0) continue;
    const bool has = c.kind != ConstraintKind::none;
    const bool closed = j < state_.active.size() && state_.active[j];
    const Real p = j < reported_pressure_.size() ? reported_pressure_[j]
                   : j < state_.pressure.size()  ? state_.pressure[j]
                                                 : 0.0;
    SlaveState st{c.slave, !has ? 0 : (closed ? 2 : 1), has ? c.gap : std::numeric_limits<Real>::quiet_NaN(), p};
    if (frictional()) {
      if (closed && j < state_.slip.size() && state_.slip[j]) st.status = 3;
      if (closed && j < state_.traction.size()) st.traction = -state_.traction[j];
      st.slip_increment = slip_increment_[j];
      st.slip_accumulated = slip_accumulated_[j];
    }
    out.push_back(st);
  }
  return out;
}

void ContactInterface::add_nodal_forces(std::vector<Vec3>& f) const {
  for (size_t j = 0; j < constraints_.size() && j < state_.pressure.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.kind == ConstraintKind::none || state_.pressure[j] == 0) continue;
    const Real lambda = state_.pressure[j] * c.weight;
    for (size_t k = 0; k < c.nodes.size(); ++k)
      for (int d = 0; d < dim_; ++d) f[c.nodes[k]](d) += lambda * c.grad(static_cast<Index>(k) * dim_ + d);
  }
}

void ContactInterface::set_reported_pressure(const std::vector<Vec3>& nodal_force) {
  reported_pressure_.assign(constraints_.size(), 0.0);
  for (size_t j = 0; j < constraints_.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.kind == ConstraintKind::none || c.weight <= 0) continue;
    reported_pressure_[j] = nodal_force[c.slave].dot(c.normal) / c.weight;
  }
}

Real ContactInterface::gap_tolerance() const {
  if (s_.gap_tolerance > 0) return s_.gap_tolerance;
  Real t = 1e300;
  for (Real h : node_size_) t = std::min(t, 1e-3 * h);
  return t;
}

bool ContactInterface::uzawa_update(Real& max_penetration) {
  // Each node against its own tolerance: given, or 1e-3 of its local facet size.
  max_penetration = 0;
  bool ok = true;
  for (size_t j = 0; j < constraints_.size(); ++j)
    if (constraints_[j].kind != ConstraintKind::none && state_.active[j]) {
      const Real pen = -constraints_[j].gap;
      max_penetration = std::max(max_penetration, pen);
      ok = ok && pen <= (s_.gap_tolerance > 0 ? s_.gap_tolerance : 1e-3 * node_size_[j]);
    }
  // Friction: a sticking node's elastic slip (the tangential part of d since the last update)
  // must be within the same tolerance.
  if (frictional())
    for (size_t j = 0; j < constraints_.size(); ++j) {
      const Constraint& c = constraints_[j];
      if (c.kind == ConstraintKind::none || !state_.active[j] || !c.has_slip || state_.slip[j]) continue;
      const Real elastic = c.tangential_slip().norm();
      ok = ok && elastic <= (s_.gap_tolerance > 0 ? s_.gap_tolerance : 1e-3 * node_size_[j]);
    }
  if (ok) return true;
  for (size_t j = 0; j < constraints_.size(); ++j)
    shift_[j] = constraints_[j].kind == ConstraintKind::none
                    ? 0.0
                    : std::max(0.0, shift_[j] - stiffness_[j] * constraints_[j].gap);
  if (frictional())
    // Uzawa on the tangential multipliers: the traction becomes the new multiplier and the
    // slip restarts from the current contact point (Simo & Laursen 1992).
    for (size_t j = 0; j < constraints_.size(); ++j) {
      const Constraint& c = constraints_[j];
      if (c.kind == ConstraintKind::none || !state_.active[j] || !c.has_slip) continue;
      traction_old_[j] = state_.traction[j];
      record_origin(j, c, origin_point_[j] + c.slip);  // x_s - offset = origin + d
    }
  return false;
}

Index ContactInterface::frozen_in_tension() const {
  // Held nodes whose final state violates the contact conditions: closed in tension, or
  // open and penetrating beyond 1e-3 of the local facet size.
  Index n = 0;
  for (size_t j = 0; j < forced_.size() && j < state_.pressure.size(); ++j) {
    if (forced_[j] > 0 && state_.pressure[j] < 0) ++n;
    if (forced_[j] < 0 && constraints_[j].kind != ConstraintKind::none && -constraints_[j].gap > 1e-3 * node_size_[j]) ++n;
  }
  for (size_t j = 0; j < friction_hold_.size() && j < state_.active.size(); ++j)
    if (state_.active[j] && friction_hold_[j] && friction_violation(j) > 0) ++n;
  return n;
}

ContactStats ContactInterface::commit() {
  ContactStats st;
  st.label = label_;
  for (size_t j = 0; j < state_.active.size(); ++j) {
    st.active += state_.active[j];
    if (state_.active[j] != committed_active_[j]) {
      ++st.changes;
      st.changed_nodes.push_back(slave_.nodes[j]);
    }
    st.frozen += forced_[j] != 0;
    const Constraint& c = constraints_[j];
    if (c.kind != ConstraintKind::none) {
      st.max_penetration = std::max(st.max_penetration, -c.gap);
      st.force += state_.pressure[j] * c.weight * c.normal;  // on the slave side, along the master normal
    }
  }
  committed_active_ = state_.active;
  shift_committed_ = shift_;
  if (frictional())
    for (size_t j = 0; j < constraints_.size(); ++j) {
      const Constraint& c = constraints_[j];
      const bool closed = state_.active[j] && c.has_slip;
      traction_old_[j] = traction_committed_[j] = closed ? state_.traction[j] : Vec3::Zero();
      slip_increment_[j] = closed ? c.tangential_slip().norm() : 0.0;
      slip_accumulated_[j] += slip_increment_[j];
      if (closed) (state_.slip[j] ? st.slipping : st.sticking)++;
      // Stick <-> slip changes count as status changes too.
      const signed char now = closed ? (state_.slip[j] ? 2 : 1) : 0;
      if (closed && committed_friction_[j] != 0 && now != committed_friction_[j]) {
        ++st.stick_slip_changes;
        st.changed_nodes.push_back(slave_.nodes[j]);
      }
      committed_friction_[j] = now;
      if (closed) st.force -= c.weight * state_.traction[j];  // friction on the slave side
    }
  return st;
}

}  // namespace signorini
