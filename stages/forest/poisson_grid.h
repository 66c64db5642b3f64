// The background grid of the forest's Poisson-disk sampler (Bridson 2007, "Fast Poisson disk
// sampling in arbitrary dimensions", with a radius per sample; layout.h): cells of
// r_min / sqrt(2) over the area list the samples in them, so a candidate is tested only against
// the samples within reach. Holds sample indices and radii; the positions stay with the caller.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "stages/forest/layout.h"

namespace sylva::forest {

class PoissonGrid {
 public:
  // The area [-width/2, width/2] x [-depth/2, depth/2] (m) for sample radii in [r_min, r_max]
  // (r_min > 0). Throws std::invalid_argument when the grid would need more than 1e8 cells.
  PoissonGrid(double width_m, double depth_m, double r_min, double r_max);

  // Adds sample `index` (an index into the caller's trees, in insertion order) at ground
  // position q (x, z) with radius r.
  void insert(const Point2& q, std::uint32_t index, double r);

  // Whether a candidate at q with radius r lies closer than max(r, r_i) to any sample i;
  // `trees[i]` is sample i.
  bool conflict(const std::vector<PlacedTree>& trees, const Point2& q, double r) const;

 private:
  std::pair<std::size_t, std::size_t> cell_of(const Point2& q) const;

  double cell_, x0_, z0_, r_max_;
  std::size_t gx_, gz_;
  std::vector<std::vector<std::uint32_t>> grid_;
  std::vector<double> r_of_;  // radius per sample
};

}  // namespace sylva::forest
