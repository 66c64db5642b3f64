// Summary statistics of a tree, for `sylva inspect` and for tests (issue 3 §1: branches per
// level, nodes, leaves, height, trunk diameter at 1.3 m, total branch length, bounding box).
//
// Definitions (metres):
//   height        highest point of the tree (nodes, leaf tips, needle tips) minus the y of the
//                 first root's base node (the ground point of the trunk);
//   dbh           diameter at breast height: 2 x the radius of the first root (the trunk),
//                 linearly interpolated where its axis first reaches 1.3 m above its base;
//                 absent (has_dbh false) if the trunk never reaches 1.3 m;
//   branch length sum over branches of their polyline length (node 0 to the last node; the
//                 implicit attachment segment is not counted);
//   bounds        axis-aligned box of node positions and foliage end points (radii excluded);
//   leaf area     one-sided: leaf quads weighted by their atlas cell's coverage, plus needle
//                 silhouettes 2 r l (foliage.h);
//   crown area    projected crown area: convex hull of the foliage seen from above (foliage.h);
//   lai           leaf area / crown area (the crown's leaf area index; 0 without foliage).
// An imported mesh (Tree::source) is summarised apart (SourceStats): its counts, its materials'
// names and alpha modes and its images' names and sizes; the numbers above are the skeleton's
// and foliage's only.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "libs/tree/tree.h"

namespace sylva::tree {

inline constexpr double kBreastHeight = 1.3;  // m, the forestry convention for DBH

// Tree::source in brief; all empty for generated and QSM trees.
struct SourceStats {
  struct Material {
    std::string name;
    AlphaMode alpha_mode = AlphaMode::kOpaque;
  };
  struct Image {
    std::string name;
    std::string mime_type;
    std::size_t bytes = 0;  // the encoded image's size
  };
  std::size_t primitives = 0;
  std::size_t triangles = 0;  // sum of index count / 3
  std::size_t vertices = 0;   // sum of position counts
  std::vector<Material> materials;
  std::vector<Image> images;
  bool empty() const { return primitives == 0 && materials.empty() && images.empty(); }
};

struct TreeStats {
  std::string name;
  std::vector<std::size_t> branches_per_level;  // index = level
  std::size_t branches = 0;
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  std::size_t needles = 0;
  double height = 0;
  bool has_dbh = false;
  double dbh = 0;
  double total_branch_length = 0;
  Vec3 bounds_min, bounds_max;  // both zero for an empty tree
  double leaf_area = 0;         // m^2, one-sided
  double crown_area = 0;        // m^2
  double lai = 0;
  SourceStats source;
};

TreeStats compute_stats(const Tree& tree);

// Human-readable, one "key: value" per line, stable for tests and diffs, e.g.
//   name: oak/adult seed 1
//   branches: 1204 (level 0: 1, level 1: 43, level 2: 1160)
//   nodes: 104211
//   ...
// followed, for a tree with an imported mesh, by (names quoted as JSON strings)
//   source: 3 primitives, 4 triangles, 10 vertices
//   source material 0: "Bark" (opaque)          one line per material: mask, blend, opaque
//   source image 0: "bark.png" (image/png, 13 bytes)   one line per image
std::string format_stats(const TreeStats& stats);

// The same as one JSON object (keys: name, branches, branches_per_level, nodes, leaves,
// needles, height_m, dbh_m (null if absent), total_branch_length_m, bounds_min_m, bounds_max_m,
// leaf_area_m2, crown_area_m2, lai), and "source" for a tree with an imported mesh:
// {"primitives", "triangles", "vertices", "materials": [{"name", "alpha_mode"}],
// "images": [{"name", "mime_type", "bytes"}]}.
std::string format_stats_json(const TreeStats& stats);

}  // namespace sylva::tree
