// Coverage-preserving alpha mipmaps (alpha_mips.h; Castaño 2010).
#include "libs/image/alpha_mips.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace sylva::image {

namespace {

const std::array<float, 256>& srgb_to_linear_table() {
  static const std::array<float, 256> t = [] {
    std::array<float, 256> a{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      a[static_cast<std::size_t>(i)] =
          static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return a;
  }();
  return t;
}

std::uint8_t linear_to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(s * 255));
}

// Box filter to half size; odd sizes fold their last row/column into the last texel.
Image half(const Image& src, std::vector<double>& alpha) {
  const auto& lin = srgb_to_linear_table();
  const int w = std::max(1, src.width() / 2), h = std::max(1, src.height() / 2);
  Image out(w, h);
  alpha.assign(static_cast<std::size_t>(w) * h, 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = 2 * x, y0 = 2 * y;
      const int x1 = x + 1 == w ? src.width() : std::min(src.width(), x0 + 2);
      const int y1 = y + 1 == h ? src.height() : std::min(src.height(), y0 + 2);
      double r = 0, g = 0, b = 0, a = 0, plain_r = 0, plain_g = 0, plain_b = 0;
      int n = 0;
      for (int yy = y0; yy < y1; ++yy)
        for (int xx = x0; xx < x1; ++xx) {
          const Rgba8 p = src.at(xx, yy);
          const double pa = p.a / 255.0;
          r += lin[p.r] * pa, g += lin[p.g] * pa, b += lin[p.b] * pa, a += pa;
          plain_r += lin[p.r], plain_g += lin[p.g], plain_b += lin[p.b];
          ++n;
        }
      Rgba8 o;
      if (a > 0) {
        o.r = linear_to_srgb(r / a), o.g = linear_to_srgb(g / a), o.b = linear_to_srgb(b / a);
      } else {
        o.r = linear_to_srgb(plain_r / n), o.g = linear_to_srgb(plain_g / n),
        o.b = linear_to_srgb(plain_b / n);
      }
      alpha[static_cast<std::size_t>(y) * w + x] = a / n;
      o.a = static_cast<std::uint8_t>(std::lround(std::clamp(a / n, 0.0, 1.0) * 255));
      out.set(x, y, o);
    }
  return out;
}

double coverage_scaled(const std::vector<double>& alpha, double scale, float cutoff) {
  std::size_t pass = 0;
  for (double a : alpha) {
    const double q = std::round(std::min(1.0, a * scale) * 255) / 255;  // as stored
    pass += q >= cutoff ? 1 : 0;
  }
  return alpha.empty() ? 0.0 : static_cast<double>(pass) / static_cast<double>(alpha.size());
}

}  // namespace

double alpha_coverage(const Image& img, float cutoff) {
  if (img.empty()) return 0;
  std::size_t pass = 0;
  const auto& b = img.bytes();
  for (std::size_t i = 3; i < b.size(); i += 4) pass += b[i] / 255.0 >= cutoff ? 1 : 0;
  return static_cast<double>(pass) / static_cast<double>(img.pixel_count());
}

std::vector<Image> coverage_preserving_mips(const Image& base, float cutoff) {
  std::vector<Image> levels{base};
  if (base.empty()) return levels;
  const double target = cutoff > 0 ? alpha_coverage(base, cutoff) : 0;
  std::vector<double> alpha;
  while (levels.back().width() > 1 || levels.back().height() > 1) {
    Image next = half(levels.back(), alpha);
    if (cutoff > 0) {
      // The smallest scale whose coverage reaches the target (coverage grows with the scale):
      // bisection over [0, 1 / min alpha], as Castaño's rescale.
      double lo = 0, hi = 1;
      while (coverage_scaled(alpha, hi, cutoff) < target && hi < 256) hi *= 2;
      for (int it = 0; it < 24; ++it) {
        const double mid = 0.5 * (lo + hi);
        (coverage_scaled(alpha, mid, cutoff) < target ? lo : hi) = mid;
      }
      // Of hi (coverage >= target) and lo (below), the one closer to the target.
      const double chi = coverage_scaled(alpha, hi, cutoff), clo = coverage_scaled(alpha, lo, cutoff);
      const double scale = std::abs(chi - target) <= std::abs(target - clo) ? hi : lo;
      auto& bytes = next.bytes();
      for (std::size_t i = 0; i < alpha.size(); ++i)
        bytes[4 * i + 3] = static_cast<std::uint8_t>(std::lround(std::min(1.0, alpha[i] * scale) * 255));
    }
    levels.push_back(std::move(next));
  }
  return levels;
}

std::vector<AlphaLevel> box_alpha_mips(const Image& base) {
  std::vector<AlphaLevel> levels;
  if (base.empty()) return levels;
  AlphaLevel l0{base.width(), base.height(), std::vector<float>(base.pixel_count())};
  const auto& b = base.bytes();
  for (std::size_t i = 0; i < l0.alpha.size(); ++i) l0.alpha[i] = b[4 * i + 3] / 255.f;
  levels.push_back(std::move(l0));
  while (levels.back().width > 1 || levels.back().height > 1) {
    const AlphaLevel& p = levels.back();
    AlphaLevel n{std::max(1, p.width / 2), std::max(1, p.height / 2), {}};
    n.alpha.resize(static_cast<std::size_t>(n.width) * n.height);
    const int sx = p.width > 1 ? 2 : 1, sy = p.height > 1 ? 2 : 1;
    for (int y = 0; y < n.height; ++y)
      for (int x = 0; x < n.width; ++x) {
        double s = 0;
        for (int dy = 0; dy < sy; ++dy)
          for (int dx = 0; dx < sx; ++dx)
            s += p.alpha[static_cast<std::size_t>(sy * y + dy) * p.width + sx * x + dx];
        n.alpha[static_cast<std::size_t>(y) * n.width + x] =
            static_cast<float>(std::round(s / (sx * sy) * 255) / 255);
      }
    levels.push_back(std::move(n));
  }
  return levels;
}

namespace {

// Bilinear sample of one level at (u, v) in [0, 1), texel centres at (i + 0.5) / width, REPEAT.
double bilinear(const AlphaLevel& l, double u, double v) {
  const double x = u * l.width - 0.5, y = v * l.height - 0.5;
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const double fx = x - fx0, fy = y - fy0;
  // u, v in [0, 1) put x, y in [-0.5, n - 0.5): the texel before 0 is the last one (REPEAT).
  const int ix = static_cast<int>(fx0), iy = static_cast<int>(fy0);
  const int x0 = ix < 0 ? l.width - 1 : ix, x1 = ix + 1 >= l.width ? 0 : ix + 1;
  const int y0 = iy < 0 ? l.height - 1 : iy, y1 = iy + 1 >= l.height ? 0 : iy + 1;
  auto at = [&](int i, int j) { return l.alpha[static_cast<std::size_t>(j) * l.width + i]; };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
         fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
}

}  // namespace

double sampled_alpha_coverage(const std::vector<AlphaLevel>& mips, double lod, float cutoff, int step) {
  if (mips.empty()) return 0;
  step = std::max(1, step);
  lod = std::max(0.0, lod);
  const std::size_t last = mips.size() - 1;
  const std::size_t l0 = std::min(last, static_cast<std::size_t>(std::floor(lod)));
  const std::size_t l1 = std::min(last, l0 + 1);
  const double t = l0 == last ? 0.0 : lod - std::floor(lod);
  const int w = mips[0].width, h = mips[0].height;
  std::size_t pass = 0, n = 0;
  for (int y = 0; y < h; y += step)
    for (int x = 0; x < w; x += step, ++n) {
      const double u = (x + 0.5) / w, v = (y + 0.5) / h;
      double a = bilinear(mips[l0], u, v);
      if (t > 0) a = (1 - t) * a + t * bilinear(mips[l1], u, v);
      pass += a >= cutoff ? 1 : 0;
    }
  return static_cast<double>(pass) / static_cast<double>(n);
}

}  // namespace sylva::image
