#include "libs/image/alpha_mips.h"

#include <gtest/gtest.h>

namespace sylva::image {
namespace {

// A foliage-like mask: small blades (discs of radius 1-4 texels, an LCG places them) covering
// about a third of the image — what a leaf atlas looks like to a coarse mip level.
Image blades(int size) {
  Image img(size, size, {40, 90, 30, 0});
  std::uint32_t s = 12345;
  auto next = [&] { return (s = s * 1664525u + 1013904223u) >> 8; };
  for (int k = 0; k < size * size / 60; ++k) {
    const int cx = static_cast<int>(next() % size), cy = static_cast<int>(next() % size);
    const int r = 1 + static_cast<int>(next() % 4);
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
        if (x >= 0 && y >= 0 && x < size && y < size && (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r)
          img.set(x, y, {60, 120, 40, 255});
  }
  return img;
}

// Every level keeps the base coverage (within 4 points: level 1 of a binary mask has only five
// alpha values); plain box filtering loses most of it
// (the blades average to alpha under the cutoff): that is what the rescale is for.
TEST(AlphaMips, CoveragePreservedOnEveryLevel) {
  const Image base = blades(128);
  const double c0 = alpha_coverage(base, 0.5f);
  EXPECT_GT(c0, 0.25);
  EXPECT_LT(c0, 0.6);
  const std::vector<Image> mips = coverage_preserving_mips(base, 0.5f);
  ASSERT_EQ(mips.size(), 8u);  // 128 .. 1
  EXPECT_EQ(mips[7].width(), 1);
  for (std::size_t l = 1; l + 2 < mips.size(); ++l)  // levels down to 4 x 4 (16 texels)
    EXPECT_NEAR(alpha_coverage(mips[l], 0.5f), c0, 0.04 + 1.0 / mips[l].pixel_count()) << "level " << l;
  const std::vector<Image> plain = coverage_preserving_mips(base, 0);
  EXPECT_LT(alpha_coverage(plain[3], 0.5f), 0.8 * c0);
  EXPECT_LT(alpha_coverage(plain[4], 0.5f), 0.8 * c0);
}

// Colour is averaged weighted by alpha: transparent black texels do not darken the edge.
TEST(AlphaMips, TransparentTexelsDoNotDarken) {
  Image img(2, 2, {0, 0, 0, 0});
  img.set(0, 0, {200, 100, 50, 255});
  const std::vector<Image> mips = coverage_preserving_mips(img, 0.5f);
  ASSERT_EQ(mips.size(), 2u);
  EXPECT_EQ(mips[1].at(0, 0).r, 200);
  EXPECT_EQ(mips[1].at(0, 0).g, 100);
}

// The plain chain as clients build it: 2 x 2 means stored in 8 bits, down to 1 x 1. Sampled at
// lod 0 it is the base's coverage exactly; at lod 1 every sample is the mean of a 2 x 2 block
// (texel centres of level 1 fall between base texels), so a checkerboard of 0 and 1 (mean 1/2,
// stored 128/255) passes a 0.5 cutoff everywhere and a 0.6 cutoff nowhere; between two levels
// the alpha is interpolated linearly.
TEST(AlphaMips, BoxChainAndDrawnCoverage) {
  Image img(4, 2, {0, 0, 0, 0});
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x)
      if ((x + y) % 2 == 0) img.set(x, y, {0, 0, 0, 255});
  const std::vector<AlphaLevel> mips = box_alpha_mips(img);
  ASSERT_EQ(mips.size(), 3u);  // 4x2, 2x1, 1x1
  EXPECT_EQ(mips[1].width, 2);
  EXPECT_EQ(mips[1].height, 1);
  EXPECT_FLOAT_EQ(mips[1].alpha[0], 128 / 255.f);
  EXPECT_EQ(mips[2].width, 1);
  EXPECT_DOUBLE_EQ(sampled_alpha_coverage(mips, 0, 0.5f), 0.5);
  EXPECT_DOUBLE_EQ(sampled_alpha_coverage(mips, 1, 0.5f), 1.0);
  EXPECT_DOUBLE_EQ(sampled_alpha_coverage(mips, 1, 0.6f), 0.0);
  EXPECT_DOUBLE_EQ(sampled_alpha_coverage(mips, 9, 0.5f), 1.0);  // past the last level: 1 x 1
  // Half way from lod 0 to 1: covered texels 0.5 x 1 + 0.5 x 0.502 pass 0.7, gaps (0.251) do not.
  EXPECT_DOUBLE_EQ(sampled_alpha_coverage(mips, 0.5, 0.7f), 0.5);
  // The blades lose coverage on the plain chain as drawn, more than the stored texels show.
  const Image base = blades(128);
  const std::vector<AlphaLevel> chain = box_alpha_mips(base);
  const double c0 = sampled_alpha_coverage(chain, 0, 0.5f);
  EXPECT_NEAR(c0, alpha_coverage(base, 0.5f), 1e-12);
  EXPECT_LT(sampled_alpha_coverage(chain, 3, 0.5f), 0.5 * c0);
}

}  // namespace
}  // namespace sylva::image
