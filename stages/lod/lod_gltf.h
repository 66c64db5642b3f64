// glTF output of a LOD chain through libs/gltf.
//
// Seeds: Zhang et al. 2017 §6 (opaque meshes, then semi-transparent lines; eq. 12's alpha per
// line vertex, docs/stages/lod.md); Microsoft MSFT_lod extension (node.extensions.MSFT_lod.ids = the coarser
// levels' nodes, highest detail first; node.extras.MSFT_screencoverage, one value per level).
//
// Files (docs/stages/lod.md "Outputs"), every byte stored once:
//   lod<i>.gltf + lod<i>.bin   one level; any glTF client opens it
//   lod.gltf                   the MSFT_lod chain; its buffer i is the same lod<i>.bin
//   leaves.png                 the leaf atlas, shared by every file that shows leaves
//   lod<i>_ribbons.gltf + lod<i>_ribbons.bin  (levels with lines, `ribbons` on) the level with
//                              its LINES as three-sided ribbons (ribbons.h); its buffer 0 is
//                              lod<i>.bin, of which it uses the leading non-line primitives
//
// One glTF node and mesh per level. A level's mesh has, each only when non-empty and in this
// order: bark (TRIANGLES, opaque), leaves (TRIANGLES, double-sided, alpha MASK with the leaf
// atlas when given), needle prisms (TRIANGLES), branch lines (LINES, BLEND, each vertex's
// drawn alpha in COLOR_0), needle lines (LINES, BLEND). Lines last, so a level's non-line data is a
// prefix of its .bin. Every level's node and mesh carry the level's extras
// (lodchain::level_extras of level_numbers()). File names are libs/lodchain's (lod_chain.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/tree/tree.h"
#include "stages/lod/chain.h"

namespace sylva::lod {

struct OutputTextures {
  std::string leaf_png;  // bytes of the leaf atlas (empty = leaves use the leaf colour only)
};

// The level's numbers as lod.json and its glTF extras state them (epsilon, delta, switch distance,
// budgets E1..E5, line alphas, polygon error, counts; no files, coverage or cards): level `index`.
lodchain::Level level_numbers(const Level& level, std::size_t index);

// The scene of a single level (lod<i>.gltf, or a GLB when encoded with gltf::encode): one root
// node; its buffer is "lod<i>.bin", the atlas "leaves.png". With `ribbons` the LINES primitives
// are replaced by ribbons (ribbons.h) in a second buffer "lod<i>_ribbons.bin".
gltf::Scene level_scene(const tree::Tree& tree, const Level& level, std::size_t index,
                        const OutputTextures& tex, bool ribbons = false);

// True when the level has LINES (branch or needle lines), i.e. a ribbons variant differs.
bool has_lines(const Level& level);

// Radius (m) of the bounding sphere of level 0's geometry (lodmodel::BoundingBox over every
// position of the level: half the diagonal of its axis-aligned box; 0 for an empty level).
double bounding_radius(const Level& level0);

// MSFT_screencoverage of every level (lodmodel::screen_coverage, docs/lod-model.md "Screen
// coverage"): value i is c at the switch distance of level i + 1 (level i is drawn while the
// coverage is at least c_i), clamped to 1 (a level whose switch distance lies where the sphere
// overfills the screen takes over where c = 1, i.e. later: a finer level is kept longer, never a
// coarser one shown early); the last value is 0 (the coarsest level is never culled).
// Non-increasing, in [0, 1]. A loader leaves level i at lodmodel::coverage_distance(c_i).
std::vector<double> screen_coverages(const std::vector<Level>& levels, const lodmodel::Camera& camera,
                                     double radius);

// The chain's scene (lod.gltf): level 0 is the scene's root node, carrying MSFT_lod ids of the
// other levels' nodes and extras.MSFT_screencoverage; those nodes are not scene roots
// (MSFT_lod). Mesh i lives in buffer "lod<i>.bin". Materials equal across levels are shared.
gltf::Scene chain_scene(const tree::Tree& tree, const std::vector<Level>& levels,
                        const lodmodel::Camera& camera, const OutputTextures& tex);

// Every output file of the chain but lod.json (names above), in a fixed order; each .bin and the
// atlas once. Throws std::logic_error if the chain and the level files would disagree on a
// .bin's bytes, gltf::GltfError if a scene cannot be written.
std::vector<gltf::EncodedFile> encode_chain_files(const tree::Tree& tree, const std::vector<Level>& levels,
                                                  const lodmodel::Camera& camera, const OutputTextures& tex,
                                                  bool ribbons);

// full.glb: the full-detail model (build_full_detail: epsilon 0, every leaf and needle) as one
// GLB, written like level 0 (level_scene index 0, atlas embedded): the reference the chain's
// levels are judged against (`sylva lodcheck`; the pack stage's measured level choice). With
// `branches_only` the leaves and needles are left out.
std::string encode_full_detail(const tree::Tree& tree, Level full, const OutputTextures& tex,
                               bool branches_only = false);

// The chain's summary, lod.json (libs/lodchain writes it: lodchain::write_lod_chain).
lodchain::LodChain chain_summary(const tree::Tree& tree, const std::vector<Level>& levels,
                                 const ChainOptions& options, bool ribbons);

// Height (y extent) of the tree's skeleton, m.
double tree_height(const tree::Tree& tree);

}  // namespace sylva::lod
