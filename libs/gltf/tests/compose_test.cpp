// append_scene: indices shifted, equal images and materials shared, roots returned, buffers reset.
#include "libs/gltf/compose.h"

#include <gtest/gtest.h>

namespace sylva::gltf {
namespace {

Scene level(const std::string& image_bytes, float red) {
  Scene s;
  s.images.push_back({"leaves.png", "image/png", image_bytes, "leaves.png"});
  Material m;
  m.name = "leaves";
  m.base_color = {red, 1, 1, 1};
  m.base_color_texture.image = 0;
  s.materials.push_back(m);
  Mesh mesh;
  mesh.buffer = 3;
  Primitive p;
  p.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  p.material = 0;
  p.buffer = 2;
  mesh.primitives.push_back(p);
  s.meshes.push_back(mesh);
  Node child;
  child.mesh = 0;
  Node root;
  root.children = {1};
  s.nodes = {root, child};
  s.roots = {0};
  s.extensions_required = {"KHR_x"};
  return s;
}

TEST(GltfCompose, AppendsWithSharedImagesAndMaterials) {
  Scene into = level("png-a", 1);
  into.extras = {{"sylva_stage", "lod"}};
  const std::vector<int> same = append_scene(into, level("png-a", 1));
  EXPECT_EQ(same, std::vector<int>{2});
  EXPECT_EQ(into.images.size(), 1u);     // equal image shared
  EXPECT_EQ(into.materials.size(), 1u);  // equal material shared
  ASSERT_EQ(into.meshes.size(), 2u);
  EXPECT_EQ(into.nodes[2].children, std::vector<int>{3});
  EXPECT_EQ(into.nodes[3].mesh, 1);
  EXPECT_EQ(into.meshes[1].buffer, 0);
  EXPECT_EQ(into.meshes[1].primitives[0].buffer, -1);
  EXPECT_EQ(into.roots, std::vector<int>{0});  // roots are the caller's
  EXPECT_EQ(into.extensions_required, std::vector<std::string>{"KHR_x"});
  EXPECT_EQ(into.extras["sylva_stage"], "lod");

  const std::vector<int> other = append_scene(into, level("png-b", 0.5f));
  EXPECT_EQ(other, std::vector<int>{4});
  ASSERT_EQ(into.images.size(), 2u);  // other bytes: a second image ...
  EXPECT_TRUE(into.images[1].uri.empty());
  ASSERT_EQ(into.materials.size(), 2u);  // ... and a second material using it
  EXPECT_EQ(into.materials[1].base_color_texture.image, 1);
  EXPECT_EQ(into.meshes[2].primitives[0].material, 1);
  into.extensions_required.clear();  // "KHR_x" is not a real extension
  into.meshes[0].buffer = 0;         // the first scene's own buffers are not append_scene's
  into.meshes[0].primitives[0].buffer = -1;
  const std::vector<std::string> errors = validate_scene(into);
  EXPECT_TRUE(errors.empty()) << errors.front();
}

}  // namespace
}  // namespace sylva::gltf
