// Conifer needle merging under E5.
//
// Seed: Zhang et al. 2017, §5.5: needles are merged two at a time, the closest pair first, by a
// linear combination of three metrics: the distance between the lines, the angle between the
// lines and the merging rank (needles represented), weights 0.25, 0.25, 0.5; a spatial index
// (the paper: an octree; here the uniform grid of pair_merge.h) finds the candidates; the merging
// is precomputed once and cut per level by E5. Needles are drawn like internodes (§5.2, §5.5):
// h(E3 / r) decides between a triangular prism and three lines.
//
// Our precise definitions (docs/stages/lod.md):
//   cost(a, b)  = 0.25 d(a, b) / L + 0.25 angle(a, b) / (pi/2) + 0.5 (1 - 2 / (rank_a + rank_b))
//     d = distance between the segments' midpoints plus half the endpoint mismatch, L the mean
//     needle length of the tree, angle between the undirected lines, rank 1 for an original;
//   merged needle = rank-weighted mean of the endpoints (b flipped when it points the other
//     way), radius keeping the projected area: r = (r_a l_a + r_b l_b) / l;
//   err(z)      = max(err(a) + disp(a, z), err(b) + disp(b, z)), disp = larger endpoint
//     distance, so err bounds how far any original needle's endpoints moved (m); cut by E5.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "libs/tree/tree.h"
#include "stages/lod/pair_merge.h"
#include "stages/lod/polygonize.h"

namespace sylva::lod {

struct NeedleLine {
  tree::Vec3 base, tip;
  double radius = 0;
  std::uint32_t rank = 1;
};

struct NeedleForest {
  std::vector<NeedleLine> needles;  // originals, then one per merge
  BinaryForest forest;
  double mean_length = 0;
};

double needle_cost(const NeedleLine& a, const NeedleLine& b, double mean_length);
NeedleLine merge_needles(const NeedleLine& a, const NeedleLine& b);

NeedleForest build_needle_forest(std::span<const tree::Needle> needles);

// Appends the needles `active` as internodes polygonised with E3 (prisms or lines).
void needle_geometry(const NeedleForest& forest, std::span<const std::uint32_t> active, double e3,
                     int max_edges, BranchGeometry& out);

}  // namespace sylva::lod
