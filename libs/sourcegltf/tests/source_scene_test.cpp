#include "libs/sourcegltf/source_scene.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "libs/gltf/writer.h"

namespace sylva::sourcegltf {
namespace {

// A bark quad (two triangles in the plane z = 0, facing +z, no normals) and a leaf triangle with
// normals and uvs, on an alpha-masked, textured material.
tree::SourceGeometry two_parts() {
  tree::SourceGeometry g;
  tree::SourcePrimitive bark;
  bark.name = "tree/br0Trunk";
  bark.material = 0;
  bark.positions = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0}};
  bark.indices = {0, 1, 2, 0, 2, 3};
  tree::SourcePrimitive leaf;
  leaf.name = "tree/lf1";
  leaf.material = 1;
  leaf.positions = {{0, 2, 0}, {0.5f, 2, 0}, {0, 2.5f, 0}};
  leaf.normals = {{0, 0, 2}, {0, 0, 1}, {0, 0, 1}};  // the first is not unit: renormalised
  leaf.uvs = {{0, 1}, {1, 1}, {0, 0}};
  leaf.indices = {0, 1, 2};
  g.primitives = {bark, leaf};
  tree::SourceMaterial m0;
  m0.name = "Bark";
  m0.base_color = {0.4f, 0.3f, 0.2f, 1};
  tree::SourceMaterial m1;
  m1.name = "Leaf";
  m1.base_color_image = 0;
  m1.alpha_mode = tree::AlphaMode::kMask;
  m1.alpha_cutoff = 0.3f;
  m1.double_sided = true;
  g.materials = {m0, m1};
  g.images = {{"leaf.png", "image/png", std::string("\x89PNG\r\n\x1a\n", 8)}};
  return g;
}

TEST(SourceScene, OnePrimitivePerSourcePrimitiveWithItsMaterialAndImage) {
  const gltf::Scene s = source_scene(two_parts(), "imported");
  ASSERT_EQ(s.nodes.size(), 1u);
  EXPECT_EQ(s.nodes[0].name, "imported");
  EXPECT_EQ(s.roots, std::vector<int>{0});
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].primitives.size(), 2u);
  const gltf::Primitive& bark = s.meshes[0].primitives[0];
  EXPECT_EQ(bark.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 2, 0, 0, 2, 0}));
  EXPECT_EQ(bark.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_TRUE(bark.texcoords.empty());
  EXPECT_EQ(bark.material, 0);
  const gltf::Primitive& leaf = s.meshes[0].primitives[1];
  EXPECT_EQ(leaf.normals, (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}));
  EXPECT_EQ(leaf.texcoords, (std::vector<float>{0, 1, 1, 1, 0, 0}));
  EXPECT_EQ(leaf.material, 1);
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "Bark");
  EXPECT_EQ(s.materials[0].base_color_texture.image, -1);
  EXPECT_EQ(s.materials[1].alpha_mode, gltf::AlphaMode::kMask);
  EXPECT_FLOAT_EQ(s.materials[1].alpha_cutoff, 0.3f);
  EXPECT_TRUE(s.materials[1].double_sided);
  EXPECT_EQ(s.materials[1].base_color_texture.image, 0);
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].bytes, std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(source_triangle_count(two_parts()), 3u);
}

TEST(SourceScene, MissingNormalsAreTheAdjacentFacesAreaWeightedNormal) {
  tree::SourceGeometry g = two_parts();
  // A tent: two faces meeting at the ridge x = 0, one twice the area of the other.
  tree::SourcePrimitive& p = g.primitives[0];
  p.positions = {{0, 0, 0}, {0, 0, 1}, {-1, 1, 0}, {2, 2, 0}};
  p.indices = {0, 2, 1, 1, 3, 0};  // face A normal ~(1,1,0)/√2 (area √2/2), face B ~(-1,1,0)/√2 (area √2)
  const gltf::Scene s = source_scene(g, "t");
  const std::vector<float>& n = s.meshes[0].primitives[0].normals;
  ASSERT_EQ(n.size(), 12u);
  // Ridge vertices: (1,1,0)*1 + (-2,2,0)*1 → (-1,3,0)/√10.
  EXPECT_NEAR(n[0], -1 / std::sqrt(10.0), 1e-6);
  EXPECT_NEAR(n[1], 3 / std::sqrt(10.0), 1e-6);
  EXPECT_NEAR(n[2], 0, 1e-6);
  // Vertex 2 is only on face A, vertex 3 only on face B.
  EXPECT_NEAR(n[6], 1 / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(n[7], 1 / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(n[9], -1 / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(n[10], 1 / std::sqrt(2.0), 1e-6);
}

TEST(SourceScene, AppendingOffsetsMaterialAndImageIndices) {
  gltf::Scene s = source_scene(two_parts(), "first");
  const int mesh = append_source_mesh(s, two_parts(), "second");
  EXPECT_EQ(mesh, 1);
  EXPECT_EQ(s.materials.size(), 4u);
  EXPECT_EQ(s.images.size(), 2u);
  EXPECT_EQ(s.meshes[1].primitives[0].material, 2);
  EXPECT_EQ(s.meshes[1].primitives[1].material, 3);
  EXPECT_EQ(s.materials[3].base_color_texture.image, 1);
  EXPECT_EQ(s.meshes[1].name, "second");
}

TEST(SourceScene, IsAValidSceneThatEncodesDeterministically) {
  const gltf::Scene s = source_scene(two_parts(), "imported");
  EXPECT_EQ(gltf::validate_scene(s), std::vector<std::string>{});
  EXPECT_EQ(gltf::encode(s), gltf::encode(s));
}

TEST(SourceScene, EmptyGeometryIsRefused) {
  gltf::Scene s;
  try {
    append_source_mesh(s, tree::SourceGeometry{}, "x");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "append_source_mesh: the tree has no source geometry");
  }
}

}  // namespace
}  // namespace sylva::sourcegltf
