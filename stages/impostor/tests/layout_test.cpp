// The atlas layout (layout.h): frames fit the bounding sphere inside their padding, the grid and
// card placement, and one clear error per impossible parameter set.
#include "stages/impostor/layout.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "libs/impostor/octahedral.h"

namespace sylva::impostor {
namespace {

SourceGeometry tree_like() {
  SourceGeometry g;
  g.bounds_min = {-4, 0, -3};
  g.bounds_max = {5, 12, 4};
  g.center = {0.5, 6, 0.5};
  g.radius = std::sqrt(4.5 * 4.5 + 6 * 6 + 3.5 * 3.5);
  g.horizontal_radius = std::sqrt(4.5 * 4.5 + 3.5 * 3.5);
  return g;
}

// Where a point lands in a view's rectangle (pixels, y down).
Eigen::Vector2d project(const render::BakeView& v, const Vec3& p) {
  const Vec3 a = p - v.center.cast<double>();
  const double s = a.dot(v.right.cast<double>()) / v.half_width,
               t = a.dot(v.up.cast<double>()) / v.half_height;
  return {v.x + (s + 1) * 0.5 * v.w, v.y + (1 - t) * 0.5 * v.h};
}

// Every point of the bounding sphere projects into its frame at least the padding away from the
// frame's border, from every frame: nothing is clipped, not even the crown top seen from the side.
TEST(Layout, FramesFitTheSphereInsideThePadding) {
  const SourceGeometry g = tree_like();
  for (Kind kind : {Kind::kHemiOctahedral, Kind::kOctahedral}) {
    LayoutParams p;
    p.kind = kind;
    p.frames_per_side = 8;
    p.frame_px = 128;
    p.mip_levels = 3;
    const Layout l = plan_layout(p, g);
    ASSERT_EQ(l.views.size(), 64u);
    EXPECT_EQ(l.padding_px, 8);
    const Vec3 c(g.center[0], g.center[1], g.center[2]);
    for (const render::BakeView& v : l.views)
      for (int a = 0; a < 360; a += 15)
        for (int e = -90; e <= 90; e += 15) {
          const double az = a * std::numbers::pi / 180, el = e * std::numbers::pi / 180;
          const Vec3 p3 =
              c + g.radius * Vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
          const Eigen::Vector2d q = project(v, p3);
          EXPECT_GE(q.x(), v.x + 8 - 1e-6);
          EXPECT_LE(q.x(), v.x + v.w - 8 + 1e-6);
          EXPECT_GE(q.y(), v.y + 8 - 1e-6);
          EXPECT_LE(q.y(), v.y + v.h - 8 + 1e-6);
        }
  }
}

// Frame (i, j) sits at pixel (i F, j F) and looks from frame_direction(i, j); the fallback cards
// are the frames nearest the four cardinal horizon directions.
TEST(Layout, OctahedralGridAndFallbackCards) {
  LayoutParams p;  // defaults: hemi, 16 x 16 x 256, mip 4
  const Layout l = plan_layout(p, tree_like());
  EXPECT_EQ(l.atlas_width, 4096);
  EXPECT_EQ(l.atlas_height, 4096);
  EXPECT_EQ(l.padding_px, 16);
  EXPECT_NEAR(l.frame_half_extent, tree_like().radius * 256 / 224, 1e-9);
  const render::BakeView& v = l.views[3 * 16 + 5];
  EXPECT_EQ(v.x, 5 * 256);
  EXPECT_EQ(v.y, 3 * 256);
  EXPECT_LT((v.dir.cast<double>() - frame_direction(5, 3, 16, true)).norm(), 1e-6);
  ASSERT_EQ(l.cards.size(), 4u);
  EXPECT_EQ(l.cards[0].name, "az0");
  EXPECT_EQ(l.card_view[0], 15);  // frame (15, 0): azimuth 0 exactly
  EXPECT_EQ(l.cards[1].name, "az90");
  EXPECT_EQ(l.card_view[1], 15 * 16 + 15);  // frame (15, 15): azimuth 90
  p.kind = Kind::kOctahedral;
  const Layout full = plan_layout(p, tree_like());
  ASSERT_EQ(full.cards.size(), 4u);
  EXPECT_LT(std::abs(full.cards[0].dir[1]), 0.1);  // the frame nearest the horizon at azimuth 0
}

// Billboards: 8 vertical cards 45° apart around the axis and the top card, 3 x 3 frames.
TEST(Layout, BillboardRing) {
  LayoutParams p;
  p.kind = Kind::kBillboards;
  const SourceGeometry g = tree_like();
  const Layout l = plan_layout(p, g);
  ASSERT_EQ(l.views.size(), 9u);
  EXPECT_EQ(l.atlas_width, 768);
  EXPECT_EQ(l.atlas_height, 768);
  for (int k = 0; k < 8; ++k) {
    const double a = k * std::numbers::pi / 4;
    EXPECT_LT((l.views[std::size_t(k)].dir.cast<double>() - Vec3(std::sin(a), 0, std::cos(a))).norm(), 1e-6);
  }
  EXPECT_EQ(l.cards[2].name, "az90");
  EXPECT_EQ(l.cards[8].name, "top");
  EXPECT_NEAR(l.views[8].half_width, g.horizontal_radius * 256 / 224, 1e-4);
  p.top_card = false;
  EXPECT_EQ(plan_layout(p, g).views.size(), 8u);
}

TEST(Layout, ImpossibleParametersAreRefused) {
  auto error = [](LayoutParams p) {
    try {
      plan_layout(p, tree_like());
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  LayoutParams p;
  p.mip_levels = 6;
  EXPECT_EQ(error(p), "mip_levels 6 needs a padding of 64 texels, more than a quarter of frame_px 256");
  p = {};
  p.frames_per_side = 80;
  EXPECT_EQ(error(p), "frames_per_side must be in 2..64");
  p = {};
  p.frames_per_side = 64;
  p.frame_px = 512;
  EXPECT_EQ(error(p), "the atlas (frames_per_side x frame_px = 32768 px) is larger than 16384 px");
  EXPECT_THROW(measure(render::Scene{}), std::invalid_argument);
}

}  // namespace
}  // namespace sylva::impostor
