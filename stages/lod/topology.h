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
#include <utility>
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

// Side-on projected area (m^2) of every branch's subtree: the sum over its internodes and those
// of all its descendants of (R_k + R_{k+1}) |P_{k+1} - P_k| (2 R L for a cylinder seen from
// the side). What a level loses in coverage when it decimates the subtree. Branches flagged in
// `drawn_by_cards` (libs/tree twigs_drawn_by_cards(); empty = none) count 0: their cards draw
// them at every level, so no level loses their coverage.
std::vector<double> subtree_areas(std::span<const BranchSkeleton> skeletons,
                                  std::span<const char> drawn_by_cards = {});

// Where a decimated subtree's coverage goes (docs/stages/lod.md, "Coverage of decimated
// branches"): eq. (12)'s alpha 2R/E3 is a line's width over E3, so a subtree of side-on area A
// carried onto the kept node j of its bearer nearest its attachment (by arc length) adds
// A / (E3 w_j) to that node's alpha, w_j the length the node stands for (half of each adjacent
// kept internode): the line then covers A more, within A(b) <= E4 of where the subtree was.
// `deposits` are (arc length on the bearer, area) pairs; returns one extra alpha per kept node
// (zeros without deposits). `kept` as merge_internodes() returns it, e3 > 0.
std::vector<double> carried_alpha(std::span<const SkeletalVector> g, std::span<const std::uint32_t> kept,
                                  std::span<const std::pair<double, double>> deposits, double e3);

// Distance from point p to the solid of a skeleton (capsules with linearly interpolated radius,
// measured as max(0, |p - c(t*)| - R(t*)) at the closest axis point c(t*)).
double distance_to_solid(std::span<const SkeletalVector> g, Vec3 p);

}  // namespace sylva::lod
