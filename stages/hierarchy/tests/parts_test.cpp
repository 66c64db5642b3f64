// Algorithm 1 (parts by shared vertices) with and without welding, and its input checks.
#include "stages/hierarchy/parts.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "stages/hierarchy/hierarchy_error.h"
#include "stages/hierarchy/tests/test_meshes.h"

namespace sylva::hierarchy {
namespace {

using testing::add_quad;

// Two quads that share an edge by position only (no shared index): one part when welded.
tree::SourceGeometry two_quads() {
  tree::SourceGeometry g;
  g.primitives.resize(1);
  g.primitives[0].name = "quads";
  add_quad(g.primitives[0], {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, 1, 1);
  add_quad(g.primitives[0], {0, 1, 0}, {0, 1, 0}, {1, 0, 0}, 1, 1);
  g.materials.resize(1);
  return g;
}

TEST(Parts, NamedTreeOnePartPerTubeAndLeaf) {
  const auto parts = split_parts(testing::named_tree(), 1e-5);
  ASSERT_EQ(parts.size(), 5u);  // trunk, a, b, two leaf quads
  EXPECT_EQ(parts[0].primitive, 0u);
  EXPECT_EQ(parts[0].points.size(), 17u * 12);
  EXPECT_EQ(parts[0].triangles.size(), 16u * 12 * 2);
  EXPECT_EQ(parts[3].primitive, 3u);
  EXPECT_EQ(parts[4].primitive, 3u);
  EXPECT_EQ(parts[4].points.size(), 4u);
  EXPECT_EQ(parts[4].min_v, (std::vector<float>{0, 0, 1, 1}));
  // An end-ring vertex is on 3 triangles (24 of them), every other one on 6.
  EXPECT_EQ(std::count(parts[0].face_count.begin(), parts[0].face_count.end(), 3u), 24);
  EXPECT_EQ(std::count(parts[0].face_count.begin(), parts[0].face_count.end(), 6u), 15 * 12);
  EXPECT_DOUBLE_EQ(parts[0].box_min.y, 0.0);
  EXPECT_NEAR(parts[0].box_max.y, 4.0, 1e-6);
}

// ez-tree's layout: every branch in one primitive, split by connectivity.
TEST(Parts, MergedPrimitiveSplitsByConnectivity) {
  const auto parts = split_parts(testing::nameless_tree(), 1e-5);
  ASSERT_EQ(parts.size(), 5u);
  EXPECT_EQ(parts[0].points.size(), 17u * 12);
  EXPECT_EQ(parts[1].points.size(), 16u * 12);
  EXPECT_EQ(parts[2].points.size(), 13u * 12);
  EXPECT_EQ(parts[2].primitive, 0u);
}

TEST(Parts, WeldJoinsCoincidentVertices) {
  EXPECT_EQ(split_parts(two_quads(), 0).size(), 2u);     // Celba's rule: shared indices only
  EXPECT_EQ(split_parts(two_quads(), 1e-5).size(), 1u);  // welded
  EXPECT_EQ(split_parts(two_quads(), 1e-5)[0].points.size(), 6u);
  // Vertices 1 mm apart join only with a tolerance above 1 mm.
  tree::SourceGeometry g = two_quads();
  for (std::size_t i = 4; i < 8; ++i) g.primitives[0].positions[i].y += 0.001f;
  EXPECT_EQ(split_parts(g, 1e-4).size(), 2u);
  EXPECT_EQ(split_parts(g, 2e-3).size(), 1u);
}

TEST(Parts, DegenerateTrianglesDropped) {
  tree::SourceGeometry g = two_quads();
  g.primitives[0].indices.insert(g.primitives[0].indices.end(), {0, 0, 1});
  const auto parts = split_parts(g, 0);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].triangles.size() + parts[1].triangles.size(), 4u);
}

TEST(Parts, BadIndicesNamed) {
  tree::SourceGeometry g = two_quads();
  g.primitives[0].indices[4] = 9;
  try {
    split_parts(g, 0);
    FAIL();
  } catch (const HierarchyError& e) {
    EXPECT_STREQ(e.what(), "source primitive 0 (\"quads\"): index 9 at triangle 1 is not below 8 positions");
  }
  g.primitives[0].indices.pop_back();
  try {
    split_parts(g, 0);
    FAIL();
  } catch (const HierarchyError& e) {
    EXPECT_STREQ(e.what(), "source primitive 0 (\"quads\"): 11 indices is not a multiple of 3");
  }
}

}  // namespace
}  // namespace sylva::hierarchy
