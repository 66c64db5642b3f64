// validate_scene(): one message per broken contract point, naming the element.
#include "libs/gltf/scene.h"

#include <gtest/gtest.h>

#include "libs/gltf/testing/sample_geometry.h"

namespace sylva::gltf {
namespace {

using testing::make_node;

Scene triangle() {
  Scene s;
  Mesh m;
  Primitive p;
  p.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  p.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  p.indices = {0, 1, 2};
  m.primitives.push_back(p);
  s.meshes.push_back(m);
  s.nodes.push_back(make_node("n", 0));
  s.roots = {0};
  return s;
}

std::string first(const Scene& s) {
  const auto e = validate_scene(s);
  return e.empty() ? std::string() : e.front();
}

// The minimal triangle is valid.
TEST(GltfScene, ValidSceneHasNoFindings) { EXPECT_TRUE(validate_scene(triangle()).empty()); }

// Every attribute and index problem names the primitive.
TEST(GltfScene, PrimitiveProblems) {
  Scene s = triangle();
  s.meshes[0].primitives[0].indices = {0, 1, 3};
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: index 2 is 3, but there are 3 vertices");
  s = triangle();
  s.meshes[0].primitives[0].indices = {0, 1};
  EXPECT_EQ(first(s),
            "meshes[0].primitives[0]: index count 2 does not fit the mode (a non-zero multiple of 3)");
  s = triangle();
  s.meshes[0].primitives[0].normals[2] = 2;
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: normal of vertex 0 has length 2.000000, expected 1");
  s = triangle();
  s.meshes[0].primitives[0].positions[4] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: positions contains a value that is not finite");
  s = triangle();
  s.meshes[0].primitives[0].tangents = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 0.5f};
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: tangent w of vertex 2 is not +1 or -1");
  s = triangle();
  s.meshes[0].primitives[0].custom.push_back({"SIZE", 1, {1, 1, 1}});
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: custom attribute 'SIZE' must start with '_'");
  s = triangle();
  s.meshes[0].primitives[0].material = 0;
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: material 0 does not exist");
  s = triangle();
  s.meshes[0].primitives[0].positions.clear();
  EXPECT_EQ(first(s), "meshes[0].primitives[0]: positions has 0 values; expected a non-zero multiple of 3");
}

// Node graph problems: bad indices, two parents, cycles, roots that are children.
TEST(GltfScene, NodeGraphProblems) {
  Scene s = triangle();
  s.nodes[0].mesh = 4;
  EXPECT_EQ(first(s), "nodes[0]: mesh 4 does not exist");
  s = triangle();
  s.nodes.push_back(make_node("a", -1, {0}));
  s.nodes.push_back(make_node("b", -1, {0}));
  EXPECT_EQ(first(s), "nodes[0]: has more than one parent");
  s = triangle();
  s.nodes.push_back(make_node("a", -1, {2}));
  s.nodes.push_back(make_node("b", -1, {1}));
  EXPECT_EQ(first(s), "nodes[1]: is part of a cycle");
  s = triangle();
  s.nodes.push_back(make_node("parent", -1, {0}));
  EXPECT_EQ(first(s), "roots: node 0 is a child of another node");
  s = triangle();
  s.nodes[0].rotation = {0, 0, 0, 2};
  EXPECT_EQ(first(s), "nodes[0]: rotation is not a unit quaternion");
}

// Materials and images.
TEST(GltfScene, MaterialAndImageProblems) {
  Scene s = triangle();
  s.images.push_back({"x.bmp", "image/bmp", "BM", ""});
  EXPECT_EQ(first(s), "images[0]: mime type 'image/bmp' is not image/png or image/jpeg");
  s = triangle();
  Material m;
  m.base_color_texture.image = 1;
  s.materials.push_back(m);
  EXPECT_EQ(first(s), "materials[0]: texture image 1 does not exist");
  s = triangle();
  m = Material();
  m.base_color[0] = 1.5f;
  s.materials.push_back(m);
  EXPECT_EQ(first(s), "materials[0]: base_color has a value outside [0, 1]");
}

}  // namespace
}  // namespace sylva::gltf
