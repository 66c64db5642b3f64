// Stage `pack`'s core (issue 14; docs/stages/pack.md): one species' LOD chain, as the lod stage
// wrote it (lod.gltf with MSFT_lod over lod<i>.gltf levels), into the files a game ships:
//   <species>.glb        every level in one file, linked by MSFT_lod + MSFT_screencoverage
//                        (Babylon.js switches levels by them);
//   <species>_lod<i>.glb each level alone (Blender, Godot, Unreal and Unity ignore MSFT_lod);
//   <species>.lod.json   engine-neutral: levels, switch distances, screen coverage, sizes.
// Every mesh is reordered by meshoptimizer (vertex cache, overdraw, fetch) and compressed as
// asked; textures are the lod stage's PNGs, byte for byte. Pure over the scenes read from the
// lod files: no file system, no clock.
#pragma once

#include <string>
#include <vector>

#include "libs/gltf/scene.h"

namespace sylva::pack {

enum class Compression { kNone, kMeshopt, kDraco };

struct PackOptions {
  Compression compression = Compression::kMeshopt;
  bool optimize = true;
};

// One output file and the input files it was made from (names in the lod artifact).
struct PackedFile {
  std::string name;
  std::string bytes;
  std::vector<std::string> inputs;
};

struct SpeciesInput {
  std::string species;                                 // file name stem
  gltf::Scene chain;                                   // lod.gltf
  std::vector<gltf::Scene> levels;                     // lod<i>.gltf, i = 0..n-1
  std::vector<std::vector<std::string>> level_inputs;  // input files of each level (gltf, bin, png)
  std::vector<std::string> chain_inputs;               // input files of the chain
};

// The species' files: chain GLB, level GLBs (nearest first), lod.json; in that order. Throws
// std::invalid_argument when the chain is not an MSFT_lod chain over the levels (its root node
// names n-1 others, each node holds a level with epsilon_m and switch_distance_m extras).
std::vector<PackedFile> pack_species(const SpeciesInput& in, const PackOptions& options);

}  // namespace sylva::pack
