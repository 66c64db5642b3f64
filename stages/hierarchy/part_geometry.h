// Geometry of one part that several phases share: principal axes and boundary loops.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libs/tree/vec3.h"
#include "stages/hierarchy/parts.h"

namespace sylva::hierarchy {

// Principal component analysis of a point set: the centroid, unit axes by decreasing variance
// (axes[0] the longest) and the extent (max - min, m) of the points along each axis. A set of
// fewer than 2 distinct points gives the coordinate axes and zero extents.
struct Principal {
  tree::Vec3 centroid;
  std::array<tree::Vec3, 3> axes;
  std::array<double, 3> extent{};
};
Principal principal_axes(const std::vector<tree::Vec3>& points);

// The closed loops of boundary edges (edges on exactly one triangle) of a part, each as its
// point indices in walk order; loops ordered by their lowest point index. An open tube has two
// (its ends), a closed part none. Non-manifold boundary vertices end a walk early: such a walk is
// kept as it is.
std::vector<std::vector<std::uint32_t>> boundary_loops(const Part& part);

// The mean of a loop's points and their mean distance to it (m).
struct LoopShape {
  tree::Vec3 centroid;
  double radius = 0;
};
LoopShape loop_shape(const Part& part, const std::vector<std::uint32_t>& loop);

}  // namespace sylva::hierarchy
