// A branch part's centre line with radii, fitted by slicing (our method, issue 37; Celba's
// thesis builds no skeleton): slices about one radius long along the part, a least-squares
// circle per slice in the plane orthogonal to the local axis. docs/stages/hierarchy.md,
// "Skeletons".
#pragma once

#include <vector>

#include "libs/tree/tree.h"
#include "stages/hierarchy/parts.h"
#include "stages/hierarchy/significant_point.h"

namespace sylva::hierarchy {

struct FitOptions {
  double slice_radii = 1.0;  // slice length in base radii, > 0
  int max_slices = 256;      // per branch, >= 2
  int iterations = 2;        // re-slicing rounds along the fitted centre line, >= 0
};

struct SkeletonFit {
  std::vector<tree::Node> nodes;  // base to tip, >= 2; radii >= 0
  double rms_residual = 0;        // m: RMS over the part's points of (distance to its slice's
                                  // centre in the slice plane) - radius
  bool axis_fallback = false;     // too short for 2 slices: 2 nodes, base towards the centroid
};

// Fits the part whose base (significant point, base loop) is `base`. Never fails: a part too
// short or too irregular for two slices gets two nodes from the base towards its centroid.
// Cost: O(points * slices * (iterations + 1)) plus a Dijkstra over the part's edges.
SkeletonFit fit_skeleton(const Part& part, const BranchBase& base, const FitOptions& options);

}  // namespace sylva::hierarchy
