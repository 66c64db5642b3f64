// Trees for the mesh tests: tiny hand-built skeletons (one scenario each), the species presets
// through the generator, and the real QSM trees through the importer (test fixtures only).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "libs/tree/tree.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"

namespace sylva::mesh::test {

// A branch from `nodes` positions with one radius.
tree::Branch branch(std::vector<tree::Vec3> positions, double radius, std::int32_t parent = -1,
                    std::uint32_t parent_node = 0, std::uint32_t level = 0, double parent_t = 0);

// A vertical trunk of `nodes` nodes, 1 m apart, radius 0.1 m.
tree::Tree straight_trunk(int nodes = 4);

// The species preset files (configs/species/*.yaml), sorted.
std::vector<std::filesystem::path> species_presets();

// Generated tree of a preset ("young" | "middle" | "adult"), seed 1, max_node_spacing 0.5 m,
// as the generate stage makes it. Cached per (preset, age).
const tree::Tree& species_tree(const std::filesystem::path& preset, const std::string& age);

// A preset's adult tree with cards as the generate stage makes it at its defaults: the card atlas
// of `texture_size` px (drawn from `seed`'s stream "leaves", then made mip-safe) and the tree
// (stream "tree", max_node_spacing 0.5 m) whose cards sample it.
struct CardTree {
  generate::CardAtlas atlas;
  tree::Tree tree;
};
CardTree adult_card_tree(const generate::SpeciesPreset& species, int texture_size, std::uint64_t seed);

// RGBA8 pixels (rows top first) as the bytes of a PNG file.
std::string png_bytes(const generate::Rgba8& pixels);

// A QSM file of the shared test data imported with the import stage's defaults; nullopt when the
// data directory is missing (tests then skip).
std::optional<tree::Tree> qsm_tree(const std::string& file_name);

}  // namespace sylva::mesh::test
