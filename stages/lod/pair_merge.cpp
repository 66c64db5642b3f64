// Cuts of the binary forest recorded by pair merging, and the grid of the agglomeration.
// Seeds: Remolar et al. (FSA/VDF), §4 (binary forest, uniform extraction of a level of detail);
// Zhang et al. 2017, §5.5 (a spatial index finds the merging candidates).
#include "stages/lod/pair_merge.h"

namespace sylva::lod {

void GridFrame::set(tree::Vec3 lo, double cell, Coord lo_cell, Coord hi_cell) {
  lo_ = lo;
  cell_ = cell;
  // One spare cell on each side: merged leaves sit a little outside the originals' centres.
  // A dense box: the agglomeration keeps it at most ~67 cells across (pair_merge.h), and every
  // search reads 27 cells, so indexing beats hashing the coordinates.
  for (int i = 0; i < 3; ++i) {
    origin_[i] = lo_cell[i] - 1;
    dims_[i] = hi_cell[i] - lo_cell[i] + 3;
  }
}

void GridFrame::grow_to(const Coord& k, Coord& origin, Coord& dims) {
  for (int i = 0; i < 3; ++i) {
    const std::int64_t first = std::min(origin[i], k[i] - 2);
    const std::int64_t end = std::max(origin[i] + dims[i], k[i] + 3);
    origin[i] = first;
    dims[i] = end - first;
  }
}

double GridFrame::distance_to_cell(tree::Vec3 p, Coord k) const {
  // cell_of() rounds (c - lo) / cell, so a centre may sit a hair outside its nominal box: widen
  // the box by a margin far above that rounding.
  const double margin = 1e-6 * cell_;
  const double q[3] = {p.x - lo_.x, p.y - lo_.y, p.z - lo_.z};
  double d2 = 0;
  for (int i = 0; i < 3; ++i) {
    const double a = static_cast<double>(k[i]) * cell_ - margin,
                 b = static_cast<double>(k[i] + 1) * cell_ + margin;
    const double gap = q[i] < a ? a - q[i] : (q[i] > b ? q[i] - b : 0.0);
    d2 += gap * gap;
  }
  return std::sqrt(d2);
}

std::size_t BinaryForest::roots() const {
  std::size_t r = 0;
  for (std::int32_t p : parent) r += p < 0 ? 1 : 0;
  return r;
}

std::vector<std::uint32_t> BinaryForest::cut_by_merges(std::size_t merges) const {
  const std::size_t limit = original + std::min(merges, size() - original);
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < limit; ++i) {
    const std::int32_t p = parent[i];
    if (p < 0 || static_cast<std::size_t>(p) >= limit) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

std::vector<std::uint32_t> BinaryForest::cut_by_count(std::size_t count) const {
  const std::size_t merges = count >= original ? 0 : original - count;
  return cut_by_merges(merges);
}

std::vector<std::uint32_t> BinaryForest::cut_by_error(double max_error) const {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < size(); ++i) {
    if (error[i] > max_error) continue;
    const std::int32_t p = parent[i];
    if (p < 0 || error[static_cast<std::size_t>(p)] > max_error) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

}  // namespace sylva::lod
