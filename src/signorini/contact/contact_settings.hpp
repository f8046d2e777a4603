// What the deck says about one contact pair: the surfaces, the discretization, the
// enforcement method and the search options. Plain data, validated by the deck reader.
#pragma once
#include <string>

#include "signorini/core/types.hpp"

namespace signorini {

struct ContactPairSettings {
  std::string name;
  std::string master;                             // facet set
  std::string slave;                              // facet set
  std::string discretization = "node_to_segment"; // node_to_segment, node_to_node
  int passes = 1;                                 // 2: each surface is also slave of the other
  std::string method = "lagrange";                // lagrange (semi-smooth Newton), penalty
  Real penalty = 0;                               // 0: automatic, penalty_factor * E / h
  Real penalty_factor = 10;
  std::string search = "bucket_grid";             // bucket_grid, bvh, all_to_all
  Real max_distance = 0;                          // 0: automatic
  std::string update = "increment";               // increment, iteration
  int max_flips = 6;                              // status changes of a node in one increment before it is frozen
  std::string where;                              // deck location
};

}  // namespace signorini
