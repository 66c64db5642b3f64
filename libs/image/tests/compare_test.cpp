#include "libs/image/compare.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva::image {
namespace {

constexpr Rgba8 kBackground{40, 60, 80, 255};
constexpr Rgba8 kSquare{230, 200, 30, 255};

// A w x h image with a filled square [x0, x0+size) x [y0, y0+size).
Image square_at(int w, int h, int x0, int y0, int size) {
  Image img(w, h, kBackground);
  for (int y = y0; y < y0 + size; ++y)
    for (int x = x0; x < x0 + size; ++x) img.set(x, y, kSquare);
  return img;
}

// The 100 x 100 image of a 30 x 30 square at (20, 20) against the same square moved `dx` pixels
// to the right.
CompareResult compare_shifted(int dx, const CompareOptions& options = {}) {
  return compare_images(square_at(100, 100, 20, 20, 30), square_at(100, 100, 20 + dx, 20, 30), options);
}

// Identical images pass with zero error and infinite PSNR.
TEST(Compare, IdenticalPasses) {
  const Image a = square_at(100, 100, 20, 20, 30);
  const CompareResult r = compare_images(a, a);
  EXPECT_TRUE(r.passed);
  EXPECT_TRUE(r.failure.empty());
  EXPECT_EQ(r.failing_pixels, 0u);
  EXPECT_EQ(r.pixels, 10000u);
  EXPECT_EQ(r.max_error, 0.0);
  EXPECT_TRUE(std::isinf(r.psnr));
}

// Shifting a 30x30 square by 4 pixels changes 2 * 4 * 30 = 240 pixels of 10,000: 2.4 % fail,
// more than the 1 % Blender allows.
TEST(Compare, ShiftedObjectFailsWithExpectedFraction) {
  const CompareResult r = compare_shifted(4);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.failing_pixels, 240u);
  EXPECT_DOUBLE_EQ(r.failing_fraction, 0.024);
  EXPECT_EQ(r.failure, "2.40% of pixels differ by more than 0.016 (allowed 1.00%)");
  EXPECT_NEAR(r.max_error, (230 - 40) / 255.0, 1e-6);
  EXPECT_GT(r.psnr, 0);
  EXPECT_FALSE(std::isinf(r.psnr));
}

// A one-pixel shift of the same square fails 60 pixels (0.6 %) and passes the 1 % budget: the
// fraction absorbs edge pixels, the per-pixel threshold does not.
TEST(Compare, OnePixelShiftIsWithinBudget) {
  const CompareResult r = compare_shifted(1);
  EXPECT_TRUE(r.passed) << r.failure;
  EXPECT_EQ(r.failing_pixels, 60u);
  CompareOptions strict;
  strict.max_failing_fraction = 0.005;
  EXPECT_FALSE(compare_shifted(1, strict).passed);
}

// Differences of up to 4/255 (0.0157) are below the 0.016 threshold; 5/255 fail.
TEST(Compare, PerPixelThreshold) {
  const Image ref(10, 10, {100, 100, 100, 255});
  Image small = ref, big = ref;
  for (int x = 0; x < 10; ++x) {
    small.set(x, 0, {104, 100, 100, 255});
    big.set(x, 0, {100, 95, 100, 255});
  }
  EXPECT_EQ(compare_images(ref, small).failing_pixels, 0u);
  const CompareResult r = compare_images(ref, big);
  EXPECT_EQ(r.failing_pixels, 10u);  // pixels, not channels
  EXPECT_FALSE(r.passed);            // 10 % > 1 %
}

// Alpha differences count unless compare_alpha is off.
TEST(Compare, AlphaOptional) {
  const Image ref(4, 4, {1, 2, 3, 255});
  const Image test(4, 4, {1, 2, 3, 0});
  EXPECT_EQ(compare_images(ref, test).failing_pixels, 16u);
  CompareOptions rgb;
  rgb.compare_alpha = false;
  EXPECT_TRUE(compare_images(ref, test, rgb).passed);
}

// Different sizes never pass and say why.
TEST(Compare, SizeMismatch) {
  const CompareResult r = compare_images(Image(8, 8), Image(8, 4));
  EXPECT_FALSE(r.passed);
  EXPECT_TRUE(r.size_mismatch);
  EXPECT_EQ(r.failure, "size mismatch: reference 8x8, test 8x4");
}

// The heat map colours identical, tolerated and failing pixels differently.
TEST(Compare, Heatmap) {
  Image ref(4, 1, {200, 200, 200, 255});
  Image test = ref;
  test.set(1, 0, {202, 200, 200, 255});  // tolerated
  test.set(2, 0, {149, 200, 200, 255});  // fails, error 51/255 = 0.2: red to yellow
  test.set(3, 0, {0, 200, 200, 255});    // fails, error 0.78 >= 0.5: white
  const Image h = diff_heatmap(ref, test);
  ASSERT_EQ(h.width(), 4);
  EXPECT_EQ(h.at(0, 0), (Rgba8{50, 50, 50, 255}));  // dimmed grey of the reference
  EXPECT_EQ(h.at(1, 0).r, 0);
  EXPECT_GT(h.at(1, 0).b, 96);
  EXPECT_EQ(h.at(2, 0).r, 255);
  EXPECT_EQ(h.at(2, 0).b, 0);
  EXPECT_EQ(h.at(3, 0), (Rgba8{255, 255, 255, 255}));
  const Image m = diff_heatmap(Image(2, 2), Image(3, 1));
  EXPECT_EQ(m.width(), 3);
  EXPECT_EQ(m.height(), 2);
  EXPECT_EQ(m.at(2, 0), (Rgba8{255, 0, 255, 255}));
  EXPECT_EQ(m.at(0, 1), (Rgba8{255, 0, 255, 255}));
}

}  // namespace
}  // namespace sylva::image
