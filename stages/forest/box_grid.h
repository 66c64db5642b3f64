// Celba §4.5.3, Algorithm 8: "Search Q for overlapping with A", Q the boxes of the trees placed so
// far. The index is a uniform grid over the forest's ground plane (x, z) rather than Celba's
// quadtree: trees of one forest have boxes of similar size, so with cells about two footprints
// wide (the caller's choice, layout.cpp) a query reads the 2 x 2 or so cells around the new box
// and nothing else (docs/performance.md, "Forest": the quadtree's query was bound by the memory
// loads of its 24 nodes and scattered leaves).
//
// Boxes are stored by the centre of their ground footprint (each in exactly one cell), in blocks
// of kBlock boxes chained per cell (the newest block first). A query visits the cells that meet
// A's footprint grown by the largest half extent stored, so every box whose footprint meets A's
// is found (the same set the quadtree finds: the layout's decisions, and so its output, do not
// depend on the index).
//
// The query is bound by memory latency, about one cache miss per block read (docs/performance.md,
// "Forest"), so: a block's count comes first, beside its first boxes, so that one miss brings
// both; the query asks for every cell's newest block before reading any, so that their misses
// overlap; and the blocks live in 2 MiB chunks that are never moved and, on Linux, are offered to
// the kernel as transparent huge pages (madvise), so that a random block costs no page walk.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "libs/forest/instances.h"

namespace sylva::forest {

class BoxGrid {
 public:
  // The square [x0, x0 + size)^2 should hold every box centre (centres outside are clamped into
  // the edge cells: still found). cell_m > 0: the cell width, ideally the largest footprint's;
  // at most kMaxCells cells a side (wider cells then).
  BoxGrid(double x0, double z0, double size, double cell_m);

  void insert(const Box3& box);
  // Calls f(const Box3&) for every stored box whose (x, z) footprint meets `box`'s (closed
  // intervals), in a deterministic order; stops early when f returns false.
  template <class F>
  void for_each_overlapping(const Box3& box, F&& f) const;

  std::size_t size() const { return count_; }

  static constexpr int kMaxCells = 4096;
  static constexpr int kBlock = 8;

 private:
  struct Block {
    std::int32_t count = 0;
    std::int32_t next = -1;  // the cell's previous block (the newest block is the cell's head)
    Box3 items[kBlock];
  };
  struct FreeChunk {
    void operator()(Block* p) const;
  };
  static constexpr std::size_t kChunkBytes = std::size_t(2) << 20;
  static constexpr std::size_t kPerChunk = kChunkBytes / sizeof(Block);

  int cell_of(double v, double origin) const {
    return std::clamp(int(std::floor((v - origin) * inv_cell_)), 0, cells_ - 1);
  }
  const Block& block(std::int32_t b) const {
    return chunks_[std::size_t(b) / kPerChunk].get()[std::size_t(b) % kPerChunk];
  }
  Block& block(std::int32_t b) {
    return chunks_[std::size_t(b) / kPerChunk].get()[std::size_t(b) % kPerChunk];
  }
  std::int32_t new_block(std::int32_t next);

  double x0_, z0_, inv_cell_;
  int cells_;
  std::vector<std::int32_t> head_;  // per cell, -1 = empty
  std::vector<std::unique_ptr<Block, FreeChunk>> chunks_;
  std::int32_t blocks_ = 0;
  std::size_t count_ = 0;
  double max_half_x_ = 0, max_half_z_ = 0;
};

template <class F>
void BoxGrid::for_each_overlapping(const Box3& a, F&& f) const {
  if (count_ == 0) return;
  const int cx0 = cell_of(a.min[0] - max_half_x_, x0_), cx1 = cell_of(a.max[0] + max_half_x_, x0_);
  const int cz0 = cell_of(a.min[2] - max_half_z_, z0_), cz1 = cell_of(a.max[2] + max_half_z_, z0_);
  for (int cz = cz0; cz <= cz1; ++cz)
    for (int cx = cx0; cx <= cx1; ++cx) {
      const std::int32_t b = head_[std::size_t(cz) * std::size_t(cells_) + std::size_t(cx)];
      if (b >= 0) __builtin_prefetch(&block(b));
    }
  for (int cz = cz0; cz <= cz1; ++cz)
    for (int cx = cx0; cx <= cx1; ++cx)
      for (std::int32_t b = head_[std::size_t(cz) * std::size_t(cells_) + std::size_t(cx)]; b >= 0;) {
        const Block& blk = block(b);
        for (int i = 0; i < blk.count; ++i) {
          const Box3& o = blk.items[i];
          if (o.max[0] < a.min[0] || o.min[0] > a.max[0] || o.max[2] < a.min[2] || o.min[2] > a.max[2])
            continue;
          if (!f(o)) return;
        }
        b = blk.next;
      }
}

}  // namespace sylva::forest
