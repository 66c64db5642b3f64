// The forest's ground mesh (stages/forest/ground.h): flat quad without a height map, the terrain's
// bilinear surface at its sample spacing with one, facing up, and a valid glTF.
#include "stages/forest/ground.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libs/gltf/scene.h"

namespace sylva::forest {
namespace {

// Unit normal of triangle t (by winding).
std::array<double, 3> face_normal(const gltf::Primitive& p, std::size_t t) {
  auto v = [&](std::size_t k) {
    const std::size_t i = p.indices[3 * t + k];
    return std::array<double, 3>{p.positions[3 * i], p.positions[3 * i + 1], p.positions[3 * i + 2]};
  };
  const auto a = v(0), b = v(1), c = v(2);
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  std::array<double, 3> n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double& x : n) x /= l;
  return n;
}

TEST(Ground, FlatQuadOfTheExtentWithoutAHeightMap) {
  const gltf::Scene s = ground_scene({}, {-45, -30}, {45, 30});
  EXPECT_TRUE(gltf::validate_scene(s).empty());
  ASSERT_EQ(s.meshes.size(), 1u);
  const gltf::Primitive& p = s.meshes[0].primitives[0];
  EXPECT_EQ(p.positions, (std::vector<float>{-45, 0, -30, 45, 0, -30, -45, 0, 30, 45, 0, 30}));
  EXPECT_EQ(p.indices, (std::vector<std::uint32_t>{0, 2, 1, 1, 2, 3}));
  for (std::size_t t = 0; t < 2; ++t)
    EXPECT_NEAR(face_normal(p, t)[1], 1.0, 1e-12);  // counter-clockwise from above
  for (std::size_t v = 0; v < 4; ++v) EXPECT_EQ(p.normals[3 * v + 1], 1.f);
  EXPECT_EQ(s.materials.at(0).base_color, kGroundColor);
  EXPECT_FALSE(s.materials[0].double_sided);
}

TEST(Ground, FollowsTheHeightMapAtItsSampleSpacing) {
  Terrain t;
  // 3 x 2 samples over [-50, 50] x [-50, 50]: a ridge along x = 0, 10 m high.
  t.field = {3, 2, {0.f, 1.f, 0.f, 0.f, 1.f, 0.f}, -50, -50, 50, 50};
  t.height_min = 0;
  t.height_max = 10;
  const gltf::Scene s = ground_scene(t, {-50, -50}, {50, 50});
  EXPECT_TRUE(gltf::validate_scene(s).empty());
  const gltf::Primitive& p = s.meshes[0].primitives[0];
  ASSERT_EQ(p.vertex_count(), 3u * 2u);  // 2 x 1 cells: the map's spacing (50 m x 100 m)
  EXPECT_EQ(p.indices.size(), 2u * 6u);
  for (std::size_t v = 0; v < p.vertex_count(); ++v) {
    const double x = p.positions[3 * v], z = p.positions[3 * v + 2];
    EXPECT_NEAR(p.positions[3 * v + 1], t.height(x, z), 1e-5) << v;
    EXPECT_GT(p.normals[3 * v + 1], 0.f);
  }
  EXPECT_NEAR(p.positions[3 * 1 + 1], 10.0, 1e-6);                           // the ridge's top
  for (std::size_t f = 0; f < 4; ++f) EXPECT_GT(face_normal(p, f)[1], 0.9);  // slope 11 degrees: facing up
  // Grid capped at kMaxGroundCells per side for a fine map.
  Terrain fine;
  fine.field.cols = fine.field.rows = 1001;
  fine.field.values.assign(1001 * 1001, 0.5f);
  fine.field.x0 = fine.field.z0 = -50;
  fine.field.x1 = fine.field.z1 = 50;
  fine.height_max = 2;
  const gltf::Scene g = ground_scene(fine, {-50, -50}, {50, 50});
  EXPECT_EQ(g.meshes[0].primitives[0].vertex_count(),
            std::size_t(kMaxGroundCells + 1) * (kMaxGroundCells + 1));
}

}  // namespace
}  // namespace sylva::forest
