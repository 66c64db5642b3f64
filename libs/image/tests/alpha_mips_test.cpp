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

}  // namespace
}  // namespace sylva::image
