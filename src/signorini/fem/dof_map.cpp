#include "signorini/fem/dof_map.hpp"

namespace signorini {

DofMap::DofMap(Index num_nodes, int dofs_per_node, const std::vector<const ElementBlock*>& cells,
               const std::vector<std::vector<Index>>& shared)
    : ndpn_(dofs_per_node), first_(num_nodes, -1) {
  std::vector<char> used(num_nodes, 0);
  for (auto* b : cells)
    for (Index n : b->conn) used[n] = 1;
  // A group's DOFs are numbered where its first node would be numbered.
  std::vector<Index> group(num_nodes, -1);
  if (!shared.empty()) shared_.assign(num_nodes, 0);
  for (size_t g = 0; g < shared.size(); ++g)
    for (Index n : shared[g]) {
      group[n] = static_cast<Index>(g);
      used[n] = 1;
      shared_[n] = 1;
    }
  std::vector<Index> group_first(shared.size(), -1);
  for (Index n = 0; n < num_nodes; ++n) {
    if (!used[n]) continue;
    if (group[n] >= 0 && group_first[group[n]] >= 0) {
      first_[n] = group_first[group[n]];
      continue;
    }
    first_[n] = num_dofs_;
    if (group[n] >= 0) group_first[group[n]] = num_dofs_;
    num_dofs_ += ndpn_;
  }
}

}  // namespace signorini
