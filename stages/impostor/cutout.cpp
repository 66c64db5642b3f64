// Convex hull (Andrew's monotone chain) of the covered texels' corners, then greedy edge removal
// to k vertices (Persson 2009, "Particle trimming"); cutout.h states the guarantees.
#include "stages/impostor/cutout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sylva::impostor {

namespace {

using P = std::array<double, 2>;  // x right, y up (texel units)

double cross(const P& o, const P& a, const P& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Counter-clockwise hull without collinear points.
std::vector<P> convex_hull(std::vector<P> pts) {
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<P> h(2 * pts.size());
  std::size_t k = 0;
  for (const P& p : pts) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p) <= 0) --k;
    h[k++] = p;
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;
}

double polygon_area(const std::vector<P>& poly) {
  double a = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const P& p = poly[i];
    const P& q = poly[(i + 1) % poly.size()];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return 0.5 * a;
}

struct Box {
  double x0, y0, x1, y1;
};

// Removing edge (i, i+1): the lines through (i-1, i) and (i+1, i+2) meet at x. Valid when x lies
// beyond the edge (the added triangle has positive area) and inside `box`.
bool removal(const std::vector<P>& poly, std::size_t i, const Box& box, P& x, double& added) {
  const std::size_t n = poly.size();
  const P& a0 = poly[(i + n - 1) % n];
  const P& a1 = poly[i];
  const P& b0 = poly[(i + 1) % n];
  const P& b1 = poly[(i + 2) % n];
  const double d1x = a1[0] - a0[0], d1y = a1[1] - a0[1];
  const double d2x = b0[0] - b1[0], d2y = b0[1] - b1[1];
  const double den = d1x * d2y - d1y * d2x;
  if (std::abs(den) < 1e-12) return false;  // parallel: they never meet beyond the edge
  const double t = ((b1[0] - a0[0]) * d2y - (b1[1] - a0[1]) * d2x) / den;
  if (!(t > 1.0)) return false;  // the intersection must lie past a1 along a0 -> a1
  x = {a0[0] + t * d1x, a0[1] + t * d1y};
  const double d2n = d2x * d2x + d2y * d2y;
  if (d2n <= 0 || ((x[0] - b1[0]) * d2x + (x[1] - b1[1]) * d2y) / d2n <= 1.0) return false;  // and past b0
  const double eps = 1e-9;
  if (x[0] < box.x0 - eps || x[1] < box.y0 - eps || x[0] > box.x1 + eps || x[1] > box.y1 + eps) return false;
  added = cross(a1, x, b0);  // triangle a1, x, b0 lies outside the edge a1 -> b0 (clockwise)
  added = std::abs(added) * 0.5;
  return true;
}

// The leftmost and rightmost covered texel of every row (-1 when none); row 0 is the top.
struct RowSpans {
  std::vector<int> lo, hi;
};

RowSpans row_spans(const image::Image& color, const PixelRect& r, int alpha_threshold) {
  const auto& b = color.bytes();
  const std::size_t stride = std::size_t(color.width());
  RowSpans s{std::vector<int>(std::size_t(r.h), -1), std::vector<int>(std::size_t(r.h), -1)};
  for (int ly = 0; ly < r.h; ++ly)
    for (int lx = 0; lx < r.w; ++lx)
      if (b[(std::size_t(r.y + ly) * stride + std::size_t(r.x + lx)) * 4 + 3] > alpha_threshold) {
        if (s.lo[std::size_t(ly)] < 0) s.lo[std::size_t(ly)] = lx;
        s.hi[std::size_t(ly)] = lx;
      }
  return s;
}

// The hull of rows [row0, row1) reduced to max_vertices, every new vertex inside the band of
// those rows (x in [0, w]); y grows upward: row ly spans y in [h - ly - 1, h - ly]. Empty when
// the rows cover nothing.
std::vector<P> fit_rows(const RowSpans& s, int row0, int row1, double w, double h, int max_vertices) {
  std::vector<P> pts;
  for (int ly = row0; ly < row1; ++ly) {
    const int lo = s.lo[std::size_t(ly)], hi = s.hi[std::size_t(ly)];
    if (lo < 0) continue;
    const double y0 = h - ly - 1, y1 = h - ly;
    pts.push_back({double(lo), y0});
    pts.push_back({double(lo), y1});
    pts.push_back({double(hi + 1), y0});
    pts.push_back({double(hi + 1), y1});
  }
  std::vector<P> poly = convex_hull(pts);
  if (poly.size() < 3) return {};
  const Box box{0, h - row1, w, h - row0};
  while (int(poly.size()) > max_vertices) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_i = 0;
    P best_x{};
    for (std::size_t i = 0; i < poly.size(); ++i) {
      P x;
      double added = 0;
      if (removal(poly, i, box, x, added) && added < best) best = added, best_i = i, best_x = x;
    }
    if (!std::isfinite(best)) {
      double x0 = w, y0 = h, x1 = 0, y1 = 0;
      for (const P& p : poly)
        x0 = std::min(x0, p[0]), y0 = std::min(y0, p[1]), x1 = std::max(x1, p[0]), y1 = std::max(y1, p[1]);
      poly = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
      break;
    }
    // Replace vertices best_i and best_i + 1 by the intersection.
    const std::size_t n = poly.size(), j = (best_i + 1) % n;
    poly[best_i] = best_x;
    poly.erase(poly.begin() + std::ptrdiff_t(j));
  }
  return poly;
}

std::vector<std::array<double, 2>> to_uv(const std::vector<P>& poly, double w, double h) {
  std::vector<std::array<double, 2>> out;
  for (const P& p : poly)
    out.push_back({std::clamp(p[0] / w, 0.0, 1.0), std::clamp(1.0 - p[1] / h, 0.0, 1.0)});
  return out;
}

}  // namespace

CutoutResult fit_cutout(const image::Image& color, const PixelRect& r, int max_vertices,
                        int alpha_threshold) {
  if (max_vertices < 3 || max_vertices > 16) throw std::invalid_argument("cutout vertices must be in 3..16");
  const double w = r.w, h = r.h;
  std::vector<P> poly = fit_rows(row_spans(color, r, alpha_threshold), 0, r.h, w, h, max_vertices);
  if (poly.empty()) poly = {{0, 0}, {w, 0}, {w, h}, {0, h}};
  CutoutResult out;
  out.area_fraction = polygon_area(poly) / (w * h);
  out.polygon = to_uv(poly, w, h);
  return out;
}

SplitCutout fit_split_cutout(const image::Image& color, const PixelRect& r, int max_vertices,
                             int lower_vertices, int alpha_threshold) {
  if (max_vertices < 3 || max_vertices > 16 || lower_vertices < 3 || lower_vertices > 16)
    throw std::invalid_argument("cutout vertices must be in 3..16");
  const double w = r.w, h = r.h;
  const RowSpans s = row_spans(color, r, alpha_threshold);
  SplitCutout out;
  std::vector<P> whole = fit_rows(s, 0, r.h, w, h, max_vertices);
  if (whole.empty()) {
    out.upper = to_uv({{0, 0}, {w, 0}, {w, h}, {0, h}}, w, h);
    out.area_fraction = 1;
    return out;
  }
  double best = polygon_area(whole);
  std::vector<P> upper = whole, lower;
  // Every boundary between two covered rows: the upper piece above it, the lower below.
  int first = 0, last = r.h - 1;
  while (s.lo[std::size_t(first)] < 0) ++first;
  while (s.lo[std::size_t(last)] < 0) --last;
  for (int row = first + 1; row <= last; ++row) {
    std::vector<P> a = fit_rows(s, 0, row, w, h, max_vertices);
    std::vector<P> b = fit_rows(s, row, r.h, w, h, lower_vertices);
    if (a.empty() || b.empty()) continue;
    const double area = polygon_area(a) + polygon_area(b);
    if (area < best) best = area, upper = std::move(a), lower = std::move(b);
  }
  out.area_fraction = best / (w * h);
  out.upper = to_uv(upper, w, h);
  out.lower = to_uv(lower, w, h);
  return out;
}

}  // namespace sylva::impostor
