// Mip-safe alpha (mip_safe_alpha.h): a sub-cutoff halo whose gain keeps the coverage drawn from
// plain box-filtered mipmaps closest to the base level's.
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

// Alpha-test coverage as a client draws the atlas at each level of detail of `lods`
// (sampled_alpha_coverage over the box mipmaps), from 4k to 16k positions whatever the size;
// from lods[strict] on, against a cutoff 2/255 higher: clients round their coarse levels
// differently (Mesa's 1 x 1 level of an atlas whose mean alpha is 0.4990 is 127/255), so the
// levels where a card is drawn whole or not must clear the cutoff by more than rounding.
std::vector<double> drawn_coverage(const Rgba8& px, float cutoff, const std::vector<double>& lods,
                                   std::size_t strict) {
  const std::vector<image::AlphaLevel> mips = image::box_alpha_mips(to_image(px));
  const int step = std::max(1, static_cast<int>(std::sqrt(double(px.width) * px.height / 4096.0)));
  std::vector<double> c;
  for (std::size_t i = 0; i < lods.size(); ++i)
    c.push_back(image::sampled_alpha_coverage(mips, lods[i], i < strict ? cutoff : cutoff + 2.f / 255, step));
  return c;
}

}  // namespace

MipSafety make_mip_safe(Rgba8& atlas, int columns, int rows, float cutoff) {
  MipSafety out;
  const int cw = atlas.width / columns, ch = atlas.height / rows;
  // Levels of detail in half steps until a cell is one texel across its short side, and half a
  // step beyond: far trees draw their cards there (a card two or three pixels long).
  for (double lod = 0; lod <= std::log2(std::min(cw, ch)) + 0.5 + 1e-9; lod += 0.5) out.lods.push_back(lod);
  const std::size_t fitted = out.lods.size();
  // Beyond, down to the 1 x 1 level, a texel covers a cell or more: a card is drawn whole or not.
  for (double lod = out.lods.back() + 0.5; lod <= std::log2(std::max(atlas.width, atlas.height)) + 1e-9;
       lod += 0.5)
    out.lods.push_back(lod);
  out.coverage_plain = drawn_coverage(atlas, cutoff, out.lods, fitted);
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
  // The error of a coverage curve: the largest factor, either way, between the coverage drawn at
  // a fitted level of detail and the base level's (|ln(c / c0)|; a level where the cards vanish
  // is infinitely wrong), thinning and thickening by the same factor weighing the same; past the
  // fitted levels, where a card is drawn whole or not at all, cards must be drawn (coverage at
  // least the base level's: a denser crown is the lesser error than a bare tree), else the curve
  // counts as worse than any curve that draws them.
  const double c0 = out.coverage_plain.empty() ? 0 : out.coverage_plain[0];
  auto error = [&](const std::vector<double>& c) {
    double e = 0;
    for (std::size_t l = 1; l < fitted; ++l)
      e = std::max(e, c[l] > 0 && c0 > 0 ? std::abs(std::log(c[l] / c0)) : HUGE_VAL);
    for (std::size_t l = fitted; l < c.size(); ++l)
      if (c[l] < c0) e += 1e6;
    return e;
  };
  // The blur radius (a third of a cell to a whole cell: the coarse levels average whole cells, so
  // the reserve must reach across the gaps between a twig's leaves) and the gain with the least
  // error. The gain may exceed the cutoff: the halo is clamped just under it, so a larger gain
  // widens the plateau of the halo, not its height. Gains in steps of cutoff / 4, then refined
  // to cutoff / 8 around the best.
  double best_gain = 0, best_error = error(out.coverage_plain);
  int best_radius = 0;
  std::vector<double> best = out.coverage_plain;
  auto consider = [&](int r, const std::vector<double>& halo, double gain) {
    const std::vector<double> c = drawn_coverage(apply(halo, gain), cutoff, out.lods, fitted);
    const double e = error(c);
    if (e < best_error) {
      best_error = e, best_gain = gain, best_radius = r, best = c;
    }
  };
  for (int r : {std::max(1, cw / 3), std::max(1, cw / 2), cw}) {
    const std::vector<double> halo = blurred(r);
    for (int k = 1; k <= 16; ++k) consider(r, halo, cutoff * k / 4.0);
  }
  if (best_gain > 0) {
    const std::vector<double> halo = blurred(best_radius);
    const double g = best_gain;
    for (double d : {-1.0, 1.0}) consider(best_radius, halo, g + d * cutoff / 8.0);
  }
  out.gain = best_gain;
  out.radius = best_radius;
  out.coverage = best;
  if (best_gain > 0) atlas = apply(blurred(best_radius), best_gain);
  return out;
}

}  // namespace sylva::generate
