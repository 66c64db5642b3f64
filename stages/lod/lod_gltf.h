// glTF output of a LOD chain through libs/gltf.
//
// Seeds: Zhang et al. 2017 §6 (opaque meshes, then semi-transparent lines with one alpha per
// level); Microsoft MSFT_lod extension (node.extensions.MSFT_lod.ids = the coarser levels'
// nodes, highest detail first; node.extras.MSFT_screencoverage, read by Babylon.js/three.js).
//
// One glTF node and mesh per level. A level's mesh has up to four primitives, each only when
// non-empty: bark (TRIANGLES, opaque), branch lines (LINES, BLEND, alpha = the level's eq. 12
// alpha), leaves (TRIANGLES, double-sided, alpha MASK with the leaf atlas when given), needles
// (LINES with their own alpha and/or TRIANGLES prisms). Every level's node and mesh carry the
// level's extras (level_extras()).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "libs/gltf/scene.h"
#include "libs/tree/tree.h"
#include "stages/lod/chain.h"

namespace sylva::lod {

struct OutputTextures {
  std::string leaf_png;  // bytes of the leaf atlas (empty = leaves use the leaf colour only)
};

// The level's description: epsilon, delta, switch distance, budgets E1..E5, counts, alpha.
nlohmann::json level_extras(const Level& level, std::size_t index);

// The scene of a single level (lod<i>.glb): one root node.
gltf::Scene level_scene(const tree::Tree& tree, const Level& level, std::size_t index, const OutputTextures& tex);

// MSFT_screencoverage of every level: the fraction of the image height the tree's height covers
// at the next level's switch distance (0 for the last level).
std::vector<double> screen_coverages(const std::vector<Level>& levels, const Camera& camera, double tree_height);

// The chain as one GLB: level 0 is the scene's root node, carrying MSFT_lod ids of the other
// levels' nodes and extras.MSFT_screencoverage; those nodes are not scene roots (MSFT_lod).
// Deterministic bytes.
std::string encode_chain_glb(const tree::Tree& tree, const std::vector<Level>& levels, const Camera& camera,
                             const OutputTextures& tex);

// Summary JSON of the chain (lod.json).
nlohmann::json chain_summary(const tree::Tree& tree, const std::vector<Level>& levels, const ChainOptions& options);

// Height (y extent) of the tree's skeleton, m.
double tree_height(const tree::Tree& tree);

}  // namespace sylva::lod
