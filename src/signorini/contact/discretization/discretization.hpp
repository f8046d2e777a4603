// The discretization seam (DESIGN.md, "the one idea that keeps contact simple"): a contact
// pair's discretization owns its kinematics. It finds the master each slave node may touch
// (global search), builds one Constraint per slave node at the current positions (gap, normal,
// their first and second variations, the master point as a combination of master nodes), and
// measures friction's slip from the master material point where the node touched at the start
// of the increment. Enforcement reads the ConstraintSet only, so a discretization plugs in
// without touching it (docs/architecture.md, "Contact, one class per stage").
//
// Implementations: node-to-segment (with node-to-edge and node-to-vertex), node-to-node, and a
// rigid analytic obstacle. Mortar adds weighted gaps and slips per slave node (its D and M
// blocks enter `grad`, `slip_jacobian` and `normal_jacobian`), Nitsche a traction term; neither
// needs a change in ContactInterface or in enforcement.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/contact_settings.hpp"
#include "signorini/contact/surface.hpp"

namespace signorini {

// Where a slave node's slip is measured from: the master material point it touched at the
// start of the increment (or at the last Uzawa update of the augmented Lagrangian).
struct SlipOrigin {
  bool valid = false;
  std::vector<std::pair<Index, Real>> nodes;  // deformable master: master nodes and their weights
  Vec3 point = Vec3::Zero();                  // rigid obstacle: the point in the obstacle's frame
};

class BoundaryTraction;
class RankExchange;

class Discretization {
 public:
  virtual ~Discretization() = default;
  virtual std::string name() const = 0;
  // Global search at positions x, within dmax of the master; tracked[j]: slave node j was
  // closed at the last accepted iterate (a discretization may keep tracking it beyond dmax).
  // `motion`: the part of dmax that is the motion expected before the next search (twice the
  // largest nodal motion of the increment's prediction), which a discretization may use to
  // bound its candidates more tightly than dmax (segment_to_segment).
  virtual void detect(const std::vector<Vec3>& x, Real dmax, Real motion, const std::vector<char>& tracked) = 0;
  // The mesh nodes whose DOFs constraint j may involve until the next detect (slave first;
  // the sparse pattern). Extra unknowns are listed by extra_dofs().
  virtual void coupled_nodes(size_t j, std::vector<Index>& nodes) const = 0;
  // Unknowns of the discretization beyond the nodes' DOFs (a rigid obstacle's displacement).
  virtual int num_extra_dofs() const { return 0; }
  virtual void set_extra_dofs(Index /*first*/) {}
  virtual Index extra_dofs() const { return -1; }
  // One constraint per slave node at positions x and unknowns z: kind, gap, normal, grad,
  // hess, normal_jacobian and master_weights (open constraints beyond dmax).
  virtual void build(const std::vector<Vec3>& x, const VecX& z, Real dmax, ConstraintSet& out) const = 0;
  // Whether the next builds need the gaps' second variations (hess: the Newton matrix) or may
  // leave them zero (a residual only: a line search's trial point, a finite difference, the
  // slip origins). 3D mortar then differentiates to first order only; the others ignore it.
  void set_second_variation(bool on) { second_variation_ = on; }
  // Whether enforcement's nodal pressure p_j is the pressure to report at slave node j:
  // segment_to_segment, whose p_j is the coefficient of the dual basis in the traction per
  // reference area, p_j = int N~_j t dA0 / int N~_j dA0, a positive-weighted average of the
  // traction. The others report the contact force on the node per its reference weight (the
  // sum of both passes of a two-pass pair; for mortar, whose multiplier is per current area, the
  // load per reference area). The two agree on linear facets; on tri6 and quad8 facets the
  // force per weight follows the consistent-load pattern (a uniform pressure p puts no force
  // on a tri6 corner and read 0 there, 5/3 p at the mid-side nodes).
  virtual bool pressure_is_multiplier() const { return false; }
  // Whether a node's slip is an average over its facets (mortar, segment_to_segment): it then
  // involves its neighbours' DOFs, and on a symmetry plane its half support's, so that friction
  // needs the symmetry planes named from the Dirichlet conditions
  // (enforcement.cpp, prescribed_slip_directions).
  virtual bool weighted_slip() const { return false; }
  // The slip origin of a constrained node: the master point of c, the slave at x_s.
  virtual SlipOrigin origin(const Constraint& c, const Vec3& x_s, const VecX& z) const;
  // Friction kinematics of c from its origin: d = x_s - x_0 and D = dd/dz (Constraint::slip,
  // slip_jacobian); origin nodes c does not involve yet are appended to it.
  virtual void add_slip(const SlipOrigin& o, const std::vector<Vec3>& x, const VecX& z, Constraint& c) const;
  // Nitsche's method (segment_to_segment): the bodies' boundary traction, set before the
  // first detect (throws Error when a discretization cannot use it or a slave facet has no
  // owning cell), and the integration points of the last build (null: none).
  virtual void set_boundary_traction(BoundaryTraction*);
  // Node-to-segment: per slave node, the master facet to keep (-1, or an empty vector: choose
  // the closest) as long as the node projects onto it, up to kHeldFacetTolerance of it beyond
  // its edges. The others ignore it.
  virtual void hold_facets(std::vector<Index> /*facet*/) {}
  // The start of an increment, at the converged positions x (after detect): Nitsche on mortar
  // integration segments its slave facets here, and keeps the cells for the increment. Others:
  // nothing.
  virtual void begin_increment(const std::vector<Vec3>& /*x*/) {}
  virtual const std::vector<PointConstraint>* integration_points() const { return nullptr; }
  // Nitsche with friction: each integration point's slip origin, the master point it projects
  // on in the last build (at the start of the increment); the points of later builds then
  // carry their slip from it (PointConstraint::has_slip). Others: nothing.
  virtual void set_point_origins() {}
  // Several MPI ranks running alike (core/rank_exchange.hpp; null: one process): mortar shares
  // its slave facets' integration out over them, each rank integrating its share and every rank
  // receiving the others' results, so that the constraints are the same bytes on every rank.
  // The others evaluate every slave node on every rank.
  void set_rank_exchange(const RankExchange* r) { ranks_ = r; }
  // Whether build shares its work out over the ranks of a set exchange.
  virtual bool shares_out() const { return false; }
  // Nitsche's integration points assembled by one rank each (partitioned assembly, issue 15):
  // from now on build makes the points of the slave facets e with e % ranks == rank only, the
  // rest of its work (the gaps of every facet, the constraints, the pattern's couplings) staying
  // whole on every rank. Returns whether this discretization has such points (segment_to_segment
  // with Nitsche's method); the others ignore it.
  virtual bool share_points(int /*rank*/, int /*ranks*/) { return false; }

 protected:
  bool second_variation_ = true;
  const RankExchange* ranks_ = nullptr;
};

// The discretization the settings name (a rigid obstacle when s.rigid), for the given slave
// surface; the master surface is built from the mesh.
std::unique_ptr<Discretization> make_discretization(const ContactPairSettings& s, const Mesh& mesh,
                                                    const SlaveSurface& slave, const AnalysisSettings& as);

}  // namespace signorini
