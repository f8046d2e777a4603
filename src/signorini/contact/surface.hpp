// Contact surfaces built from facet sets: the master side (facets, node-to-facet adjacency,
// averaged nodal normals) and the slave side (its nodes with their tributary areas).
#pragma once
#include <string>
#include <vector>

#include "signorini/contact/constraint.hpp"
#include "signorini/contact/geometry/facet_projection.hpp"
#include "signorini/fem/analysis_settings.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

struct MasterSurface {
  std::vector<ElementType> type;              // per facet
  std::vector<std::vector<Index>> facets;     // node indices per facet (outward order)
  std::vector<std::vector<Index>> node_facets;  // facets of each mesh node (empty if not master)
  std::vector<Index> nodes;                   // the master nodes
  int corners(Index f) const { return element_info(type[f]).num_corners; }
  Index size() const { return static_cast<Index>(facets.size()); }
  // Facets sharing a node with facet f, f included.
  std::vector<Index> neighbourhood(Index f) const;
  // Average outward normal at a master node (current positions x).
  Vec3 node_normal(Index node, const std::vector<Vec3>& x, int dim) const;
  // The same normal in 3D, n = s / |s| with s = sum_f n_f the sum of the unit normals of the
  // facets around the node at its parameter, and its derivative J = dn/dx over `nodes` (the
  // nodes of those facets, 3 columns each): dn = (I - n n^T) ds / |s|, dn_f = (I - n_f n_f^T)
  // dm / |m| with m = a1 x a2, dm = da1 x a2 + a1 x da2, da_alpha = sum_i N_i,alpha dx_i
  // (course, "covariant basis"; checked against central differences in test_contact_geometry).
  void node_normal_jacobian_3d(Index node, const std::vector<Vec3>& x, Vec3& n, std::vector<Index>& nodes,
                               MatX& jacobian) const;
  // Hermite smoothing (2D): per facet, the node before its first node and the node after its
  // second (-1: none, at an end of the surface or a corner kept sharp). Empty: faceted.
  std::vector<Index> prev, next;
  // Bicubic smoothing (3D, quad4): per facet, the nodes its patch depends on and the 16 x
  // nodes matrix of the grid points (FacetBasis::bicubic). Empty: faceted.
  std::vector<std::vector<Index>> patch_nodes;
  std::vector<MatX> patch;
  bool smooth() const { return !prev.empty() || !patch.empty(); }
  // The parameterisation of facet f and the nodes it depends on, in the basis's order.
  FacetBasis basis(Index f) const;
  std::vector<Index> basis_nodes(Index f) const;
};

// Kinks sharper than this (degrees between neighbouring segments, reference configuration)
// stay sharp under smoothing.
constexpr Real kSmoothingMaxKink = 45;

// Turns on Hermite smoothing of a master surface (`x`: reference positions): the C1 curve
// of FacetBasis::hermite on a 2D surface of line2 facets, the bicubic patches of
// FacetBasis::bicubic on a 3D surface of quad4 facets. Throws Error for other facet types.
void smooth_master_surface(MasterSurface& m, const std::vector<Vec3>& x);

struct SlaveSurface {
  std::vector<Index> nodes;     // slave nodes
  std::vector<Real> weights;    // tributary area (reference configuration)
};

// One constraint per slave node, with its node and tributary weight, of kind none: where
// every discretization starts.
ConstraintSet open_constraints(const SlaveSurface& slave);

MasterSurface make_master_surface(const Mesh& mesh, const std::string& facet_set);
// The basis whose integrals int N~_j dA0 are the slave nodes' weights: the shape functions
// (`standard`), segment_to_segment's modified basis (segment_to_segment.hpp, Popp et al.'s
// alpha = 1/5), or 3D mortar's transformed basis of non-negative functions (mortar.hpp,
// mortar_positive_basis); the last two differ from N on quadratic facets only.
enum class SlaveBasis { standard, modified, positive };
// The basis a pair's discretization (and its enforcement `method`: Nitsche on mortar
// integration has segment_to_segment's) weighs its slave nodes with.
SlaveBasis slave_basis(const std::string& discretization, bool rigid_master, bool three_d, const std::string& method);
// Throws Error when a slave facet type gives a node a non-positive weight (tri6, quad8 with the
// standard basis; the other two are positive for every facet type).
SlaveSurface make_slave_surface(const Mesh& mesh, const std::string& facet_set, const AnalysisSettings& settings,
                                SlaveBasis basis = SlaveBasis::standard);

}  // namespace signorini
