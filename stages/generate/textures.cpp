// Procedural bark and leaf-atlas textures (see textures.h). Periodic value noise and periodic
// cellular noise make the bark tile exactly; the leaf silhouettes are half-width profiles along
// the blade, one family per leaf shape, varied per atlas quadrant.
#include "stages/generate/textures.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace sylva::generate {

namespace {

constexpr double kPi = std::numbers::pi;

double smooth(double t) { return t * t * (3 - 2 * t); }
double clamp01(double v) { return std::clamp(v, 0.0, 1.0); }
double smoothstep(double a, double b, double x) { return smooth(clamp01((x - a) / (b - a))); }

// A periodic lattice of random values: noise(u, v) with u, v in [0, 1) tiles with period 1.
class PeriodicNoise {
 public:
  PeriodicNoise(int pu, int pv, Rng& rng) : pu_(pu), pv_(pv), values_(static_cast<std::size_t>(pu * pv)) {
    for (double& v : values_) v = rng.uniform();
  }
  double at(double u, double v) const {
    const double x = u * pu_, y = v * pv_;
    const double fx = std::floor(x), fy = std::floor(y);
    const int x0 = wrap(static_cast<int>(fx), pu_), y0 = wrap(static_cast<int>(fy), pv_);
    const int x1 = wrap(x0 + 1, pu_), y1 = wrap(y0 + 1, pv_);
    const double tx = smooth(x - fx), ty = smooth(y - fy);
    const double a = val(x0, y0) + (val(x1, y0) - val(x0, y0)) * tx;
    const double b = val(x0, y1) + (val(x1, y1) - val(x0, y1)) * tx;
    return a + (b - a) * ty;
  }

 private:
  // i is at most a few periods outside [0, n): cheaper than two integer divisions per lookup.
  static int wrap(int i, int n) {
    while (i < 0) i += n;
    while (i >= n) i -= n;
    return i;
  }
  double val(int x, int y) const { return values_[static_cast<std::size_t>(y * pu_ + x)]; }
  int pu_, pv_;
  std::vector<double> values_;
};

// Fractal sum of periodic octaves (periods double per octave), normalised to about [0, 1].
class Fbm {
 public:
  Fbm(int pu, int pv, int octaves, Rng& rng) {
    for (int o = 0; o < octaves; ++o) layers_.emplace_back(pu << o, pv << o, rng);
  }
  double at(double u, double v) const {
    double sum = 0, amp = 1, norm = 0;
    for (const auto& l : layers_) {
      sum += amp * l.at(u, v);
      norm += amp;
      amp *= 0.5;
    }
    return sum / norm;
  }

 private:
  std::vector<PeriodicNoise> layers_;
};

// Periodic cellular noise: distances to the nearest and second-nearest feature point, one
// jittered point per cell of an n x m grid that wraps.
class PeriodicCells {
 public:
  PeriodicCells(int n, int m, Rng& rng) : n_(n), m_(m), pts_(static_cast<std::size_t>(n * m)) {
    for (auto& p : pts_) p = {rng.uniform(0.1, 0.9), rng.uniform(0.1, 0.9)};
  }
  // (f1, f2) in cell units.
  std::pair<double, double> at(double u, double v) const {
    const double x = u * n_, y = v * m_;
    const int cx = static_cast<int>(std::floor(x)), cy = static_cast<int>(std::floor(y));
    double f1 = 1e9, f2 = 1e9;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int gx = cx + dx, gy = cy + dy;
        int wx = gx, wy = gy;
        while (wx < 0) wx += n_;
        while (wx >= n_) wx -= n_;
        while (wy < 0) wy += m_;
        while (wy >= m_) wy -= m_;
        const auto& p = pts_[static_cast<std::size_t>(wy * n_ + wx)];
        const double px = gx + p.first, py = gy + p.second;
        const double ex = px - x, ey = (py - y) * 0.6;  // plates taller than wide
        const double d = std::sqrt(ex * ex + ey * ey);
        if (d < f1) {
          f2 = f1;
          f1 = d;
        } else if (d < f2) {
          f2 = d;
        }
      }
    return {f1, f2};
  }

 private:
  int n_, m_;
  std::vector<std::pair<double, double>> pts_;
};

std::uint8_t to_byte(double v) { return static_cast<std::uint8_t>(clamp01(v) * 255.0 + 0.5); }

void put(Rgba8& img, int x, int y, double r, double g, double b, double a) {
  std::uint8_t* p = &img.pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) +
                                 static_cast<std::size_t>(x)) *
                                4];
  p[0] = to_byte(r);
  p[1] = to_byte(g);
  p[2] = to_byte(b);
  p[3] = to_byte(a);
}

struct Rgb {
  double r, g, b;
};
Rgb mix(tree::Color a, tree::Color b, double t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}
Rgb scale(Rgb c, double s) { return {c.r * s, c.g * s, c.b * s}; }

void check_size(int size) {
  if (size < 16 || size > 8192 || (size & (size - 1)) != 0)
    throw std::invalid_argument("texture size must be a power of two in [16, 8192]");
}

}  // namespace

// Leaf silhouettes: half-width of the blade (in [0, 1] of the half-quadrant) at position tau in
// [0, 1] from the blade's base to its tip.
double blade_half_width(LeafShape shape, double tau, const LeafVariant& v) {
  if (tau <= 0 || tau >= 1) return 0;
  const double ovate = std::pow(std::sin(kPi * std::pow(tau, 0.8)), 0.8);
  switch (shape) {
    case LeafShape::kOvate:  // birch: ovate-triangular, serrate
      return v.width * std::pow(std::sin(kPi * std::pow(tau, 0.65)), 0.9) *
             (1 - 0.07 * std::abs(std::sin(kPi * 22 * tau)));
    case LeafShape::kLobed:  // oak: obovate with rounded lobes
      return v.width * std::pow(std::sin(kPi * std::pow(tau, 1.4)), 0.75) *
             (0.5 + 0.5 * std::pow(std::abs(std::cos(kPi * (v.lobes * tau + v.phase))), 0.45));
    case LeafShape::kPalmate:  // white poplar: broad, 3-5 coarse lobes
      return v.width * std::pow(std::sin(kPi * std::pow(tau, 0.55)), 0.7) *
             (0.72 + 0.28 * std::abs(std::cos(kPi * (2.5 * tau + v.phase))));
    case LeafShape::kSpiny: {  // holly: elliptic with spine tips
      const double spines = std::pow(std::max(0.0, std::cos(2 * kPi * (v.lobes * tau + v.phase))), 6);
      return v.width * std::pow(std::sin(kPi * tau), 0.6) * (0.72 + 0.28 * spines);
    }
    case LeafShape::kLanceolate:  // willow: long, narrow, finely serrate
      return v.width * std::pow(std::sin(kPi * std::pow(tau, 0.9)), 1.2) *
             (1 - 0.04 * std::abs(std::sin(kPi * 30 * tau)));
    case LeafShape::kNeedle:
      return v.width * 0.45 * std::min(1.0, (1 - tau) * 6) * std::min(1.0, tau * 12 + 0.4);
  }
  return ovate;
}

tree::Color srgb_to_linear(tree::Color c) {
  auto f = [](float s) {
    const double v = s;
    return static_cast<float>(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
  };
  return {f(c.r), f(c.g), f(c.b)};
}

Rgba8 make_bark_texture(const BarkLook& look, int size, Rng& rng) {
  check_size(size);
  Rgba8 img{size, size, std::vector<std::uint8_t>(static_cast<std::size_t>(size) * size * 4)};
  // Noise fields, all periodic in [0, 1)^2: u across the bark (x), v along it (y).
  const Fbm fine(16, 16, 3, rng);
  const Fbm ridges(7, 1, 3, rng);    // long vertical structures
  const Fbm cracks(14, 2, 2, rng);   // finer vertical cracks
  const Fbm streaks(48, 4, 2, rng);  // fibre grain
  const Fbm warp(4, 4, 2, rng);
  const Fbm dashes(3, 24, 3, rng);  // short horizontal structures (lenticels)
  const PeriodicCells plates(5, 4, rng);
  for (int y = 0; y < size; ++y) {
    const double v = (y + 0.5) / size;
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size;
      const double grain = fine.at(u, v);
      double dark = 0;  // 0 = surface colour, 1 = dark colour
      double shade = 0.85 + 0.3 * grain;
      switch (look.style) {
        case BarkStyle::kFissured: {
          // Valleys where a warped, vertically stretched field crosses its mid level.
          const double w = warp.at(u, v) - 0.5;
          const double f = ridges.at(u + 0.04 * w, v);
          const double fv = (f - 0.5) / 0.03, cv = (cracks.at(u, v) - 0.5) / 0.02;
          const double valley = std::exp(-fv * fv);
          const double crack = 0.6 * std::exp(-cv * cv);
          const double height = clamp01(std::abs(f - 0.5) * 6);  // ridge crest lighter
          dark = clamp01(std::max(valley, crack) + 0.2 * (grain - 0.5));
          shade = (0.75 + 0.3 * height) * (0.9 + 0.2 * streaks.at(u, v));
          break;
        }
        case BarkStyle::kSmooth: {
          dark = 0.25 * smoothstep(0.45, 0.75, warp.at(u, v)) + 0.6 * smoothstep(0.72, 0.8, dashes.at(u, v));
          shade = (0.92 + 0.16 * grain) * (0.95 + 0.1 * streaks.at(u, v));
          break;
        }
        case BarkStyle::kBirch: {
          // White bark, dark horizontal lenticels and a few dark patches.
          const double lent = smoothstep(0.66, 0.74, dashes.at(u, v));
          const double patch = smoothstep(0.68, 0.78, warp.at(u, v * 0.5 + 0.25 * ridges.at(u, v)));
          dark = clamp01(lent + patch);
          shade = 0.9 + 0.2 * grain;
          break;
        }
        case BarkStyle::kScaly: {
          const auto [f1, f2] = plates.at(u, v);
          const double edge = 1 - smoothstep(0.02, 0.12, f2 - f1);
          dark = clamp01(edge + 0.2 * (grain - 0.5));
          shade *= 0.9 + 0.2 * smoothstep(0.0, 0.6, f1);
          break;
        }
      }
      const Rgb c = scale(mix(look.color, look.dark, dark), shade);
      put(img, x, y, c.r, c.g, c.b, 1);
    }
  }
  return img;
}

Rgba8 make_leaf_atlas(const LeafLook& look, int size, Rng& rng, std::vector<float>* coverage) {
  check_size(size);
  Rgba8 img{size, size, std::vector<std::uint8_t>(static_cast<std::size_t>(size) * size * 4)};
  const int q = size / 2;
  const Fbm mottle(8, 8, 2, rng);
  constexpr double kPetiole = 0.14;  // fraction of the card taken by the petiole (low v)
  for (int variant = 0; variant < 4; ++variant) {
    LeafVariant lv;
    lv.width = rng.uniform(0.82, 0.95);
    lv.phase = rng.uniform(0, 0.5);
    lv.bend = rng.uniform(-0.12, 0.12);
    lv.tint = rng.uniform(0.9, 1.1);
    lv.lobes = rng.uniform(3.5, 5.0);
    const int ox = (variant % 2) * q, oy = (variant / 2) * q;
    if (coverage) {
      // The blade's share of the quadrant, integrated from its outline at a fixed resolution
      // (independent of `size`); the petiole is not leaf area.
      constexpr int kRows = 1024;
      double sum = 0;
      for (int y = 0; y < kRows; ++y) {
        const double t = (y + 0.5) / kRows;
        const double tau = (t - kPetiole) / (1 - kPetiole - 0.01);
        const double half = blade_half_width(look.shape, tau, lv), mid = lv.bend * tau * tau;
        if (half > 0) sum += (std::clamp(mid + half, -1.0, 1.0) - std::clamp(mid - half, -1.0, 1.0)) / 2;
      }
      coverage->push_back(static_cast<float>(sum / kRows));
    }
    for (int y = 0; y < q; ++y) {
      const double t = (y + 0.5) / q;  // 0 at the petiole end (top of the quadrant), 1 at the tip
      const double tau = (t - kPetiole) / (1 - kPetiole - 0.01);
      const double mid = lv.bend * tau * tau;
      const double half = blade_half_width(look.shape, tau, lv);  // depends on the row only
      for (int x = 0; x < q; ++x) {
        const double xs = (x + 0.5) / q * 2 - 1;  // [-1, 1] across
        const double dx = xs - mid;
        const double px = 2.0 / q;  // one pixel in xs units
        // Coverage: blade, or petiole (a thin stalk from the top edge down into the blade).
        double a = clamp01((half - std::abs(dx)) / px + 0.5);
        const double stalk = (t < kPetiole + 0.05) ? clamp01((0.035 - std::abs(xs)) / px + 0.5) : 0.0;
        const bool in_stalk = stalk > a;
        a = std::max(a, stalk * clamp01((t - 0.02) / 0.02));
        // Colour: blade with midrib, lateral veins, darker margin, soft mottling.
        double vein = 0;
        if (!in_stalk && half > 0) {
          const double rel = std::abs(dx) / half;
          vein = std::max(vein, clamp01(1 - std::abs(dx) / (0.025 + 0.02 * (1 - tau))));
          const double lateral = std::abs(std::fmod(tau * 7 - rel * 1.2 + 10, 1.0) - 0.5);
          if (look.shape != LeafShape::kNeedle)
            vein = std::max(vein, 0.55 * clamp01(1 - lateral / 0.05) * (1 - rel));
          (void)rel;
        } else {
          vein = 1;
        }
        const double margin = half > 0 ? smoothstep(0.6, 1.0, std::abs(dx) / half) : 0;
        const double shade =
            lv.tint * (0.9 + 0.2 * mottle.at(static_cast<double>(x) / q, t)) * (1 - 0.18 * margin);
        const Rgb c = scale(mix(look.color, look.vein, vein), shade);
        put(img, ox + x, oy + y, c.r, c.g, c.b, a);
      }
    }
  }
  return img;
}

}  // namespace sylva::generate
