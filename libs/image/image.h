// The image type every sylva library exchanges: 8-bit RGBA in memory, rows top to bottom.
//
// Colour channels hold display-encoded (sRGB) values, alpha is straight (not premultiplied).
// This is what the renderer reads back from its framebuffer and what PNG stores, so an Image
// round-trips through write_png/read_image bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sylva::image {

struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

class Image {
 public:
  Image() = default;
  // A width x height image filled with `fill`. Negative sizes are treated as 0.
  Image(int width, int height, Rgba8 fill = {});

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0 || height_ == 0; }
  std::size_t pixel_count() const { return std::size_t(width_) * std::size_t(height_); }

  // (0, 0) is the top-left pixel. No bounds checks beyond an assert.
  Rgba8 at(int x, int y) const;
  void set(int x, int y, Rgba8 c);

  // width*height*4 bytes, row-major, top row first, RGBA.
  const std::vector<std::uint8_t>& bytes() const { return rgba_; }
  std::vector<std::uint8_t>& bytes() { return rgba_; }

  friend bool operator==(const Image&, const Image&) = default;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> rgba_;
};

}  // namespace sylva::image
