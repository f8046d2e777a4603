#include "signorini/contact/contact_interface.hpp"

#include <algorithm>
#include <cmath>
#include <istream>
#include <limits>
#include <ostream>

#include "signorini/contact/compatibility.hpp"
#include "signorini/contact/discretization/rigid_obstacle.hpp"
#include "signorini/core/binary_io.hpp"
#include "signorini/core/error.hpp"
#include "signorini/core/first_error.hpp"
#include "signorini/core/log.hpp"

namespace signorini {

ContactInterface::ContactInterface(const ContactPairSettings& s, const Mesh& mesh, const AnalysisSettings& as,
                                   Real stiffness_scale, bool second_pass)
    : s_(s), dim_(as.spatial_dim()), node_ids_(&mesh.node_ids) {
  check_contact_pair(s_, mesh, as.dimension);  // the compatibility table (the deck reader checked it with the place)
  if (second_pass) std::swap(s_.master, s_.slave);
  label_ = s_.name + (second_pass ? " (pass 2)" : "");
  slave_ = make_slave_surface(mesh, s_.slave, as, slave_basis(s_.discretization, s_.rigid, dim_ == 3, s_.method));
  if (second_pass) {
    // A node that coincides with a node of the other surface carries the same constraint in
    // both passes: keep it once (twice makes the multiplier system singular).
    const MasterSurface master = make_master_surface(mesh, s_.master);
    Real h = 0;
    for (Index f = 0; f < master.size(); ++f)
      h = std::max(h, (mesh.nodes[master.facets[f][0]] - mesh.nodes[master.facets[f][1]]).norm());
    SlaveSurface kept;
    for (size_t j = 0; j < slave_.nodes.size(); ++j) {
      bool duplicate = false;
      for (Index m : master.nodes)
        duplicate = duplicate || (mesh.nodes[m] - mesh.nodes[slave_.nodes[j]]).norm() <= 1e-8 * h;
      if (duplicate) continue;
      kept.nodes.push_back(slave_.nodes[j]);
      kept.weights.push_back(slave_.weights[j]);
    }
    slave_ = std::move(kept);
  }
  discretization_ = make_discretization(s_, mesh, slave_, as);
  is_slave_.assign(mesh.num_nodes(), 0);
  for (Index n : slave_.nodes) is_slave_[n] = 1;
  enforcement_ = make_enforcement(s_.method, s_.nitsche_theta, s_.nitsche_exact_tangent);
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
  nodes_.assign(n, NodeRecord{});
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
    for (Index j = 0; j < n; ++j) {
      const Index node = slave_.nodes[j];
      NodeRecord& r = nodes_[j];
      r.size = count[node] ? sum[node] / count[node] : h;
      r.stiffness = s_.penalty > 0 ? s_.penalty : s_.penalty_factor * stiffness_scale / r.size;
    }
  }
  dmax_ = s_.max_distance > 0 ? s_.max_distance : 2 * mean_master_edge_;
  if (s_.friction != "none") {
    friction_ = make_friction_law(s_.friction, s_.friction_parameter);
    // Automatic: the penalty, the normal one of the node (a regularization of stick); Lagrange
    // multipliers, the tangential complementarity constant kTangentialComplementarity E / h,
    // an order below the node's tangential stiffness (about E / h): the stick/slip decision
    // of the semi-smooth Newton method, |lambda_T + c_T d| <= F, then follows the traction
    // more than the unconverged slip of the iterate. The converged solution does not depend
    // on it; measured on the press-then-shear family (docs/contact.md), 0.01 to 0.3 E/h
    // converge in one increment per step, E/h and above cut back. That is the value for a node
    // that closes in the increment; begin_increment raises it to E/h for a node closed at the
    // increment's start, whose slip is the one to trust (gross sliding: docs/contact.md, "The
    // choice of c_T").
    for (NodeRecord& r : nodes_) {
      r.tangential_stiffness = s_.tangential_penalty > 0 ? s_.tangential_penalty
                               : uses_multipliers()     ? kTangentialComplementarity * stiffness_scale / r.size
                                                        : r.stiffness;
      r.tangential_closing = s_.tangential_penalty <= 0 && uses_multipliers() ? r.tangential_stiffness : 0;
    }
  }
}

void ContactInterface::detect(const std::vector<Vec3>& x, Real max_step) {
  // Maximal detection distance: given, or twice the master facet size plus twice the motion
  // expected before the next search.
  dmax_ = s_.max_distance > 0 ? s_.max_distance : 2 * mean_master_edge_ + 2 * max_step;
  std::vector<char> tracked(nodes_.size());
  for (size_t j = 0; j < nodes_.size(); ++j) tracked[j] = nodes_[j].last_closed;
  discretization_->detect(x, dmax_, 2 * max_step, tracked);
}

void ContactInterface::couplings(const DofMap& dofs, std::vector<std::vector<Index>>& out) const {
  std::vector<Index> nodes;
  for (size_t j = 0; j < nodes_.size(); ++j) {
    std::vector<Index> g;
    auto add_node = [&](Index n) {
      for (int d = 0; d < dim_; ++d) g.push_back(dofs.dof(n, d));
      // A turning rigid body's angle couples with its nodes.
      if (rotations_ && rotations_->body_of_node[n] >= 0)
        for (int i = 0; i < rotations_->angles; ++i) g.push_back(rotations_->dof[rotations_->body_of_node[n]] + i);
    };
    discretization_->coupled_nodes(j, nodes);
    for (Index n : nodes) add_node(n);
    if (frictional())
      for (auto [node, w] : nodes_[j].origin.nodes) add_node(node);
    if (uses_multipliers()) {
      g.push_back(offset_ + static_cast<Index>(j));
      if (frictional())
        for (int d = 0; d < dim_; ++d) g.push_back(offset_ + static_cast<Index>(nodes_.size() + j * dim_ + d));
    }
    for (int d = 0; d < num_obstacle_dofs(); ++d) g.push_back(obstacle_dofs() + d);
    out.push_back(std::move(g));
  }
}

void ContactInterface::begin_increment(const std::vector<Vec3>& x, const VecX& z, bool unmoved) {
  // The stick predictor (penalty and augmented Lagrangian friction; not Nitsche's, whose
  // statuses are its integration points'): in the increment where the
  // pair's contact zone forms, with every node open at its start (see end_stick_predictor).
  stick_predictor_ = frictional() && s_.stick_predictor && !uses_multipliers() && enforcement_->node_statuses() &&
                     std::none_of(nodes_.begin(), nodes_.end(), [](const NodeRecord& r) { return r.committed_closed; });
  for (NodeRecord& r : nodes_) {
    // Lagrange friction's automatic c_T (kTangentialComplementarity*): E/h for a node closed at
    // the increment's start, a tenth of it for one that closes in the increment.
    if (r.tangential_closing > 0)
      r.tangential_stiffness =
          r.committed_closed
              ? r.tangential_closing * (kTangentialComplementaritySliding / kTangentialComplementarity)
              : r.tangential_closing;
    r.flips = 0;
    r.hold = Hold::none;
    r.last_closed = r.committed_closed;
    r.friction_flips = 0;
    r.swapped = false;
    r.friction_hold = StickSlip::none;
    r.last_slip = r.committed_friction == StickSlip::slip;
    r.feature_changes = r.feature_returns = 0;
    r.last_kind = r.before_kind = -1;
    r.last_facet = r.before_facet = r.held_facet = -1;
  }
  // The first Newton matrix of an increment that starts where the last one converged: a
  // closed node has not slipped (d = 0) and its trial is its committed traction, on the rim of
  // its disc if it slipped. Either branch of the return map is a valid Newton derivative there
  // and round-off chooses between them; the stick branch is the elastic predictor, and the only
  // one that gives the bodies a tangential stiffness in the slip's direction: measured on
  // examples/rolling_rigid_ball, whose 'ease' step lowers the moment that turned the ball at
  // full slip, the slip branch left the turn about the vertical held by nothing (6.5 rad asked
  // at the first step, then stick/slip cycling at the rim and the increment cut to its minimum).
  stick_at_kink_ = frictional() && unmoved && enforcement_->node_statuses();
  discretization_->hold_facets({});
  discretization_->begin_increment(x);
  frozen_reported_ = 0;
  enforcement_->begin_increment(nodes_);
  if (!frictional()) return;
  // The slip origins: where each slave node touches the master material now.
  build_constraints(x, z);
  for (size_t j = 0; j < constraints_.size(); ++j)
    nodes_[j].origin = discretization_->origin(constraints_[j], x[constraints_[j].slave], z);
  discretization_->set_point_origins();
}

bool ContactInterface::share_points() {
  if (!ranks_ || ranks_->size() < 2 || !enforcement_->needs_points()) return false;
  points_shared_ = discretization_->share_points(ranks_->rank(), ranks_->size());
  return points_shared_;
}

void ContactInterface::build_constraints(const std::vector<Vec3>& x, const VecX& z) {
  if (points_shared_) {
    // Each rank builds its own points (the slave body's stress at them may fail on one rank
    // only: an inverted cell): the ranks agree on the lowest rank's failure, which all of them
    // throw, a SolverError (Newton shortens its step) or an Error alike.
    FirstError failure;
    failure.run([&] { discretization_->build(x, z, dmax_, constraints_); });
    failure.rethrow_agreed(*ranks_);
  } else {
    discretization_->build(x, z, dmax_, constraints_);
  }
  for (size_t j = 0; j < constraints_.size(); ++j) {
    Constraint& c = constraints_[j];
    if (frictional()) {
      c.has_slip = false;
      if (c.kind != ConstraintKind::none && nodes_[j].origin.valid) discretization_->add_slip(nodes_[j].origin, x, z, c);
    }
    if (rotations_ && c.kind != ConstraintKind::none) add_rigid_rotations(c, z);
  }
}

void ContactInterface::add_rigid_rotations(Constraint& c, const VecX& z) const {
  const int dim = dim_;
  const RigidRotations& rr = *rotations_;
  const int na = rr.angles;
  // The turning bodies among c's nodes, each `na` new columns after the existing ones.
  std::vector<int> bodies;
  for (Index n : c.nodes)
    if (rr.body_of_node[n] >= 0 && std::find(bodies.begin(), bodies.end(), rr.body_of_node[n]) == bodies.end())
      bodies.push_back(rr.body_of_node[n]);
  if (bodies.empty()) return;
  const Index m = c.grad.size(), nb = static_cast<Index>(bodies.size()) * na;
  std::vector<Rotation> rot;
  for (int b : bodies) rot.push_back(rotation(z.data() + rr.dof[b], na));
  // Per node k of a turning body: its offset D_k from the body's point, x_k = ... + R D_k, so
  // dx_k/dtheta_i = R_,i D_k and d2x_k/dtheta_i dtheta_j = R_,ij D_k.
  std::vector<Vec3> D(c.nodes.size(), Vec3::Zero());
  std::vector<int> slot(c.nodes.size(), -1);  // index into bodies
  for (size_t k = 0; k < c.nodes.size(); ++k) {
    const int b = rr.body_of_node[c.nodes[k]];
    if (b < 0) continue;
    slot[k] = static_cast<int>(std::find(bodies.begin(), bodies.end(), b) - bodies.begin());
    D[k] = (*rr.reference)[c.nodes[k]] - rr.ref[b];
  }
  // T: the old columns' derivative in each new column (m x nb).
  MatX T = MatX::Zero(m, nb);
  for (size_t k = 0; k < c.nodes.size(); ++k)
    if (slot[k] >= 0)
      for (int i = 0; i < na; ++i) {
        const Vec3 t = rot[slot[k]].dR[i] * D[k];
        for (int a = 0; a < dim; ++a) T(static_cast<Index>(k) * dim + a, slot[k] * na + i) = t(a);
      }
  auto second = [&](const VecX& g) {  // sum_k g_k . R_,ij D_k per pair of new columns (the body blocks)
    MatX v = MatX::Zero(nb, nb);
    for (size_t k = 0; k < c.nodes.size(); ++k)
      if (slot[k] >= 0) {
        Vec3 gk = Vec3::Zero();
        for (int a = 0; a < dim; ++a) gk(a) = g(static_cast<Index>(k) * dim + a);
        for (int i = 0; i < na; ++i)
          for (int j = 0; j < na; ++j)
            v(slot[k] * na + i, slot[k] * na + j) += gk.dot(rot[slot[k]].d2R[i][j] * D[k]);
      }
    return v;
  };
  const VecX g_theta = T.transpose() * c.grad;
  const MatX HT = c.hess * T;
  MatX H = MatX::Zero(m + nb, m + nb);
  H.topLeftCorner(m, m) = c.hess;
  H.topRightCorner(m, nb) = HT;
  H.bottomLeftCorner(nb, m) = HT.transpose();
  H.bottomRightCorner(nb, nb) = T.transpose() * HT + second(c.grad);
  c.hess = std::move(H);
  c.grad.conservativeResize(m + nb);
  c.grad.tail(nb) = g_theta;
  const MatX NT = c.normal_jacobian * T;
  c.normal_jacobian.conservativeResize(Eigen::NoChange, m + nb);
  c.normal_jacobian.rightCols(nb) = NT;
  if (c.has_slip) {
    const MatX DT = c.slip_jacobian * T;
    std::vector<MatX> sh(dim, MatX::Zero(m + nb, m + nb));
    for (int d = 0; d < dim; ++d) {
      if (static_cast<int>(c.slip_hessian.size()) > d) sh[d].topLeftCorner(m, m) = c.slip_hessian[d];
      sh[d].bottomRightCorner(nb, nb) += second(c.slip_jacobian.row(d).transpose());
    }
    c.slip_hessian = std::move(sh);
    c.slip_jacobian.conservativeResize(Eigen::NoChange, m + nb);
    c.slip_jacobian.rightCols(nb) = DT;
  }
  for (int b : bodies)
    for (int i = 0; i < na; ++i) c.extra_dofs.push_back(rr.dof[b] + i);
}

void ContactInterface::assemble(const std::vector<Vec3>& x, const VecX& z, const DofMap& dofs, VecX& residual,
                                GlobalMatrix* K, const std::vector<char>* fixed) {
  discretization_->set_second_variation(K != nullptr);
  build_constraints(x, z);
  discretization_->set_second_variation(true);
  EnforcementInput in;
  in.constraints = &constraints_;
  in.dofs = &dofs;
  in.dim = dim_;
  in.nodes = &nodes_;
  in.multiplier_offset = offset_;
  in.points = discretization_->integration_points();
  in.share = points_shared_ ? ranks_ : nullptr;
  if (frictional()) {
    in.friction = friction_.get();
    in.fixed = fixed;
    if (discretization_->weighted_slip()) in.slave_nodes = &is_slave_;
    in.stick_predictor = stick_predictor_;
    in.stick_at_kink = stick_at_kink_ && K;
  }
  enforcement_->assemble(in, z, residual, K, state_);
  if (K) stick_at_kink_ = false;
}

Index ContactInterface::end_stick_predictor(bool converged, Real step, bool first_iteration) {
  // In the increment where the pair's contact zone forms (every node open at its start), while
  // the normal statuses change, a node that closes sticks (its trial traction is taken whole:
  // Penalty::add_friction). Its slip at those iterates is the slip of a contact point that is
  // still moving into place: measured on the press of the friction grid (mu 0.1, penalty), a
  // free return map sent nodes into slip on it at iterations 1-4, and each came back to stick
  // one per iteration under the line search (17 iterations; with the predictor 8). Not once
  // the zone exists: the nodes that then close are at its edge, where they may truly slip
  // (Klang's pin: with the predictor in every increment, its increments 2-10 took 5-21
  // iterations instead of 3-6, 129 in all against 57).
  // The predictor ends at the first accepted iterate
  // - whose normal statuses did not change;
  // - or whose step the line search cut to kStickPredictorStep or less, the first iteration
  //   apart (its step carries the bodies' approach and is often cut: 1/16 on the friction
  //   grid's press with mortar, which needs the predictor after it). Such a step means the
  //   linearization is far from the residual, and holding nodes in stick only restrains a
  //   body that has to move: Klang's pin, pushed by a force into its hole, closes a node or a
  //   few per iteration at steps of 1/64-1/16; with the predictor held to the end of the
  //   closing its first increment failed twice, 25 iterations each;
  // - or whose residual, shaped by the predictor, has converged.
  // The residual is then that of the free law, and Newton goes on from there. Returns how many
  // closed nodes the predictor held in stick outside their friction disc (0: ending it changes
  // nothing).
  if (!stick_predictor_) return 0;
  const bool force = converged || (!first_iteration && step <= kStickPredictorStep);
  if (!force && iterate_status_.newly_closed + iterate_status_.newly_opened > 0) return 0;
  stick_predictor_ = false;
  Index held = 0;
  for (size_t j = 0; j < state_.cone_excess.size(); ++j)
    if (state_.active[j] && state_.cone_excess[j] > 0) ++held;
  return held;
}

void ContactInterface::count_status_changes() {
  // Chattering guard, on accepted iterates only: a node whose status keeps flipping within
  // the increment is held in its current status.
  std::vector<Index> newly_frozen;
  iterate_status_ = {};
  for (size_t j = 0; j < state_.active.size(); ++j) {
    NodeRecord& r = nodes_[j];
    const bool closed = state_.active[j], was_closed = r.last_closed;
    iterate_status_.closed += closed;
    if (closed != r.last_closed) {
      ++(closed ? iterate_status_.newly_closed : iterate_status_.newly_opened);
      ++r.flips;
    }
    r.last_closed = closed;
    if (!enforcement_->node_statuses()) continue;
    if (r.flips > s_.max_flips && !guard_hold(r.hold)) {
      r.hold = closed ? Hold::closed : Hold::open;
      newly_frozen.push_back(slave_.nodes[j]);
    }
    // Stick/slip of a closed node: held in its status after max_flips changes.
    if (frictional() && closed && j < state_.slip.size()) {
      const bool slip = state_.slip[j];
      iterate_status_.slipping += slip;
      if (slip != r.last_slip) ++r.friction_flips;
      if (slip != r.last_slip && was_closed) ++(slip ? iterate_status_.to_slip : iterate_status_.to_stick);
      r.last_slip = slip;
      if (r.friction_flips > s_.max_flips && r.friction_hold == StickSlip::none) {
        r.friction_hold = slip ? StickSlip::slip : StickSlip::stick;
        // Once per node, held in both its statuses at the same iteration.
        if (newly_frozen.empty() || newly_frozen.back() != slave_.nodes[j]) newly_frozen.push_back(slave_.nodes[j]);
      }
    }
  }
  // Closed nodes whose master feature (facet, edge or vertex) changed at this iterate; a node
  // back on the feature it left for the second time is held on its facet (NodeRecord).
  std::vector<Index> moved, held;
  for (size_t j = 0; j < state_.active.size() && j < constraints_.size(); ++j) {
    NodeRecord& r = nodes_[j];
    const int kind = static_cast<int>(constraints_[j].kind);
    const Index facet = constraints_[j].facet;
    if (state_.active[j] && r.last_kind >= 0 && (kind != r.last_kind || facet != r.last_facet)) {
      ++r.feature_changes;
      if (kind == r.before_kind && facet == r.before_facet) ++r.feature_returns;
      moved.push_back(static_cast<Index>(j));
      r.before_kind = r.last_kind;
      r.before_facet = r.last_facet;
    }
    r.last_kind = kind;
    r.last_facet = facet;
    if (state_.active[j] && r.held_facet < 0 && r.feature_returns >= 2 &&
        constraints_[j].kind == ConstraintKind::segment) {
      r.held_facet = facet;
      held.push_back(static_cast<Index>(j));
    }
  }
  if (!moved.empty()) {
    std::string ids;
    for (size_t k = 0; k < moved.size() && k < 8; ++k)
      ids += fmt::format("{}{} ({} changes)", k ? ", " : "", (*node_ids_)[slave_.nodes[moved[k]]],
                         nodes_[moved[k]].feature_changes);
    log::debug("contact '{}': {} closed slave node(s) met another master facet, edge or vertex (mesh nodes {}{})",
               label_, moved.size(), ids, moved.size() > 8 ? ", ..." : "");
  }
  if (!held.empty()) {
    std::vector<Index> facets(nodes_.size(), -1);
    for (size_t j = 0; j < nodes_.size(); ++j) facets[j] = nodes_[j].held_facet;
    discretization_->hold_facets(facets);
    std::string ids;
    for (size_t k = 0; k < held.size() && k < 8; ++k)
      ids += fmt::format("{}{}", k ? ", " : "", (*node_ids_)[slave_.nodes[held[k]]]);
    log::debug("contact '{}': {} slave node(s) went back and forth between master facets and are held on their "
               "facet until the increment ends (mesh nodes {}{})",
               label_, held.size(), ids, held.size() > 8 ? ", ..." : "");
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

std::vector<Real> ContactInterface::penetrations() const {
  std::vector<Real> p(constraints_.size(), 0.0);
  for (size_t j = 0; j < constraints_.size(); ++j) {
    if (j < state_.active.size() && state_.active[j]) p[j] = std::numeric_limits<Real>::quiet_NaN();  // closed
    else if (constraints_[j].kind != ConstraintKind::none) p[j] = std::max(Real(0), -constraints_[j].gap);
  }
  return p;
}

std::pair<Real, Index> ContactInterface::penetration_growth(const std::vector<Real>& before) const {
  Real worst = 0;
  Index node = -1;
  for (size_t j = 0; j < constraints_.size() && j < before.size() && j < nodes_.size(); ++j) {
    if (std::isnan(before[j]) || constraints_[j].kind == ConstraintKind::none || !(nodes_[j].size > 0)) continue;
    const Real growth = (std::max(Real(0), -constraints_[j].gap) - before[j]) / nodes_[j].size;
    if (growth > worst) {
      worst = growth;
      node = (*node_ids_)[slave_.nodes[j]];
    }
  }
  return {worst, node};
}

Index ContactInterface::fix_held_nodes() {
  // A node held closed that ends in tension is released (held open instead), once; a node
  // held open that penetrates beyond the tolerance cannot be fixed here.
  Index changed = 0;
  for (size_t j = 0; j < nodes_.size() && j < state_.pressure.size(); ++j) {
    if (nodes_[j].hold == Hold::closed && state_.pressure[j] < 0) {
      nodes_[j].hold = Hold::released;
      ++changed;
    }
  }
  // A node held in stick (slip) whose trial traction ends outside (inside) the friction disc
  // beyond the tolerance takes the other status, once.
  if (frictional())
    for (size_t j = 0; j < nodes_.size() && j < state_.active.size(); ++j) {
      NodeRecord& r = nodes_[j];
      if (state_.active[j] && r.friction_hold != StickSlip::none && !r.swapped && friction_violation(j) > 0) {
        r.friction_hold = r.friction_hold == StickSlip::stick ? StickSlip::slip : StickSlip::stick;
        r.swapped = true;
        ++changed;
      }
    }
  return changed;
}

Index ContactInterface::hold_touching(const std::vector<Vec3>& x, const VecX& z) {
  if (!enforcement_->node_statuses()) return 0;
  build_constraints(x, z);
  // Penalty and the augmented Lagrangian close a constraint at g <= 0 by themselves; the
  // touching ones are closed only where none is, which is where the first solve would have no
  // support from this pair (mortar's and segment-to-segment's weighted gaps at a point
  // contact). Closing them beside a node at g = 0 changed a path that worked: Klang's pin
  // (node_to_segment, penalty, Coulomb; 3 loads x 3 friction coefficients) cut back in 6 of 9
  // cases and took 49-102 Newton iterations against 46-61 without a cutback (session 65).
  if (!uses_multipliers())
    for (const Constraint& c : constraints_)
      if (c.kind != ConstraintKind::none && c.gap <= 0) return 0;
  Index n = 0;
  for (size_t j = 0; j < constraints_.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.kind == ConstraintKind::none || !(c.gap > 0) || c.gap > kTouching * nodes_[j].size) continue;
    // Multipliers: held closed (released after convergence if in tension). Penalty: closed
    // while touching, without adhesion (Hold::touching), so that a node that should open does
    // not pin the bodies until Newton has converged.
    nodes_[j].hold = uses_multipliers() ? Hold::closed : Hold::touching;
    ++n;
  }
  if (n) log::info("contact '{}': {} slave node(s) touching to within {:g} of their facet size start closed", label_, n, kTouching);
  return n;
}

Index ContactInterface::release_holds() {
  // Only holds the converged state does not satisfy exactly are released: a node held closed
  // in tension, held open and penetrating, held in stick outside the friction disc or in slip
  // inside it. A hold the state satisfies is the exact solution's status already; releasing it
  // would only spend iterations.
  Index n = 0;
  for (size_t j = 0; j < nodes_.size() && j < state_.pressure.size(); ++j) {
    NodeRecord& r = nodes_[j];
    const Constraint& c = constraints_[j];
    const bool open_wrong = held_open(r.hold) && c.kind != ConstraintKind::none && c.gap < 0;
    const bool closed_wrong = held_closed(r.hold) && state_.pressure[j] < 0;
    const bool friction_wrong = r.friction_hold != StickSlip::none && j < state_.cone_excess.size() &&
                                (r.friction_hold == StickSlip::stick ? state_.cone_excess[j] > 0 : state_.cone_excess[j] < 0);
    if (!(open_wrong || closed_wrong || friction_wrong)) continue;
    ++n;
    if (guard_hold(r.hold)) r.flips = s_.max_flips;
    if (r.friction_hold != StickSlip::none) r.friction_flips = s_.max_flips;
    r.hold = Hold::none;
    r.friction_hold = StickSlip::none;
    r.swapped = false;
  }
  return n;
}

Real ContactInterface::friction_violation(size_t j) const {
  // How far a held node's trial traction lies on the wrong side of the disc's rim, beyond
  // kHeldFrictionTolerance of the bound (<= 0: within the tolerance).
  const bool stick = nodes_[j].friction_hold == StickSlip::stick;
  const Real excess = state_.cone_excess[j];
  const Real bound = std::abs(state_.traction[j].norm() - (stick ? excess : 0.0));
  const Real wrong = stick ? excess : -excess;
  return wrong - kHeldFrictionTolerance * bound;
}

std::vector<ContactInterface::SlaveState> ContactInterface::slave_states() const {
  std::vector<SlaveState> out;
  for (size_t j = 0; j < constraints_.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.slave < 0) continue;
    const bool has = c.kind != ConstraintKind::none;
    const bool closed = j < state_.active.size() && state_.active[j];
    const Real p = pressure_reported_                ? nodes_[j].reported_pressure
                   : j < state_.pressure.size() ? state_.pressure[j]
                                                : 0.0;
    SlaveState st{c.slave, !has ? far : (closed ? Status::closed : Status::open),
                  has ? c.gap : std::numeric_limits<Real>::quiet_NaN(), p};
    if (frictional()) {
      if (closed && j < state_.slip.size() && state_.slip[j]) st.status = slipping;
      if (closed && j < state_.traction.size()) st.traction = -state_.traction[j];
      st.slip_increment = nodes_[j].slip_increment;
      st.slip_accumulated = nodes_[j].slip_accumulated;
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
  pressure_reported_ = true;
  for (size_t j = 0; j < constraints_.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.kind == ConstraintKind::none || c.weight <= 0) nodes_[j].reported_pressure = 0;
    else if (discretization_->pressure_is_multiplier())
      nodes_[j].reported_pressure = j < state_.pressure.size() ? state_.pressure[j] * c.pressure_factor : 0.0;
    else nodes_[j].reported_pressure = nodal_force[c.slave].dot(c.normal) / c.weight;
  }
}

Real ContactInterface::gap_tolerance() const {
  Real t = s_.gap_tolerance > 0 ? s_.gap_tolerance : 1e300;
  for (const NodeRecord& r : nodes_) t = std::min(t, r.gap_tolerance(s_.gap_tolerance));
  return t;
}

bool ContactInterface::augment(const std::vector<Vec3>& x, const VecX& z, Real& max_penetration) {
  const Augmentation a = enforcement_->augment(constraints_, state_, frictional(), s_.gap_tolerance, nodes_);
  max_penetration = a.max_penetration;
  for (Index j : a.restart_slip)
    nodes_[j].origin = discretization_->origin(constraints_[j], x[constraints_[j].slave], z);
  return a.converged;
}

Index ContactInterface::frozen_in_tension() const {
  // Held nodes whose final state violates the contact conditions: closed in tension, or
  // open and penetrating beyond 1e-3 of the local facet size.
  Index n = 0;
  for (size_t j = 0; j < nodes_.size() && j < state_.pressure.size(); ++j) {
    const Hold h = nodes_[j].hold;
    if (held_closed(h) && state_.pressure[j] < 0) ++n;
    if (held_open(h) && constraints_[j].kind != ConstraintKind::none && -constraints_[j].gap > 1e-3 * nodes_[j].size) ++n;
  }
  if (frictional())
    for (size_t j = 0; j < nodes_.size() && j < state_.active.size(); ++j)
      if (state_.active[j] && nodes_[j].friction_hold != StickSlip::none && friction_violation(j) > 0) ++n;
  return n;
}

Vec3 ContactInterface::slave_force() const {
  // The normal part: p w dg/dx over the pair's slave nodes (node-to-segment: p w n on the slave
  // node, n the master normal; mortar: the weighted gap's variation over the slave facets'
  // nodes). Friction: -w D_k^T t on each slave node k of the constraint (D_k = dd/dx_k; the
  // slave node's is I for node-to-segment, so the slave is pulled by -t per unit area). In
  // self-contact the master nodes are slave nodes too, and the sum is zero by balance.
  if (state_.has_slave_force) return state_.slave_force;
  Vec3 f = Vec3::Zero();
  for (size_t j = 0; j < constraints_.size() && j < state_.pressure.size(); ++j) {
    const Constraint& c = constraints_[j];
    if (c.kind == ConstraintKind::none) continue;
    const bool friction = frictional() && j < state_.active.size() && state_.active[j] && c.has_slip;
    for (size_t k = 0; k < c.nodes.size(); ++k) {
      if (!is_slave_[c.nodes[k]]) continue;
      const Index at = static_cast<Index>(k) * dim_;
      f.head(dim_) += state_.pressure[j] * c.weight * c.grad.segment(at, dim_);
      if (friction)
        f.head(dim_) -= c.weight * (c.slip_jacobian.middleCols(at, dim_).transpose() * state_.traction[j].head(dim_));
    }
  }
  return f;
}

ContactStats ContactInterface::commit() {
  ContactStats st;
  st.label = label_;
  for (size_t j = 0; j < state_.active.size(); ++j) {
    NodeRecord& r = nodes_[j];
    const bool closed = state_.active[j];
    st.active += closed;
    if (closed != r.committed_closed) {
      ++st.changes;
      st.changed_nodes.push_back(slave_.nodes[j]);
    }
    r.committed_closed = closed;
    st.frozen += guard_hold(r.hold);
    const Constraint& c = constraints_[j];
    if (c.kind != ConstraintKind::none) {
      st.max_penetration = std::max(st.max_penetration, -c.gap);
    }
  }
  st.force = slave_force();
  enforcement_->end_increment(constraints_, state_, nodes_);
  if (frictional())
    for (size_t j = 0; j < constraints_.size(); ++j) {
      NodeRecord& r = nodes_[j];
      const Constraint& c = constraints_[j];
      const bool closed = state_.active[j] && c.has_slip;
      r.slip_increment = closed ? c.tangential_slip().norm() : 0.0;
      r.slip_accumulated += r.slip_increment;
      if (closed) (state_.slip[j] ? st.slipping : st.sticking)++;
      // Stick <-> slip changes count as status changes too.
      const StickSlip now = !closed ? StickSlip::none : state_.slip[j] ? StickSlip::slip : StickSlip::stick;
      if (closed && r.committed_friction != StickSlip::none && now != r.committed_friction) {
        ++st.stick_slip_changes;
        st.changed_nodes.push_back(slave_.nodes[j]);
      }
      r.committed_friction = now;
    }
  return st;
}

void ContactInterface::save(std::ostream& os) const {
  using namespace binary;
  put<std::int64_t>(os, static_cast<std::int64_t>(nodes_.size()));
  for (const NodeRecord& r : nodes_) {
    put(os, r.stiffness);
    put(os, r.tangential_stiffness);
    put(os, r.shift_committed);
    put(os, r.committed_closed);
    put(os, r.committed_friction);
    put_vec3(os, r.traction_committed);
    put(os, r.slip_increment);
    put(os, r.slip_accumulated);
    put(os, r.reported_pressure);
    put(os, r.origin.valid);
    put_vec3(os, r.origin.point);
    std::vector<Index> nodes;
    std::vector<Real> weights;
    for (const auto& [n, w] : r.origin.nodes) nodes.push_back(n), weights.push_back(w);
    put_vector(os, nodes);
    put_vector(os, weights);
  }
}

void ContactInterface::load(std::istream& is) {
  using namespace binary;
  const auto n = get<std::int64_t>(is);
  if (n != static_cast<std::int64_t>(nodes_.size()))
    throw Error("contact '" + label_ + "': " + std::to_string(n) + " slave nodes in the file, the model has " +
                std::to_string(nodes_.size()));
  for (NodeRecord& r : nodes_) {
    r.stiffness = get<Real>(is);
    r.tangential_stiffness = get<Real>(is);
    r.shift = r.shift_committed = get<Real>(is);
    r.last_closed = r.committed_closed = get<bool>(is);
    r.committed_friction = get<StickSlip>(is);
    r.traction_old = r.traction_committed = get_vec3(is);
    r.slip_increment = get<Real>(is);
    r.slip_accumulated = get<Real>(is);
    r.reported_pressure = get<Real>(is);
    r.origin.valid = get<bool>(is);
    r.origin.point = get_vec3(is);
    const std::vector<Index> nodes = get_vector<Index>(is, -1, "slip origin");
    const std::vector<Real> weights = get_vector<Real>(is, static_cast<std::int64_t>(nodes.size()), "slip origin");
    r.origin.nodes.clear();
    for (size_t k = 0; k < nodes.size(); ++k) r.origin.nodes.emplace_back(nodes[k], weights[k]);
  }
}

}  // namespace signorini
