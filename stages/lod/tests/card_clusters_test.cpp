// Card clusters (card_clusters.h): the spread bound, the overlap ratio, the survivor's area, and
// the coarse levels' card counts of a generated tree with and without the clusters.
#include "stages/lod/card_clusters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "pipeline/rng.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"
#include "stages/lod/card_coverage.h"
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
  // Half-transparent masks over each other draw 1 - (1/2)^2 = 3/4 of the cell, against 1/2 + 1/2.
  const std::vector<double> halves = {0.5, 0.5};
  EXPECT_NEAR(overlap_ratio(same, both, halves), 0.75, 1e-12);
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

// Opacity weighting: of two cards apart, one opaque and one drawing a quarter of its quad, the
// cluster's survivor draws what both draw (alpha_s A_z = W_a + W_b), the centroid is weighted
// by drawn area, and the opaque card survives ~4/5 of the seeds (W_a / (W_a + W_b)).
TEST(CardClusters, SurvivorPreservesDrawnCoverageNotArea) {
  const LeafQuad a = leaf_quad(card({0, 1, 0}, {0, 1, 0}, {0, 0, 1}));
  const LeafQuad b = leaf_quad(card({1, 1, 0}, {0, 1, 0}, {0, 0, 1}));
  const std::vector<LeafQuad> cards = {a, b};
  const std::vector<double> alpha = {1.0, 0.25};
  int opaque = 0;
  const int seeds = 400;
  for (int seed = 0; seed < seeds; ++seed) {
    const CardForest f = build_card_forest(cards, alpha, static_cast<std::uint64_t>(seed) * 7919 + 1);
    ASSERT_EQ(f.forest.size(), 3u);
    EXPECT_NEAR(f.clusters[2].drawn, 1.25 * a.area, 1e-12);
    EXPECT_NEAR(length(f.clusters[2].centroid - Vec3{0.2, 1.2, 0}), 0.0,
                1e-6);  // (1 * 0 + 0.25 * 1) / 1.25, float positions
    double k = 0;
    const LeafQuad z = cluster_card(f, 2, &k);
    const double alpha_s = alpha[f.clusters[2].survivor];
    EXPECT_NEAR(alpha_s * z.area, 1.25 * a.area, 1e-9);
    EXPECT_NEAR(k, std::sqrt(1.25 / alpha_s), 1e-9);
    opaque += f.clusters[2].survivor == 0;
  }
  EXPECT_GT(opaque, 0.75 * seeds);
  EXPECT_LT(opaque, 0.85 * seeds);
  // Without opacities (every alpha 1) the area-preserving cluster: the sum of the areas.
  const CardForest g = build_card_forest(cards);
  EXPECT_NEAR(cluster_card(g, 2).area, 2 * a.area, 1e-9);
  EXPECT_THROW(build_card_forest(cards, {1.0}), std::invalid_argument);
  EXPECT_THROW(build_card_forest(cards, {1.0, 1.5}), std::invalid_argument);
}

// card_max_scale: a cluster whose survivor would grow beyond the cap is cut into its children.
// Four equal cards apart, in two pairs: the root's survivor grows by 2 (linear), a pair's by sqrt(2).
TEST(CardClusters, MaxScaleSplitsClustersThatGrowTooMuch) {
  std::vector<LeafQuad> cards;
  for (double x : {0.0, 1.5, 6.0, 7.5}) cards.push_back(leaf_quad(card({x, 1, 0}, {0, 1, 0}, {0, 0, 1})));
  const CardForest f = build_card_forest(cards);
  ASSERT_EQ(f.forest.size(), 7u);
  const double all = 100;  // the cut at a huge error: the root
  const ClusterCut free = cluster_cut(f, all);
  ASSERT_EQ(free.cards.size(), 1u);
  EXPECT_EQ(free.split, 0u);
  EXPECT_NEAR(free.cards[0].area, 4 * cards[0].area, 1e-9);
  const ClusterCut pairs = cluster_cut(f, all, 1.5);
  ASSERT_EQ(pairs.cards.size(), 2u);
  EXPECT_EQ(pairs.split, 1u);
  for (const LeafQuad& q : pairs.cards) EXPECT_NEAR(q.area, 2 * cards[0].area, 1e-9);
  const ClusterCut singles = cluster_cut(f, all, 1.2);
  ASSERT_EQ(singles.cards.size(), 4u);
  EXPECT_EQ(singles.split, 3u);
  EXPECT_EQ(cluster_cut(f, all, 2.001).cards.size(), 1u);  // the root's scale 2 is under the cap
  EXPECT_EQ(singles.opacity, (std::vector<double>{1, 1, 1, 1}));
}

// The forest: 2n - 1 elements; every merged element's spread bounds the distance from its
// centroid to each of its cards' centres; errors are monotone; the cut at 0 keeps every card.
TEST(CardClusters, SpreadBoundsEveryMemberAndErrorsAreMonotone) {
  std::vector<LeafQuad> cards;
  for (int i = 0; i < 60; ++i) {
    const double x = 0.13 * (i % 10), y = 1 + 0.11 * (i / 10), z = 0.05 * (i % 3);
    cards.push_back(leaf_quad(card({x, y, z}, {0, 1, 0}, {0, 0, 1}, 0.1f + 0.01f * float(i % 4))));
  }
  const CardForest f = build_card_forest(cards, {}, 1, 1.0);
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

// A crossed pair as the generator emits one place (foliage_placement.cpp): two cards on one
// base point, chord and size, rolled 90 degrees apart about the chord (vertical here).
std::vector<tree::Leaf> crossed_pair(Vec3 at, double roll, float length = 0.4f, float width = 0.3f) {
  const Vec3 n0{std::sin(roll), 0, std::cos(roll)};
  const Vec3 n1{std::cos(roll), 0, -std::sin(roll)};
  return {card(at, {0, 1, 0}, n0, length, width), card(at, {0, 1, 0}, n1, length, width)};
}

// card_places: cards with the same branch, base, direction, length and width form one place,
// whatever their order; a card that differs in any of them (by one float step) is another.
TEST(CardClusters, PlacesAreTheCardsOfOnePlacement) {
  std::vector<tree::Leaf> leaves;
  const std::vector<tree::Leaf> a = crossed_pair({0, 1, 0}, 0.0);
  const std::vector<tree::Leaf> b = crossed_pair({1, 1, 0}, 0.3);
  tree::Leaf longer = a[0];
  longer.length = std::nextafter(a[0].length, 1.0f);
  tree::Leaf other_branch = b[1];
  other_branch.branch = 3;
  tree::Leaf third = b[0];  // a third layer of b's place
  third.normal = tree::to_float(Vec3{0, 0, 1});
  third.variant = 2;
  leaves = {a[0], b[0], longer, a[1], other_branch, b[1], third};
  const std::vector<std::vector<std::uint32_t>> places = card_places(leaves);
  EXPECT_EQ(places, (std::vector<std::vector<std::uint32_t>>{{0, 3}, {1, 5, 6}, {2}, {4}}));
  EXPECT_TRUE(card_places({}).empty());
  // The forest checks that the places partition the cards.
  std::vector<LeafQuad> quads;
  for (const tree::Leaf& l : leaves) quads.push_back(leaf_quad(l));
  EXPECT_THROW(build_card_forest(quads, {}, 0, 1.0, {{0, 3}, {1, 5, 6}, {2}}), std::invalid_argument);
  EXPECT_THROW(build_card_forest(quads, {}, 0, 1.0, {{0, 3}, {1, 5, 6}, {2, 3}, {4}}), std::invalid_argument);
  EXPECT_THROW(build_card_forest(quads, {}, 0, 1.0, {{0, 3}, {1, 5, 6}, {2}, {4}, {}}),
               std::invalid_argument);
  EXPECT_THROW(build_card_forest(quads, {}, 0, 1.0, {{0, 3}, {1, 5, 6}, {2}, {4, 7}}), std::invalid_argument);
  const CardForest f = build_card_forest(quads, {}, 0, 1.0, places);
  EXPECT_EQ(f.forest.original, 4u);
  EXPECT_EQ(f.forest.size(), 7u);
  // Original elements draw their own cards unchanged: the cut at 0 is every card.
  EXPECT_EQ(cluster_cut(f, 0).cards.size(), 7u);
  EXPECT_THROW(cluster_card(f, 1), std::invalid_argument);  // a place of three cards
  EXPECT_EQ(cluster_card(f, 2).v, quads[2].v);
}

// Two crossed pairs 1 m apart in one orientation, the first opaque, the second drawing half of
// its cards. With places the forest has two elements and one merge; the survivor is the
// heavier (opaque) pair, two cards again, at the drawn-area-weighted centroid, each card scaled
// by k with k^2 = rho_z sum W / (rho_s W_s), so the two cards draw what the four drew: their
// drift against the four cards (card_coverage.h, four horizontal views) is within 2 %. Card by
// card (no places), the same four cards cluster into one flat card, which draws nothing edge-on.
TEST(CardClusters, CrossedPairsClusterAsOneUnitAndSurviveAsAPair) {
  std::vector<tree::Leaf> leaves = crossed_pair({0, 1, 0}, 0.0);
  for (const tree::Leaf& l : crossed_pair({1, 1, 0}, 0.0)) leaves.push_back(l);
  std::vector<LeafQuad> cards;
  for (const tree::Leaf& l : leaves) cards.push_back(leaf_quad(l));
  const std::vector<double> alpha = {1.0, 1.0, 0.5, 0.5};
  const std::vector<std::vector<std::uint32_t>> places = card_places(leaves);
  ASSERT_EQ(places, (std::vector<std::vector<std::uint32_t>>{{0, 1}, {2, 3}}));
  const CardForest f = build_card_forest(cards, alpha, 7, 1.0, places);
  ASSERT_EQ(f.forest.original, 2u);
  ASSERT_EQ(f.forest.size(), 3u);
  const double a = cards[0].area;  // 0.4 x 0.3
  EXPECT_NEAR(a, 0.12, 1e-6);
  EXPECT_NEAR(f.clusters[0].drawn, 2 * a, 1e-12);
  EXPECT_NEAR(f.clusters[1].drawn, a, 1e-12);
  EXPECT_NEAR(f.clusters[0].spread, 0.0, 1e-9);  // the pair's cards share their centre
  const CardCluster& z = f.clusters[2];
  EXPECT_NEAR(z.drawn, 3 * a, 1e-12);
  EXPECT_EQ(z.survivor, 0u);  // the heavier place
  EXPECT_NEAR(length(z.centroid - Vec3{1.0 / 3, 1.2, 0}), 0.0, 1e-6);
  std::vector<LeafQuad> out;
  std::vector<double> out_alpha;
  const double k = cluster_cards(f, 2, out, &out_alpha);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out_alpha, (std::vector<double>{1.0, 1.0}));
  const double rho_z = overlap_ratio(cards, std::vector<std::uint32_t>{0, 1, 2, 3}, alpha);
  const double rho_s = overlap_ratio(cards, std::vector<std::uint32_t>{0, 1}, alpha);
  EXPECT_LT(rho_s, 1.0);  // a crossed pair overlaps itself seen from most directions
  EXPECT_NEAR(k * k, rho_z * 3 * a / (rho_s * 2 * a), 1e-9);
  EXPECT_GT(k, 1.1);
  EXPECT_LT(k, 1.3);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(out[i].normal, cards[i].normal);  // the heavier pair's orientation
    EXPECT_EQ(out[i].uv, cards[i].uv);
    EXPECT_NEAR(length(out[i].center() - z.centroid), 0.0, 1e-6);  // still crossed on one centre
    EXPECT_NEAR(out[i].area, k * k * a, 1e-9);
  }
  // Drawn coverage kept: the survivor pair's drawn area with its own overlap, rho_s k^2 W_s,
  // is the cluster's, rho_z sum W (overlap_ratio does not change with scale or position).
  double drawn = 0;
  for (int i = 0; i < 2; ++i) drawn += out_alpha[i] * out[i].area;
  EXPECT_NEAR(overlap_ratio(out, std::vector<std::uint32_t>{0, 1}, out_alpha) * drawn, rho_z * 3 * a, 1e-6);
  const double pixel = 2.0;  // both pairs within a pixel: the linear regime of the pixel model
  EXPECT_LT(std::abs(coverage_drift(out, out_alpha, cards, alpha, pixel)), 0.02);
  // The cut and card_max_scale see the pair as one cluster of two cards.
  EXPECT_EQ(cluster_cut(f, 100).cards.size(), 2u);
  const ClusterCut capped = cluster_cut(f, 100, 1.1);
  EXPECT_EQ(capped.split, 1u);
  EXPECT_EQ(capped.cards.size(), 4u);
  // Card by card the same cards merge into one flat survivor: half the drawn coverage lost
  // seen edge-on to it, or more.
  const CardForest g = build_card_forest(cards, alpha, 7, 1.0);
  ASSERT_EQ(g.forest.size(), 7u);
  const ClusterCut flat = cluster_cut(g, 100);
  ASSERT_EQ(flat.cards.size(), 1u);
  EXPECT_LT(coverage_drift(flat.cards, flat.opacity, cards, alpha, pixel), -0.3);
}

std::vector<std::size_t> card_counts(const tree::Tree& t, const ChainOptions& o) {
  std::vector<std::size_t> out;
  for (const Level& l : build_chain(t, o)) out.push_back(l.counts.leaves);
  return out;
}

// The adult birch of the preset with its twig cards (4,700 in the tests' generator settings): FSA alone keeps
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
  EXPECT_EQ(with, (std::vector<std::size_t>{4700, 4700, 4700, 4700, 4661, 3318}));
  EXPECT_EQ(without, (std::vector<std::size_t>{4700, 4700, 4700, 4700, 4698, 4499}));
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

// A species tree as the generate stage makes it with cards (tests' node spacing, seed 1): the
// preset's card atlas (256 px) and the tree whose cards refer to its cells, with each cell's
// opacity measured on that atlas (as the lod stage measures it on leaves.png).
struct AtlasTree {
  tree::Tree tree;
  std::vector<double> opacity;
};

const AtlasTree& atlas_tree(const std::string& species) {
  static std::map<std::string, AtlasTree> cache;
  auto it = cache.find(species);
  if (it != cache.end()) return it->second;
  const generate::SpeciesPreset preset = generate::load_species_preset(
      std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species" / (species + ".yaml"));
  Rng leaf_rng(1, "leaves");
  const generate::CardAtlas atlas =
      generate::make_card_atlas(preset.card, preset.leaf, preset.bark, 256, leaf_rng);
  generate::GenerateOptions o;
  o.max_node_spacing = 0.5;
  o.foliage = generate::FoliageMode::kCards;
  o.atlas = {atlas.columns, atlas.rows, atlas.coverage};
  Rng rng(1, "tree");
  AtlasTree out;
  out.tree = generate::generate_tree(preset.age("adult").params, o, rng);
  out.opacity =
      measure_cell_opacity(atlas.image.pixels, atlas.image.width, atlas.image.height, out.tree.materials);
  return cache.emplace(species, std::move(out)).first->second;
}

// The adult Scots pine's shoot cards: the opacity-weighted clusters at kappa = 0.5 with the
// coverage check cut the coarsest level to a fraction of FSA's; the check measures what each
// cluster level draws against FSA's cut and rejects the ones that drift beyond its tolerance.
TEST(CardClusters, ScotsPineCoarseLevelsWithOpacityWeightsAndCoverageCheck) {
  const AtlasTree& at = atlas_tree("scots_pine");
  const tree::Tree& t = at.tree;
  ChainOptions o;
  o.card_opacity = at.opacity;
  o.card_cluster_px = 0.5;
  o.card_coverage_check = 0.05;
  ChainOptions fsa = o;
  fsa.card_cluster_px = 0;
  ChainOptions unchecked = o;
  unchecked.card_coverage_check = 0;
  const std::vector<Level> with = build_chain(t, o);
  const std::vector<std::size_t> without = card_counts(t, fsa);
  const std::vector<std::size_t> free = card_counts(t, unchecked);
  ASSERT_EQ(with.size(), 6u);
  // The same cuts with Cook's area-preserving clusters (every card weighs 1), their drift
  // measured with the cards' real opacities.
  std::vector<LeafQuad> cards;
  std::vector<double> alpha;
  for (const tree::Leaf& l : t.leaves) {
    cards.push_back(leaf_quad(l, t.materials));
    alpha.push_back(card_opacity(cards.back(), t.materials, at.opacity));
  }
  const CardForest by_area = build_card_forest(cards, {}, o.card_seed, o.card_cluster_px / o.card_size_px);
  const Precomputed pre = precompute(t, o);
  std::vector<double> area_drift;
  for (std::size_t i = 0; i < with.size(); ++i) {
    const LevelSpec& spec = with[i].spec;
    const double pixel = spec.epsilon / spec.delta;
    const ClusterCut cut = cluster_cut(by_area, o.card_cluster_px * pixel);
    std::vector<double> cut_alpha;
    for (const LeafQuad& q : cut.cards) cut_alpha.push_back(card_opacity(q, t.materials, at.opacity));
    std::vector<LeafQuad> fsa_cards;
    std::vector<double> fsa_alpha;
    for (std::uint32_t id : pre.leaf_forest.forest.cut_by_error(spec.e5)) {
      fsa_cards.push_back(pre.leaf_forest.quads[id]);
      fsa_alpha.push_back(card_opacity(fsa_cards.back(), t.materials, at.opacity));
    }
    area_drift.push_back(coverage_drift(cut.cards, cut_alpha, fsa_cards, fsa_alpha, pixel));
    std::printf(
        "level %zu: %zu (FSA %zu, unchecked %zu) clustered %d cut %zu split %zu drift %.4f rejected %d; "
        "area-weighted cut %zu drift %.4f\n",
        i, with[i].counts.leaves, without[i], free[i], int(with[i].cards.clustered), with[i].cards.cut,
        with[i].cards.split, with[i].cards.measured ? with[i].cards.drift : -9.0, int(with[i].cards.rejected),
        cut.cards.size(), area_drift.back());
  }
  std::printf("opacity per cell:");
  for (double a : at.opacity) std::printf(" %.4f", a);
  std::printf("\n");
  // The atlas's cells draw a quarter of their rectangles (needles and twig), not all of it.
  for (double a : at.opacity) {
    EXPECT_GT(a, 0.2);
    EXPECT_LT(a, 0.3);
  }
  // Deterministic: the exact counts. FSA keeps 96 % of the cards at level 5, the clusters 31 %.
  EXPECT_EQ(without, (std::vector<std::size_t>{16426, 16426, 16426, 16426, 16415, 15790}));
  const std::vector<std::size_t> counts = [&] {
    std::vector<std::size_t> c;
    for (const Level& l : with) c.push_back(l.counts.leaves);
    return c;
  }();
  EXPECT_EQ(counts, (std::vector<std::size_t>{16426, 16426, 16426, 16426, 16415, 5041}));
  EXPECT_EQ(free, counts);
  // Level 5 draws the clusters, and they draw what FSA's cut draws within 2 % (the check's 5 %
  // passes); Cook's area-preserving clusters of the same cut draw over 10 % less (the overlap
  // ratio of opaque quads removes coverage that quarter-opaque masks over each other keep), so
  // the check would reject them and the level would keep FSA's 15,790 cards.
  for (std::size_t i = 0; i < 5; ++i) EXPECT_FALSE(with[i].cards.clustered) << i;
  ASSERT_TRUE(with[5].cards.clustered);
  ASSERT_TRUE(with[5].cards.measured);
  EXPECT_LT(std::abs(with[5].cards.drift), 0.02);
  EXPECT_FALSE(with[5].cards.rejected);
  EXPECT_EQ(with[5].cards.split, 0u);
  EXPECT_LT(area_drift[5], -0.10);
  // A tolerance under the level's drift rejects it: FSA's cut, as without clusters.
  ChainOptions strict = o;
  strict.card_coverage_check = 0.005;
  const std::vector<Level> checked = build_chain(t, strict);
  EXPECT_TRUE(checked[5].cards.rejected);
  EXPECT_FALSE(checked[5].cards.clustered);
  EXPECT_EQ(checked[5].counts.leaves, without[5]);
  // card_max_scale splits the clusters whose survivor grows more than the cap: at 2 (linear),
  // 318 splits, each one card more, and the drift stays within 2 %.
  ChainOptions capped = o;
  capped.card_max_scale = 2.0;
  const std::vector<Level> c = build_chain(t, capped);
  EXPECT_EQ(c[5].cards.split, 318u);
  EXPECT_EQ(c[5].counts.leaves, 5359u);
  EXPECT_LT(std::abs(c[5].cards.drift), 0.02);
}

// The adult oak's twig cards are crossed places of three cards (configs/species/oak.yaml `card:`,
// layers fitted to the leaf area index). As the default recipe's lod_oak (kappa 1, sigma 2,
// tau 0.05): with card_places each place is one unit and every survivor is a place again; card
// by card a place's cards merge into one flat card (fewer cards, but none of them crossed).
TEST(CardClusters, OakCrossedPairsClusterAsPlaces) {
  const AtlasTree& at = atlas_tree("oak");
  const tree::Tree& t = at.tree;
  const std::vector<std::vector<std::uint32_t>> places = card_places(t.leaves);
  std::map<std::size_t, std::size_t> sizes;
  for (const auto& p : places) ++sizes[p.size()];
  std::printf("oak: %zu cards, %zu places:", t.leaves.size(), places.size());
  for (const auto& [n, c] : sizes) std::printf(" %zu x %zu", c, n);
  std::printf("\n");
  ChainOptions o;
  o.card_opacity = at.opacity;
  o.card_cluster_px = 1.0;
  o.card_size_px = 2;
  o.card_coverage_check = 0.05;
  o.card_places = true;
  ChainOptions cards = o;
  cards.card_places = false;
  ChainOptions fsa = o;
  fsa.card_cluster_px = 0;
  const std::vector<Level> with = build_chain(t, o);
  const std::vector<Level> by_card = build_chain(t, cards);
  const std::vector<std::size_t> without = card_counts(t, fsa);
  ASSERT_EQ(with.size(), 6u);
  std::vector<std::size_t> counts, card_by_card;
  for (std::size_t i = 0; i < with.size(); ++i) {
    counts.push_back(with[i].counts.leaves);
    card_by_card.push_back(by_card[i].counts.leaves);
    std::printf(
        "level %zu: places %zu (cut %zu, drift %.4f, rejected %d) | card by card %zu (cut %zu, drift %.4f, "
        "rejected %d) | FSA %zu\n",
        i, counts.back(), with[i].cards.cut, with[i].cards.measured ? with[i].cards.drift : -9.0,
        int(with[i].cards.rejected), card_by_card.back(), by_card[i].cards.cut,
        by_card[i].cards.measured ? by_card[i].cards.drift : -9.0, int(by_card[i].cards.rejected),
        without[i]);
  }
  // Every place is three crossed cards (the adult oak's LAI fit takes three layers).
  EXPECT_EQ(sizes, (std::map<std::size_t, std::size_t>{{3, 6798}}));
  EXPECT_EQ(without, (std::vector<std::size_t>{20394, 20394, 20394, 20393, 20387, 18458}));
  // At sigma = 2 px only level 5's cards are small enough to cluster; levels 0-4 keep FSA's cut.
  // Card by card a place's cards merge first (spread 0) into one flat card.
  EXPECT_EQ(card_by_card, (std::vector<std::size_t>{20394, 20394, 20394, 20393, 20387, 3472}));
  EXPECT_EQ(counts, (std::vector<std::size_t>{20394, 20394, 20394, 20393, 20387, 8595}));
  EXPECT_EQ(counts.front(), t.leaves.size());
  for (std::size_t i = 1; i < counts.size(); ++i) EXPECT_LE(counts[i], counts[i - 1]) << i;
  for (std::size_t i = 0; i < with.size(); ++i) {
    if (!with[i].cards.clustered) continue;
    EXPECT_LE(std::abs(with[i].cards.drift), 0.05) << i;
    EXPECT_EQ(with[i].counts.leaves % 3, 0u) << i;  // every survivor a place of three cards
  }
  ASSERT_TRUE(with[5].cards.clustered);
  EXPECT_LT(double(counts[5]), 0.75 * double(without[5]));
}

}  // namespace
}  // namespace sylva::lod
