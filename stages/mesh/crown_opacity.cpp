// Crown opacity of a side view (crown_opacity.h).
#include "stages/mesh/crown_opacity.h"

#include <algorithm>
#include <vector>

namespace sylva::mesh {

CrownOpacity crown_opacity(const image::Image& img) {
  const int w = img.width(), h = img.height();
  const auto& px = img.bytes();
  auto covered = [&](int x, int y) { return px[(static_cast<std::size_t>(y) * w + x) * 4 + 3] >= 128; };
  // Per row: first and last covered column and the count in between.
  std::vector<int> first(h, -1), last(h, -1), count(h, 0);
  int x0 = w, x1 = -1;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!covered(x, y)) continue;
      if (first[y] < 0) first[y] = x;
      last[y] = x;
      ++count[y];
    }
    if (first[y] >= 0) {
      x0 = std::min(x0, first[y]);
      x1 = std::max(x1, last[y]);
    }
  }
  CrownOpacity r;
  if (x1 < x0) return r;
  r.tree_width = x1 - x0 + 1;
  double sum = 0;
  for (int y = 0; y < h; ++y) {
    if (first[y] < 0) continue;
    const int span = last[y] - first[y] + 1;
    if (span <= 0.25 * r.tree_width) continue;
    sum += static_cast<double>(count[y]) / span;
    ++r.crown_rows;
  }
  r.opacity = r.crown_rows > 0 ? sum / r.crown_rows : 0.0;
  return r;
}

}  // namespace sylva::mesh
