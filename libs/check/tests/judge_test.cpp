// libs/check/judge.h over hand-made images: the statistics are over the footprint (not the
// frame), the bounds are strict, the sentences are the reports' text.
#include "libs/check/judge.h"

#include <gtest/gtest.h>

namespace sylva::check {
namespace {

using image::Image;
using image::Rgba8;

constexpr Rgba8 kClear{0, 0, 0, 0};
constexpr Rgba8 kLeaf{40, 120, 30, 255};

// A 20 x 20 frame whose top-left 10 x 10 block (100 pixels) is covered with `fill`.
Image block(Rgba8 fill) {
  Image img(20, 20, kClear);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) img.set(x, y, fill);
  return img;
}

// `img` with the first n pixels of the block's top row cleared.
Image without(Image img, int n) {
  for (int x = 0; x < n; ++x) img.set(x, 0, kClear);
  return img;
}

TEST(CheckJudge, IdenticalImagesPassWithTheirFootprint) {
  const ViewJudgement j = judge_coverage(block(kLeaf), block(kLeaf), {}, "tree");
  EXPECT_EQ(j.stats.footprint_pixels, 100u);
  EXPECT_EQ(j.stats.failing_fraction, 0);
  EXPECT_EQ(j.stats.coverage_mean_error, 0);
  EXPECT_EQ(j.stats.shade_mean_error, 0);
  EXPECT_TRUE(j.passed());
  EXPECT_EQ(j.failure, "");
}

// 2 of the 100 footprint pixels lose their coverage: 2 % of the footprint (0.5 % of the frame,
// which would pass), above the default 1 %.
TEST(CheckJudge, FailingFractionIsOverTheFootprintNotTheFrame) {
  const ViewJudgement j = judge_coverage(block(kLeaf), without(block(kLeaf), 2), {}, "tree");
  EXPECT_EQ(j.stats.footprint_pixels, 100u);
  EXPECT_DOUBLE_EQ(j.stats.failing_fraction, 0.02);
  EXPECT_DOUBLE_EQ(j.stats.coverage_bias, -0.02);
  EXPECT_FALSE(j.passed());
  EXPECT_EQ(j.failure, "coverage of 2.00% of the tree's 100 pixels changed by more than 0.5 (allowed 1.00%)");
}

TEST(CheckJudge, BoundsAreStrict) {
  // 1 of 100 = exactly the allowed 1 %: passes.
  EXPECT_TRUE(judge_coverage(block(kLeaf), without(block(kLeaf), 1), {}, "tree").passed());
  // A mean change of exactly max_coverage_error passes, a hair above fails.
  image::FootprintStats s;
  s.footprint_pixels = 10;
  s.coverage_mean_error = 0.15;
  EXPECT_EQ(coverage_failure(s, {}, "tree"), "");
  s.coverage_mean_error = 0.1500001;
  EXPECT_EQ(coverage_failure(s, {}, "tree"),
            "mean coverage change over the tree's 10 pixels is 0.1500 (allowed 0.1500)");
}

// Every pixel keeps 60 % of its coverage: no pixel changes by more than delta = 0.5, but the mean
// change 0.4 is above 0.15. The noun is the caller's.
TEST(CheckJudge, MeanCoverageChange) {
  const ViewJudgement j = judge_coverage(block(kLeaf), block({40, 120, 30, 153}), {}, "forest");
  EXPECT_EQ(j.stats.failing_fraction, 0);
  EXPECT_NEAR(j.stats.coverage_mean_error, 0.4, 1e-12);
  EXPECT_EQ(j.failure, "mean coverage change over the forest's 100 pixels is 0.4000 (allowed 0.1500)");
  // With delta = 0.3 every pixel fails, which is reported first.
  CoverageThresholds t;
  t.pixel_threshold = 0.3;
  EXPECT_EQ(judge_coverage(block(kLeaf), block({40, 120, 30, 153}), t, "forest").failure,
            "coverage of 100.00% of the forest's 100 pixels changed by more than 0.3 (allowed 1.00%)");
  // Looser bounds pass the same pair.
  t.max_failing_fraction = 1;
  t.max_coverage_error = 0.4;
  EXPECT_TRUE(judge_coverage(block(kLeaf), block({40, 120, 30, 153}), t, "forest").passed());
}

TEST(CheckJudge, EmptyFootprint) {
  const Image clear(8, 8, kClear);
  EXPECT_TRUE(judge_coverage(clear, clear, {}, "tree").passed());
  CoverageThresholds t;
  t.empty_fails = true;
  const ViewJudgement j = judge_coverage(clear, clear, t, "tree");
  EXPECT_EQ(j.stats.footprint_pixels, 0u);
  EXPECT_EQ(j.failure, "neither render covers a pixel");
  // A footprint of one pixel is judged on coverage as usual.
  Image one = clear;
  one.set(3, 3, kLeaf);
  EXPECT_EQ(judge_coverage(clear, one, t, "tree").failure,
            "coverage of 100.00% of the tree's 1 pixels changed by more than 0.5 (allowed 1.00%)");
}

// Colour is not part of the coverage verdict: the same coverage in another colour passes it, and
// the shade difference says how far the colours are apart (weighted by the shared coverage).
TEST(CheckJudge, ColourIsMeasuredNotJudgedByCoverage) {
  const ViewJudgement j = judge_coverage(block({255, 0, 0, 255}), block({0, 255, 0, 255}), {}, "tree");
  EXPECT_TRUE(j.passed());
  EXPECT_DOUBLE_EQ(j.stats.shade_mean_error, 2.0 / 3);
  EXPECT_DOUBLE_EQ(j.stats.colour_mean_error, 2.0 / 3);
  EXPECT_EQ(colour_failure(j.stats.shade_mean_error, 0.1),
            "mean colour difference where both cover the tree is 0.6667 (allowed 0.1000)");
}

TEST(CheckJudge, ColourBoundFollowsTheBaseline) {
  EXPECT_EQ(colour_bound(0.1, 1.5, -1), 0.1);    // no baseline
  EXPECT_EQ(colour_bound(0.1, 1.5, 0.04), 0.1);  // the guard is the floor
  EXPECT_DOUBLE_EQ(colour_bound(0.1, 1.5, 0.2), 0.3);
  EXPECT_EQ(colour_failure(0.1, 0.1), "");  // strict
  EXPECT_EQ(colour_failure(0.1001, 0.1),
            "mean colour difference where both cover the tree is 0.1001 (allowed 0.1000)");
}

TEST(CheckJudge, MeanColourAgainstTheBaseline) {
  EXPECT_EQ(mean_colour_failure(0.06, 0.05, 0.02, "lod5.glb"), "");
  EXPECT_EQ(mean_colour_failure(0.08, 0.05, 0.02, "lod5.glb"),
            "mean colour difference over the views is 0.0800, more than the lod5.glb's 0.0500 + 0.02");
}

// Images of different sizes give no statistics: the caller reports the mismatch.
TEST(CheckJudge, SizeMismatchHasNoStatistics) {
  const ViewJudgement j = judge_coverage(block(kLeaf), Image(10, 10, kLeaf), {}, "tree");
  EXPECT_EQ(j.stats.footprint_pixels, 0u);
}

}  // namespace
}  // namespace sylva::check
