// Line levels for clients that do not draw LINES (Blender, Godot, most engines): each line
// internode of Zhang et al. 2017 §5.2/§5.5 (three segments on the same axis, normals 120° apart)
// becomes a thin, camera-independent triangular prism ("three-sided ribbon") around that axis.
//
// Same coverage: the three lines of an internode of radius R are drawn so that they cover a
// pixel by c = delta * 2 / rho with rho = E3 / R at the level's switch distance d, where one pixel
// is s(d) = E3 / delta metres wide (chain.h, drawn_line_alpha; e3 = 1): a strip c * s(d) = 2R
// wide, the branch's own width. The prism's corners sit at k * R from the axis in the directions
// of the three line normals; the mean width of an equilateral triangle of circumradius kR over
// all viewing directions is its perimeter / pi = 3 sqrt(3) k R / pi, so k = 2 pi / (3 sqrt(3))
// (about 1.209) makes the ribbon as wide as the branch on average, from any side.
//
// Cost: the same vertices as the lines (3 per node, one per corner, the line normal as the
// corner's smooth normal); per line internode 3 quads = 6 triangles (18 indices) instead of
// 3 segments (6 indices). Opaque, so no per-level alpha and no blending order.
#pragma once

#include <cstdint>
#include <vector>

#include "stages/lod/polygonize.h"

namespace sylva::lod {

// k: corner distance from the axis in units of the branch radius (see above).
inline constexpr double kRibbonCornerFactor = 1.2091995761561452;  // 2 pi / (3 sqrt 3)

struct Ribbons {
  std::vector<float> positions, normals;  // xyz per vertex
  std::vector<std::uint32_t> indices;     // triangles, counter-clockwise seen from outside
  std::size_t triangles = 0;
};

// The ribbons of every line internode of `g` (its line_* arrays as polygonize_branch writes
// them: 3 vertices per node, one per normal direction, and 3 segments per internode).
Ribbons line_ribbons(const BranchGeometry& g);

}  // namespace sylva::lod
