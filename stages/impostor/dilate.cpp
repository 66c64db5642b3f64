// Multi-source breadth-first dilation inside each frame (dilate.h says why), frames in parallel.
#include "stages/impostor/dilate.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace sylva::impostor {

namespace {

// One frame; touches only texels inside `r`.
void dilate_frame(std::vector<std::uint8_t>& cb, std::vector<std::uint8_t>& nb, std::size_t stride,
                  const PixelRect& r, int band) {
  const std::size_t n = std::size_t(r.w) * std::size_t(r.h);
  std::vector<std::int32_t> source(n, -1);  // per texel of the frame: its source texel (frame-local), -1 none
  std::vector<std::int32_t> dist(n, 0);     // its breadth-first distance from the source
  std::vector<std::int32_t> queue;
  auto at = [&](int lx, int ly) { return (std::size_t(r.y + ly) * stride + std::size_t(r.x + lx)) * 4; };
  for (int ly = 0; ly < r.h; ++ly)
    for (int lx = 0; lx < r.w; ++lx)
      if (cb[at(lx, ly) + 3] > 0) {
        const auto i = std::int32_t(ly * r.w + lx);
        source[std::size_t(i)] = i;
        queue.push_back(i);
      }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::int32_t i = queue[head];
    if (dist[std::size_t(i)] >= band) continue;
    const int lx = i % r.w, ly = i / r.w;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = lx + dx, ny = ly + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= r.w || ny >= r.h) continue;
        const std::size_t j = std::size_t(ny * r.w + nx);
        if (source[j] >= 0) continue;
        source[j] = source[std::size_t(i)];
        dist[j] = dist[std::size_t(i)] + 1;
        queue.push_back(std::int32_t(j));
      }
  }
  for (int ly = 0; ly < r.h; ++ly)
    for (int lx = 0; lx < r.w; ++lx) {
      const std::size_t d = at(lx, ly);
      if (cb[d + 3] > 0) continue;
      nb[d + 3] = 0;  // the back of the sphere: a ray marching through the depth map passes it
      const std::int32_t s = source[std::size_t(ly * r.w + lx)];
      if (s < 0) continue;
      const std::size_t from = at(s % r.w, s / r.w);
      std::memcpy(&cb[d], &cb[from], 3);
      std::memcpy(&nb[d], &nb[from], 3);
    }
}

bool overlap(const PixelRect& a, const PixelRect& b) {
  return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
}

}  // namespace

void dilate_frames(image::Image& color, image::Image& normal_depth, const std::vector<PixelRect>& rects,
                   int band) {
  if (color.width() != normal_depth.width() || color.height() != normal_depth.height())
    throw std::invalid_argument("dilate_frames: the maps differ in size");
  for (std::size_t k = 0; k < rects.size(); ++k) {
    const PixelRect& r = rects[k];
    if (r.x < 0 || r.y < 0 || r.w <= 0 || r.h <= 0 || r.x + r.w > color.width() || r.y + r.h > color.height())
      throw std::invalid_argument("dilate_frames: a frame lies outside the atlas");
    for (std::size_t m = 0; m < k; ++m)
      if (overlap(r, rects[m])) throw std::invalid_argument("dilate_frames: two frames overlap");
  }
  auto& cb = color.bytes();
  auto& nb = normal_depth.bytes();
  const std::size_t stride = std::size_t(color.width());
  // Frames are disjoint and each reads and writes only its own texels, so they run in parallel
  // and the bytes do not depend on the order or the thread count.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rects.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t k = range.begin(); k != range.end(); ++k)
                        dilate_frame(cb, nb, stride, rects[k], band);
                    });
}

}  // namespace sylva::impostor
