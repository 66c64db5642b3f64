// The uniform grid of placed boxes (box_grid.h).
#include "stages/forest/box_grid.h"

#include <cstdlib>
#include <new>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace sylva::forest {

void BoxGrid::FreeChunk::operator()(Block* p) const { std::free(p); }

BoxGrid::BoxGrid(double x0, double z0, double size, double cell_m) : x0_(x0), z0_(z0) {
  const double cell = std::max(cell_m, size / kMaxCells);
  cells_ = std::clamp(int(std::ceil(size / cell)), 1, kMaxCells);
  inv_cell_ = cells_ / size;
  head_.assign(std::size_t(cells_) * std::size_t(cells_), -1);
}

std::int32_t BoxGrid::new_block(std::int32_t next) {
  if (std::size_t(blocks_) / kPerChunk == chunks_.size()) {
    // One huge page's worth, aligned to it, so that the kernel can back it with one.
    void* p = std::aligned_alloc(kChunkBytes, kChunkBytes);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    (void)madvise(p, kChunkBytes, MADV_HUGEPAGE);  // a hint: without it (or refused) only slower
#endif
    chunks_.emplace_back(static_cast<Block*>(p));
  }
  Block* b = new (&block(blocks_)) Block;
  b->next = next;
  return blocks_++;
}

void BoxGrid::insert(const Box3& box) {
  ++count_;
  max_half_x_ = std::max(max_half_x_, 0.5 * (box.max[0] - box.min[0]));
  max_half_z_ = std::max(max_half_z_, 0.5 * (box.max[2] - box.min[2]));
  const int cx = cell_of(0.5 * (box.min[0] + box.max[0]), x0_);
  const int cz = cell_of(0.5 * (box.min[2] + box.max[2]), z0_);
  std::int32_t& head = head_[std::size_t(cz) * std::size_t(cells_) + std::size_t(cx)];
  if (head < 0 || block(head).count == kBlock) head = new_block(head);
  Block& b = block(head);
  b.items[b.count++] = box;
}

}  // namespace sylva::forest
