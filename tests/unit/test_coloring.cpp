// The colouring behind the deterministic assembly (fem/coloring.hpp): every item in exactly one
// colour, no two items of a colour sharing a slot, items ascending within a colour.
#include <gtest/gtest.h>

#include <functional>
#include <set>

#include "signorini/fem/coloring.hpp"
#include "signorini/mesh/structured.hpp"

using namespace signorini;

TEST(Coloring, ItemsOfAColourShareNoSlot) {
  // The cells of a structured hex8 box (each node in up to 8 cells), and a star: 70 items that
  // all share slot 0 (more than one palette of 64 colours) plus a slot of their own.
  const Mesh mesh = structured_box(ElementType::hex8, 6, 5, 4, 1, 1, 1);
  const ElementBlock& b = mesh.regions.begin()->second.front();
  const int npe = b.nodes_per_element();
  auto cells = [&](Index e, std::vector<Index>& s) {
    for (int a = 0; a < npe; ++a) s.push_back(b.element(e)[a]);
  };
  auto star = [](Index i, std::vector<Index>& s) { s = {0, i + 1, -1}; };
  struct Case {
    Index n, slots;
    std::function<void(Index, std::vector<Index>&)> f;
  };
  for (const Case& c : {Case{b.size(), mesh.num_nodes(), cells}, Case{70, 71, star}}) {
    const Coloring col = color_items(c.n, c.slots, c.f);
    ASSERT_EQ(static_cast<Index>(col.items.size()), c.n);
    std::vector<int> seen(c.n, 0);
    for (int k = 0; k < col.colors(); ++k) {
      std::set<Index> used;
      for (Index i = col.begin(k); i < col.end(k); ++i) {
        const Index item = col.items[i];
        ++seen[item];
        if (i > col.begin(k)) {
          EXPECT_LT(col.items[i - 1], item);
        }
        std::vector<Index> s;
        c.f(item, s);
        for (Index slot : s)
          if (slot >= 0) {
            EXPECT_TRUE(used.insert(slot).second) << "colour " << k << " slot " << slot;
          }
      }
    }
    for (Index i = 0; i < c.n; ++i) EXPECT_EQ(seen[i], 1);
    if (c.n == 70) {
      EXPECT_EQ(col.colors(), 70);
    } else {
      EXPECT_LE(col.colors(), 27);
    }  // a hex8 cell touches at most 26 others
  }
}
