// Every species preset under configs/species/ generates, for every age, a valid tree whose
// height lies in the range the preset states (several seeds, so ScaleV is exercised).
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "libs/tree/stats.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"

namespace sylva::generate {
namespace {

std::vector<std::filesystem::path> preset_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator("configs/species"))
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

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
  for (const char* n : {"oak", "birch", "white_poplar", "holly", "scots_pine", "norway_spruce", "weeping_willow",
                        "mugo_pine"})
    EXPECT_TRUE(names.count(n)) << n;
}

TEST(Species, EveryPresetAndAgeWithinItsHeightRange) {
  for (const auto& f : preset_files()) {
    const SpeciesPreset s = load_species_preset(f);
    for (const AgeVariant& a : s.ages) {
      for (std::uint64_t seed : {1, 2, 3}) {
        GenerateOptions o;
        o.max_node_spacing = 0.5;  // the stage's default
        Rng rng(seed, "tree");
        const tree::Tree t = generate_tree(a.params, o, rng);
        ASSERT_TRUE(tree::validate_tree(t).empty()) << f;
        const tree::TreeStats st = tree::compute_stats(t);
        EXPECT_GE(st.height, a.height_min) << s.species << "/" << a.age << " seed " << seed;
        EXPECT_LE(st.height, a.height_max) << s.species << "/" << a.age << " seed " << seed;
        if (a.params.foliage == Foliage::kLeaves) {
          EXPECT_GT(st.leaves, 0u);
          EXPECT_EQ(st.needles, 0u);
        } else {
          EXPECT_GT(st.needles, 0u);
          EXPECT_EQ(st.leaves, 0u);
        }
      }
    }
  }
}

// The mugo pine is the shrub of the library: 1-2.5 m when adult, several stems from the base.
TEST(Species, MugoPineIsAShrub) {
  const SpeciesPreset s = load_species_preset("configs/species/mugo_pine.yaml");
  const AgeVariant& a = s.age("adult");
  EXPECT_GE(a.height_min, 1.0);
  EXPECT_LE(a.height_max, 2.5);
  Rng rng(1, "tree");
  const tree::Tree t = generate_tree(a.params, {}, rng);
  EXPECT_GE(tree::compute_stats(t).branches_per_level.at(0), 3u);
}

}  // namespace
}  // namespace sylva::generate
