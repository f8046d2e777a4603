// Degrees of freedom: one per node and displacement component, numbered node by node,
// only for nodes used by a cell of some body. Constrained DOFs keep their numbers. The nodes
// of a group (a rigid body and its reference node) share one set of DOFs: they translate
// together.
#pragma once
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

class DofMap {
 public:
  DofMap() = default;
  DofMap(Index num_nodes, int dofs_per_node, const std::vector<const ElementBlock*>& cells,
         const std::vector<std::vector<Index>>& shared = {});
  int dofs_per_node() const { return ndpn_; }
  Index num_dofs() const { return num_dofs_; }
  // DOF of a node component, -1 when the node has no DOFs.
  Index dof(Index node, int comp) const {
    return first_[node] < 0 ? -1 : first_[node] + comp;
  }
  bool has_dofs(Index node) const { return first_[node] >= 0; }
  Index num_nodes() const { return static_cast<Index>(first_.size()); }
  // Whether the node shares its DOFs with other nodes (a rigid body's).
  bool shared(Index node) const { return !shared_.empty() && shared_[node]; }

 private:
  int ndpn_ = 0;
  Index num_dofs_ = 0;
  std::vector<Index> first_;
  std::vector<char> shared_;
};

}  // namespace signorini
