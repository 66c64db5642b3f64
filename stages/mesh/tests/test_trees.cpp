#include "stages/mesh/tests/test_trees.h"

#include <algorithm>
#include <map>
#include <mutex>

#include "libs/image/png.h"
#include "pipeline/rng.h"
#include "stages/generate/mip_safe_alpha.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"
#include "stages/import/import_file.h"
#include "tests/support/test_support.h"

namespace sylva::mesh::test {

tree::Branch branch(std::vector<tree::Vec3> positions, double radius, std::int32_t parent,
                    std::uint32_t parent_node, std::uint32_t level, double parent_t) {
  tree::Branch b;
  b.parent = parent;
  b.parent_node = parent_node;
  b.parent_t = parent_t;
  b.level = level;
  for (const auto& p : positions) b.nodes.push_back({p, radius});
  return b;
}

tree::Tree straight_trunk(int nodes) {
  tree::Tree t;
  t.name = "straight";
  std::vector<tree::Vec3> p;
  for (int i = 0; i < nodes; ++i) p.push_back({0, static_cast<double>(i), 0});
  t.branches.push_back(branch(p, 0.1));
  return t;
}

std::vector<std::filesystem::path> species_presets() {
  return generate::species_preset_files(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species");
}

const tree::Tree& species_tree(const std::filesystem::path& preset, const std::string& age) {
  static std::mutex mu;
  static std::map<std::string, tree::Tree> cache;
  std::lock_guard<std::mutex> lock(mu);
  const std::string key = preset.string() + "|" + age;
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const generate::SpeciesPreset species = generate::load_species_preset(preset);
  generate::GenerateOptions o;
  o.max_node_spacing = 0.5;
  o.name = species.species + "/" + age + " seed 1";
  Rng rng(1, "tree");
  tree::Tree t = generate::generate_tree(species.age(age).params, o, rng);
  t.materials.bark_texture.clear();  // tests attach textures themselves when they need them
  t.materials.leaf_texture.clear();
  return cache.emplace(key, std::move(t)).first->second;
}

CardTree adult_card_tree(const generate::SpeciesPreset& species, int texture_size, std::uint64_t seed) {
  Rng leaf_rng(seed, "leaves"), tree_rng(seed, "tree");
  CardTree out{generate::make_card_atlas(species.card, species.leaf, species.bark, texture_size, leaf_rng),
               {}};
  generate::CardAtlas& atlas = out.atlas;
  generate::GenerateOptions g;
  g.atlas = {atlas.columns, atlas.rows, atlas.coverage};
  g.foliage = generate::FoliageMode::kCards;
  g.max_node_spacing = 0.5;
  generate::make_mip_safe(atlas.image, atlas.columns, atlas.rows);
  out.tree = generate::generate_tree(species.age("adult").params, g, tree_rng);
  return out;
}

std::string png_bytes(const generate::Rgba8& pixels) {
  image::Image img(pixels.width, pixels.height);
  img.bytes() = pixels.pixels;
  const std::vector<std::uint8_t> b = image::encode_png(img);
  return {b.begin(), b.end()};
}

std::optional<tree::Tree> qsm_tree(const std::string& file_name) {
  const auto data = sylva::test::data_dir();
  if (!data) return std::nullopt;
  const auto path = *data / "qsm" / file_name;
  if (!std::filesystem::exists(path)) return std::nullopt;
  import::ImportOptions o;
  return import::import_tree(sylva::test::read_file(path), path.string(), o);
}

}  // namespace sylva::mesh::test
