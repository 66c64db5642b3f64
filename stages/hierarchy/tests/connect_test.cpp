// Algorithm 2: connections by names (level by level), by derived levels, the leaf rule with the
// thesis's slip fixed, and what stays unconnected.
#include "stages/hierarchy/connect.h"

#include <gtest/gtest.h>

namespace sylva::hierarchy {
namespace {

using tree::Vec3;

// A part that is just its points (a segment's end points and midpoint) with their box.
Part segment(Vec3 a, Vec3 b) {
  Part p;
  p.points = {a, (a + b) * 0.5, b};
  p.box_min = {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
  p.box_max = {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
  return p;
}

// trunk (0..4 on y), a (level 1, from y 2 to +x), b (level 1, from y 3 to -x), c (level 2 on a).
struct Fixture {
  std::vector<Part> parts{segment({0, 0, 0}, {0, 4, 0}), segment({0, 2, 0}, {1, 2.5, 0}),
                          segment({0, 3, 0}, {-1, 3.5, 0}), segment({0.6, 2.3, 0}, {0.8, 2.9, 0.1})};
  std::vector<BranchNode> nodes(bool named) const {
    const std::int32_t l[4] = {0, 1, 1, 2};
    std::vector<BranchNode> n;
    for (std::size_t i = 0; i < parts.size(); ++i)
      n.push_back({&parts[i], parts[i].points[0], named ? l[i] : -1});
    return n;
  }
};

TEST(Connect, ByNames) {
  Fixture f;
  const Hierarchy h = connect_parts(f.nodes(true), {}, 0.01);
  EXPECT_TRUE(h.levels_from_names);
  EXPECT_EQ(h.parent, (std::vector<std::int32_t>{-1, 0, 0, 1}));
  EXPECT_EQ(h.level, (std::vector<std::int32_t>{0, 1, 1, 2}));
}

TEST(Connect, DerivedLevelsMatchNames) {
  Fixture f;
  const Hierarchy h = connect_parts(f.nodes(false), {}, 0.01);
  EXPECT_FALSE(h.levels_from_names);
  EXPECT_EQ(h.parent, (std::vector<std::int32_t>{-1, 0, 0, 1}));
  EXPECT_EQ(h.level, (std::vector<std::int32_t>{0, 1, 1, 2}));
}

// A branch whose point is in no grown box stays out (-2), and so does its child.
TEST(Connect, UnconnectedBranch) {
  Fixture f;
  f.parts[1] = segment({0.5, 2, 0}, {1, 2.5, 0});  // a floats 0.5 m from the trunk
  f.parts[3] = segment({0.8, 2.3, 0}, {0.9, 2.9, 0});
  auto nodes = f.nodes(true);
  const Hierarchy h = connect_parts(nodes, {}, 0.01);
  EXPECT_EQ(h.parent, (std::vector<std::int32_t>{-1, -2, 0, -2}));
  EXPECT_EQ(h.level, (std::vector<std::int32_t>{0, -1, 1, -1}));
  // Grown by 0.6 m, the trunk's box holds it.
  EXPECT_EQ(connect_parts(nodes, {}, 0.6).parent, (std::vector<std::int32_t>{-1, 0, 0, 1}));
}

// The leaf's first candidate (a, index 1) holds its point in a grown box but is not the nearest;
// the nearest (b, index 2) wins because the connect follows the loop over all candidates.
TEST(Connect, LeafConnectsToNearestCandidateNotFirst) {
  std::vector<Part> parts{segment({0, 0, 0}, {0, 4, 0}), segment({0, 2, 0}, {1, 3, 0}),
                          segment({0, 2.9, 0}, {1, 3.1, 0})};
  std::vector<BranchNode> nodes;
  for (std::size_t i = 0; i < parts.size(); ++i)
    nodes.push_back({&parts[i], parts[i].points[0], i == 0 ? 0 : 1});
  // In both boxes: 0.48 from a's nearest vertex, 0.02 from b's. The second leaf is in a's box
  // alone, the third in none.
  const Hierarchy h = connect_parts(nodes, {{0.5, 2.98, 0}, {0.5, 2.45, 0}, {5, 5, 5}}, 0.01);
  EXPECT_EQ(h.leaf_branch, (std::vector<std::int32_t>{2, 1, -1}));
  EXPECT_EQ(h.leaves_below_top, 0u);
  // Only the trunk's box holds this leaf: it falls back to the trunk, and is counted.
  EXPECT_EQ(connect_parts(nodes, {{0, 1, 0}}, 0.01).leaf_branch, (std::vector<std::int32_t>{0}));
  EXPECT_EQ(connect_parts(nodes, {{0, 1, 0}}, 0.01).leaves_below_top, 1u);
}

TEST(Connect, NearestVertexAndGrownBox) {
  const Part p = segment({0, 0, 0}, {0, 2, 0});
  EXPECT_DOUBLE_EQ(nearest_vertex_distance(p, {0.3, 1.4, 0}), std::hypot(0.3, 0.4));
  EXPECT_TRUE(in_grown_box(p, {0.1, 1, 0}, 0.1));
  EXPECT_FALSE(in_grown_box(p, {0.11, 1, 0}, 0.1));
}

}  // namespace
}  // namespace sylva::hierarchy
