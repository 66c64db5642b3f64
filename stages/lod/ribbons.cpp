// Line internodes as three-sided ribbons (ribbons.h). Seed: Zhang et al. 2017 §5.2 and §5.5
// (three lines with normals 120° apart stand for a branch of radius R, eq. 12).
#include "stages/lod/ribbons.h"

#include <array>

namespace sylva::lod {

Ribbons line_ribbons(const BranchGeometry& g) {
  Ribbons out;
  const std::size_t vertices = g.line_positions.size() / 3;
  out.positions.resize(3 * vertices);
  out.normals = g.line_normals;
  // 1. Corners: the axis point moved by k R along the line normal of its copy.
  for (std::size_t v = 0; v < vertices; ++v) {
    const double k = kRibbonCornerFactor * g.line_radii[v];
    for (int c = 0; c < 3; ++c)
      out.positions[3 * v + c] =
          static_cast<float>(g.line_positions[3 * v + c] + k * g.line_normals[3 * v + c]);
  }
  // 2. Faces: the internode's segments are (a_c, b_c) for the copies c = 0, 1, 2 at angles
  // 0°, 120°, 240° counter-clockwise around the axis; the face between copies c and c + 1 runs
  // a_c, a_c+1, b_c+1, b_c, counter-clockwise seen from outside (docs/stages/lod.md).
  out.indices.reserve(g.line_indices.size() * 3);
  for (std::size_t s = 0; s + 5 < g.line_indices.size(); s += 6) {
    std::array<std::uint32_t, 3> a{}, b{};
    for (int c = 0; c < 3; ++c) {
      a[c] = g.line_indices[s + 2 * c];
      b[c] = g.line_indices[s + 2 * c + 1];
    }
    for (int c = 0; c < 3; ++c) {
      const int d = (c + 1) % 3;
      out.indices.insert(out.indices.end(), {a[c], a[d], b[d], a[c], b[d], b[c]});
      out.triangles += 2;
    }
  }
  return out;
}

}  // namespace sylva::lod
