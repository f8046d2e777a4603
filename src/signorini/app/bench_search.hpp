// `signorini bench search`: times every contact search method on two curved, non-matching
// 3D surfaces and checks them against all-to-all on a subset of the slave nodes.
#pragma once
#include <string>

#include "signorini/core/types.hpp"

namespace signorini {

struct BenchSearchOptions {
  Index slave_nodes = 1000000;
  Index master_facets = 1000000;
  Real gap = 1e-3;  // of the generated slave sheet above the master
  bool quads = false;  // generated master facets: quadrilaterals instead of triangles
  std::string method;      // empty: every fast method
  Index check_subset = 2000;
  int repeats = 2;         // the second build+query models re-detection in a later increment
  std::string slave_file;  // Gmsh .msh: its nodes are the slave nodes (instead of generated ones)
  std::string master_file; // Gmsh .msh: its triangles and quadrilaterals are the master facets
  std::string write_dir;   // write the surfaces searched as slave.msh and master.msh there
};

// Returns 0 when every method agrees with all-to-all on the subset, 1 otherwise.
int bench_search(const BenchSearchOptions& options);

}  // namespace signorini
