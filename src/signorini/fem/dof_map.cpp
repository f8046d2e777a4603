#include "signorini/fem/dof_map.hpp"

namespace signorini {

DofMap::DofMap(Index num_nodes, int dofs_per_node, const std::vector<const ElementBlock*>& cells)
    : ndpn_(dofs_per_node), first_(num_nodes, -1) {
  std::vector<char> used(num_nodes, 0);
  for (auto* b : cells)
    for (Index n : b->conn) used[n] = 1;
  for (Index n = 0; n < num_nodes; ++n)
    if (used[n]) {
      first_[n] = num_dofs_;
      num_dofs_ += ndpn_;
    }
}

}  // namespace signorini
