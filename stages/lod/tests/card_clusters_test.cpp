// Card clusters (card_clusters.h): the spread bound, the overlap ratio, the survivor's area, and
// the coarse levels' card counts of a generated tree with and without the clusters.
#include "stages/lod/card_clusters.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "stages/lod/chain.h"
#include "stages/lod/tests/test_trees.h"

namespace sylva::lod {
namespace {

using tree::Vec3;

tree::Leaf card(Vec3 at, Vec3 dir, Vec3 normal, float length = 0.4f, float width = 0.3f) {
  tree::Leaf l;
  l.position = tree::to_float(at);
  l.direction = tree::to_float(dir);
  l.normal = tree::to_float(normal);
  l.length = length;
  l.width = width;
  return l;
}

// Coincident cards overlap completely: rho = 1/2 and the survivor keeps the area of one card,
// not of two (Cook's plain area preservation would double it). Cards apart: rho = 1, the sum.
TEST(CardClusters, OverlapRatioKeepsTheUnionNotTheSum) {
  const LeafQuad a = leaf_quad(card({0, 1, 0}, {0, 1, 0}, {0, 0, 1}));
  const std::vector<LeafQuad> same = {a, a};
  const std::vector<std::uint32_t> both = {0, 1};
  EXPECT_NEAR(overlap_ratio(same, both), 0.5, 1e-12);
  const CardForest f = build_card_forest(same);
  ASSERT_EQ(f.forest.size(), 3u);
  const LeafQuad z = cluster_card(f, 2);
  EXPECT_NEAR(z.area, a.area, 1e-9);
  // Two cards side by side, 1 m apart: nothing overlaps from any direction.
  const std::vector<LeafQuad> apart = {a, leaf_quad(card({1, 1, 0}, {0, 1, 0}, {0, 0, 1}))};
  EXPECT_DOUBLE_EQ(overlap_ratio(apart, both), 1.0);
  const CardForest g = build_card_forest(apart);
  const LeafQuad y = cluster_card(g, 2);
  EXPECT_NEAR(y.area, 2 * a.area, 1e-9);
  // The survivor is moved to the centroid, keeps its normal and uvs.
  EXPECT_NEAR(length(y.center() - Vec3{0.5, 1.2, 0}), 0.0, 1e-6);
  EXPECT_EQ(y.normal, a.normal);
  EXPECT_EQ(y.uv, a.uv);
  // A half-overlapping pair (shifted by half a width across): the union is 3/4 of the sum seen
  // face-on; from the other directions less, so rho lies strictly between 1/2 and 1.
  const std::vector<LeafQuad> half = {a, leaf_quad(card({0.15, 1, 0}, {0, 1, 0}, {0, 0, 1}))};
  const double rho = overlap_ratio(half, both);
  EXPECT_GT(rho, 0.5);
  EXPECT_LT(rho, 1.0);
}

// The forest: 2n - 1 elements; every merged element's spread bounds the distance from its
// centroid to each of its cards' centres; errors are monotone; the cut at 0 keeps every card.
TEST(CardClusters, SpreadBoundsEveryMemberAndErrorsAreMonotone) {
  std::vector<LeafQuad> cards;
  for (int i = 0; i < 60; ++i) {
    const double x = 0.13 * (i % 10), y = 1 + 0.11 * (i / 10), z = 0.05 * (i % 3);
    cards.push_back(leaf_quad(card({x, y, z}, {0, 1, 0}, {0, 0, 1}, 0.1f + 0.01f * float(i % 4))));
  }
  const CardForest f = build_card_forest(cards, 1.0);
  ASSERT_EQ(f.forest.size(), 119u);
  EXPECT_EQ(f.forest.cut_by_error(0).size(), 60u);
  for (std::size_t id = 60; id < f.forest.size(); ++id) {
    std::vector<std::size_t> stack{id};
    while (!stack.empty()) {
      const std::size_t e = stack.back();
      stack.pop_back();
      if (e < 60) {
        EXPECT_LE(length(cards[e].center() - f.clusters[id].centroid), f.clusters[id].spread + 1e-12);
        continue;
      }
      stack.push_back(static_cast<std::size_t>(f.forest.left[e]));
      stack.push_back(static_cast<std::size_t>(f.forest.right[e]));
    }
    const std::int32_t p = f.forest.parent[id];
    if (p >= 0) {
      EXPECT_LE(f.forest.error[id], f.forest.error[static_cast<std::size_t>(p)]);
    }
    EXPECT_GE(f.forest.error[id], f.clusters[id].size);  // size weight 1
  }
  std::size_t prev = SIZE_MAX;
  for (double e : {0.0, 0.1, 0.2, 0.4, 1.0, 10.0}) {
    const std::size_t n = f.forest.cut_by_error(e).size();
    EXPECT_LE(n, prev);
    prev = n;
  }
  EXPECT_EQ(f.forest.cut_by_error(10.0).size(), 1u);
}

std::vector<std::size_t> card_counts(const tree::Tree& t, const ChainOptions& o) {
  std::vector<std::size_t> out;
  for (const Level& l : build_chain(t, o)) out.push_back(l.counts.leaves);
  return out;
}

// The adult birch of the preset with its twig cards (4,196 in the tests' generator settings): FSA alone keeps
// ~all of them at every level (a collapse costs at least the 0.2-0.4 m between card centres, above every
// epsilon); the clusters cut the coarsest level to a fraction, monotone over the levels, and the full detail
// keeps every card.
TEST(CardClusters, CoarseLevelsOfAnAdultBirchKeepAFractionOfTheCards) {
  const tree::Tree& t = test::species_tree(
      std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species/birch.yaml", "adult", true);
  ChainOptions o;
  o.card_cluster_px = 0.35;  // as the default recipe's birch
  const std::vector<std::size_t> with = card_counts(t, o);
  ChainOptions fsa = o;
  fsa.card_cluster_px = 0;
  const std::vector<std::size_t> without = card_counts(t, fsa);
  ASSERT_EQ(with.size(), 6u);
  for (std::size_t i = 0; i < with.size(); ++i)
    std::printf("level %zu: %zu (FSA only %zu)\n", i, with[i], without[i]);
  // Deterministic (seeded survivors, ties on ids): the exact counts.
  EXPECT_EQ(with, (std::vector<std::size_t>{4196, 4196, 4196, 4196, 4193, 3314}));
  EXPECT_EQ(without, (std::vector<std::size_t>{4196, 4196, 4196, 4196, 4195, 4126}));
  EXPECT_EQ(with.front(), t.leaves.size());
  for (std::size_t i = 1; i < with.size(); ++i) EXPECT_LE(with[i], with[i - 1]) << i;
  EXPECT_GT(double(without.back()), 0.9 * double(t.leaves.size()));
  EXPECT_LT(double(with.back()), 0.8 * double(t.leaves.size()));
  // The same chain with another seed draws other survivors, not other clusters.
  ChainOptions other = o;
  other.card_seed = 12345;
  EXPECT_EQ(card_counts(t, other), with);
  const Precomputed pre = precompute(t, o);
  EXPECT_EQ(build_full_detail(t, pre, o).counts.leaves, t.leaves.size());
}

}  // namespace
}  // namespace sylva::lod
