// Mip-safe alpha (mip_safe_alpha.h): a sub-cutoff halo whose gain keeps the coverage of plain
// box-filtered mipmaps closest to the base level's.
#include "stages/generate/mip_safe_alpha.h"

#include <algorithm>
#include <cmath>

#include "libs/image/alpha_mips.h"

namespace sylva::generate {

namespace {

// Two passes of a separable box blur of radius r over one cell's alpha (in [0, 1]).
std::vector<double> blur_cell(const std::vector<double>& a, int w, int h, int r) {
  std::vector<double> cur = a, tmp(a.size());
  for (int pass = 0; pass < 2; ++pass) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double s = 0;
        int n = 0;
        for (int k = std::max(0, x - r); k <= std::min(w - 1, x + r); ++k, ++n)
          s += cur[static_cast<std::size_t>(y) * w + k];
        tmp[static_cast<std::size_t>(y) * w + x] = s / n;
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double s = 0;
        int n = 0;
        for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k, ++n)
          s += tmp[static_cast<std::size_t>(k) * w + x];
        cur[static_cast<std::size_t>(y) * w + x] = s / n;
      }
  }
  return cur;
}

image::Image to_image(const Rgba8& px) {
  image::Image img(px.width, px.height);
  img.bytes() = px.pixels;
  return img;
}

std::vector<double> level_coverage(const Rgba8& px, float cutoff, std::size_t levels) {
  const std::vector<image::Image> mips = image::coverage_preserving_mips(to_image(px), 0);
  std::vector<double> c;
  for (std::size_t l = 0; l < std::min(levels, mips.size()); ++l)
    c.push_back(image::alpha_coverage(mips[l], cutoff));
  return c;
}

}  // namespace

MipSafety make_mip_safe(Rgba8& atlas, int columns, int rows, float cutoff) {
  MipSafety out;
  const int cw = atlas.width / columns, ch = atlas.height / rows;
  // Levels while a cell is at least 2 texels across (a card a few pixels wide on screen).
  std::size_t levels = 1;
  for (int s = std::min(cw, ch); s >= 4; s /= 2) ++levels;
  out.coverage_plain = level_coverage(atlas, cutoff, levels);
  // The blurred leaf mask of every texel, cell by cell, for a blur radius.
  auto blurred = [&](int r) {
    std::vector<double> halo(static_cast<std::size_t>(atlas.width) * atlas.height, 0.0);
    for (int cy = 0; cy < rows; ++cy)
      for (int cx = 0; cx < columns; ++cx) {
        std::vector<double> a(static_cast<std::size_t>(cw) * ch);
        for (int y = 0; y < ch; ++y)
          for (int x = 0; x < cw; ++x)
            a[static_cast<std::size_t>(y) * cw + x] =
                atlas.pixels[(static_cast<std::size_t>(cy * ch + y) * atlas.width + cx * cw + x) * 4 + 3] /
                255.0;
        const std::vector<double> b = blur_cell(a, cw, ch, r);
        for (int y = 0; y < ch; ++y)
          for (int x = 0; x < cw; ++x)
            halo[static_cast<std::size_t>(cy * ch + y) * atlas.width + cx * cw + x] =
                b[static_cast<std::size_t>(y) * cw + x];
      }
    return halo;
  };
  auto apply = [&](const std::vector<double>& halo, double gain) {
    Rgba8 t = atlas;
    for (std::size_t i = 0; i < halo.size(); ++i) {
      std::uint8_t& a = t.pixels[4 * i + 3];
      // Strictly under the cutoff, as stored in 8 bits: invisible at full resolution.
      const double h = std::min(gain * halo[i], cutoff - 1.0 / 255);
      a = std::max<std::uint8_t>(a, static_cast<std::uint8_t>(std::floor(std::max(0.0, h) * 255)));
    }
    return t;
  };
  // The blur radius and gain whose levels' coverage stays closest (worst relative error) to the
  // base level's. The gain may exceed the cutoff: the halo is clamped just under it, so a larger
  // gain widens the plateau of the halo, not its height.
  const double c0 = out.coverage_plain.empty() ? 0 : out.coverage_plain[0];
  auto error = [&](const std::vector<double>& c) {
    double e = 0;
    for (std::size_t l = 1; l < c.size(); ++l) e = std::max(e, std::abs(c[l] - c0) / std::max(c0, 1e-9));
    return e;
  };
  double best_gain = 0, best_error = error(out.coverage_plain);
  int best_radius = 0;
  std::vector<double> best = out.coverage_plain;
  for (int r : {std::max(1, cw / 24), std::max(1, cw / 12), std::max(1, cw / 6), std::max(1, cw / 3)}) {
    const std::vector<double> halo = blurred(r);
    for (int k = 1; k <= 16; ++k) {
      const double gain = cutoff * k / 8.0;
      const std::vector<double> c = level_coverage(apply(halo, gain), cutoff, levels);
      const double e = error(c);
      if (e < best_error) {
        best_error = e;
        best_gain = gain;
        best_radius = r;
        best = c;
      }
    }
  }
  out.gain = best_gain;
  out.radius = best_radius;
  out.coverage = best;
  if (best_gain > 0) atlas = apply(blurred(best_radius), best_gain);
  return out;
}

}  // namespace sylva::generate
