// Cutout polygons (cutout.h): convex, at most k vertices, counter-clockwise, containing every
// covered texel, and cheaper than the frame.
#include "stages/impostor/cutout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sylva::impostor {
namespace {

using P = std::array<double, 2>;

// (u, 1 - v): y up, where the polygon is counter-clockwise.
P up(const P& uv) { return {uv[0], 1 - uv[1]}; }

double cross(const P& o, const P& a, const P& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

bool inside(const std::vector<P>& poly, const P& q) {
  for (std::size_t i = 0; i < poly.size(); ++i)
    if (cross(up(poly[i]), up(poly[(i + 1) % poly.size()]), up(q)) < -1e-9) return false;
  return true;
}

image::Image disc(int size, double cx, double cy, double r) {
  image::Image img(size, size, {0, 0, 0, 0});
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) < r) img.set(x, y, {255, 255, 255, 255});
  return img;
}

TEST(Cutout, HugsADiscWithAConvexPolygon) {
  const image::Image img = disc(64, 30, 34, 20);
  for (int k : {4, 6, 8}) {
    const CutoutResult c = fit_cutout(img, {0, 0, 64, 64}, k);
    ASSERT_LE(c.polygon.size(), std::size_t(k));
    ASSERT_GE(c.polygon.size(), 3u);
    for (std::size_t i = 0; i < c.polygon.size(); ++i)  // convex, counter-clockwise
      EXPECT_GT(cross(up(c.polygon[i]), up(c.polygon[(i + 1) % c.polygon.size()]),
                      up(c.polygon[(i + 2) % c.polygon.size()])),
                0);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        if (img.at(x, y).a == 0) continue;
        for (double dx : {0.0, 1.0})
          for (double dy : {0.0, 1.0})
            EXPECT_TRUE(inside(c.polygon, {(x + dx) / 64, (y + dy) / 64})) << k << " " << x << "," << y;
      }
    EXPECT_GT(c.area_fraction, std::numbers::pi * 400 / 4096);
    EXPECT_LT(c.area_fraction, k == 4 ? 0.45 : 0.40);
  }
  // More vertices hug tighter.
  EXPECT_LT(fit_cutout(img, {0, 0, 64, 64}, 8).area_fraction,
            fit_cutout(img, {0, 0, 64, 64}, 4).area_fraction);
}

// Only the rectangle's own texels count; an empty frame is the whole frame.
TEST(Cutout, WorksInItsRectangleAndFallsBackToTheFrame) {
  image::Image img(32, 16, {0, 0, 0, 0});
  img.set(20, 4, {0, 0, 0, 255});
  const CutoutResult empty = fit_cutout(img, {0, 0, 16, 16}, 8);
  EXPECT_DOUBLE_EQ(empty.area_fraction, 1.0);
  ASSERT_EQ(empty.polygon.size(), 4u);
  const CutoutResult one = fit_cutout(img, {16, 0, 16, 16}, 8);
  EXPECT_NEAR(one.area_fraction, 1.0 / 256, 1e-12);  // exactly texel (4, 4)
  EXPECT_THROW(fit_cutout(img, {0, 0, 16, 16}, 2), std::invalid_argument);
}

// A crown (a disc) over a trunk (a narrow bar to the bottom, beside the disc's centre): split
// into a crown polygon and a trunk polygon that together contain every covered texel, do not
// overlap (the trunk polygon lies below the crown polygon) and cost far less than one polygon;
// the trunk polygon is no wider at the bottom than the trunk and a texel.
TEST(Cutout, SplitsACrownFromItsTrunk) {
  image::Image img = disc(128, 56, 44, 36);
  for (int y = 70; y < 128; ++y)
    for (int x = 70; x < 76; ++x) img.set(x, y, {255, 255, 255, 255});
  const CutoutResult one = fit_cutout(img, {0, 0, 128, 128}, 8);
  const SplitCutout two = fit_split_cutout(img, {0, 0, 128, 128}, 8);
  ASSERT_FALSE(two.lower.empty());
  EXPECT_LE(two.upper.size(), 8u);
  EXPECT_LE(two.lower.size(), 4u);
  EXPECT_LT(two.area_fraction, 0.85 * one.area_fraction);
  double upper_bottom = 0, lower_top = 1, bottom_lo = 1, bottom_hi = 0;
  for (const P& q : two.upper) upper_bottom = std::max(upper_bottom, q[1]);
  for (const P& q : two.lower) lower_top = std::min(lower_top, q[1]);
  EXPECT_LE(upper_bottom, lower_top + 1e-12);  // no texel of the frame lies in both
  for (const P& q : two.lower)
    if (q[1] > 1 - 1.5 / 128) bottom_lo = std::min(bottom_lo, q[0]), bottom_hi = std::max(bottom_hi, q[0]);
  EXPECT_LE((bottom_hi - bottom_lo) * 128, 6 + 1 + 1e-9);
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      if (img.at(x, y).a > 0) {
        const P q{(x + 0.5) / 128, (y + 0.5) / 128};
        EXPECT_TRUE(inside(two.upper, q) || inside(two.lower, q)) << x << ", " << y;
      }
}

}  // namespace
}  // namespace sylva::impostor
