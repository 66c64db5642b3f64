// The forest's ground (issue 13 "Ground"): a mesh of the terrain under the forest's area, so that
// forest views, glTF viewers and 3D Tiles clients show the trees standing on something. With a
// height map, a regular grid over the forest's extent at the height map's sample spacing (at most
// kMaxGroundCells cells per side), heights h(x, z) of the bilinear terrain the layout sets the trees
// on (fields.h), normals from its central differences; without, one flat quad of the extent at
// y = 0. One neutral, opaque, single-sided material (kGroundColor), facing +Y.
#pragma once

#include <array>

#include "libs/gltf/scene.h"
#include "stages/forest/fields.h"

namespace sylva::forest {

inline constexpr int kMaxGroundCells = 256;
// Linear base colour of the ground: a neutral dry-soil khaki (sRGB ~ 130, 124, 109).
inline constexpr std::array<float, 4> kGroundColor{0.223f, 0.202f, 0.153f, 1.f};

// extent_min/max: x, z of the forest's area. The scene has one mesh drawn by one root node.
gltf::Scene ground_scene(const Terrain& terrain, const std::array<double, 2>& extent_min,
                         const std::array<double, 2>& extent_max);

}  // namespace sylva::forest
