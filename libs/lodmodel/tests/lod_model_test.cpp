// The LOD error model (libs/lodmodel/lod_model.h) on numbers worked by hand, and the identities
// the pipeline's bytes rely on (the same double whichever way a stage used to spell a formula).
#include "libs/lodmodel/lod_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace sylva::lodmodel {
namespace {

// 45° and 1080 px, the lod and impostor stages' default camera.
const Camera kCamera = camera_from_degrees(45, 1080);

// s(d) = 2 d tan(phi/2) / H: 45° and 1080 px give 0.767 mm per pixel at 1 m.
TEST(LodModel, PixelSizeAt45DegreesAnd1080Rows) {
  EXPECT_EQ(kCamera.fov_y_rad, std::numbers::pi / 4);
  EXPECT_EQ(kCamera.height_px, 1080);
  EXPECT_DOUBLE_EQ(pixel_size(kCamera, 1.0), 2 * std::tan(std::numbers::pi / 8) / 1080);
  EXPECT_NEAR(pixel_size(kCamera, 1.0), 7.670621525427681e-4, 1e-18);
  EXPECT_NEAR(pixel_size(kCamera, 100.0), 0.07670621525427682, 1e-16);
  EXPECT_EQ(pixel_size(kCamera, 0.0), 0.0);
  // Half the rows: pixels twice as large.
  EXPECT_DOUBLE_EQ(pixel_size(camera_from_degrees(45, 540), 1.0), 2 * pixel_size(kCamera, 1.0));
}

// d = epsilon / (delta s(1)): Zhang §6's coarsest epsilon 0.22 m at delta 0.5 px is 573.6 m away.
TEST(LodModel, SwitchDistanceAndItsInverse) {
  EXPECT_NEAR(switch_distance(kCamera, 0.22, 0.5), 573.6171424198477, 1e-9);
  // s(1) = 2 tan(22.5 deg) / 1080; d = eps / (delta s(1)).
  const double s1 = 2 * std::tan(22.5 * std::numbers::pi / 180) / 1080;
  EXPECT_NEAR(switch_distance(camera_from_degrees(45, 1080), 0.1, 0.5), 0.1 / (0.5 * s1), 1e-9);
  EXPECT_NEAR(switch_distance(camera_from_degrees(45, 540), 0.1, 1.0), 0.1 / (1.0 * 2 * s1), 1e-9);
  // At its switch distance a level's epsilon is delta pixels: epsilon = delta s(d).
  for (double eps : {0.001, 0.0047, 0.22}) {
    const double d = switch_distance(kCamera, eps, 0.5);
    EXPECT_NEAR(0.5 * pixel_size(kCamera, d), eps, 1e-15);
    EXPECT_NEAR(spatial_error(kCamera, d, 0.5), eps, 1e-15);
    EXPECT_DOUBLE_EQ(switch_pixel_size(eps, 0.5), pixel_size(kCamera, d));
  }
}

// Degrees and radians: the one conversion, and the spellings it replaced give the same doubles.
TEST(LodModel, DegreeConversionsAgreeWithEverySpelling) {
  EXPECT_EQ(degrees(radians(45)), 45.0);
  EXPECT_EQ(degrees(radians(180)), 180.0);
  for (double deg = 1; deg < 179.5; deg += 0.37) {
    const double rad = radians(deg);
    EXPECT_EQ(rad, deg * std::numbers::pi / 180);
    // tan(phi / 2) as (deg pi / 180) / 2, 0.5 deg pi / 180 and deg pi / 360: one double.
    EXPECT_EQ(tan_half_fov(camera_from_degrees(deg, 1080)), std::tan(0.5 * deg * std::numbers::pi / 180));
    EXPECT_EQ(tan_half_fov(camera_from_degrees(deg, 1080)), std::tan(deg * std::numbers::pi / 360));
    EXPECT_EQ(pixel_size(camera_from_degrees(deg, 720), 1.0), 2 * std::tan(0.5 * rad) / double(720));
  }
}

// The factor between two cameras' switch distances.
TEST(LodModel, DistanceScaleBetweenCamerasAndDeltas) {
  EXPECT_EQ(distance_scale(kCamera, 0.5, kCamera, 0.5), 1.0);
  EXPECT_NEAR(distance_scale(kCamera, 1.0, kCamera, 0.5), 2.0, 1e-15);
  EXPECT_NEAR(distance_scale(camera_from_degrees(45, 540), 0.5, kCamera, 0.5), 2.0, 1e-15);
  // A wider camera to move to (larger pixels): nearer.
  const double k = std::tan(22.5 * std::numbers::pi / 180) / std::tan(30 * std::numbers::pi / 180);
  EXPECT_NEAR(distance_scale(kCamera, 0.5, camera_from_degrees(60, 1080), 0.5), k, 1e-15);
}

// MSFT_screencoverage: pi R^2 / (2 d tan(phi/2))^2, clamped to 1, and its inverses.
TEST(LodModel, ScreenCoverageAndItsInverses) {
  const double r = 7.1, t = tan_half_fov(kCamera);
  const double c = screen_coverage(kCamera, r, 300);
  EXPECT_NEAR(c, 0.00256398476340975, 1e-17);
  EXPECT_EQ(c, screen_coverage(t, r, 300));
  EXPECT_NEAR(c, std::numbers::pi * r * r / std::pow(2 * 300 * t, 2), 1e-17);
  EXPECT_NEAR(coverage_distance(kCamera, r, c), 300.0, 1e-12);
  EXPECT_NEAR(coverage_tan_half_fov(r, c, 300), t, 1e-15);
  // Quadratic falloff: twice as far, a quarter of the screen.
  EXPECT_NEAR(screen_coverage(kCamera, r, 600), c / 4, 1e-17);
  // Nearer than the sphere fills the screen: 1 (a loader never sees more than the whole screen).
  EXPECT_EQ(screen_coverage(kCamera, r, 1.0), 1.0);
  EXPECT_EQ(coverage_distance(kCamera, r, 0.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(coverage_distance(kCamera, r, -1.0), std::numeric_limits<double>::infinity());
}

// R = half the diagonal of the box of every position; 0 without positions.
TEST(LodModel, BoundingRadiusIsHalfTheBoxDiagonal) {
  BoundingBox empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.radius(), 0.0);
  BoundingBox b;
  const std::vector<float> xyz = {0, 0, 0, 2, 3, 6, 1, 1, 1, 9};  // the trailing 9 is no point
  b.extend(xyz);
  EXPECT_FALSE(b.empty());
  EXPECT_EQ(b.radius(), 3.5);  // sqrt(4 + 9 + 36) / 2
  b.extend(-2, 0, 0);
  EXPECT_EQ(b.radius(), 0.5 * std::sqrt(16.0 + 9 + 36));
  BoundingBox point;
  point.extend(1, 2, 3);
  EXPECT_EQ(point.radius(), 0.0);
}

// Drawn alpha: coverage delta * eq. 12, shared by three overlapping lines.
TEST(LodModel, DrawnLineAlpha) {
  EXPECT_NEAR(drawn_line_alpha(0.5, 0.5), 1 - std::cbrt(0.75), 1e-15);
  EXPECT_NEAR(1 - std::pow(1 - drawn_line_alpha(0.5, 0.5), 3), 0.25, 1e-12);  // three lines blend to 0.25
  EXPECT_NEAR(drawn_line_alpha(0.8, 2.0), 1.0, 1e-15);                        // coverage clamps at 1
  EXPECT_NEAR(drawn_line_alpha(0.4, 1.0), 1 - std::cbrt(0.6), 1e-15);         // delta = 1: eq. 12 itself
  EXPECT_EQ(line_alpha(-0.5), 0.0);
  EXPECT_EQ(line_alpha(1.0), 1.0);
  // No cancellation for a needle line's tiny coverage.
  EXPECT_NEAR(line_alpha(3e-16), 1e-16, 1e-30);
  EXPECT_NEAR(line_coverage(line_alpha(0.3)), 0.3, 1e-15);
}

// A line drawn from nearer than its switch distance covers proportionally more of a pixel.
TEST(LodModel, LineAlphaAtAnotherDistance) {
  const double a = line_alpha(0.2);
  EXPECT_NEAR(line_alpha_at(a, 1.0), a, 1e-15);
  EXPECT_NEAR(line_alpha_at(a, 2.0), line_alpha(0.4), 1e-15);
  EXPECT_EQ(line_alpha_at(a, 10.0), 1.0);  // 2.0 of a pixel: capped
  EXPECT_EQ(line_alpha_at(1.0, 0.5), 1.0);
  EXPECT_EQ(line_alpha_at(-0.25, 3.0), 0.0);
}

}  // namespace
}  // namespace sylva::lodmodel
