// The lod chain as the pack reads it (docs/stages/pack.md): each mesh level's numbers from its
// node in lod.gltf (lodchain::read_chain_levels), and the counts and bounds the pack states for
// a level's scene. Pure over the scenes.
#pragma once

#include <cstdint>
#include <vector>

#include "libs/gltf/scene.h"
#include "libs/pack/lod_json.h"
#include "stages/pack/pack_core.h"

namespace sylva::pack {

// The numbers of mesh level i, from its node in the lod chain (level 0: the root). `node` points
// into SpeciesInput::chain.
struct ChainLevel {
  const gltf::Node* node = nullptr;
  double epsilon_m = 0, pixel_error_px = 0, switch_distance_m = 0, coverage = 0;
};

struct ParsedChain {
  std::vector<ChainLevel> levels;  // one per SpeciesInput::levels
  std::vector<double> coverage;    // the chain's MSFT_screencoverage
};

// The chain's MSFT_lod links and every level's numbers. Throws std::invalid_argument when the
// chain is not an MSFT_lod chain over `in.levels` (lodchain::read_chain_levels' messages).
ParsedChain parse_chain(const SpeciesInput& in);

// Adds the scene's triangles and lines to `l.triangles` and `l.lines` (indexed or not).
void count_primitives(const gltf::Scene& s, LodLevel& l);

// Triangles + lines + points of the scene.
std::uint64_t primitives_of(const gltf::Scene& s);

// The radius of the bounding sphere the lod stage's MSFT_screencoverage is for: the
// lodmodel::BoundingBox of every position of the scene's meshes (level 0's, as the lod stage).
double bounding_radius(const gltf::Scene& s);

}  // namespace sylva::pack
