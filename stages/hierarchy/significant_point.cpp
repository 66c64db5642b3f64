// Significant points. Celba's branch rule picks a vertex of an end ring of a tube: on his XFrog
// meshes one ring vertex happened to be on fewer faces than the rest. On a regular tube (ez-tree,
// sylva's own meshes, SpeedTree exports) both end rings tie, and the vertex is off the axis by
// one radius; the centroid of the base loop is on the axis, where a child meets its parent.
#include "stages/hierarchy/significant_point.h"

#include <algorithm>
#include <cmath>

#include "stages/hierarchy/part_geometry.h"

namespace sylva::hierarchy {

using tree::Vec3;

BranchBase branch_base(const Part& part) {
  BranchBase base;
  const auto loops = boundary_loops(part);
  if (!loops.empty()) {
    std::size_t best = 0;
    LoopShape best_shape = loop_shape(part, loops[0]);
    for (std::size_t i = 1; i < loops.size(); ++i) {
      const LoopShape s = loop_shape(part, loops[i]);
      const double bigger = std::max(s.radius, best_shape.radius);
      const bool same = std::abs(s.radius - best_shape.radius) <= 0.02 * bigger;
      if ((!same && s.radius > best_shape.radius) || (same && s.centroid.y < best_shape.centroid.y)) {
        best = i;
        best_shape = s;
      }
    }
    base.point = best_shape.centroid;
    base.loop = loops[best];
    base.radius = best_shape.radius;
    return base;
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < part.points.size(); ++i) {
    const bool fewer = part.face_count[i] < part.face_count[best];
    const bool tie_lower =
        part.face_count[i] == part.face_count[best] && part.points[i].y < part.points[best].y;
    if (fewer || tie_lower) best = i;
  }
  base.point = part.points[best];
  return base;
}

Vec3 leaf_point(const Part& part, LeafPoint rule, bool* fell_back) {
  if (fell_back) *fell_back = false;
  if (rule == LeafPoint::kPetiole && !part.min_v.empty()) {
    const float lo = *std::min_element(part.min_v.begin(), part.min_v.end());
    const float hi = *std::max_element(part.min_v.begin(), part.min_v.end());
    const float eps = 1e-4f * std::max(hi - lo, 1e-6f);  // equal up to rounding
    Vec3 sum;
    int n = 0;
    for (std::size_t i = 0; i < part.points.size(); ++i)
      if (part.min_v[i] <= lo + eps) {
        sum += part.points[i];
        ++n;
      }
    return sum / n;
  }
  if (rule == LeafPoint::kPetiole && fell_back) *fell_back = true;
  Vec3 sum;
  for (const Vec3& p : part.points) sum += p;
  return sum / static_cast<double>(part.points.size());
}

}  // namespace sylva::hierarchy
