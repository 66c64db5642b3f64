#include "libs/tree/foliage.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libs/tree/tests/sample_tree.h"

namespace sylva::tree {
namespace {

// The 2x2 default: variant i in column i % 2, row i / 2 (row 0 at the top).
TEST(Foliage, AtlasCellDefaultGrid) {
  const Materials m;
  EXPECT_EQ(atlas_cell(m, 0), (UvRect{0, 0, 0.5f, 0.5f}));
  EXPECT_EQ(atlas_cell(m, 1), (UvRect{0.5f, 0, 1, 0.5f}));
  EXPECT_EQ(atlas_cell(m, 2), (UvRect{0, 0.5f, 0.5f, 1}));
  EXPECT_EQ(atlas_cell(m, 3), (UvRect{0.5f, 0.5f, 1, 1}));
}

// A 4x2 card atlas: eight cells, the last column and row end exactly at 1.
TEST(Foliage, AtlasCellCardGrid) {
  Materials m;
  m.atlas_columns = 4;
  m.atlas_rows = 2;
  EXPECT_EQ(atlas_cell(m, 5), (UvRect{0.25f, 0.5f, 0.5f, 1}));
  EXPECT_EQ(atlas_cell(m, 3), (UvRect{0.75f, 0, 1, 0.5f}));
  EXPECT_EQ(atlas_cell(m, 7), (UvRect{0.75f, 0.5f, 1, 1}));
}

TEST(Foliage, LeafAreaUsesCellCoverage) {
  Materials m;
  Leaf l;
  l.length = 0.4f;
  l.width = 0.25f;
  l.variant = 2;
  EXPECT_NEAR(leaf_area(m, l), 0.1, 1e-7);  // no coverage given: the whole quad
  m.cell_coverage = {0.1f, 0.2f, 0.5f, 0.7f};
  EXPECT_NEAR(leaf_area(m, l), 0.05, 1e-7);
  Needle n;
  n.base = {0, 0, 0};
  n.tip = {0, 0.05f, 0};
  n.radius = 0.001f;
  EXPECT_NEAR(needle_area(n), 1e-4, 1e-9);
}

// Unit square with interior and duplicate points; a triangle; collinear points have no area.
TEST(Foliage, ConvexHullArea) {
  EXPECT_DOUBLE_EQ(convex_hull_area({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.2, 0.9}, {1, 1}}), 1.0);
  EXPECT_DOUBLE_EQ(convex_hull_area({{0, 0}, {4, 0}, {0, 3}}), 6.0);
  EXPECT_DOUBLE_EQ(convex_hull_area({{0, 0}, {1, 1}, {2, 2}, {3, 3}}), 0.0);
  EXPECT_DOUBLE_EQ(convex_hull_area({{0, 0}, {1, 0}}), 0.0);
}

// Many points (the octagon filter runs): a regular 1000-gon plus 20,000 interior points has the
// polygon's area, 0.5 n sin(2 pi / n).
TEST(Foliage, ConvexHullAreaOfManyPoints) {
  std::vector<std::pair<double, double>> p;
  const int n = 1000;
  for (int i = 0; i < n; ++i) p.emplace_back(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n));
  std::uint32_t s = 7;
  for (int i = 0; i < 20000; ++i) {
    s = s * 1664525u + 1013904223u;
    const double r = 0.99 * (s >> 8) / 16777216.0;
    s = s * 1664525u + 1013904223u;
    const double a = 2 * M_PI * (s >> 8) / 16777216.0;
    p.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  EXPECT_NEAR(convex_hull_area(p), 0.5 * n * std::sin(2 * M_PI / n), 1e-9);
}

// Four horizontal 1 m x 1 m cards at the corners of a 3 m square, coverage 0.5: leaf area 2 m^2
// over a crown (hull of the card corners) of 4 x 4 m: LAI 0.125.
TEST(Foliage, CrownLeafAreaIndex) {
  Tree t = testing::sample_tree();
  t.needles.clear();
  t.materials.cell_coverage = {0.5f, 0.5f, 0.5f, 0.5f};
  t.leaves.clear();
  for (float x : {-1.5f, 1.5f})
    for (float z : {-1.5f, 1.5f}) {
      Leaf l;
      l.branch = 1;
      l.position = {x, 2.0f, z - 0.5f};
      l.direction = {0, 0, 1};
      l.normal = {0, 1, 0};
      l.length = 1;
      l.width = 1;
      t.leaves.push_back(l);
    }
  const CrownFoliage c = crown_foliage(t);
  EXPECT_NEAR(c.leaf_area, 2.0, 1e-9);
  EXPECT_NEAR(c.crown_area, 16.0, 1e-6);
  EXPECT_NEAR(c.lai(), 0.125, 1e-7);
}

// Cards draw the childless branches that carry them from their base; a twig in leaf only at its
// tip and a branch with children stay bark; a tree of single leaves draws nothing with its leaves.
TEST(Foliage, TwigsDrawnByCards) {
  Tree t = testing::sample_tree();
  EXPECT_TRUE(twigs_drawn_by_cards(t).empty());
  t.materials.leaf_kind = LeafKind::kTwigCards;
  t.leaves[0].position = {0.3f, 2.0f, 0};  // 5 cm from the lateral's first node
  EXPECT_EQ(twigs_drawn_by_cards(t), (std::vector<char>{0, 1}));
  t.leaves[0].position = {0.9f, 2.0f, 0};  // 0.65 m from the lateral's base, a 0.1 m card
  EXPECT_EQ(twigs_drawn_by_cards(t), (std::vector<char>{0, 0}));
  t.leaves[0].length = 0.7f;  // now it reaches the base
  EXPECT_EQ(twigs_drawn_by_cards(t), (std::vector<char>{0, 1}));
  t.leaves[0].branch = 0;  // a card on the trunk, which has a child
  EXPECT_EQ(twigs_drawn_by_cards(t), (std::vector<char>{0, 0}));
}

}  // namespace
}  // namespace sylva::tree
