// merge_coincident_lines (line_merge.h): runs of consecutive coincident segments become one
// segment carrying their normals in drawing order; anything else stays apart.
#include "libs/render/line_merge.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace sylva::render {
namespace {

// Segments (0,0,0)-(1,0,0) drawn `copies` times with normals (0,1,0), (0,0,1), (0,-1,0), ...
// each from its own two vertices (as the lod stage writes its three lines per internode).
Primitive tripled(int copies, float alpha = 0.25f) {
  Primitive p;
  p.topology = Topology::kLines;
  const Vec3 normals[4] = {{0, 1, 0}, {0, 0, 1}, {0, -1, 0}, {0, 0, -1}};
  for (int c = 0; c < copies; ++c) {
    const auto base = std::uint32_t(p.positions.size());
    for (float x : {0.f, 1.f}) {
      p.positions.push_back({x, 0, 0});
      p.normals.push_back(normals[c % 4]);
      p.colors.push_back({1, 1, 1, alpha});
    }
    p.indices.insert(p.indices.end(), {base, base + 1});
  }
  return p;
}

TEST(LineMerge, ThreeCoincidentLinesBecomeOneWithTheirNormalsInOrder) {
  const MergedLines m = merge_coincident_lines(tripled(3));
  EXPECT_EQ(m.source_segments, 3u);
  ASSERT_EQ(m.positions.size(), 2u);
  EXPECT_EQ(m.copies, (std::vector<float>{3, 3}));
  EXPECT_EQ(m.positions[1], Vec3(1, 0, 0));
  EXPECT_EQ(m.normals[0][0], Vec3(0, 1, 0));
  EXPECT_EQ(m.normals[1][1], Vec3(0, 0, 1));
  EXPECT_EQ(m.normals[2][0], Vec3(0, -1, 0));
  EXPECT_EQ(m.colors[0], Vec4(1, 1, 1, 0.25f));
  EXPECT_TRUE(m.texcoords.empty());
}

TEST(LineMerge, LongerRunsContinueInANewSegmentThatRepeatsItsLastNormal) {
  const MergedLines m = merge_coincident_lines(tripled(4));
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.copies, (std::vector<float>{3, 3, 1, 1}));
  for (int j = 0; j < kMaxMergedLines; ++j) EXPECT_EQ(m.normals[std::size_t(j)][2], Vec3(0, 0, -1)) << j;
}

TEST(LineMerge, OnlyConsecutiveIdenticalSegmentsMerge) {
  Primitive p = tripled(2);
  // A different segment between two coincident ones keeps all three apart.
  const auto b = std::uint32_t(p.positions.size());
  p.positions.insert(p.positions.end(), {{0, 1, 0}, {1, 1, 0}});
  p.normals.insert(p.normals.end(), 2, Vec3(0, 0, 1));
  p.colors.insert(p.colors.end(), 2, Vec4(1, 1, 1, 0.25f));
  p.indices = {0, 1, b, b + 1, 2, 3};
  EXPECT_EQ(merge_coincident_lines(p).positions.size(), 6u);
  // Reversed endpoints, another colour or another texcoord: not the same line.
  Primitive r = tripled(2);
  r.indices = {0, 1, 3, 2};
  EXPECT_EQ(merge_coincident_lines(r).positions.size(), 4u);
  Primitive c = tripled(2);
  c.colors[3] = Vec4(1, 1, 1, 0.5f);
  EXPECT_EQ(merge_coincident_lines(c).positions.size(), 4u);
  Primitive t = tripled(2);
  t.texcoords = {{0, 0}, {1, 0}, {0, 0}, {1, 1}};
  EXPECT_EQ(merge_coincident_lines(t).positions.size(), 4u);
  t.texcoords[3] = {1, 0};
  EXPECT_EQ(merge_coincident_lines(t).positions.size(), 2u);
}

TEST(LineMerge, RefusesWhatIsNotLines) {
  Primitive p = tripled(1);
  p.topology = Topology::kTriangles;
  EXPECT_THROW(merge_coincident_lines(p), std::invalid_argument);
  Primitive q = tripled(1);
  q.indices.push_back(0);
  EXPECT_THROW(merge_coincident_lines(q), std::invalid_argument);
}

// A scene of one mesh whose LINES primitive is `p` with a material of `mode`.
Scene scene_with(Primitive p, AlphaMode mode) {
  Scene s;
  Material m;
  m.alpha_mode = mode;
  s.materials.push_back(m);
  p.material = 0;
  Mesh mesh;
  mesh.primitives.push_back(std::move(p));
  mesh.instances.push_back(Mat4::Identity());
  s.meshes.push_back(std::move(mesh));
  return s;
}

TEST(LineMerge, BlendedLineCopiesBecomeOneLineThatCountsThem) {
  Scene s = scene_with(tripled(4), AlphaMode::kBlend);
  merge_line_copies(s);
  const Primitive& p = s.meshes[0].primitives[0];
  EXPECT_EQ(p.topology, Topology::kLines);
  EXPECT_EQ(p.material, 0);
  EXPECT_EQ(p.element_count(), 2u);
  EXPECT_EQ(p.indices, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(p.copies, (std::vector<float>{3, 3, 1, 1}));
  EXPECT_EQ(p.colors, (std::vector<Vec4>(4, Vec4(1, 1, 1, 0.25f))));  // the renderer raises the alpha
  EXPECT_TRUE(p.normals.empty());                                     // LINES are drawn unlit
  EXPECT_EQ(p.positions[3], Vec3(1, 0, 0));
}

TEST(LineMerge, OpaqueMaskedAndLoneLinesStayAsTheyAre) {
  for (AlphaMode mode : {AlphaMode::kOpaque, AlphaMode::kMask}) {
    Scene s = scene_with(tripled(3), mode);
    merge_line_copies(s);
    EXPECT_EQ(s.meshes[0].primitives[0].element_count(), 3u);
    EXPECT_TRUE(s.meshes[0].primitives[0].copies.empty());
  }
  Scene lone = scene_with(tripled(1), AlphaMode::kBlend);
  merge_line_copies(lone);
  EXPECT_EQ(lone.meshes[0].primitives[0].normals.size(), 2u);  // untouched
  EXPECT_TRUE(lone.meshes[0].primitives[0].copies.empty());
}

}  // namespace
}  // namespace sylva::render
