// Celba's grouping, read literally: the items of one level (instances, then the nodes made from
// them, ...) are split by a quadtree of the square around their box centres until each quadrant
// holds at most nodes_per_node items; each quadrant becomes a node of the next level. The levels
// are built bottom-up and then numbered from the root down (breadth first), so node 0 is the top.
#include "stages/forest/hierarchy.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace sylva::forest {

namespace {

Box3 merge(const Box3& a, const Box3& b) {
  Box3 o;
  for (int k = 0; k < 3; ++k) {
    o.min[std::size_t(k)] = std::min(a.min[std::size_t(k)], b.min[std::size_t(k)]);
    o.max[std::size_t(k)] = std::max(a.max[std::size_t(k)], b.max[std::size_t(k)]);
  }
  return o;
}

struct Item {
  double x, z;
  std::uint32_t index;
};

void group(std::vector<Item>& items, std::size_t lo, std::size_t hi, double x0, double z0, double size,
           int limit, int depth, std::vector<std::vector<std::uint32_t>>& out) {
  if (hi - lo <= std::size_t(limit) || depth > 48) {
    if (hi > lo) {
      std::vector<std::uint32_t> g;
      for (std::size_t i = lo; i < hi; ++i) g.push_back(items[i].index);
      out.push_back(std::move(g));
    }
    return;
  }
  const double h = size / 2;
  // Quadrants in (x, z) order: x-major split then z, stable so the order is deterministic.
  auto mid_x = std::stable_partition(items.begin() + long(lo), items.begin() + long(hi),
                                     [&](const Item& it) { return it.x < x0 + h; });
  const auto mx = std::size_t(mid_x - items.begin());
  auto mid_z0 =
      std::stable_partition(items.begin() + long(lo), mid_x, [&](const Item& it) { return it.z < z0 + h; });
  auto mid_z1 =
      std::stable_partition(mid_x, items.begin() + long(hi), [&](const Item& it) { return it.z < z0 + h; });
  const auto a = std::size_t(mid_z0 - items.begin()), b = std::size_t(mid_z1 - items.begin());
  group(items, lo, a, x0, z0, h, limit, depth + 1, out);
  group(items, a, mx, x0, z0 + h, h, limit, depth + 1, out);
  group(items, mx, b, x0 + h, z0, h, limit, depth + 1, out);
  group(items, b, hi, x0 + h, z0 + h, h, limit, depth + 1, out);
}

std::vector<std::vector<std::uint32_t>> groups_of(const std::vector<Box3>& boxes, int limit) {
  std::vector<Item> items;
  double x0 = INFINITY, z0 = INFINITY, x1 = -INFINITY, z1 = -INFINITY;
  for (std::uint32_t i = 0; i < boxes.size(); ++i) {
    const double x = 0.5 * (boxes[i].min[0] + boxes[i].max[0]), z = 0.5 * (boxes[i].min[2] + boxes[i].max[2]);
    items.push_back({x, z, i});
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    z0 = std::min(z0, z);
    z1 = std::max(z1, z);
  }
  std::vector<std::vector<std::uint32_t>> out;
  if (items.empty()) return out;
  const double size = std::max({x1 - x0, z1 - z0, 1e-9}) * (1 + 1e-12) + 1e-12;
  group(items, 0, items.size(), x0, z0, size, limit, 0, out);
  return out;
}

}  // namespace

std::vector<HierarchyNode> build_hierarchy(const std::vector<Box3>& boxes, int nodes_per_node) {
  const int limit = std::max(2, nodes_per_node);
  // levels[0]: leaf nodes over instances; levels[k]: nodes over levels[k-1].
  std::vector<std::vector<HierarchyNode>> levels;
  std::vector<Box3> current = boxes;
  bool leaf = true;
  do {
    std::vector<HierarchyNode> level;
    std::vector<std::vector<std::uint32_t>> groups = groups_of(current, limit);
    // With 2 or 3 children per node the quadtree can put every item of a level in a quadrant of
    // its own (3 items, limit 2: three singletons), and the level would never shrink. Then runs of
    // `limit` consecutive groups, in the quadrant order (spatially coherent), make the nodes.
    if (!leaf && current.size() > 1 && groups.size() >= current.size()) {
      std::vector<std::vector<std::uint32_t>> runs;
      for (std::size_t i = 0; i < groups.size(); ++i) {
        if (i % std::size_t(limit) == 0) runs.emplace_back();
        runs.back().insert(runs.back().end(), groups[i].begin(), groups[i].end());
      }
      groups = std::move(runs);
    }
    for (auto& g : groups) {
      HierarchyNode n;
      n.leaf = leaf;
      n.bounds = current[g.front()];
      for (std::uint32_t c : g) n.bounds = merge(n.bounds, current[c]);
      n.children = std::move(g);
      level.push_back(std::move(n));
    }
    if (level.empty()) level.push_back(HierarchyNode{{}, true, {}});
    current.clear();
    for (const auto& n : level) current.push_back(n.bounds);
    levels.push_back(std::move(level));
    leaf = false;
  } while (levels.back().size() > 1);
  // Number breadth first from the root: new index of (level, i).
  std::vector<HierarchyNode> out;
  std::vector<std::pair<std::size_t, std::uint32_t>> queue{{levels.size() - 1, 0}};
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto [lv, i] = queue[head];
    HierarchyNode n = levels[lv][i];
    if (!n.leaf) {
      for (std::uint32_t& c : n.children) {
        const auto child_index = std::uint32_t(queue.size());
        queue.emplace_back(lv - 1, c);
        c = child_index;
      }
    }
    out.push_back(std::move(n));
  }
  return out;
}

std::vector<Tile> build_tiles(std::vector<Instance>& instances, const std::vector<Box3>& boxes,
                              const std::array<double, 2>& extent_min, double tile_size_m) {
  std::map<std::pair<int, int>, Tile> by_key;  // (iz, ix)
  for (std::uint32_t i = 0; i < instances.size(); ++i) {
    const int ix = int(std::floor((instances[i].position[0] - extent_min[0]) / tile_size_m));
    const int iz = int(std::floor((instances[i].position[2] - extent_min[1]) / tile_size_m));
    auto [it, fresh] = by_key.try_emplace({iz, ix});
    Tile& t = it->second;
    if (fresh) {
      t.ix = ix;
      t.iz = iz;
      t.bounds = boxes[i];
    }
    t.bounds = merge(t.bounds, boxes[i]);
    t.instances.push_back(i);
  }
  std::vector<Tile> tiles;
  for (auto& [key, t] : by_key) {
    for (std::uint32_t i : t.instances) instances[i].tile = std::uint32_t(tiles.size());
    tiles.push_back(std::move(t));
  }
  return tiles;
}

}  // namespace sylva::forest
