// The impostor's error model (error_model.h) on numbers worked by hand.
#include "libs/impostor/error_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sylva::impostor {
namespace {

// s(d) and d = epsilon / (delta s(1)) as docs/lod-model.md writes them: 45°, 1080 px, delta 0.5 px.
TEST(ErrorModel, SwitchDistanceOfTheSummedTerms) {
  const lodmodel::Camera cam{std::numbers::pi / 4, 1080};
  EXPECT_NEAR(lodmodel::pixel_size(cam, 1.0), 2 * std::tan(std::numbers::pi / 8) / 1080, 1e-15);
  const ErrorTerms t{0.05, 0.10, 0.07};
  EXPECT_DOUBLE_EQ(t.epsilon_m(), 0.22);
  // 0.22 m at delta 0.5: 0.22 / (0.5 * 7.6696e-4) = 573.7 m, the lod chain's level-5 distance.
  EXPECT_NEAR(switch_distance(cam, t, 0.5), 573.7, 0.1);
}

// Billboards: 8 cards 45° apart with a top card; the worst view is at the elevation where the
// nearest vertical card (acos(cos e cos 22.5°)) and the top card (90° - e) are equally far:
// tan e = cos 22.5°, e = 42.7°, angle 47.3°. Without the top card a view from above is 90° off.
TEST(ErrorModel, BillboardViewAngle) {
  const double deg = 180 / std::numbers::pi;
  EXPECT_NEAR(billboard_max_view_angle(8, true) * deg, 90 - std::atan(std::cos(std::numbers::pi / 8)) * deg,
              0.02);
  EXPECT_NEAR(billboard_max_view_angle(8, false) * deg, 90, 1e-9);
  EXPECT_LT(billboard_max_view_angle(16, true), billboard_max_view_angle(8, true));
}

}  // namespace
}  // namespace sylva::impostor
