// Mip-safe alpha (mip_safe_alpha.h): a sub-cutoff halo whose gain keeps the coverage drawn from
// plain box-filtered mipmaps closest to the base level's.
#include "stages/generate/mip_safe_alpha.h"

#include <algorithm>
#include <cmath>

#include "libs/image/alpha_mips.h"

namespace sylva::generate {

namespace {

// Two passes of a separable box blur of radius r over one cell's alpha (in [0, 1]); a texel's
// window is clipped to the cell (the mean of the texels inside it), from running sums.
std::vector<double> blur_cell(const std::vector<double>& a, int w, int h, int r) {
  std::vector<double> cur = a, tmp(a.size()), prefix(static_cast<std::size_t>(std::max(w, h)) + 1);
  // One pass along a line of n texels at `at(i)`, written to `put(i, mean)`.
  auto line = [&](int n, auto&& at, auto&& put) {
    prefix[0] = 0;
    for (int i = 0; i < n; ++i)
      prefix[static_cast<std::size_t>(i) + 1] = prefix[static_cast<std::size_t>(i)] + at(i);
    for (int i = 0; i < n; ++i) {
      const int lo = std::max(0, i - r), hi = std::min(n - 1, i + r);
      put(i,
          (prefix[static_cast<std::size_t>(hi) + 1] - prefix[static_cast<std::size_t>(lo)]) / (hi - lo + 1));
    }
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (int y = 0; y < h; ++y)
      line(
          w, [&](int x) { return cur[static_cast<std::size_t>(y) * w + x]; },
          [&](int x, double v) { tmp[static_cast<std::size_t>(y) * w + x] = v; });
    for (int x = 0; x < w; ++x)
      line(
          h, [&](int y) { return tmp[static_cast<std::size_t>(y) * w + x]; },
          [&](int y, double v) { cur[static_cast<std::size_t>(y) * w + x] = v; });
  }
  return cur;
}

image::Image to_image(const Rgba8& px) {
  image::Image img(px.width, px.height);
  img.bytes() = px.pixels;
  return img;
}

// Alpha-test coverage as a client draws the atlas at each level of detail of `lods`
// (sampled_alpha_coverage over the box mipmaps), from about `samples` positions whatever the
// size; from lods[strict] on, against a cutoff 2/255 higher: clients round their coarse levels
// differently (Mesa's 1 x 1 level of an atlas whose mean alpha is 0.4990 is 127/255), so the
// levels where a card is drawn whole or not must clear the cutoff by more than rounding.
// `give_up(l, c)` may stop the measure after level l (the curve is then cut short).
template <class GiveUp>
std::vector<double> drawn_coverage(const Rgba8& px, float cutoff, const std::vector<double>& lods,
                                   std::size_t strict, double samples, GiveUp&& give_up) {
  const std::vector<image::AlphaLevel> mips = image::box_alpha_mips(to_image(px));
  const int step = std::max(1, static_cast<int>(std::sqrt(double(px.width) * px.height / samples)));
  std::vector<double> c;
  for (std::size_t i = 0; i < lods.size(); ++i) {
    c.push_back(image::sampled_alpha_coverage(mips, lods[i], i < strict ? cutoff : cutoff + 2.f / 255, step));
    if (give_up(i, c)) break;
  }
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
  // The search measures from ~2k positions per candidate; the curves reported, from ~8k.
  constexpr double kSearchSamples = 2048, kReportSamples = 8192;
  auto never = [](std::size_t, const std::vector<double>&) { return false; };
  out.coverage_plain = drawn_coverage(atlas, cutoff, out.lods, fitted, kReportSamples, never);
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
  auto apply = [&](const std::vector<double>& halo, double gain, double cap) {
    Rgba8 t = atlas;
    for (std::size_t i = 0; i < halo.size(); ++i) {
      std::uint8_t& a = t.pixels[4 * i + 3];
      // At most `cap`, strictly under the cutoff as stored in 8 bits: invisible at full resolution.
      const double h = std::min({gain * halo[i], cap, cutoff - 1.0 / 255});
      a = std::max<std::uint8_t>(a, static_cast<std::uint8_t>(std::floor(std::max(0.0, h) * 255)));
    }
    return t;
  };
  // The error of a coverage curve: the mean factor, either way, between the coverage drawn at
  // the fitted levels of detail and the base level's (mean |ln(c / c0)|, thinning and thickening
  // by the same factor weighing the same; a level where the cards vanish is infinitely wrong);
  // past the fitted levels, where a card is drawn whole or not at all, cards must be drawn
  // (coverage at least the base level's: a denser crown is the lesser error than a bare tree),
  // else the curve counts as worse than any curve that draws them. The mean, not the worst
  // level: the worst is always a coarse level where a card is a pixel or two, and fitting it
  // alone thickens the near levels (hero views) for nothing.
  const double c0 = out.coverage_plain.empty() ? 0 : out.coverage_plain[0];
  auto error = [&](const std::vector<double>& c) {
    double e = 0;
    for (std::size_t l = 1; l < std::min(fitted, c.size()); ++l)
      e += c[l] > 0 && c0 > 0 ? std::abs(std::log(c[l] / c0)) / static_cast<double>(fitted - 1) : HUGE_VAL;
    for (std::size_t l = fitted; l < c.size(); ++l)
      if (c[l] < c0) e += 1e6;
    return e;
  };
  // The blur radius (a third of a cell to a whole cell: the coarse levels average whole cells, so
  // the reserve must reach across the gaps between a twig's leaves), the halo's cap (0.8, 0.9 or
  // 1 x the cutoff: a lower cap keeps a texel next to a leaf from tipping over the cutoff in the
  // first levels, where one leaf texel of four averages (1 + 3 h) / 4) and the gain with the
  // least error. The gain may exceed the cutoff: the halo is clamped, so a larger gain widens the
  // plateau of the halo, not its height. Gains in steps of cutoff / 2, refined to cutoff / 8.
  double best_gain = 0, best_cap = 0, best_error = error(out.coverage_plain);
  int best_radius = 0;
  // A candidate's measure stops as soon as its error cannot beat the best (errors only grow).
  auto hopeless = [&](std::size_t, const std::vector<double>& c) { return error(c) >= best_error; };
  auto consider = [&](int r, const std::vector<double>& halo, double gain, double cap) {
    if (gain <= 0) return;
    const std::vector<double> c =
        drawn_coverage(apply(halo, gain, cap), cutoff, out.lods, fitted, kSearchSamples, hopeless);
    if (c.size() < out.lods.size()) return;
    const double e = error(c);
    if (e < best_error) {
      best_error = e, best_gain = gain, best_cap = cap, best_radius = r;
    }
  };
  for (int r : {std::max(1, cw / 3), std::max(1, cw / 2), cw}) {
    const std::vector<double> halo = blurred(r);
    for (double cap : {0.8 * cutoff, 0.9 * cutoff, 1.0 * cutoff})
      for (int k = 1; k <= 8; ++k) consider(r, halo, cutoff * k / 2.0, cap);
  }
  if (best_gain > 0) {
    const std::vector<double> halo = blurred(best_radius);
    for (double step : {cutoff / 4.0, cutoff / 8.0}) {
      const double g = best_gain;
      for (double d : {-1.0, 1.0}) consider(best_radius, halo, g + d * step, best_cap);
    }
  }
  out.gain = best_gain;
  out.cap = best_cap;
  out.radius = best_radius;
  if (best_gain > 0) atlas = apply(blurred(best_radius), best_gain, best_cap);
  out.coverage = drawn_coverage(atlas, cutoff, out.lods, fitted, kReportSamples, never);
  return out;
}

}  // namespace sylva::generate
