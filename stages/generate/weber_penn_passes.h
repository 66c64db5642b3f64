// The three passes of the Weber & Penn generator and the plain records each hands to the next;
// weber_penn.cpp runs them in order (its comment gives the process outline, Nystad 2010 §4.1).
// Private to the generate stage: weber_penn.h is the contract.
#pragma once

#include <cstdint>
#include <numbers>
#include <vector>

#include "libs/tree/tree.h"
#include "pipeline/rng.h"
#include "stages/generate/weber_penn.h"

namespace sylva::generate::weber_penn {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180;

// The parameters of branch level `level`; levels past the preset's list take its last entry.
const LevelParams& level_params(const Preset& p, std::size_t level);

// One stem: a W&P branch with all its clones (they share length, taper and segment length).
struct Stem {
  double length = 0;   // m
  double radius = 0;   // base radius the taper profile is relative to (m); set in pass 2
  double seg_len = 0;  // m
  int curve_res = 1;
  double offset = 0;  // attachment offset along the parent stem (m), laterals only
  double parent_length = 0;
  bool trunk = false;
};

// How one split groups n members (the primary continuation and n − 1 clones).
struct SplitPlan {
  int base = 0;  // segment node index on the splitting branch
  int n = 2;     // members
  double primary_azimuth = 0, primary_deviation = 0;
  std::uint32_t first_clone = 0;  // clones are consecutive plans
};

struct BranchPlan {
  std::int32_t parent = -1;
  std::uint32_t level = 0;
  bool clone = false;
  std::uint32_t stem = 0;
  int nseg = 1;                // segments of this branch (clones: the stem's remaining ones)
  int seg_offset = 0;          // stem segment index of this branch's first segment
  double attach_s = 0;         // lateral: arc position on the parent
  double azimuth = 0;          // around the parent's frame at the junction
  double deviation = 0;        // lateral: down angle; clone: split deviation (rad)
  double primary_angle = 0;    // lateral: Murray's primary deviation x it causes (rad)
  double ratio = 1;            // lateral: S_s; clone: n (members of its split)
  double hem = 0;              // last level with Hem > 0: the height (m) it ends at; 0 = none
  std::uint32_t curve_at = 0;  // curve[] per segment node 0..nseg in a shared pool
  std::int64_t pull_at = -1;   // trunk split compensation per segment node, or -1
  std::uint32_t first_child = 0, child_count = 0;  // laterals, consecutive, by attach_s
  std::uint32_t first_split = 0, split_count = 0;  // splits, by base
  // Set in pass 2.
  double start_radius = 0;
  std::uint32_t junction = 0;  // node of the parent it grows from
};

// What pass 1 decides, for passes 2 and 3.
struct Growth {
  std::vector<Stem> stems;
  std::vector<BranchPlan> plans;  // breadth-first by level, parents before children; 0 is the trunk
  std::vector<SplitPlan> splits;
  std::vector<double> curve, pull;        // per segment node (BranchPlan::curve_at, pull_at), rad
  std::vector<std::uint32_t> last_level;  // the branches that carry foliage
};

// Pass 1, growth (weber_penn_growth.cpp): `levels` branch levels, breadth-first, with every
// random draw of the branches from `rng`, in a fixed order.
Growth grow(const Preset& p, int levels, Rng& rng);

// Per-node data of pass 2 that pass 3 needs (nodes of all branches, concatenated).
struct NodeInfo {
  double s = 0;
  int base = -1;                                   // segment node index, or -1 for inserted nodes
  std::uint32_t first_child = 0, child_count = 0;  // laterals at this junction (plan ids)
  std::int32_t split = -1;                         // split plan at this node
};

// What pass 2 builds: the nodes of every branch in arc-length space, concatenated.
struct Structure {
  std::vector<std::uint32_t> node_begin;  // per plan, its first node; one more entry: the node count
  std::vector<double> s, radius;          // arc position along the branch (m), radius (m)
  std::vector<NodeInfo> info;
};

// Pass 2, structure (weber_penn_structure.cpp): nodes and radii of every branch, parents first.
// Sets the stems' radii and the plans' start_radius and junction in `g`. Throws
// std::length_error when the tree would exceed o.max_nodes.
Structure build_structure(const Preset& p, const GenerateOptions& o, Growth& g);

// Pass 3, world (weber_penn_world.cpp): t.branches (one per plan, same order) with world
// positions, walking each branch's nodes with a frame.
void place_branches(const Preset& p, const Growth& g, const Structure& s, tree::Tree& t);

// Foliage on the `last_level` branches of `t` (foliage_placement.h, drawing from `rng` after the
// branches), its materials, and the bark tint heights. Sets *o.foliage_result when given.
void add_foliage(const Preset& p, const GenerateOptions& o, const std::vector<std::uint32_t>& last_level,
                 Rng& rng, tree::Tree& t);

}  // namespace sylva::generate::weber_penn
