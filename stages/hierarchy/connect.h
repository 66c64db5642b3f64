// The hierarchy of parts (Celba 2007, seed 000 §4.2.4, Algorithm 2): each branch connects to the
// branch one level lower whose grown bounding box holds its significant point and has the
// nearest vertex to it; leaves connect likewise to the highest-level branches.
// docs/stages/hierarchy.md, "Hierarchy".
#pragma once

#include <cstdint>
#include <vector>

#include "libs/tree/vec3.h"
#include "stages/hierarchy/parts.h"

namespace sylva::hierarchy {

// One branch part as the hierarchy sees it.
struct BranchNode {
  const Part* part = nullptr;
  tree::Vec3 point;         // significant point (m)
  std::int32_t level = -1;  // from its name; -1 unknown
};

struct Hierarchy {
  // Per branch node: its parent (index into the branch nodes), -1 for a root, -2 when it was
  // not connected to a root (no candidate, or its parent was not connected).
  std::vector<std::int32_t> parent;
  std::vector<std::int32_t> level;  // per branch node; -1 when not connected
  // Per leaf point: the branch node it grows on, -1 when not connected.
  std::vector<std::int32_t> leaf_branch;
  bool levels_from_names = false;    // every branch had a Celba level
  std::size_t leaves_below_top = 0;  // leaves connected by the fallback to a lower level
};

// The nearest distance from `p` to a vertex of `part` (m).
double nearest_vertex_distance(const Part& part, tree::Vec3 p);

// True when `p` lies in the part's bounding box grown by `tolerance` (m) on every side.
bool in_grown_box(const Part& part, tree::Vec3 p, double tolerance);

// Connects branches and leaves. When every branch has a level, that is Algorithm 2 as the
// thesis has it; otherwise the levels are derived (our extension): the trunk is the branch that
// reaches lowest (lowest box minimum y; ties: more triangles, then the lower index); every other
// branch's preferred parent is, among all branches whose grown box holds its point, the one with
// the nearest vertex; branches join once their preferred parent has joined (in index order,
// repeated until nothing changes), and a branch whose preferred parent never joins (a cycle)
// joins the nearest joined candidate instead; level = parent's level + 1.
// Leaves: among the connected branches of the highest level whose grown box holds the leaf's
// point, the one with the nearest vertex — chosen after all candidates are seen (the thesis's
// pseudocode connects inside the candidate loop, a slip); when none holds it, the nearest among
// all connected branches whose box holds it (our extension, counted in leaves_below_top).
Hierarchy connect_parts(const std::vector<BranchNode>& branches, const std::vector<tree::Vec3>& leaf_points,
                        double tolerance);

}  // namespace sylva::hierarchy
