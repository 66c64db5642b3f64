// Footprint statistics (coverage.h). Plain loops over the bytes: OpenImageIO's statistics are
// over the whole frame, and these are over a mask.
#include "libs/image/coverage.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace sylva::image {

FootprintStats footprint_stats(const Image& ref, const Image& test, double pixel_threshold) {
  FootprintStats s;
  if (ref.width() != test.width() || ref.height() != test.height()) return s;
  const auto& rb = ref.bytes();
  const auto& tb = test.bytes();
  double coverage_sum = 0, coverage_signed = 0, colour_sum = 0, shade_sum = 0;
  std::size_t failing = 0;
  for (std::size_t p = 0; p + 3 < rb.size(); p += 4) {
    if (rb[p + 3] == 0 && tb[p + 3] == 0) continue;
    ++s.footprint_pixels;
    const double signed_change = (int(tb[p + 3]) - int(rb[p + 3])) / 255.0;
    coverage_sum += std::abs(signed_change);
    coverage_signed += signed_change;
    failing += std::abs(signed_change) > pixel_threshold ? 1 : 0;
    double d = 0;
    for (int ch = 0; ch < 3; ++ch) d += std::abs(int(rb[p + ch]) - int(tb[p + ch])) / 255.0;
    colour_sum += d;
    const double shared = std::min(rb[p + 3], tb[p + 3]) / 255.0;
    shade_sum += shared * d;
    s.shade_weight += shared;
  }
  if (s.footprint_pixels == 0) return s;
  const double n = double(s.footprint_pixels);
  s.failing_fraction = double(failing) / n;
  s.coverage_mean_error = coverage_sum / n;
  s.coverage_bias = coverage_signed / n;
  s.colour_mean_error = colour_sum / (3.0 * n);
  if (s.shade_weight > 0) s.shade_mean_error = shade_sum / (3.0 * s.shade_weight);
  return s;
}

}  // namespace sylva::image
