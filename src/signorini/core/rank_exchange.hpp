// Work shared out over the MPI ranks of a run whose ranks otherwise compute alike (every rank
// holds the whole mesh's nodes and contact surfaces, its own cells, and runs the same Newton
// iterations, docs/architecture.md): a rank computes its share of a loop, then every rank
// receives every rank's results, so that all of them go on with the same bytes. The contact
// evaluation of mortar's slave facets uses it (Discretization::set_rank_exchange); the mesh,
// which rank 0 alone reads, is broadcast to the others (GmshOptions::ranks). Implemented over
// MPI in solver/petsc_solver.cpp; one process has none (a null pointer), and code written
// against it runs its whole loop then.
#pragma once
#include <string>
#include <vector>

namespace signorini {

class RankExchange {
 public:
  virtual ~RankExchange() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Collective over all ranks: every rank's `mine`, in rank order (mine included), on every rank.
  virtual std::vector<std::string> allgather(const std::string& mine) const = 0;
  // Collective over all ranks: `bytes` of rank `root` on every rank (any size).
  virtual void broadcast(std::string& bytes, int root) const = 0;
};

}  // namespace signorini
