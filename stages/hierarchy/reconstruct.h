// Stage `hierarchy`'s core: an imported tree's source geometry -> its skeleton (branches) and
// leaves, through Celba 2007 (seed 000 §4.2.4) Algorithm 1 (parts), the branch/leaf rules,
// significant points and Algorithm 2 (hierarchy), then a slice-and-circle skeleton per branch.
// Plain data in, plain data out, no I/O. docs/stages/hierarchy.md documents every option.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "libs/tree/tree.h"
#include "stages/hierarchy/classify.h"
#include "stages/hierarchy/significant_point.h"
#include "stages/hierarchy/skeleton_fit.h"

namespace sylva::hierarchy {

struct ReconstructOptions {
  double weld_tolerance = 1e-5;  // m, >= 0; 0 = only shared indices connect (Algorithm 1)
  ClassifyOptions classify;
  LeafPoint leaf_point = LeafPoint::kPetiole;
  double tolerance = 0.05;  // m, >= 0: bounding-box growth of Algorithm 2
  FitOptions fit;
};

// A part left out of the tree: no grown box held its significant point (or, with names, it had
// no Celba name, or its parent was left out).
struct LeftOutPart {
  std::size_t part = 0;
  std::uint32_t primitive = 0;
  std::string kind;  // "branch", "leaf" or "skipped" (classify names: not a Celba name)
  std::size_t triangles = 0;
  double size_m = 0;  // diagonal of its bounding box
};

struct BranchReport {
  std::size_t part = 0;      // the part it was fitted to
  std::int32_t parent = -1;  // output branch index
  std::uint32_t level = 0;
  std::size_t nodes = 0;
  double base_radius_m = 0;
  double fit_rms_m = 0;  // SkeletonFit::rms_residual
  bool axis_fallback = false;
};

struct Report {
  std::size_t parts = 0, branch_parts = 0, leaf_parts = 0, skipped_parts = 0;
  bool classify_fallback = false;  // auto called every part a leaf; the geometry rule decided
  bool levels_from_names = false;
  std::vector<std::size_t> branches_by_level;
  std::size_t leaves = 0;
  std::size_t leaves_below_top = 0;    // attached by the fallback below the highest level
  std::size_t leaves_without_uvs = 0;  // petiole rule fell back to the centroid
  std::vector<LeftOutPart> left_out;   // in part order
  std::vector<BranchReport> branches;  // in output branch order
};

struct Reconstruction {
  tree::Tree tree;
  Report report;
};

// `in` must carry source geometry and no skeleton. The result is `in` with branches, leaves and
// materials (colours from the source materials, leaf kind twig cards, a 1x1 atlas) rebuilt,
// needles cleared, source untouched; it passes validate_tree(). Throws HierarchyError: no source
// geometry, a skeleton already present, no triangles, no branch part, no trunk (names without a
// level 0), malformed primitives (naming the primitive).
Reconstruction reconstruct(const tree::Tree& in, const ReconstructOptions& options);

}  // namespace sylva::hierarchy
