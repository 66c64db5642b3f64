// An imported mesh moved into sylva's frame: metres, Y up, right-handed, the trunk foot at the
// origin. Pure.
//
// In this order:
//   1. axes: a Z-up file is turned Y up by (x, y, z) -> (x, z, -y) (a rotation: the winding and
//      the handedness stay; QSM tables are turned the same way, qsm_to_tree.h); normals too;
//   2. units: positions multiplied by facts.unit_scale (the file's unit in metres) * options.scale;
//   3. recentring (options.recenter): the trunk foot goes to the origin. The foot is the centre,
//      in x and z, of the bounding box of the bottom-most vertices — those within 1 % of the
//      model's height above its lowest point — at the lowest y. After it, min y = 0 and the
//      foot's x and z are 0. Without recentring the file's placement is kept.
// facts.up must be 'y' or 'z'; facts.height is set to the model's height (max y - min y, m).
#pragma once

#include "libs/tree/source_geometry.h"
#include "stages/import/mesh_options.h"

namespace sylva::import {

// The band above the lowest point whose vertices make the foot (fraction of the height).
inline constexpr double kFootBand = 0.01;

void to_sylva_frame(tree::SourceGeometry& g, MeshFacts& facts, const MeshOptions& options);

}  // namespace sylva::import
