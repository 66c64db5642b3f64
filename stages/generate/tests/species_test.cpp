// Every species preset under configs/species/ generates, for every age, a valid tree whose
// height lies in the range the preset states (several seeds, so ScaleV is exercised).
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "libs/tree/stats.h"
#include "stages/generate/tests/species_trees.h"

namespace sylva::generate {
namespace {

using test::generate_with_cards;
using test::preset_files;

// The library holds at least the eight species the issue names, each with three ages.
TEST(Species, LibraryIsComplete) {
  std::set<std::string> names;
  for (const auto& f : preset_files()) {
    const SpeciesPreset s = load_species_preset(f);
    EXPECT_EQ(s.species, f.stem().string()) << f;
    EXPECT_EQ(s.ages.size(), 3u);
    EXPECT_FALSE(s.sources.empty()) << f;
    for (const auto& a : s.ages) EXPECT_FALSE(a.source.empty()) << f << " " << a.age;
    names.insert(s.species);
  }
  for (const char* n : {"oak", "birch", "white_poplar", "holly", "scots_pine", "norway_spruce",
                        "weeping_willow", "mugo_pine"})
    EXPECT_TRUE(names.count(n)) << n;
}

// Every preset and age, three seeds: the height in the preset's range; the crown's leaf area
// index (one-sided leaf area / crown projected area) in the preset's published range, within
// 10 % of the age's target; cards of the species' kind, the card scale inside its clamp.
TEST(Species, EveryPresetAndAgeWithinItsHeightAndLeafAreaRange) {
  for (const auto& f : preset_files()) {
    const SpeciesPreset s = load_species_preset(f);
    ASSERT_FALSE(s.lai_source.empty()) << f;
    for (const AgeVariant& a : s.ages) {
      ASSERT_GT(a.params.leaf_area_index, 0) << s.species << "/" << a.age;
      for (std::uint64_t seed : {1, 2, 3}) {
        FoliageResult fit;
        const tree::Tree t = generate_with_cards(s, a, seed, &fit);
        const std::string what = s.species + "/" + a.age + " seed " + std::to_string(seed);
        ASSERT_TRUE(tree::validate_tree(t).empty()) << f;
        const tree::TreeStats st = tree::compute_stats(t);
        EXPECT_GE(st.height, a.height_min) << what;
        EXPECT_LE(st.height, a.height_max) << what;
        EXPECT_GE(st.lai, s.lai_min) << what;
        EXPECT_LE(st.lai, s.lai_max) << what;
        EXPECT_NEAR(st.lai, a.params.leaf_area_index, 0.1 * a.params.leaf_area_index) << what;
        EXPECT_GE(fit.card_scale, kMinCardScale) << what;
        EXPECT_LT(fit.card_scale, kMaxCardScale) << what << ": the cards cannot carry the target";
        EXPECT_GT(fit.density, 0.1) << what << ": too few cards for the crown";
        EXPECT_GT(st.leaves, 0u);
        EXPECT_EQ(st.needles, 0u);
        EXPECT_EQ(t.materials.leaf_kind, a.params.foliage == Foliage::kLeaves ? tree::LeafKind::kTwigCards
                                                                              : tree::LeafKind::kShootCards);
      }
    }
  }
}

// No branch below the ground, over many seeds of every adult and young preset: every node of a
// branch that grows from another (laterals and split clones) keeps its radius and the square
// bark section (1.42 r) above y = 0, the trunk's axis never goes below it, and no foliage quad
// dips below it.
TEST(Species, NothingBelowTheGround) {
  for (const auto& f : preset_files()) {
    const SpeciesPreset s = load_species_preset(f);
    for (const char* age : {"young", "adult"}) {
      for (std::uint64_t seed = 1; seed <= 12; ++seed) {
        const tree::Tree t = generate_with_cards(s, s.age(age), seed);
        const std::string what = s.species + "/" + age + " seed " + std::to_string(seed);
        double lowest = 1e9;
        for (const tree::Branch& b : t.branches)
          for (const tree::Node& n : b.nodes)
            lowest = std::min(lowest, n.position.y - (b.parent >= 0 ? 1.42 * n.radius : 0));
        EXPECT_GE(lowest, 0.0) << what;
        double foliage = 1e9;
        for (const tree::Leaf& l : t.leaves) {
          const tree::Vec3 p = tree::to_double(l.position), d = tree::to_double(l.direction);
          const tree::Vec3 side = tree::cross(tree::to_double(l.normal), d) * (0.5 * l.width);
          for (const tree::Vec3 q :
               {p - side, p + side, p + d * double(l.length) + side, p + d * double(l.length) - side})
            foliage = std::min(foliage, q.y);
        }
        EXPECT_GE(foliage, 0.0) << what;
      }
    }
  }
}

// The mugo pine is the shrub of the library (issue 9): 1-2.5 m when adult, many stems rising
// from the base (at least 8 branches growing from the trunk's stump within 25 cm of the ground,
// each at least 0.4 of the shrub's height long), and wider than tall; for every age and seeds 1-3.
TEST(Species, MugoPineIsAMultiStemmedShrub) {
  const SpeciesPreset s = load_species_preset("configs/species/mugo_pine.yaml");
  const AgeVariant& adult = s.age("adult");
  EXPECT_GE(adult.height_min, 1.0);
  EXPECT_LE(adult.height_max, 2.5);
  for (const AgeVariant& a : s.ages) {
    for (std::uint64_t seed : {1, 2, 3}) {
      const tree::Tree t = generate_with_cards(s, a, seed);
      const tree::TreeStats st = tree::compute_stats(t);
      const std::string what = a.age + " seed " + std::to_string(seed);
      int stems = 0;
      for (const tree::Branch& b : t.branches) {
        if (b.parent != 0 || b.level != 1) continue;
        double len = 0;
        for (std::size_t k = 1; k < b.nodes.size(); ++k)
          len += tree::length(b.nodes[k].position - b.nodes[k - 1].position);
        if (b.nodes.front().position.y <= 0.25 && len >= 0.4 * st.height) ++stems;
      }
      EXPECT_GE(stems, a.age == "young" ? 5 : 8) << what;
      const double width = std::min(st.bounds_max.x - st.bounds_min.x, st.bounds_max.z - st.bounds_min.z);
      EXPECT_GT(width, st.height) << what;
    }
  }
}

}  // namespace
}  // namespace sylva::generate
