// Greedy pairwise agglomeration with a spatial index, shared by leaf collapse (FSA) and needle
// merging (E5), and the binary forest it records.
//
// Seeds: Remolar et al. (FSA/VDF), §3–4: "From the list of the active leaves, the algorithm
// repeatedly selects a pair that minimizes the error function... the structure is made up of a
// forest of binary trees"; Zhang et al. 2017, §5.5: needles merged pairwise, "an Octree data
// structure is used to improve finding the most similar needles".
//
// Algorithm: every active element keeps its best partner among the active elements in the
// neighbouring cells of a uniform grid (the spatial index; the search widens ring by ring until
// a candidate is found); a priority queue holds (cost, a, b) and is popped lowest first; an entry
// naming a merged element is stale: if its first element is still active, that element's best
// partner is recomputed and pushed again. The grid is rebuilt with twice the cell size whenever
// the active count halves, so cells stay populated. Ties break on element ids: deterministic.
// The queue pops pairs in cost order among the pairs it knows (each element's best within its
// neighbourhood), an approximation of the global minimum that docs/stages/lod.md states.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <unordered_map>
#include <vector>

#include "libs/tree/vec3.h"

namespace sylva::lod {

// The binary forest: elements 0..n_leaves-1 are the originals; element n_leaves + i is made by
// merge i from left[i'] and right[i'] (i' = element index). error is monotone towards the roots.
struct BinaryForest {
  std::size_t original = 0;          // number of original elements
  std::vector<std::int32_t> parent;  // per element, -1 for roots
  std::vector<std::int32_t> left, right;  // per element, -1 for originals
  std::vector<double> error;         // per element, m; 0 for originals

  std::size_t size() const { return parent.size(); }
  // Active elements after the first `merges` merges (merge order), ascending ids.
  std::vector<std::uint32_t> cut_by_merges(std::size_t merges) const;
  // Active elements when every element with error <= max_error is used: the roots of the
  // subforest of elements with error <= max_error (an element is active when its error fits and
  // its parent's does not, or it has no parent). Ascending ids.
  std::vector<std::uint32_t> cut_by_error(double max_error) const;
  // Active elements for `count` elements (clamped to [roots, original]).
  std::vector<std::uint32_t> cut_by_count(std::size_t count) const;
  std::size_t roots() const;
};

// Runs the agglomeration. `items` holds the originals on entry and every merged element
// appended on exit. cost(a, b) >= 0 orders pairs (lower first), merge(a, b) returns the new
// element and its error; center(x) places elements in the grid. Elements whose cost is +inf
// never merge.
template <class Item, class CostFn, class MergeFn, class CenterFn>
BinaryForest agglomerate(std::vector<Item>& items, CostFn cost, MergeFn merge, CenterFn center) {
  using tree::Vec3;
  const std::size_t n = items.size();
  BinaryForest f;
  f.original = n;
  f.parent.assign(n, -1);
  f.left.assign(n, -1);
  f.right.assign(n, -1);
  f.error.assign(n, 0.0);
  if (n < 2) return f;
  items.reserve(2 * n);
  std::vector<char> alive(n, 1);
  std::size_t alive_count = n;
  // Grid set-up from the bounding box: about two elements per cell.
  Vec3 lo = center(items[0]), hi = lo;
  for (const Item& it : items) {
    const Vec3 c = center(it);
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  const Vec3 ext = hi - lo;
  // Flat or linear sets: no axis thinner than 1/64 of the largest, and at most 64 cells across,
  // so a widening search never walks more than 65 rings.
  const double max_extent = std::max({ext.x, ext.y, ext.z, 1e-6});
  const double floor_ext = max_extent / 64;
  const double vol = std::max(ext.x, floor_ext) * std::max(ext.y, floor_ext) * std::max(ext.z, floor_ext);
  double cell = std::max(floor_ext, std::cbrt(2 * vol / static_cast<double>(n)));
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  auto key_of = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) | (static_cast<std::uint64_t>(y & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(z & 0x1fffff);
  };
  auto cell_of = [&](Vec3 c, std::int64_t& x, std::int64_t& y, std::int64_t& z) {
    x = static_cast<std::int64_t>(std::floor((c.x - lo.x) / cell));
    y = static_cast<std::int64_t>(std::floor((c.y - lo.y) / cell));
    z = static_cast<std::int64_t>(std::floor((c.z - lo.z) / cell));
  };
  auto insert = [&](std::uint32_t id) {
    std::int64_t x, y, z;
    cell_of(center(items[id]), x, y, z);
    grid[key_of(x, y, z)].push_back(id);
  };
  std::size_t built_at = n;
  auto rebuild = [&]() {
    grid.clear();
    for (std::uint32_t i = 0; i < items.size(); ++i)
      if (alive[i]) insert(i);
    built_at = alive_count;
  };
  rebuild();
  struct Entry {
    double cost;
    std::uint32_t a, b;
    bool operator>(const Entry& o) const {
      if (cost != o.cost) return cost > o.cost;
      if (a != o.a) return a > o.a;
      return b > o.b;
    }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  // Best partner of `id` among active elements, widening the search ring by ring.
  // At most kMaxCandidates active elements are evaluated per search (own cell first, then the
  // ring's cells in a fixed order): clustered sets (needles on a twig) would otherwise put
  // hundreds into one cell.
  constexpr int kMaxCandidates = 24;
  auto push_best = [&](std::uint32_t id) {
    std::int64_t cx, cy, cz;
    cell_of(center(items[id]), cx, cy, cz);
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t best_id = id;
    int seen = 0;
    auto visit = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      const auto it = grid.find(key_of(x, y, z));
      if (it == grid.end()) return;
      for (std::uint32_t other : it->second) {
        if (other == id || !alive[other]) continue;
        if (seen >= kMaxCandidates) return;
        ++seen;
        const double c = cost(items[id], items[other]);
        if (c < best || (c == best && other < best_id)) {
          best = c;
          best_id = other;
        }
      }
    };
    visit(cx, cy, cz);
    const auto max_ring = static_cast<std::int64_t>(std::ceil(max_extent / cell)) + 1;
    for (std::int64_t ring = 1; ring <= max_ring && seen < kMaxCandidates; ++ring) {
      for (std::int64_t dx = -ring; dx <= ring; ++dx)
        for (std::int64_t dy = -ring; dy <= ring; ++dy)
          for (std::int64_t dz = -ring; dz <= ring; ++dz) {
            // Only the shell of this ring (the inside was searched before).
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
            visit(cx + dx, cy + dy, cz + dz);
          }
      if (seen > 0) break;  // ring 1 always, wider rings only until something is found
    }
    if (seen > 0 && std::isfinite(best)) queue.push({best, id, best_id});
  };
  for (std::uint32_t i = 0; i < n; ++i) push_best(i);
  while (!queue.empty() && alive_count > 1) {
    const Entry e = queue.top();
    queue.pop();
    if (!alive[e.a]) continue;
    if (!alive[e.b]) {
      push_best(e.a);
      continue;
    }
    auto [item, err] = merge(items[e.a], items[e.b], f.error[e.a], f.error[e.b]);
    const auto id = static_cast<std::uint32_t>(items.size());
    items.push_back(std::move(item));
    alive.push_back(1);
    alive[e.a] = alive[e.b] = 0;
    alive_count -= 1;
    f.parent.push_back(-1);
    f.left.push_back(static_cast<std::int32_t>(e.a));
    f.right.push_back(static_cast<std::int32_t>(e.b));
    f.error.push_back(std::max({err, f.error[e.a], f.error[e.b]}));
    f.parent[e.a] = f.parent[e.b] = static_cast<std::int32_t>(id);
    if (alive_count * 2 < built_at) {
      cell *= 2;
      rebuild();
    } else {
      insert(id);
    }
    push_best(id);
  }
  return f;
}

}  // namespace sylva::lod
