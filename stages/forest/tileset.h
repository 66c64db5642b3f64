// The forest as a 3D Tiles 1.1 tileset (issue 13; OGC 3D Tiles 1.1, glTF content), so that
// CesiumJS streams it with no conversion.
//
// Error model, one-to-one: sylva's level of spatial error epsilon is valid from the distance d
// where epsilon / s(d) <= delta pixels, s(d) = 2 d tan(phi/2) / H (docs/lod-model.md); 3D Tiles refines a
// tile when its screen-space error geometricError * H / (2 d tan(phi/2)) exceeds the client's
// maximumScreenSpaceError. With geometricError = epsilon of the level a tile draws, the two are
// the same test: a client with maximumScreenSpaceError = delta shows exactly sylva's levels
// (measuring d to the tile's box instead of to each tree's, so never a coarser level).
//
// Structure: a quadtree over the square tiles (content-less inner nodes), each square tile the
// top of a chain of single-child tiles, coarsest level first: tile (level N-1) -> (level N-2) ...
// -> (level 0), each with the tile's trees at that level (species_level) as its content. refine
// is REPLACE throughout: a finer level of the same trees replaces the coarser one (ADD would draw
// both), and the content-less inner nodes have nothing to keep. geometricError: level L's tile =
// the largest error of the tile's species at that level (a mesh level's epsilon; an impostor's
// the error its recorded switch distance stands for, d delta s(1), so clients switch where
// sylva's views do), raised to at least the error of level
// L - 1 below it (a chain's errors never grow toward its leaves, so a client never refines into
// a larger error: an impostor whose epsilon is below the coarsest lod level's is shown only from
// where that level would be); an inner node = the error of drawing none of its trees, the
// largest tree's height (scaled), so a client always refines into the forest while a tree would
// cover more than its budget. Coordinates: glTF content is Y-up and 3D Tiles rotates it to Z-up
// (x, y, z) -> (x, -z, y); the root transform places the forest's frame (east = +x, north = -z,
// up = +y) at a WGS84 longitude / latitude / height (east-north-up).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "libs/forest/instances.h"

namespace sylva::forest {

struct Georeference {
  double longitude_deg = 0, latitude_deg = 0, height_m = 0;
};

// The level of species `s` that tile level `tile_level` (of `level_count`, the largest level count
// of the forest's species) draws: min(tile_level, lod levels - 1), except at the last tile level,
// which draws every species' last level (its impostor, when it has one).
std::size_t species_level(const Species& s, int tile_level, int level_count);

// `level_count` levels per chain; content uri of tile t at level L = content_uri(t, L). When the
// forest has a ground (Forest::ground), the root gets one more child: a leaf tile (geometricError
// 0) with the ground as content and `ground_bounds` (its box, forest frame) as volume, so clients
// draw the ground wherever they draw trees; the root's volume then covers it too.
std::string tileset_json(const Forest& forest, int level_count, const Georeference& geo,
                         const std::function<std::string(std::size_t tile, int level)>& content_uri,
                         const Box3& ground_bounds = {});

// Column-major east-north-up -> ECEF (WGS84) matrix at the georeference.
std::array<double, 16> enu_to_ecef(const Georeference& geo);

}  // namespace sylva::forest
