// A cell of r_min / sqrt(2) holds at most one sample of the smallest radius, and a candidate
// needs to look only ceil(max(r, r_max) / cell) cells around its own: any sample farther away
// is beyond both radii.
#include "stages/forest/poisson_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sylva::forest {

PoissonGrid::PoissonGrid(double width_m, double depth_m, double r_min, double r_max)
    : cell_(r_min / std::sqrt(2.0)), x0_(-0.5 * width_m), z0_(-0.5 * depth_m), r_max_(r_max) {
  gx_ = std::size_t(std::ceil(width_m / cell_)) + 1;
  gz_ = std::size_t(std::ceil(depth_m / cell_)) + 1;
  // 24 bytes a cell (an empty vector): 1e8 cells are 2.4 GB before any tree.
  if (double(gx_) * double(gz_) > 1e8)
    throw std::invalid_argument("the Poisson grid would need more than 1e8 cells: raise min_spacing_m");
  grid_.resize(gx_ * gz_);
}

std::pair<std::size_t, std::size_t> PoissonGrid::cell_of(const Point2& q) const {
  const auto cx = std::size_t(std::clamp((q[0] - x0_) / cell_, 0.0, double(gx_ - 1)));
  const auto cz = std::size_t(std::clamp((q[1] - z0_) / cell_, 0.0, double(gz_ - 1)));
  return std::pair(cx, cz);
}

void PoissonGrid::insert(const Point2& q, std::uint32_t index, double r) {
  const auto [cx, cz] = cell_of(q);
  grid_[cz * gx_ + cx].push_back(index);
  r_of_.push_back(r);
}

bool PoissonGrid::conflict(const std::vector<PlacedTree>& trees, const Point2& q, double r) const {
  const int reach = int(std::ceil(std::max(r, r_max_) / cell_));
  const auto [cx, cz] = cell_of(q);
  for (int dz = -reach; dz <= reach; ++dz)
    for (int dx = -reach; dx <= reach; ++dx) {
      const long x = long(cx) + dx, z = long(cz) + dz;
      if (x < 0 || z < 0 || x >= long(gx_) || z >= long(gz_)) continue;
      for (std::uint32_t i : grid_[std::size_t(z) * gx_ + std::size_t(x)]) {
        const PlacedTree& t = trees[i];
        const double need = std::max(r, r_of_[i]);
        const double ddx = t.position[0] - q[0], ddz = t.position[2] - q[1];
        if (ddx * ddx + ddz * ddz < need * need) return true;
      }
    }
  return false;
}

}  // namespace sylva::forest
