// A bucket quadtree on box centres (Celba §4.5.3, Algorithm 8's Q). Centre storage keeps every
// box in exactly one leaf (no duplicates to filter, no straddling lists); the price is that a
// query grows its window by the largest half extent seen, which for trees of one forest (boxes of
// similar size) costs a ring of neighbouring leaves.
#include "stages/forest/box_quadtree.h"

#include <algorithm>

namespace sylva::forest {

BoxQuadtree::BoxQuadtree(double x0, double z0, double size) { nodes_.push_back({x0, z0, size, -1, {}}); }

std::uint32_t BoxQuadtree::leaf_for(double x, double z, int& depth) const {
  std::uint32_t n = 0;
  depth = 0;
  while (nodes_[n].child >= 0) {
    const Node& node = nodes_[n];
    const double h = node.size * 0.5;
    const int cx = x >= node.x0 + h ? 1 : 0, cz = z >= node.z0 + h ? 1 : 0;
    n = std::uint32_t(node.child + cx * 2 + cz);
    ++depth;
  }
  return n;
}

void BoxQuadtree::split(std::uint32_t n, int depth) {
  if (depth >= kMaxDepth) return;
  const double h = nodes_[n].size * 0.5;
  const double x0 = nodes_[n].x0, z0 = nodes_[n].z0;
  const auto first = std::int32_t(nodes_.size());
  for (int cx = 0; cx < 2; ++cx)
    for (int cz = 0; cz < 2; ++cz) nodes_.push_back({x0 + cx * h, z0 + cz * h, h, -1, {}});
  std::vector<Box3> items = std::move(nodes_[n].items);
  nodes_[n].items = {};
  nodes_[n].child = first;
  for (const Box3& b : items) {
    const double x = 0.5 * (b.min[0] + b.max[0]), z = 0.5 * (b.min[2] + b.max[2]);
    const int cx = x >= x0 + h ? 1 : 0, cz = z >= z0 + h ? 1 : 0;
    nodes_[std::size_t(first + cx * 2 + cz)].items.push_back(b);
  }
  for (int c = 0; c < 4; ++c)
    if (nodes_[std::size_t(first + c)].items.size() > std::size_t(kBucket))
      split(std::uint32_t(first + c), depth + 1);
}

void BoxQuadtree::insert(const Box3& box) {
  ++count_;
  max_half_x_ = std::max(max_half_x_, 0.5 * (box.max[0] - box.min[0]));
  max_half_z_ = std::max(max_half_z_, 0.5 * (box.max[2] - box.min[2]));
  const Node& root = nodes_[0];
  const double x = std::clamp(0.5 * (box.min[0] + box.max[0]), root.x0, root.x0 + root.size);
  const double z = std::clamp(0.5 * (box.min[2] + box.max[2]), root.z0, root.z0 + root.size);
  int depth = 0;
  const std::uint32_t leaf = leaf_for(x, z, depth);
  nodes_[leaf].items.push_back(box);
  if (nodes_[leaf].items.size() > std::size_t(kBucket)) split(leaf, depth);
}

}  // namespace sylva::forest
