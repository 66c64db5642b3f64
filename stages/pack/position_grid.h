// The position grid of KHR_mesh_quantization for a pack level (docs/stages/pack.md,
// "Compression and size"): how many bits a mesh's positions need so that their rounding stays a
// fraction of the level's spatial error epsilon. Pure over a mesh's positions.
#pragma once

#include "libs/gltf/scene.h"

namespace sylva::pack {

// The position grid for a mesh at a level of spatial error `epsilon` (m): the fewest bits B
// (1..16) whose step extent / (2^B - 1) rounds every coordinate by at most
// sqrt(3)/2 step <= fraction x epsilon, extent the mesh's largest axis extent; when 16 bits are
// not enough for that, 16 bits if they round by at most max_fraction x epsilon (`relaxed`), else
// 0 (float; also when epsilon <= 0). max_error_m is sqrt(3)/2 step (0 for float positions).
struct PositionGrid {
  int bits = 0;
  double max_error_m = 0;
  bool relaxed = false;  // 16 bits within max_fraction, not fraction, x epsilon
};
PositionGrid position_grid(const gltf::Mesh& mesh, double epsilon, double fraction, double max_fraction = 0);

// The largest axis extent of the mesh's positions (m): what its position grid spans (0 for a
// mesh without positions).
double mesh_extent(const gltf::Mesh& mesh);

// sqrt(3)/2 of a step of a `bits` grid (1..16) over `extent` (m): the largest rounding error (m).
double grid_error(double extent, int bits);

}  // namespace sylva::pack
