#include "libs/image/image.h"

#include <algorithm>
#include <cassert>

namespace sylva::image {

Image::Image(int width, int height, Rgba8 fill) : width_(std::max(width, 0)), height_(std::max(height, 0)) {
  rgba_.resize(pixel_count() * 4);
  for (std::size_t i = 0; i < pixel_count(); ++i) {
    rgba_[i * 4 + 0] = fill.r;
    rgba_[i * 4 + 1] = fill.g;
    rgba_[i * 4 + 2] = fill.b;
    rgba_[i * 4 + 3] = fill.a;
  }
}

Rgba8 Image::at(int x, int y) const {
  assert(x >= 0 && y >= 0 && x < width_ && y < height_);
  const std::uint8_t* p = &rgba_[(std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 4];
  return {p[0], p[1], p[2], p[3]};
}

void Image::set(int x, int y, Rgba8 c) {
  assert(x >= 0 && y >= 0 && x < width_ && y < height_);
  std::uint8_t* p = &rgba_[(std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 4];
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
  p[3] = c.a;
}

}  // namespace sylva::image
