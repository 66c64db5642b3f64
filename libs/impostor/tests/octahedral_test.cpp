// The frame grid's formulas (octahedral.h) on hand-picked directions.
#include "libs/impostor/octahedral.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sylva::impostor {
namespace {

Vec3 azel(double az_deg, double el_deg) {
  const double a = az_deg * std::numbers::pi / 180, e = el_deg * std::numbers::pi / 180;
  return Vec3(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
}

// Encoding then decoding gives the direction back, over the whole sphere (octahedral) and the
// upper hemisphere (hemi).
TEST(Octahedral, EncodeDecodeRoundTrip) {
  for (int az = -180; az <= 180; az += 15)
    for (int el = -90; el <= 90; el += 10) {
      const Vec3 v = azel(az, el);
      EXPECT_LT((decode_direction(encode_direction(v, false), false) - v).norm(), 1e-12) << az << " " << el;
      if (el >= 0) {
        EXPECT_LT((decode_direction(encode_direction(v, true), true) - v).norm(), 1e-12) << az << " " << el;
      }
    }
}

// The hemi square's corners are the four cardinal horizon directions, its centre is straight up.
TEST(Octahedral, HemiCornersAreTheCardinalHorizon) {
  EXPECT_LT((decode_direction(Vec2(1, -1), true) - Vec3::UnitZ()).norm(), 1e-12);   // azimuth 0
  EXPECT_LT((decode_direction(Vec2(1, 1), true) - Vec3::UnitX()).norm(), 1e-12);    // azimuth 90
  EXPECT_LT((decode_direction(Vec2(-1, 1), true) + Vec3::UnitZ()).norm(), 1e-12);   // azimuth 180
  EXPECT_LT((decode_direction(Vec2(-1, -1), true) + Vec3::UnitX()).norm(), 1e-12);  // azimuth 270
  EXPECT_LT((decode_direction(Vec2(0, 0), true) - Vec3::UnitY()).norm(), 1e-12);
  // Every point of the border is on the horizon.
  for (double t = -1; t <= 1; t += 0.125) {
    EXPECT_NEAR(decode_direction(Vec2(t, 1), true).y(), 0, 1e-12);
    EXPECT_NEAR(decode_direction(Vec2(-1, t), true).y(), 0, 1e-12);
  }
  // Octahedral: the centre is up, the corners are straight down.
  EXPECT_LT((decode_direction(Vec2(0, 0), false) - Vec3::UnitY()).norm(), 1e-12);
  EXPECT_LT((decode_direction(Vec2(1, 1), false) + Vec3::UnitY()).norm(), 1e-12);
  EXPECT_LT((decode_direction(Vec2(-1, 1), false) + Vec3::UnitY()).norm(), 1e-12);
}

// A view from below the horizon uses the horizon frame of its azimuth.
TEST(Octahedral, HemiClampsViewsFromBelow) {
  EXPECT_LT((clamp_to_hemisphere(azel(30, -40)) - azel(30, 0)).norm(), 1e-12);
  EXPECT_LT((clamp_to_hemisphere(Vec3(0, -1, 0)) - Vec3::UnitZ()).norm(), 1e-12);
}

// Frames sit on grid vertices: the corner frames of a 16 x 16 hemi grid are the cardinal
// directions, and a view along a frame's direction blends that frame alone (or, on the full
// octahedron's border, which folds onto itself, frames with that same direction).
TEST(Octahedral, FrameDirectionsAndBlending) {
  EXPECT_LT((frame_direction(15, 0, 16, true) - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_LT((frame_direction(15, 15, 16, true) - Vec3::UnitX()).norm(), 1e-12);
  for (bool hemi : {true, false})
    for (int i = 0; i < 16; i += 3)
      for (int j = 0; j < 16; j += 5) {
        const FrameBlend b = blend_frames(frame_direction(i, j, 16, hemi), 16, hemi);
        double w = 0;
        const Vec3 d = frame_direction(i, j, 16, hemi);
        for (int k = 0; k < 3; ++k)
          if ((frame_direction(b.i[k], b.j[k], 16, hemi) - d).norm() < 1e-9) w += b.weight[k];
        EXPECT_NEAR(w, 1.0, 1e-9) << i << " " << j << " hemi " << hemi;
      }
}

// Weights are barycentric: non-negative, summing to one, and the three frames form a triangle
// of one grid cell.
TEST(Octahedral, BlendWeightsAreBarycentric) {
  for (int az = 0; az < 360; az += 7)
    for (int el = 0; el <= 90; el += 9) {
      const FrameBlend b = blend_frames(azel(az, el), 12, true);
      double sum = 0;
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(b.weight[k], 0);
        sum += b.weight[k];
        EXPECT_GE(b.i[k], 0);
        EXPECT_LT(b.i[k], 12);
        EXPECT_GE(b.j[k], 0);
        EXPECT_LT(b.j[k], 12);
      }
      EXPECT_NEAR(sum, 1, 1e-12);
      EXPECT_EQ(std::abs(b.i[1] - b.i[2]) + std::abs(b.j[1] - b.j[2]), 2);  // the cell's diagonal
    }
}

// The basis is orthonormal and right-handed (right x up = dir), +X right and +Y up from the
// front, -Z at the top of a frame from straight above.
TEST(Octahedral, FrameBasis) {
  const FrameBasis front = frame_basis(Vec3::UnitZ());
  EXPECT_LT((front.right - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_LT((front.up - Vec3::UnitY()).norm(), 1e-12);
  const FrameBasis top = frame_basis(Vec3::UnitY());
  EXPECT_LT((top.right - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_LT((top.up + Vec3::UnitZ()).norm(), 1e-12);
  for (int az = 0; az < 360; az += 20)
    for (int el = -80; el <= 80; el += 20) {
      const FrameBasis b = frame_basis(azel(az, el));
      EXPECT_NEAR(b.right.dot(b.up), 0, 1e-12);
      EXPECT_NEAR(b.right.norm(), 1, 1e-12);
      EXPECT_LT((b.right.cross(b.up) - b.dir).norm(), 1e-12);
    }
}

// The view-error factor falls about as 1/N^2 (second order in the frame spacing), and the full
// octahedron (twice the solid angle on the same frames) is coarser than the hemi one.
TEST(Octahedral, ViewErrorFactorFallsWithTheGrid) {
  const double f8 = view_error_factor(8, true), f16 = view_error_factor(16, true),
               f32 = view_error_factor(32, true);
  EXPECT_GT(f8, f16);
  EXPECT_GT(f16, f32);
  EXPECT_NEAR(f8 / f16, 4.0, 0.6);
  EXPECT_NEAR(f16 / f32, 4.0, 0.6);
  EXPECT_GT(view_error_factor(16, false), f16);
  // The 16 x 16 hemi grid: measured 0.0131 (farthest blended frame 18.3°).
  EXPECT_NEAR(f16, 0.0131, 0.0005);
  EXPECT_NEAR(max_blend_angle(16, true) * 180 / std::numbers::pi, 18.3, 0.2);
}

}  // namespace
}  // namespace sylva::impostor
