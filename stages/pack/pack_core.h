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
  // KHR_mesh_quantization (not with Draco, which quantises itself): each level's positions on
  // the coarsest grid whose rounding error (sqrt(3)/2 of a step) is at most position_error x the
  // level's epsilon, so the quantised level stays within a fraction of the error the lod stage
  // proved; a level that would need more than 16 bits keeps float positions, with meshopt
  // through its EXPONENTIAL filter within the same bound (gltf::QuantizeOptions::
  // float_position_error). Normals octahedral
  // with normal_bits, uvs in [0, 1] with texcoord_bits (gltf::QuantizeOptions).
  bool quantize = true;
  double position_error = 0.25;  // (0, 1]
  int normal_bits = 8;           // 1..16
  int texcoord_bits = 12;        // 1..16
};

// The position grid for a mesh at a level of spatial error `epsilon` (m): the fewest bits B
// (1..16) whose step extent / (2^B - 1) rounds every coordinate by at most
// sqrt(3)/2 step <= fraction x epsilon, extent the mesh's largest axis extent; 0 when 16 bits
// are not enough (or epsilon <= 0). max_error_m is sqrt(3)/2 step (0 for float positions).
struct PositionGrid {
  int bits = 0;
  double max_error_m = 0;
};
PositionGrid position_grid(const gltf::Mesh& mesh, double epsilon, double fraction);

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
