// Deterministic parallel assembly. Items (cells, contact constraints) that write to a common
// slot (a node's DOFs) get different colours; the items of one colour run in parallel and
// never write the same entry, so each entry receives its contributions in one fixed order
// (colour by colour) whatever the number of threads or their timing, and no atomics are
// needed. A run is then reproducible bit for bit, which the atomic adds it replaces were not:
// their summation order varied from run to run and so did Newton's path at every kink.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "signorini/core/types.hpp"

namespace signorini {

struct Coloring {
  std::vector<Index> items;  // grouped by colour; ascending within a colour
  std::vector<Index> start;  // colour c holds items[start[c] .. start[c + 1])
  int colors() const { return static_cast<int>(start.size()) - 1; }
  Index begin(int c) const { return start[c]; }
  Index end(int c) const { return start[c + 1]; }
};

// Greedy colouring in item order: each item takes the lowest colour that no earlier item
// sharing a slot has. `slots_of(i, out)` fills the slots item i writes to (entries < 0 and
// >= num_slots are ignored). Colours come in palettes of 64 (one bit each per slot), a new
// palette only when an item's slots have used all 64 of the previous ones.
template <class SlotsOf>
Coloring color_items(Index n, Index num_slots, SlotsOf&& slots_of) {
  std::vector<std::vector<std::uint64_t>> palettes;
  std::vector<int> color(n, 0);
  std::vector<Index> slots;
  int ncolors = 0;
  for (Index i = 0; i < n; ++i) {
    slots.clear();
    slots_of(i, slots);
    for (size_t p = 0;; ++p) {
      if (p == palettes.size()) palettes.emplace_back(static_cast<size_t>(num_slots), 0);
      std::vector<std::uint64_t>& mask = palettes[p];
      std::uint64_t used = 0;
      for (Index s : slots)
        if (s >= 0 && s < num_slots) used |= mask[s];
      if (used == ~std::uint64_t{0}) continue;
      const int bit = std::countr_one(used);
      for (Index s : slots)
        if (s >= 0 && s < num_slots) mask[s] |= std::uint64_t{1} << bit;
      color[i] = static_cast<int>(64 * p) + bit;
      break;
    }
    ncolors = std::max(ncolors, color[i] + 1);
  }
  Coloring c;
  c.start.assign(ncolors + 1, 0);
  for (Index i = 0; i < n; ++i) ++c.start[color[i] + 1];
  for (int k = 0; k < ncolors; ++k) c.start[k + 1] += c.start[k];
  c.items.resize(n);
  std::vector<Index> next(c.start.begin(), c.start.end() - 1);
  for (Index i = 0; i < n; ++i) c.items[next[color[i]]++] = i;
  return c;
}

}  // namespace signorini
