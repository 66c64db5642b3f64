// The forest's glTF files (issue 13 "Output"): per species and level, the level's mesh alone
// (the lod artifact's lod<i>.gltf, its buffer and atlas renamed to this artifact's copies); and per
// tile and level, one .gltf with one node per species carrying EXT_mesh_gpu_instancing
// (TRANSLATION, ROTATION, SCALE, _ID) over that species' level mesh's triangle primitives. The
// level's LINES (bark lines) and POINTS primitives are not instanced: clients instance only
// triangle meshes (three.js's loader draws a mesh with lines once, not per instance), so they form
// a second mesh that one plain node per instance draws — children of a node `<species>_lines` at
// the tile origin, with the instance's TRANSLATION, ROTATION, SCALE (the same float values) and
// `extras.instance_id`. Tiles store no geometry of
// their own: their buffers are the species' level .bin files (the same bytes the lod stage wrote,
// stored once in the cache) plus one small .bin per tile with its instances' attributes, so a
// forest of many tiles costs little more than its instances.
//
// Why JSON and not libs/gltf: the level meshes are already encoded (accessors, views, materials
// as the lod stage wrote them); the tile files reuse them by reference, which a writer that
// encodes geometry from plain data cannot do without re-encoding every level per tile.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libs/forest/instances.h"

namespace sylva::forest {

// A species' level as the stage reads it: the lod artifact's glTF JSON (one buffer, one mesh
// drawn by one root node with no transform) and the names its copies get in this artifact.
struct LevelSource {
  nlohmann::json gltf;   // parsed lod<i>.gltf
  std::string bin_name;  // e.g. "oak_lod3.bin": the copy of its buffer 0
  std::size_t bin_bytes = 0;
  std::string image_prefix;  // e.g. "oak_": its images' uris get this prefix
};

// The level's own .gltf (buffer and image uris renamed). Throws std::invalid_argument when the
// source is not a single-buffer, single-mesh glTF with one untransformed root node.
std::string species_level_gltf(const LevelSource& level);

// One tile at one level. `levels[s]` is species s's source at this level (nullptr when the tile has
// no tree of that species); `instances` of the forest, `tile` the tile. The instance attributes of
// every species of the tile are written into `tile_bin` (same bytes for every level: call with the
// same tile and get the same bin) named `tile_bin_name`. Throws std::invalid_argument when a
// species' base rotation cannot be expressed as instancing TRS with its scales (see .cpp).
// With TileInstancing::kNodes the tile uses no extension: each tree is one plain node (children of
// a node `<species>` at the tile origin) drawing the species' whole level mesh with the tree's
// TRANSLATION, ROTATION, SCALE and `extras.instance_id`; `bin` is then empty (no tile .bin).
enum class TileInstancing { kGpu, kNodes };
struct TileFiles {
  std::string gltf;
  std::string bin;
};
TileFiles tile_gltf(const Forest& forest, const Tile& tile, const std::vector<const LevelSource*>& levels,
                    const std::string& tile_bin_name, TileInstancing instancing = TileInstancing::kGpu);

// The node translation of a tile (its square's centre on y = 0): instance translations are
// relative to it, which keeps them small in float.
Vec3d tile_origin(const Forest& forest, const Tile& tile);

}  // namespace sylva::forest
