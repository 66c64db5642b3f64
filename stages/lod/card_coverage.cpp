// Atlas opacity per variant and the drawn coverage of card sets (definitions: card_coverage.h).
// Why a raster with an exponential pixel model rather than summed areas: the clusters' survivors
// stand for many overlapping cards, and what a far view shows of them is the union per pixel,
// not the sum; 1 - exp(-D / s^2) is the coverage of randomly placed sub-pixel cards of total
// drawn area D in a pixel, and of one opaque card over the pixel's whole area it is 1 - 1/e
// rather than 1 — the same for both cuts compared, which is all the drift needs.
#include "stages/lod/card_coverage.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "libs/tree/foliage.h"

namespace sylva::lod {

using tree::Vec3;

namespace {

constexpr int kDirections = 4;
constexpr int kMaxPixels = 1024;

// Horizontal view direction at azimuth i * 45 degrees, and the plane's axes: u horizontal, w up.
struct Axes {
  double ux, uz;  // u = (ux, 0, uz); w = (0, 1, 0)
};

Axes axes(int i) {
  const double a = i * 0.25 * 3.14159265358979323846;
  // v = (sin a, 0, cos a); u = (cos a, 0, -sin a).
  return {std::cos(a), -std::sin(a)};
}

struct Box2 {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  void add(double x, double y) {
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
};

void add_box(Box2& box, const Axes& ax, std::span<const LeafQuad> cards) {
  for (const LeafQuad& q : cards)
    for (const Vec3& v : q.v) box.add(ax.ux * v.x + ax.uz * v.z, v.y);
}

// The drawn coverage (m^2) of `cards` on the raster of `box` with pixels of `pixel` m.
double coverage_on(const Box2& box, double pixel, const Axes& ax, std::span<const LeafQuad> cards,
                   std::span<const double> alpha) {
  if (cards.empty() || !(box.x1 >= box.x0)) return 0;
  double s = pixel;
  const double extent = std::max(box.x1 - box.x0, box.y1 - box.y0);
  if (extent / s > kMaxPixels) s = extent / kMaxPixels;
  const int nx = std::max(1, static_cast<int>(std::ceil((box.x1 - box.x0) / s)) + 1);
  const int ny = std::max(1, static_cast<int>(std::ceil((box.y1 - box.y0) / s)) + 1);
  std::vector<double> density(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), 0.0);
  for (std::size_t c = 0; c < cards.size(); ++c) {
    const LeafQuad& q = cards[c];
    std::array<double, 8> p{};
    for (int i = 0; i < 4; ++i) {
      p[2 * i] = ax.ux * q.v[i].x + ax.uz * q.v[i].z - box.x0;
      p[2 * i + 1] = q.v[i].y - box.y0;
    }
    const double area = 0.5 * std::abs((p[4] - p[0]) * (p[7] - p[3]) - (p[5] - p[1]) * (p[6] - p[2]));
    const double drawn = alpha[c] * area;
    if (!(drawn > 0)) continue;
    double edge = 0;
    for (int i = 0; i < 4; ++i) {
      const int j = (i + 1) % 4;
      edge = std::max(edge, std::hypot(p[2 * j] - p[2 * i], p[2 * j + 1] - p[2 * i + 1]));
    }
    const int n = std::clamp(static_cast<int>(std::ceil(2 * edge / s)), 1, 16);
    const double share = drawn / (n * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // Bilinear point (a, b) of the quad p0 p1 p2 p3: p0 -> p1 along b, p0 -> p3 along a.
        const double a = (i + 0.5) / n, b = (j + 0.5) / n;
        const double x = (1 - a) * ((1 - b) * p[0] + b * p[2]) + a * ((1 - b) * p[6] + b * p[4]);
        const double y = (1 - a) * ((1 - b) * p[1] + b * p[3]) + a * ((1 - b) * p[7] + b * p[5]);
        const int px = std::clamp(static_cast<int>(x / s), 0, nx - 1);
        const int py = std::clamp(static_cast<int>(y / s), 0, ny - 1);
        density[static_cast<std::size_t>(py) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(px)] +=
            share;
      }
  }
  const double pixel_area = s * s;
  double sum = 0;
  for (double d : density)
    if (d > 0) sum += -std::expm1(-d / pixel_area);
  return sum * pixel_area;
}

void check_sizes(std::span<const LeafQuad> cards, std::span<const double> alpha, double pixel_m) {
  if (cards.size() != alpha.size())
    throw std::invalid_argument("card coverage: " + std::to_string(alpha.size()) + " opacities for " +
                                std::to_string(cards.size()) + " cards");
  if (!(pixel_m > 0) || !std::isfinite(pixel_m))
    throw std::invalid_argument("card coverage: the pixel size must be a positive number of metres");
}

}  // namespace

std::vector<double> measure_cell_opacity(std::span<const std::uint8_t> rgba, int width, int height,
                                         const tree::Materials& m, double cutoff) {
  if (width <= 0 || height <= 0 ||
      rgba.size() != 4 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument(
        "card opacity: the atlas image is empty or its size disagrees with its texels");
  const std::size_t cells = m.atlas_cells();
  std::vector<double> out(cells, 0.0);
  const double threshold = std::clamp(cutoff, 0.0, 1.0) * 255.0;
  for (std::size_t v = 0; v < cells; ++v) {
    const tree::UvRect r = tree::atlas_cell(m, static_cast<unsigned>(v));
    // Texels whose centres lie in the cell's rectangle.
    const int x0 = std::clamp(static_cast<int>(std::lround(r.u0 * width)), 0, width);
    const int x1 = std::clamp(static_cast<int>(std::lround(r.u1 * width)), 0, width);
    const int y0 = std::clamp(static_cast<int>(std::lround(r.v0 * height)), 0, height);
    const int y1 = std::clamp(static_cast<int>(std::lround(r.v1 * height)), 0, height);
    std::size_t drawn = 0, all = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        ++all;
        drawn += rgba[4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                           static_cast<std::size_t>(x)) +
                      3] >= threshold;
      }
    out[v] = all ? static_cast<double>(drawn) / static_cast<double>(all) : 0.0;
  }
  return out;
}

double card_opacity(const LeafQuad& q, const tree::Materials& m, std::span<const double> per_variant) {
  const double u = 0.25 * (q.uv[0][0] + q.uv[1][0] + q.uv[2][0] + q.uv[3][0]);
  const double v = 0.25 * (q.uv[0][1] + q.uv[1][1] + q.uv[2][1] + q.uv[3][1]);
  const int cols = std::max(1, static_cast<int>(m.atlas_columns));
  const int rows = std::max(1, static_cast<int>(m.atlas_rows));
  const int col = std::clamp(static_cast<int>(std::floor(u * cols)), 0, cols - 1);
  const int row = std::clamp(static_cast<int>(std::floor(v * rows)), 0, rows - 1);
  const auto variant = static_cast<unsigned>(row * cols + col);
  if (!per_variant.empty()) return per_variant[variant % per_variant.size()];
  return tree::cell_coverage(m, variant);
}

std::vector<double> drawn_coverage(std::span<const LeafQuad> cards, std::span<const double> alpha,
                                   double pixel_m) {
  check_sizes(cards, alpha, pixel_m);
  std::vector<double> out;
  for (int d = 0; d < kDirections; ++d) {
    const Axes ax = axes(d);
    Box2 box;
    add_box(box, ax, cards);
    out.push_back(coverage_on(box, pixel_m, ax, cards, alpha));
  }
  return out;
}

double coverage_drift(std::span<const LeafQuad> a, std::span<const double> alpha_a,
                      std::span<const LeafQuad> b, std::span<const double> alpha_b, double pixel_m) {
  check_sizes(a, alpha_a, pixel_m);
  check_sizes(b, alpha_b, pixel_m);
  double drift = 0;
  for (int d = 0; d < kDirections; ++d) {
    const Axes ax = axes(d);
    Box2 box;
    add_box(box, ax, a);
    add_box(box, ax, b);
    const double ca = coverage_on(box, pixel_m, ax, a, alpha_a);
    const double cb = coverage_on(box, pixel_m, ax, b, alpha_b);
    const double rel = cb > 0 ? (ca - cb) / cb : ca > 0 ? 1.0 : 0.0;
    if (std::abs(rel) > std::abs(drift)) drift = rel;
  }
  return drift;
}

}  // namespace sylva::lod
