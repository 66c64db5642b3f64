// Developer report of the foliage every preset and age gets at the stage's defaults (cards):
// crown LAI against the preset's published range, card scale and layers, card count, crown and
// leaf area, height, and the generation time. docs/stages/generate.md's table is its output.
//   foliage_report [configs/species] [seed]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/tree/stats.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"

using namespace sylva;

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "configs/species";
  const std::uint64_t seed = argc > 2 ? std::stoull(argv[2]) : 7;
  const std::vector<std::filesystem::path> files = generate::species_preset_files(dir);
  std::printf(
      "| preset | age | LAI | published range | target | card scale | layers | cards | crown area m2 | leaf "
      "area m2 | height m | generate ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& f : files) {
    const generate::SpeciesPreset s = generate::load_species_preset(f);
    for (const generate::AgeVariant& a : s.ages) {
      const auto t0 = std::chrono::steady_clock::now();
      Rng leaf_rng(seed, "leaves");
      const generate::CardAtlas atlas = generate::make_card_atlas(s.card, s.leaf, s.bark, 64, leaf_rng);
      generate::GenerateOptions o;
      o.max_node_spacing = 0.5;
      o.foliage = generate::FoliageMode::kCards;
      o.atlas = {atlas.columns, atlas.rows, atlas.coverage};
      generate::FoliageResult fit;
      o.foliage_result = &fit;
      Rng rng(seed, "tree");
      const tree::Tree t = generate::generate_tree(a.params, o, rng);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const tree::TreeStats st = tree::compute_stats(t);
      std::printf("| %s | %s | %.2f | %.1f–%.1f | %.1f | %.2f | %d | %zu | %.1f | %.1f | %.1f | %.0f |\n",
                  s.species.c_str(), a.age.c_str(), st.lai, s.lai_min, s.lai_max, a.params.leaf_area_index,
                  fit.card_scale, fit.layers, t.leaves.size(), st.crown_area, st.leaf_area, st.height, ms);
    }
  }
  return 0;
}
