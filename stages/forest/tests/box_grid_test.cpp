// The grid of placed boxes (box_grid.h): every query finds exactly the stored boxes whose ground
// footprint meets the query's, as a scan of all boxes does, whatever the cell size, with cells
// holding many chained blocks, blocks over several 2 MiB chunks, and boxes beyond the square.
#include "stages/forest/box_grid.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "pipeline/rng.h"

namespace sylva::forest {
namespace {

Box3 random_box(Rng& rng, double lo, double hi, double max_w) {
  const double x = rng.uniform(lo, hi), z = rng.uniform(lo, hi);
  const double wx = rng.uniform(0.1, max_w), wz = rng.uniform(0.1, max_w);
  return {{x - 0.5 * wx, 0, z - 0.5 * wz}, {x + 0.5 * wx, rng.uniform(1, 20), z + 0.5 * wz}};
}

bool meets(const Box3& a, const Box3& b) {
  return !(b.max[0] < a.min[0] || b.min[0] > a.max[0] || b.max[2] < a.min[2] || b.min[2] > a.max[2]);
}

std::size_t key(const Box3& b, const std::vector<Box3>& all) {
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all[i] == b) return i;
  return all.size();
}

TEST(BoxGrid, FindsExactlyTheBoxesWhoseFootprintsMeet) {
  for (const double cell : {0.5, 4.0, 30.0}) {
    Rng rng(3, "box_grid");
    BoxGrid g(-50, -50, 100, cell);
    std::vector<Box3> all;
    // Centres also beyond the square (clamped into the edge cells), 8000 boxes: with 0.5 m cells
    // one block each, more than a 2 MiB chunk holds; with 30 m cells tens of blocks per cell.
    for (int i = 0; i < 8000; ++i) {
      all.push_back(random_box(rng, -60, 60, 8));
      g.insert(all.back());
    }
    EXPECT_EQ(g.size(), all.size());
    for (int q = 0; q < 300; ++q) {
      const Box3 a = random_box(rng, -65, 65, 12);
      std::set<std::size_t> want, got;
      for (std::size_t i = 0; i < all.size(); ++i)
        if (meets(a, all[i])) want.insert(i);
      std::size_t calls = 0;
      g.for_each_overlapping(a, [&](const Box3& b) {
        ++calls;
        got.insert(key(b, all));
        return true;
      });
      EXPECT_EQ(got, want) << "cell " << cell << " query " << q;
      EXPECT_EQ(calls, want.size());
    }
    // Stops at the first box for which f returns false.
    std::size_t calls = 0;
    g.for_each_overlapping({{-60, 0, -60}, {60, 1, 60}}, [&](const Box3&) { return ++calls < 5; });
    EXPECT_EQ(calls, 5u);
  }
}

}  // namespace
}  // namespace sylva::forest
