// card_coverage.h: the atlas cells' measured opacity, the cell a quad shows, and the drawn
// coverage drift between two card sets.
#include "stages/lod/card_coverage.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace sylva::lod {
namespace {

using tree::Vec3;

LeafQuad square(Vec3 centre, double side) {
  tree::Leaf l;
  l.position = tree::to_float(centre - Vec3{0, side / 2, 0});
  l.direction = {0, 1, 0};
  l.normal = {0, 0, 1};
  l.length = static_cast<float>(side);
  l.width = static_cast<float>(side);
  return leaf_quad(l);
}

// A 4 x 2 atlas of 8 x 4 texels (2 x 2 per cell) with a few cells' alpha set: each cell's
// fraction is exact, alpha at the cutoff counts and alpha just below it does not.
TEST(CardCoverage, MeasuresEachCellsOpaqueFraction) {
  tree::Materials m;
  m.atlas_columns = 4;
  m.atlas_rows = 2;
  const int w = 8, h = 4;
  std::vector<std::uint8_t> rgba(4 * w * h, 0);
  auto set_alpha = [&](int x, int y, std::uint8_t a) { rgba[4 * (y * w + x) + 3] = a; };
  // Cell 1 (column 1, row 0: x 2..3, y 0..1): one texel opaque, one just below 128.
  set_alpha(2, 0, 255);
  set_alpha(3, 0, 127);
  // Cell 2: three texels at exactly the cutoff (128 >= 0.5 * 255).
  set_alpha(4, 0, 128);
  set_alpha(5, 0, 128);
  set_alpha(4, 1, 200);
  // Cell 7 (column 3, row 1: x 6..7, y 2..3): all four.
  for (int y = 2; y < 4; ++y)
    for (int x = 6; x < 8; ++x) set_alpha(x, y, 255);
  const std::vector<double> a = measure_cell_opacity(rgba, w, h, m);
  EXPECT_EQ(a, (std::vector<double>{0, 0.25, 0.75, 0, 0, 0, 0, 1}));
  EXPECT_THROW(measure_cell_opacity(rgba, w, h + 1, m), std::invalid_argument);
  EXPECT_THROW(measure_cell_opacity({}, 0, 0, m), std::invalid_argument);

  // A card of variant 2 shows cell 2 and gets its opacity; without a table the tree's coverage.
  tree::Leaf l;
  l.direction = {0, 1, 0};
  l.normal = {0, 0, 1};
  l.length = 1;
  l.width = 1;
  l.variant = 2;
  const LeafQuad q = leaf_quad(l, m);
  EXPECT_EQ(card_opacity(q, m, a), 0.75);
  m.cell_coverage = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f};
  EXPECT_FLOAT_EQ(static_cast<float>(card_opacity(q, m, {})), 0.3f);
  m.cell_coverage.clear();
  EXPECT_EQ(card_opacity(q, m, {}), 1.0);
}

// The same cards draw the same (drift 0); dropping one of two sub-pixel cards far apart halves
// what is drawn (-1/2; the converse +1); a card twice as large at half the opacity draws what the original
// draws; a card that covers its pixels many times over draws little more than one that covers them once.
TEST(CardCoverage, DriftMeasuresWhatTheCardsDraw) {
  const double s = 0.5;  // pixel, m
  const std::vector<LeafQuad> two = {square({0.1, 1.1, 0}, 0.1), square({5.1, 1.1, 0}, 0.1)};
  const std::vector<double> ones = {1, 1};
  EXPECT_EQ(coverage_drift(two, ones, two, ones, s), 0.0);
  const std::vector<LeafQuad> one = {two[0]};
  EXPECT_NEAR(coverage_drift(one, {ones.data(), 1}, two, ones, s), -0.5, 1e-9);  // draws less
  EXPECT_NEAR(coverage_drift(two, ones, one, {ones.data(), 1}, s), 1.0, 1e-9);   // twice as much
  const std::vector<LeafQuad> big = {square({0.1, 1.1, 0}, 0.1 * std::sqrt(2.0))};
  const std::vector<double> half = {0.5};
  EXPECT_NEAR(coverage_drift(big, half, one, {ones.data(), 1}, s), 0.0, 1e-6);  // float sizes
  // 1 - exp(-D / s^2), seen face-on (direction 0): a card of 0.49 x 0.49 m inside one pixel
  // draws 1 - exp(-0.9604) of it; 16 such cards stacked draw 1 - exp(-15.37), not 16 times
  // as much; edge-on (direction 2, azimuth 90 degrees) nothing.
  const std::vector<LeafQuad> single = {square({0.25, 1.25, 0}, 0.49)};
  const std::vector<double> cov = drawn_coverage(single, {ones.data(), 1}, s);
  ASSERT_EQ(cov.size(), 4u);
  EXPECT_NEAR(cov[0], 0.25 * -std::expm1(-0.49 * 0.49 / 0.25), 1e-6);
  EXPECT_NEAR(cov[2], 0.0, 1e-12);
  const std::vector<LeafQuad> stack(16, single[0]);
  const std::vector<double> stack_alpha(16, 1.0);
  const std::vector<double> stacked = drawn_coverage(stack, stack_alpha, s);
  EXPECT_NEAR(stacked[0], 0.25 * -std::expm1(-16 * 0.49 * 0.49 / 0.25), 1e-6);
  EXPECT_THROW(coverage_drift(two, {ones.data(), 1}, two, ones, s), std::invalid_argument);
  EXPECT_THROW(coverage_drift(two, ones, two, ones, 0), std::invalid_argument);
}

}  // namespace
}  // namespace sylva::lod
