// Dilation (dilate.h) on hand-built frames: colour and normal spread within the band and no
// farther, alpha stays 0, depth of empty texels is the back, frames do not bleed into each other.
#include "stages/impostor/dilate.h"

#include <gtest/gtest.h>

namespace sylva::impostor {
namespace {

TEST(Dilate, SpreadsColourAndNormalWithinTheBandOfItsFrame) {
  image::Image color(16, 8, {0, 0, 0, 0}), nd(16, 8, {0, 0, 0, 0});
  color.set(2, 3, {200, 100, 50, 255});  // frame A: one covered texel
  nd.set(2, 3, {10, 20, 30, 222});
  dilate_frames(color, nd, {{0, 0, 8, 8}, {8, 0, 8, 8}}, 2);
  // Within 2 texels (8-connected): the covered texel's colour and normal, alpha 0, depth 0.
  for (auto [x, y] : {std::pair{4, 3}, {0, 1}, {4, 5}, {3, 4}}) {
    EXPECT_EQ(color.at(x, y), (image::Rgba8{200, 100, 50, 0})) << x << "," << y;
    EXPECT_EQ(nd.at(x, y), (image::Rgba8{10, 20, 30, 0})) << x << "," << y;
  }
  // Three texels away: black, depth 0; the source keeps its own values.
  EXPECT_EQ(color.at(5, 3), (image::Rgba8{0, 0, 0, 0}));
  EXPECT_EQ(nd.at(5, 3), (image::Rgba8{0, 0, 0, 0}));
  EXPECT_EQ(color.at(2, 3), (image::Rgba8{200, 100, 50, 255}));
  EXPECT_EQ(nd.at(2, 3), (image::Rgba8{10, 20, 30, 222}));
  // Frame B (x >= 8) is untouched although texel (8, 3) is within reach across the border.
  for (int y = 0; y < 8; ++y)
    for (int x = 8; x < 16; ++x) EXPECT_EQ(color.at(x, y), (image::Rgba8{0, 0, 0, 0})) << x << "," << y;
}

// The nearest source wins; partly covered texels keep their own colour.
TEST(Dilate, NearestCoveredTexelWins) {
  image::Image color(8, 1, {0, 0, 0, 0}), nd(8, 1, {0, 0, 0, 0});
  color.set(0, 0, {255, 0, 0, 255});
  color.set(7, 0, {0, 0, 255, 40});
  dilate_frames(color, nd, {{0, 0, 8, 1}}, 8);
  EXPECT_EQ(color.at(2, 0).r, 255);
  EXPECT_EQ(color.at(5, 0).b, 255);
  EXPECT_EQ(color.at(7, 0), (image::Rgba8{0, 0, 255, 40}));
  EXPECT_THROW(dilate_frames(color, nd, {{4, 0, 8, 1}}, 2), std::invalid_argument);
  EXPECT_THROW(dilate_frames(color, nd, {{0, 0, 4, 1}, {3, 0, 4, 1}}, 2), std::invalid_argument);
}

}  // namespace
}  // namespace sylva::impostor
