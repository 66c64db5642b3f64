// Loading glTF into a Scene: what is read, and how bad files are reported.
#include "libs/render/gltf_scene.h"

#include <gtest/gtest.h>

#include "libs/render/testing/gltf_builder.h"
#include "tests/support/test_support.h"

namespace sylva::render {
namespace {

using testing::GltfBuilder;
using testing::MaterialData;
using testing::NodeData;
using testing::PrimitiveData;

std::string load_error(const std::filesystem::path& p) {
  try {
    load_gltf_scene(p);
    return "";
  } catch (const SceneLoadError& e) {
    return e.what();
  }
}

// A quad with a material: geometry, material and bounds come through.
TEST(GltfScene, LoadsQuad) {
  test::TempDir dir;
  GltfBuilder b;
  const int m = b.add_material({.base_color = Vec4(0.5f, 0.25f, 1, 1),
                                .alpha_mode = "MASK",
                                .alpha_cutoff = 0.3f,
                                .double_sided = true});
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(2.f, m)}, "leaf"), .translation = Vec3(0, 1, 0)}));
  b.write_glb(dir / "q.glb");
  const Scene s = load_gltf_scene(dir / "q.glb");
  EXPECT_EQ(s.source, (dir / "q.glb").string());
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].name, "leaf");
  const Primitive& p = s.meshes[0].primitives.at(0);
  EXPECT_EQ(p.topology, Topology::kTriangles);
  EXPECT_EQ(p.positions.size(), 4u);
  EXPECT_EQ(p.normals.size(), 4u);
  EXPECT_EQ(p.indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].alpha_mode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(s.materials[0].alpha_cutoff, 0.3f);
  EXPECT_TRUE(s.materials[0].double_sided);
  EXPECT_TRUE(s.materials[0].base_color.isApprox(Vec4(0.5f, 0.25f, 1, 1)));
  const Bounds bb = s.bounds();
  EXPECT_TRUE(bb.min.isApprox(Vec3(-1, 0, 0)));
  EXPECT_TRUE(bb.max.isApprox(Vec3(1, 2, 0)));
  EXPECT_EQ(s.triangle_count(), 2u);
}

// Strips, fans and loops become lists; non-indexed primitives get 0..n-1.
TEST(GltfScene, ExpandsStripsFansAndLoops) {
  test::TempDir dir;
  GltfBuilder b;
  PrimitiveData strip, fan, loop;
  strip.mode = TINYGLTF_MODE_TRIANGLE_STRIP;
  strip.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  fan.mode = TINYGLTF_MODE_TRIANGLE_FAN;
  fan.positions = strip.positions;
  loop.mode = TINYGLTF_MODE_LINE_LOOP;
  loop.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  b.add_root(b.add_node({.mesh = b.add_mesh({strip, fan, loop})}));
  b.write_glb(dir / "s.glb");
  const Scene s = load_gltf_scene(dir / "s.glb");
  const auto& prims = s.meshes.at(0).primitives;
  EXPECT_EQ(prims[0].indices, (std::vector<std::uint32_t>{0, 1, 2, 2, 1, 3}));  // winding kept
  EXPECT_EQ(prims[1].indices, (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0}));
  EXPECT_EQ(prims[2].topology, Topology::kLines);
  EXPECT_EQ(prims[2].indices, (std::vector<std::uint32_t>{0, 1, 1, 2, 2, 0}));
}

// Node hierarchy and EXT_mesh_gpu_instancing give world matrices: parent * node * instance TRS.
TEST(GltfScene, InstancingAndHierarchy) {
  test::TempDir dir;
  GltfBuilder b;
  NodeData n;
  n.mesh = b.add_mesh({testing::quad(1.f)});
  n.scale = Vec3::Constant(2.f);
  n.instance_translations = {{1, 0, 0}, {0, 0, 3}};
  n.instance_scales = {{1, 1, 1}, {0.5f, 0.5f, 0.5f}};
  const int child = b.add_node(n);
  b.add_root(b.add_node({.translation = Vec3(10, 0, 0), .children = {child}}));
  b.write_glb(dir / "i.glb");
  const Scene s = load_gltf_scene(dir / "i.glb");
  ASSERT_EQ(s.meshes.at(0).instances.size(), 2u);
  const Mat4& a = s.meshes[0].instances[0];
  const Mat4& c = s.meshes[0].instances[1];
  EXPECT_TRUE((a * Vec4(0, 0, 0, 1)).isApprox(Vec4(12, 0, 0, 1)));  // 10 + 2 * 1
  EXPECT_TRUE((c * Vec4(1, 0, 0, 1)).isApprox(Vec4(11, 0, 6, 1)));  // 10 + 2*0.5*1, 2*3
}

// _SIZE and COLOR_0 are read for points.
TEST(GltfScene, PointAttributes) {
  test::TempDir dir;
  GltfBuilder b;
  PrimitiveData p;
  p.mode = TINYGLTF_MODE_POINTS;
  p.positions = {{0, 0, 0}, {1, 0, 0}};
  p.colors = {{1, 0, 0, 1}, {0, 1, 0, 0.5f}};
  p.sizes = {0.1f, 0.2f};
  b.add_root(b.add_node({.mesh = b.add_mesh({p})}));
  b.write_glb(dir / "p.glb");
  const Scene s = load_gltf_scene(dir / "p.glb");
  const Primitive& q = s.meshes.at(0).primitives.at(0);
  EXPECT_EQ(q.topology, Topology::kPoints);
  EXPECT_EQ(q.sizes, (std::vector<float>{0.1f, 0.2f}));
  EXPECT_TRUE(q.colors[1].isApprox(Vec4(0, 1, 0, 0.5f)));
  EXPECT_EQ(s.point_count(), 2u);
}

// Draco primitives decode to the same triangles (positions within quantisation error).
TEST(GltfScene, DracoDecodes) {
  test::TempDir dir;
  GltfBuilder b;
  PrimitiveData c = testing::cube(1.f);
  c.draco = true;
  b.add_root(b.add_node({.mesh = b.add_mesh({c})}));
  b.write_glb(dir / "d.glb");
  const Scene s = load_gltf_scene(dir / "d.glb");
  const Primitive& p = s.meshes.at(0).primitives.at(0);
  EXPECT_EQ(p.indices.size(), 36u);
  EXPECT_EQ(p.normals.size(), p.positions.size());
  EXPECT_EQ(p.texcoords.size(), 0u);  // no textured material: TEXCOORD_0 is not needed
  const Bounds bb = p.bounds();
  EXPECT_TRUE(bb.min.isApprox(Vec3::Constant(-0.5f), 1e-3f));
  EXPECT_TRUE(bb.max.isApprox(Vec3::Constant(0.5f), 1e-3f));
  // Every triangle's geometric normal agrees with its vertex normal (winding survived).
  for (std::size_t t = 0; t < p.indices.size(); t += 3) {
    const Vec3 e1 = p.positions[p.indices[t + 1]] - p.positions[p.indices[t]];
    const Vec3 e2 = p.positions[p.indices[t + 2]] - p.positions[p.indices[t]];
    EXPECT_GT(e1.cross(e2).dot(p.normals[p.indices[t]]), 0.f) << "triangle " << t / 3;
  }
}

// Bad input: each failure is one line naming the file.
TEST(GltfScene, MissingAndGarbageFiles) {
  test::TempDir dir;
  EXPECT_EQ(load_error(dir / "none.glb"), (dir / "none.glb").string() + ": error: No such file or directory");
  test::write_file(dir / "junk.glb", "definitely not glTF");
  const std::string junk = load_error(dir / "junk.glb");
  EXPECT_EQ(junk.rfind((dir / "junk.glb").string() + ": error: invalid glTF: ", 0), 0u) << junk;
  test::write_file(dir / "trunc.glb", std::string("glTF\x02\0\0\0", 8));
  const std::string trunc = load_error(dir / "trunc.glb");
  EXPECT_EQ(trunc.rfind((dir / "trunc.glb").string() + ": error: invalid glTF: ", 0), 0u) << trunc;
  EXPECT_EQ(load_error(dir.path()), dir.path().string() + ": error: Is a directory");
}

// A buffer uri naming a directory (a fuzzer's "../%./etc/passwd" resolved to one): a clear error,
// not an allocation of the size tellg() gives a directory (-1).
TEST(GltfScene, BufferUriNamingADirectoryIsAnError) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "sub");
  test::write_file(dir / "b.gltf", R"({
  "asset": {"version": "2.0"},
  "buffers": [{"byteLength": 44, "uri": "sub"}]
})");
  const std::string e = load_error(dir / "b.gltf");
  EXPECT_EQ(e.rfind((dir / "b.gltf").string() + ": error: invalid glTF: ", 0), 0u) << e;
  EXPECT_NE(e.find("sub"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// A .gltf whose texture file does not exist.
TEST(GltfScene, MissingTextureNamesTheImage) {
  test::TempDir dir;
  test::write_file(dir / "t.gltf", R"({
  "asset": {"version": "2.0"},
  "images": [{"uri": "bark.png"}],
  "textures": [{"source": 0}],
  "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
})");
  const std::string e = load_error(dir / "t.gltf");
  EXPECT_EQ(e, (dir / "t.gltf").string() +
                   ": error: texture 'bark.png' (image 0) could not be loaded: no such file " +
                   (dir / "bark.png").string());
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

// Out-of-range indices, bad accessors and unsupported required extensions are refused.
// Issue 15 item 7: an optional extension the renderer does not draw is a warning, not silence.
TEST(GltfScene, IgnoredExtensionsAreWarnedAbout) {
  test::TempDir dir;
  GltfBuilder b;
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f)})}));
  b.model().extensionsUsed.push_back("KHR_materials_clearcoat");
  b.model().extensionsUsed.push_back("KHR_materials_unlit");  // drawn: no warning
  b.write_glb(dir / "tt.glb");
  const Scene s = load_gltf_scene(dir / "tt.glb");
  EXPECT_EQ(s.warnings,
            (std::vector<std::string>{(dir / "tt.glb").string() +
                                      ": warning: uses glTF extension 'KHR_materials_clearcoat', which "
                                      "sylva's renderer ignores: the image may differ from other viewers'"}));
}

// KHR_texture_transform on the base colour texture: uv' = offset + R(rotation) (scale * uv).
TEST(GltfScene, TextureTransformAppliesToTheBaseColourUvs) {
  test::TempDir dir;
  GltfBuilder b;
  MaterialData m;
  m.texture = b.add_texture(image::Image(2, 2, {255, 0, 0, 255}));
  const int mat = b.add_material(m);
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f, mat)})}));
  tinygltf::Value::Object t;
  t.emplace("offset", tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(0.5), tinygltf::Value(0.25)}));
  t.emplace("scale", tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(2.0), tinygltf::Value(3.0)}));
  t.emplace("rotation", tinygltf::Value(1.5707963267948966));
  b.model()
      .materials[std::size_t(mat)]
      .pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
      tinygltf::Value(std::move(t));
  b.model().extensionsUsed.push_back("KHR_texture_transform");
  b.model().extensionsRequired.push_back("KHR_texture_transform");
  b.write_glb(dir / "t.glb");
  const Scene s = load_gltf_scene(dir / "t.glb");
  EXPECT_TRUE(s.warnings.empty());
  const PrimitiveData q = testing::quad(1.f, mat);
  const Primitive& p = s.meshes.at(0).primitives.at(0);
  ASSERT_EQ(p.texcoords.size(), q.texcoords.size());
  for (std::size_t i = 0; i < q.texcoords.size(); ++i) {
    // A quarter turn counter-clockwise: (u, v) -> (-v, u) after the scale.
    const float u = 2 * q.texcoords[i].x(), v = 3 * q.texcoords[i].y();
    EXPECT_NEAR(p.texcoords[i].x(), 0.5f - v, 1e-5f) << i;
    EXPECT_NEAR(p.texcoords[i].y(), 0.25f + u, 1e-5f) << i;
  }
}

TEST(GltfScene, InvalidContent) {
  test::TempDir dir;
  {
    GltfBuilder b;
    PrimitiveData p = testing::quad(1.f);
    p.indices = {0, 1, 7};
    b.add_root(b.add_node({.mesh = b.add_mesh({p})}));
    b.write_glb(dir / "idx.glb");
    EXPECT_EQ(load_error(dir / "idx.glb"),
              (dir / "idx.glb").string() + ": error: mesh 0 primitive 0: index 7 out of range (4 vertices)");
  }
  {
    GltfBuilder b;
    b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f)})}));
    b.model().extensionsRequired.push_back("KHR_materials_volume");
    b.model().extensionsUsed.push_back("KHR_materials_volume");
    b.write_glb(dir / "ext.glb");
    EXPECT_EQ(
        load_error(dir / "ext.glb"),
        (dir / "ext.glb").string() + ": error: requires unsupported glTF extension 'KHR_materials_volume'");
  }
  {
    GltfBuilder b;
    b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f)})}));
    b.model().accessors[0].count = 1000;  // POSITION claims more data than its buffer view holds
    b.write_glb(dir / "acc.glb");
    const std::string e = load_error(dir / "acc.glb");
    EXPECT_EQ(e.rfind((dir / "acc.glb").string() + ": error: ", 0), 0u) << e;
  }
}

}  // namespace
}  // namespace sylva::render
