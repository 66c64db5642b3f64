// A grid step s moves a point by at most half its diagonal, sqrt(3)/2 s, so the coarsest grid
// whose half diagonal fits the budget is the one the level's epsilon allows.
#include "stages/pack/position_grid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace sylva::pack {

double mesh_extent(const gltf::Mesh& mesh) {
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& p : mesh.primitives)
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
      lo[i % 3] = std::min<double>(lo[i % 3], p.positions[i]);
      hi[i % 3] = std::max<double>(hi[i % 3], p.positions[i]);
    }
  double extent = 0;
  for (std::size_t c = 0; c < 3; ++c) extent = std::max(extent, hi[c] - lo[c]);
  return extent;
}

double grid_error(double extent, int bits) {
  return std::sqrt(3.0) / 2 * (extent / double((1u << bits) - 1));
}

PositionGrid position_grid(const gltf::Mesh& mesh, double epsilon, double fraction, double max_fraction) {
  const double extent = mesh_extent(mesh);
  const double budget = fraction * epsilon;  // allowed rounding error, m
  if (!(budget > 0) || !(extent >= 0)) return {};
  const double half_diagonal = std::sqrt(3.0) / 2;
  for (int bits = 1; bits <= 16; ++bits) {
    const double step = extent / double((1u << bits) - 1);
    if (half_diagonal * step <= budget) return {bits, half_diagonal * step, false};
  }
  // KHR_mesh_quantization stops at 16 bits. Its grid is still far finer than the level's own
  // error when it rounds within max_fraction x epsilon, and far smaller than float positions.
  const double step16 = extent / double((1u << 16) - 1);
  if (half_diagonal * step16 <= max_fraction * epsilon) return {16, half_diagonal * step16, true};
  return {};
}

}  // namespace sylva::pack
