// Species presets as the generate stage makes them by default (twig/shoot cards on the species'
// atlas, max_node_spacing 0.5 m), for the species tests.
#pragma once

#include <algorithm>
#include <filesystem>
#include <vector>

#include "stages/generate/card_atlas.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"

namespace sylva::generate::test {

// Every preset under configs/species/ (the tests run from the source directory), sorted.
inline std::vector<std::filesystem::path> preset_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator("configs/species"))
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// As the stage does by default: cards on the species' card atlas (its coverage sets the leaf
// area each card carries; the atlas is drawn small, coverage does not depend on the size).
inline tree::Tree generate_with_cards(const SpeciesPreset& s, const AgeVariant& a, std::uint64_t seed,
                                      FoliageResult* fit = nullptr) {
  Rng leaf_rng(seed, "leaves");
  const CardAtlas atlas = make_card_atlas(s.card, s.leaf, s.bark, 64, leaf_rng);
  GenerateOptions o;
  o.max_node_spacing = 0.5;  // the stage's default
  o.foliage = FoliageMode::kCards;
  o.atlas = {atlas.columns, atlas.rows, atlas.coverage};
  o.foliage_result = fit;
  Rng rng(seed, "tree");
  return generate_tree(a.params, o, rng);
}

}  // namespace sylva::generate::test
