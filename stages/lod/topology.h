// Topology simplification (branch decimation) by the accumulated Hausdorff distance E4.
//
// Seed: Zhang et al. 2017, §5.3: "The distance is computed between each branch and its parent
// branch (its bearer). The accumulated distance of the branch to its parent and all its child
// branches defines when the branch can be deleted. E4 is the error threshold."
//
// Our precise definition (docs/stages/lod.md):
//   h(b)  = max over the skeleton nodes P_i of b of  max(0, dist(P_i, axis(bearer)) - R_bearer) + R_i,
//           i.e. how far b's solid reaches out of its bearer's solid (one-sided Hausdorff, nodes);
//   A(b)  = h(b) + max over the children c of b of A(c)          (accumulated, bottom-up);
// A point of c's solid is within h(c) of b's solid, which is within h(b) of the bearer's solid,
// so A(b) bounds the distance from the whole subtree to its bearer by the triangle inequality.
// A branch (with its subtree) is deleted at a level when A(b) <= E4. Roots are never deleted.
// A(parent) >= A(child), so a kept branch always has a kept bearer.
#pragma once

#include <span>
#include <vector>

#include "stages/lod/internodes.h"

namespace sylva::lod {

// h(b) for every branch (0 for roots), computed on the full-detail skeletons once per tree.
// Cost O(sum over branches of K_b * K_bearer).
std::vector<double> bearer_distances(std::span<const BranchSkeleton> skeletons);

// A(b) from h(b): children come after their parents (tree.h), so one backward pass.
// Roots get +infinity (never deleted).
std::vector<double> accumulated_distances(std::span<const BranchSkeleton> skeletons,
                                          std::span<const double> h);

// Distance from point p to the solid of a skeleton (capsules with linearly interpolated radius,
// measured as max(0, |p - c(t*)| - R(t*)) at the closest axis point c(t*)).
double distance_to_solid(std::span<const SkeletalVector> g, Vec3 p);

}  // namespace sylva::lod
