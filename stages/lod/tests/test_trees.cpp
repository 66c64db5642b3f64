#include "stages/lod/tests/test_trees.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>

#include "pipeline/rng.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"

namespace sylva::lod::test {

tree::Tree helix(double helix_radius, double pitch, int turns, int per_turn, double radius) {
  tree::Tree t;
  t.name = "helix";
  tree::Branch b;
  for (int i = 0; i <= turns * per_turn; ++i) {
    const double a = 2 * std::numbers::pi * i / per_turn;
    b.nodes.push_back(
        {{helix_radius * std::cos(a), pitch * i / per_turn, helix_radius * std::sin(a)}, radius});
  }
  t.branches.push_back(b);
  return t;
}

std::vector<std::filesystem::path> species_presets() {
  return generate::species_preset_files(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species");
}

const tree::Tree& species_tree(const std::filesystem::path& preset, const std::string& age, bool cards) {
  static std::mutex mu;
  static std::map<std::string, tree::Tree> cache;
  std::lock_guard<std::mutex> lock(mu);
  const std::string key = preset.string() + "|" + age + (cards ? "|cards" : "");
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const generate::SpeciesPreset species = generate::load_species_preset(preset);
  generate::GenerateOptions o;
  o.max_node_spacing = 0.5;
  o.name = species.species + "/" + age + " seed 1";
  if (cards) o.foliage = generate::FoliageMode::kCards;
  Rng rng(1, "tree");
  tree::Tree t = generate::generate_tree(species.age(age).params, o, rng);
  return cache.emplace(key, std::move(t)).first->second;
}

tree::Tree scaled_to_height(const tree::Tree& t, double height) {
  double lo = 1e300, hi = -1e300;
  for (const auto& b : t.branches)
    for (const auto& n : b.nodes) {
      lo = std::min(lo, n.position.y);
      hi = std::max(hi, n.position.y);
    }
  const double s = height / std::max(hi - lo, 1e-9);
  const auto sf = static_cast<float>(s);
  tree::Tree out = t;
  for (auto& b : out.branches)
    for (auto& n : b.nodes) {
      n.position = n.position * s;
      n.radius *= s;
    }
  for (auto& l : out.leaves) {
    l.position = {l.position.x * sf, l.position.y * sf, l.position.z * sf};
    l.length *= sf;
    l.width *= sf;
  }
  for (auto& n : out.needles) {
    n.base = {n.base.x * sf, n.base.y * sf, n.base.z * sf};
    n.tip = {n.tip.x * sf, n.tip.y * sf, n.tip.z * sf};
    n.radius *= sf;
  }
  return out;
}

}  // namespace sylva::lod::test
