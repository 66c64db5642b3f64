// The full-detail budget of a hero tree (issue 9, "Budgets a game can ship"; docs/performance.md,
// "Trees in leaf"): every adult preset made as the default recipe makes it — the generate
// stage's defaults (cards, mip-safe atlas, 512² textures) and the mesh stage's defaults — stays
// within 300,000 triangles, 30,000 cards and 16 MB of GLB before compression.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "libs/gltf/writer.h"
#include "libs/image/png.h"
#include "pipeline/rng.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/mip_safe_alpha.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"
#include "stages/mesh/tests/test_trees.h"
#include "stages/mesh/tree_mesh.h"

namespace sylva::mesh {
namespace {

constexpr std::size_t kMaxTriangles = 300'000;
constexpr std::size_t kMaxCards = 30'000;
constexpr std::size_t kMaxBytes = 16'000'000;

struct Measured {
  std::size_t triangles = 0, cards = 0, bytes = 0;
};

Measured hero(const std::filesystem::path& preset, std::uint64_t seed) {
  const generate::SpeciesPreset species = generate::load_species_preset(preset);
  constexpr int kTextureSize = 512;  // the generate stage's default
  Rng bark_rng(seed, "bark");
  const test::CardTree cards = test::adult_card_tree(species, kTextureSize, seed);
  const tree::Tree& t = cards.tree;
  const TreeMesh m = mesh_tree(t, MeshOptions{});
  const Texture bark{"bark.png",
                     test::png_bytes(generate::make_bark_texture(species.bark, kTextureSize, bark_rng))};
  const Texture leaves{"leaves.png", test::png_bytes(cards.atlas.image)};
  Measured r;
  r.triangles =
      m.bark_surface.indices.size() / 3 + m.leaves.indices.size() / 3 + m.needles.indices.size() / 3;
  r.cards = m.stats.leaves;
  r.bytes = gltf::encode(make_scene(m, t, bark, leaves, {{"statistics", stats_json(m.stats)}})).size();
  return r;
}

TEST(Budget, EveryAdultPresetFitsAHeroBudgetAtTheDefaults) {
  for (const auto& preset : test::species_presets()) {
    for (std::uint64_t seed : {1, 7}) {
      const Measured r = hero(preset, seed);
      const std::string what = preset.stem().string() + " seed " + std::to_string(seed);
      std::printf("%s: %zu triangles, %zu cards, %zu bytes\n", what.c_str(), r.triangles, r.cards, r.bytes);
      EXPECT_LE(r.triangles, kMaxTriangles) << what;
      EXPECT_LE(r.cards, kMaxCards) << what;
      EXPECT_LE(r.bytes, kMaxBytes) << what;
      EXPECT_GT(r.cards, 0u) << what;
    }
  }
}

}  // namespace
}  // namespace sylva::mesh
