// Significant points (Celba 2007, seed 000 §4.2.4): the point of a part nearest to the part it
// grows from. docs/stages/hierarchy.md, "Significant points".
#pragma once

#include <cstdint>
#include <vector>

#include "libs/tree/vec3.h"
#include "stages/hierarchy/parts.h"

namespace sylva::hierarchy {

// Celba's -m1 (petiole: the mean of the vertices with the lowest texture v) and -m2 (centroid).
enum class LeafPoint : std::uint8_t { kPetiole, kCentroid };

struct BranchBase {
  tree::Vec3 point;                 // m, the significant point
  std::vector<std::uint32_t> loop;  // the base's boundary loop (point indices); empty: closed part
  double radius = 0;                // m, the loop's mean radius; 0 for a closed part
};

// A branch's significant point. Celba takes "the vertex which appears on the lowest number of
// faces". On an open tube every vertex of both end rings ties; we take the centroid of the end
// loop with the largest mean radius (a branch tapers towards its tip), radii within 2 % counting
// as equal and then the lowest loop (smallest centroid y) winning. A closed part keeps Celba's
// rule: the vertex on the fewest faces, ties to the lowest y, then the lowest index.
BranchBase branch_base(const Part& part);

// A leaf's significant point: -m1 or -m2. A part without texture coordinates has no petiole
// rule: it gets the centroid, and `*fell_back` (when given) is set.
tree::Vec3 leaf_point(const Part& part, LeafPoint rule, bool* fell_back = nullptr);

}  // namespace sylva::hierarchy
