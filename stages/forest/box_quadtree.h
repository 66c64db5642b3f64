// Celba §4.5.3, Algorithm 8: "Let Q be quad tree of axis-aligned bounding boxes ... Search Q for
// overlapping with A". The quadtree of the boxes of the trees placed so far, over the forest's
// ground plane (x, z).
//
// Boxes are stored by the centre of their ground footprint in bucket leaves (a leaf splits into
// four when it holds more than kBucket boxes, down to a depth limit); a query for box A visits
// the nodes whose square meets A's footprint grown by the largest half extent stored, so every
// box whose footprint meets A's is found. Nodes live in one array (indices, no pointers) and a
// leaf holds copies of its boxes, so a query reads each leaf's boxes from one contiguous run
// (indices into one array of boxes in insertion order cost a cache miss per box at 10^6 trees).
#pragma once

#include <cstdint>
#include <vector>

#include "libs/forest/instances.h"

namespace sylva::forest {

class BoxQuadtree {
 public:
  // The square [x0, x0 + size) x [z0, z0 + size) must hold every box centre inserted (centres
  // outside are clamped into it: still found, only slower).
  BoxQuadtree(double x0, double z0, double size);

  void insert(const Box3& box);
  // Calls f(const Box3&) for every stored box whose (x, z) footprint meets `box`'s (closed
  // intervals), in no particular but deterministic order; stops early when f returns false.
  template <class F>
  void for_each_overlapping(const Box3& box, F&& f) const;

  std::size_t size() const { return count_; }

 private:
  static constexpr int kBucket = 64;
  static constexpr int kMaxDepth = 20;
  struct Node {
    double x0, z0, size;
    std::int32_t child = -1;  // index of the first of four children (x-major order), -1 = leaf
    std::vector<Box3> items;
  };
  void split(std::uint32_t node, int depth);
  std::uint32_t leaf_for(double x, double z, int& depth) const;

  std::vector<Node> nodes_;
  std::size_t count_ = 0;
  double max_half_x_ = 0, max_half_z_ = 0;
};

template <class F>
void BoxQuadtree::for_each_overlapping(const Box3& a, F&& f) const {
  const double qx0 = a.min[0] - max_half_x_, qx1 = a.max[0] + max_half_x_;
  const double qz0 = a.min[2] - max_half_z_, qz1 = a.max[2] + max_half_z_;
  std::uint32_t stack[4 * kMaxDepth + 8];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (n.x0 > qx1 || n.x0 + n.size < qx0 || n.z0 > qz1 || n.z0 + n.size < qz0) continue;
    if (n.child >= 0) {
      for (int c = 0; c < 4; ++c) stack[top++] = std::uint32_t(n.child + c);
      continue;
    }
    for (const Box3& b : n.items) {
      if (b.max[0] < a.min[0] || b.min[0] > a.max[0] || b.max[2] < a.min[2] || b.min[2] > a.max[2]) continue;
      if (!f(b)) return;
    }
  }
}

}  // namespace sylva::forest
