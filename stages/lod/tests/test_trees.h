// Trees for the lod tests: a helix (Zhang Figure 7) and species presets from configs/species
// (generated with the generate core, like stages/mesh's tests do; the stage itself never links it).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "libs/tree/tree.h"

namespace sylva::lod::test {

// One branch sampled from a circular helix: `turns` turns of radius `helix_radius` and `pitch`
// per turn, `per_turn` nodes per turn, constant branch radius `radius`.
tree::Tree helix(double helix_radius, double pitch, int turns, int per_turn, double radius);

// configs/species/*.yaml, sorted.
std::vector<std::filesystem::path> species_presets();

// A preset's tree (seed 1, max node spacing 0.5 m), cached per (preset, age, cards), with single
// leaves/needles or, `cards` true, the preset's twig/shoot cards (as the generate stage's default).
const tree::Tree& species_tree(const std::filesystem::path& preset, const std::string& age,
                               bool cards = false);

// The tree uniformly scaled (positions, radii, foliage) so its height is `height` m.
tree::Tree scaled_to_height(const tree::Tree& t, double height);

}  // namespace sylva::lod::test
