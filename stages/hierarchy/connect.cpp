// Algorithm 2 of Celba 2007 (seed 000 §4.2.4, "Tree hierarchy reconstruction algorithm").
//
// Fix of the thesis's pseudocode: in its leaf loop, "Connect leaf A to branch B with lowest
// minimal distance" sits inside the loop over candidate branches, so a leaf would connect to the
// first candidate whose box holds it, and again to each later one; the prose (and the branch
// loop above it) mean the nearest of all candidates, so the connect here follows the loop.
//
// Files without Celba's names carry no levels; connect_parts() derives them (header) — our
// extension, not the thesis's. A branch's significant point touches its parent, so the nearest
// vertex among all boxes that hold it is its parent whatever the levels; joining in rounds from
// the trunk keeps parents before children and makes cycles impossible.
#include "stages/hierarchy/connect.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva::hierarchy {

using tree::Vec3;

namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// The nearest candidate among `allowed` branch nodes whose grown box holds `p`: (index, distance)
// or (-1, inf).
template <typename Allowed>
std::pair<std::int32_t, double> nearest_candidate(const std::vector<BranchNode>& branches, Vec3 p, double tol,
                                                  Allowed allowed) {
  std::int32_t best = -1;
  double best_d = kNone;
  for (std::size_t b = 0; b < branches.size(); ++b) {
    if (!allowed(b) || !in_grown_box(*branches[b].part, p, tol)) continue;
    const double d = nearest_vertex_distance(*branches[b].part, p);
    if (d < best_d) {
      best_d = d;
      best = static_cast<std::int32_t>(b);
    }
  }
  return {best, best_d};
}

void connect_by_names(const std::vector<BranchNode>& branches, double tol, Hierarchy& h) {
  std::int32_t max_level = 0;
  for (const BranchNode& b : branches) max_level = std::max(max_level, b.level);
  for (std::int32_t level = 0; level <= max_level; ++level)
    for (std::size_t a = 0; a < branches.size(); ++a) {
      if (branches[a].level != level) continue;
      if (level == 0) {
        h.parent[a] = -1;
        h.level[a] = 0;
        continue;
      }
      // Candidates: connected branches one level lower (a parent not connected to a root
      // cannot carry a child into the tree).
      const auto [best, d] = nearest_candidate(branches, branches[a].point, tol, [&](std::size_t b) {
        return branches[b].level == level - 1 && h.level[b] >= 0;
      });
      (void)d;
      if (best >= 0) {
        h.parent[a] = best;
        h.level[a] = level;
      }
    }
}

std::size_t trunk_of(const std::vector<BranchNode>& branches) {
  std::size_t t = 0;
  for (std::size_t b = 1; b < branches.size(); ++b) {
    const Part& p = *branches[b].part;
    const Part& q = *branches[t].part;
    if (p.box_min.y < q.box_min.y || (p.box_min.y == q.box_min.y && p.triangles.size() > q.triangles.size()))
      t = b;
  }
  return t;
}

void connect_derived(const std::vector<BranchNode>& branches, double tol, Hierarchy& h) {
  const std::size_t n = branches.size();
  const std::size_t trunk = trunk_of(branches);
  std::vector<std::int32_t> preferred(n, -1);
  for (std::size_t a = 0; a < n; ++a)
    if (a != trunk)
      preferred[a] =
          nearest_candidate(branches, branches[a].point, tol, [&](std::size_t b) { return b != a; }).first;
  h.parent[trunk] = -1;
  h.level[trunk] = 0;
  for (bool changed = true; changed;) {
    changed = false;
    // Preferred parents first; only when none joins, one branch joins its nearest joined
    // candidate (breaking a cycle), and the preferred rule gets another round.
    for (std::size_t a = 0; a < n; ++a) {
      const std::int32_t p = preferred[a];
      if (h.level[a] >= 0 || p < 0 || h.level[static_cast<std::size_t>(p)] < 0) continue;
      h.parent[a] = p;
      h.level[a] = h.level[static_cast<std::size_t>(p)] + 1;
      changed = true;
    }
    if (changed) continue;
    for (std::size_t a = 0; a < n && !changed; ++a) {
      if (h.level[a] >= 0 || preferred[a] < 0) continue;
      const auto [best, d] = nearest_candidate(branches, branches[a].point, tol,
                                               [&](std::size_t b) { return b != a && h.level[b] >= 0; });
      (void)d;
      if (best < 0) continue;
      h.parent[a] = best;
      h.level[a] = h.level[static_cast<std::size_t>(best)] + 1;
      changed = true;
    }
  }
}

}  // namespace

double nearest_vertex_distance(const Part& part, Vec3 p) {
  double best = kNone;
  for (const Vec3& v : part.points) {
    const Vec3 d = v - p;
    best = std::min(best, dot(d, d));
  }
  return std::sqrt(best);
}

bool in_grown_box(const Part& part, Vec3 p, double tol) {
  return p.x >= part.box_min.x - tol && p.x <= part.box_max.x + tol && p.y >= part.box_min.y - tol &&
         p.y <= part.box_max.y + tol && p.z >= part.box_min.z - tol && p.z <= part.box_max.z + tol;
}

Hierarchy connect_parts(const std::vector<BranchNode>& branches, const std::vector<Vec3>& leaf_points,
                        double tol) {
  Hierarchy h;
  h.parent.assign(branches.size(), -2);
  h.level.assign(branches.size(), -1);
  h.leaf_branch.assign(leaf_points.size(), -1);
  h.levels_from_names = !branches.empty() && std::all_of(branches.begin(), branches.end(),
                                                         [](const BranchNode& b) { return b.level >= 0; });
  if (branches.empty()) return h;
  if (h.levels_from_names)
    connect_by_names(branches, tol, h);
  else
    connect_derived(branches, tol, h);

  const std::int32_t top = *std::max_element(h.level.begin(), h.level.end());
  for (std::size_t l = 0; l < leaf_points.size(); ++l) {
    // All candidates first, then the connect (the fixed slip: see the top of this file).
    auto best =
        nearest_candidate(branches, leaf_points[l], tol, [&](std::size_t b) { return h.level[b] == top; });
    if (best.first < 0) {
      best = nearest_candidate(branches, leaf_points[l], tol, [&](std::size_t b) { return h.level[b] >= 0; });
      if (best.first >= 0) ++h.leaves_below_top;
    }
    h.leaf_branch[l] = best.first;
  }
  return h;
}

}  // namespace sylva::hierarchy
