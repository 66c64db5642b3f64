// The uniform grid of placed boxes (box_grid.h).
#include "stages/forest/box_grid.h"

namespace sylva::forest {

BoxGrid::BoxGrid(double x0, double z0, double size, double cell_m) : x0_(x0), z0_(z0) {
  const double cell = std::max(cell_m, size / kMaxCells);
  cells_ = std::clamp(int(std::ceil(size / cell)), 1, kMaxCells);
  inv_cell_ = cells_ / size;
  head_.assign(std::size_t(cells_) * std::size_t(cells_), -1);
}

void BoxGrid::insert(const Box3& box) {
  ++count_;
  max_half_x_ = std::max(max_half_x_, 0.5 * (box.max[0] - box.min[0]));
  max_half_z_ = std::max(max_half_z_, 0.5 * (box.max[2] - box.min[2]));
  const int cx = cell_of(0.5 * (box.min[0] + box.max[0]), x0_);
  const int cz = cell_of(0.5 * (box.min[2] + box.max[2]), z0_);
  std::int32_t& head = head_[std::size_t(cz) * std::size_t(cells_) + std::size_t(cx)];
  if (head < 0 || blocks_[std::size_t(head)].count == kBlock) {
    Block b;
    b.next = head;
    head = std::int32_t(blocks_.size());
    blocks_.push_back(b);
  }
  Block& b = blocks_[std::size_t(head)];
  b.items[b.count++] = box;
}

}  // namespace sylva::forest
