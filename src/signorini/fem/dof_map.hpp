// Degrees of freedom: one per node and displacement component, numbered node by node,
// only for nodes used by a cell of some body. Constrained DOFs keep their numbers.
#pragma once
#include <vector>

#include "signorini/core/types.hpp"
#include "signorini/mesh/mesh.hpp"

namespace signorini {

class DofMap {
 public:
  DofMap() = default;
  DofMap(Index num_nodes, int dofs_per_node, const std::vector<const ElementBlock*>& cells);
  int dofs_per_node() const { return ndpn_; }
  Index num_dofs() const { return num_dofs_; }
  // DOF of a node component, -1 when the node has no DOFs.
  Index dof(Index node, int comp) const {
    return first_[node] < 0 ? -1 : first_[node] + comp;
  }
  bool has_dofs(Index node) const { return first_[node] >= 0; }
  Index num_nodes() const { return static_cast<Index>(first_.size()); }

 private:
  int ndpn_ = 0;
  Index num_dofs_ = 0;
  std::vector<Index> first_;
};

}  // namespace signorini
