// What the renderer draws: geometry, materials, lighting, lines, points, instancing and Draco,
// each checked at chosen pixels of a small hand-built scene (render_fixture.h).
#include <gtest/gtest.h>

#include <cmath>

#include "libs/image/compare.h"
#include "libs/render/tests/render_fixture.h"

namespace sylva::render::render_test {
namespace {

// The device is the software rasteriser the references are made with.
TEST_F(RenderTest, RunsOnHeadlessDevice) {
  EXPECT_NE(renderer_->device_description().find("OpenGL"), std::string::npos)
      << renderer_->device_description();
  std::cout << "device: " << renderer_->device_description() << "\n";
}

// A unit quad facing the camera, unlit: its colour in the middle, background around it.
TEST_F(RenderTest, UnitQuadFacingCamera) {
  GltfBuilder b;
  const int red = b.add_material({.base_color = Vec4(1, 0, 0, 1)});
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f, red)})}));
  const Scene scene = load(b);
  const Camera cam = look(Vec3(0, 0, 2));
  const RenderOptions o = unlit_options();
  const Image img = render(scene, cam, o);
  keep(img, "unit_quad");
  ASSERT_EQ(img.width(), 64);
  EXPECT_TRUE(near(img.at(32, 32), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(2, 2), kBackground, 0));
  // The quad spans +-0.5 m at 2 m with a 45 degree fov: +-19.3 pixels around the centre.
  EXPECT_TRUE(near(img.at(32 - 18, 32), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(32 - 21, 32), kBackground, 0));
  EXPECT_TRUE(near(img.at(32, 32 + 18), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(32, 32 + 21), kBackground, 0));
}

// With the default lighting the quad's colour is base * (ambient + light * n.l), sRGB-encoded.
TEST_F(RenderTest, LightingModel) {
  GltfBuilder b;
  const int grey = b.add_material({.base_color = Vec4(0.8f, 0.6f, 0.4f, 1)});
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f, grey)})}));
  const Scene scene = load(b);
  const RenderOptions o = small();
  const Image img = render(scene, look(Vec3(0, 0, 2)), o);
  const double ndotl = o.lighting.direction_to_light.normalized().z();
  const double k = 0.35 + 0.75 * ndotl;
  EXPECT_TRUE(near(img.at(32, 32), {std::uint8_t(srgb8(0.8 * k)), std::uint8_t(srgb8(0.6 * k)),
                                    std::uint8_t(srgb8(0.4 * k)), 255}));
}

// A textured cube seen face on: the front face shows the texture's four quadrants with uv (0,0)
// at the top left; seen obliquely, the lit faces differ as n.l says.
TEST_F(RenderTest, TexturedCube) {
  GltfBuilder b;
  const int tex = b.add_texture(quadrant_texture());
  const int mat = b.add_material({.texture = tex});
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::cube(1.f, mat)})}));
  const Scene scene = load(b);
  const Image front = render(scene, look(Vec3(0, 0, 3)), unlit_options());
  keep(front, "textured_cube_front");
  EXPECT_TRUE(near(front.at(24, 24), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(front.at(40, 24), {0, 255, 0, 255}, 0));
  EXPECT_TRUE(near(front.at(24, 40), {0, 0, 255, 255}, 0));
  EXPECT_TRUE(near(front.at(40, 40), {255, 255, 255, 255}, 0));
  EXPECT_TRUE(near(front.at(4, 32), kBackground, 0));

  // Oblique and lit: the white texel of each face is at uv (0.75, 0.75).
  const RenderOptions o = small(128);
  const Camera cam = look(Vec3(2.0f, 2.2f, 3.0f));
  const Image lit = render(scene, cam, o);
  keep(lit, "textured_cube_lit");
  const Vec3 l = o.lighting.direction_to_light.normalized();
  auto expect_face = [&](const Vec3& point, const Vec3& normal) {
    const auto px = project(cam, o, point);
    const int v = srgb8(0.35 + 0.75 * std::max(0.f, normal.dot(l)));
    EXPECT_TRUE(near(lit.at(px.x(), px.y()), {std::uint8_t(v), std::uint8_t(v), std::uint8_t(v), 255}))
        << "face with normal " << normal.transpose();
  };
  expect_face(Vec3(0.25f, -0.25f, 0.5f), Vec3::UnitZ());   // front, white quadrant
  expect_face(Vec3(0.5f, -0.25f, -0.25f), Vec3::UnitX());  // right, white quadrant
  expect_face(Vec3(0.25f, 0.5f, 0.25f), Vec3::UnitY());    // top, white quadrant
}

// Alpha-masked, double-sided leaf (Celba 4.6.3): the masked-out half is not drawn; seen from
// behind, the normal is flipped toward the eye, so the back is lit by a light behind the leaf
// and only ambient-lit by a light in front of it. A single-sided leaf is culled from behind.
TEST_F(RenderTest, AlphaMaskedTwoSidedLeaves) {
  Image mask(2, 1);
  mask.set(0, 0, {0, 255, 0, 255});  // left half: opaque green
  mask.set(1, 0, {0, 255, 0, 0});    // right half: cut away
  // A 1 m quad textured with the mask (cutoff 0.5), written as `file` and loaded.
  auto masked_quad = [&](bool double_sided, const std::string& file) {
    GltfBuilder b;
    const int tex = b.add_texture(mask);
    const int m = b.add_material(
        {.texture = tex, .alpha_mode = "MASK", .alpha_cutoff = 0.5f, .double_sided = double_sided});
    b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f, m)})}));
    return load(b, file);
  };
  const Scene leaf = masked_quad(true, "leaf.glb");
  const Scene single = masked_quad(false, "single.glb");

  RenderOptions o = small();
  o.lighting.ambient = Vec3::Constant(0.2f);
  o.lighting.light_color = Vec3::Constant(0.8f);
  o.lighting.direction_to_light = Vec3::UnitZ();  // light in front (+Z)
  const Camera front = look(Vec3(0, 0, 2));
  const Camera back = look(Vec3(0, 0, -2));

  const Image f = render(leaf, front, o);
  keep(f, "leaf_front");
  EXPECT_TRUE(near(f.at(24, 32), {0, 255, 0, 255}));  // lit fully: 0.2 + 0.8
  EXPECT_TRUE(near(f.at(40, 32), kBackground, 0));    // masked out

  // From behind, the leaf's left half appears on the image's right.
  const Image bk = render(leaf, back, o);
  keep(bk, "leaf_back_light_in_front");
  EXPECT_TRUE(near(bk.at(40, 32), {0, std::uint8_t(srgb8(0.2)), 0, 255}));  // ambient only
  EXPECT_TRUE(near(bk.at(24, 32), kBackground, 0));

  o.lighting.direction_to_light = -Vec3::UnitZ();  // light behind (-Z)
  const Image bk2 = render(leaf, back, o);
  keep(bk2, "leaf_back_light_behind");
  EXPECT_TRUE(near(bk2.at(40, 32), {0, 255, 0, 255}));  // flipped normal faces the light

  EXPECT_TRUE(near(render(single, back, o).at(40, 32), kBackground, 0));  // culled
  EXPECT_TRUE(near(render(single, front, o).at(24, 32), {0, std::uint8_t(srgb8(0.2)), 0, 255}));
}

// glTF's two-sided rule (3.9.2): the back face -- decided by winding, not by the eye -- is lit
// with the reversed normal. A leaf wound clockwise (against its +Z normal) is a back face from
// the front, so its normal turns to -Z and a light in front leaves it ambient-lit (dark, as
// three.js, Babylon.js and Cycles draw it); from behind it is a front face lit by the light
// behind. Under a mirroring node (scale -1 in x, determinant < 0) glTF's front face is the
// clockwise one on screen: the well-wound leaf stays lit and the mis-wound one stays dark.
TEST_F(RenderTest, TwoSidedBackFaceUsesReversedNormalByWinding) {
  const int two_sided_mat = 0;
  auto leaf = [&](bool mis_wound, Vec3 scale) {
    GltfBuilder b;
    const int m = b.add_material({.base_color = Vec4(0, 1, 0, 1), .double_sided = true});
    EXPECT_EQ(m, two_sided_mat);
    PrimitiveData q = testing::quad(1.f, m);
    if (q.indices.empty())
      for (std::uint32_t i = 0; i < q.positions.size(); ++i) q.indices.push_back(i);
    if (mis_wound)
      for (std::size_t t = 0; t + 2 < q.indices.size(); t += 3) std::swap(q.indices[t + 1], q.indices[t + 2]);
    b.add_root(b.add_node({.mesh = b.add_mesh({q}), .scale = scale}));
    return load(b, mis_wound ? "miswound.glb" : "wound.glb");
  };
  RenderOptions o = small();
  o.lighting.ambient = Vec3::Constant(0.2f);
  o.lighting.light_color = Vec3::Constant(0.8f);
  o.lighting.direction_to_light = Vec3::UnitZ();  // light in front (+Z)
  const Camera front = look(Vec3(0, 0, 2));
  const Camera back = look(Vec3(0, 0, -2));
  const Rgba8 lit{0, 255, 0, 255}, ambient{0, std::uint8_t(srgb8(0.2)), 0, 255};

  const Scene good = leaf(false, Vec3::Ones());
  const Scene bad = leaf(true, Vec3::Ones());
  EXPECT_TRUE(near(render(good, front, o).at(32, 32), lit));
  const Image f = render(bad, front, o);
  keep(f, "miswound_leaf_front");
  EXPECT_TRUE(near(f.at(32, 32), ambient));        // back face: reversed normal, away from the light
  o.lighting.direction_to_light = -Vec3::UnitZ();  // light behind (-Z)
  EXPECT_TRUE(near(render(bad, back, o).at(32, 32), ambient));  // front face, normal +Z, light at -Z
  EXPECT_TRUE(near(render(good, back, o).at(32, 32), lit));     // back face of the good leaf: -Z
  o.lighting.direction_to_light = Vec3::UnitZ();
  EXPECT_TRUE(near(render(leaf(false, Vec3(-1, 1, 1)), front, o).at(32, 32), lit));
  EXPECT_TRUE(near(render(leaf(true, Vec3(-1, 1, 1)), front, o).at(32, 32), ambient));
}

// Semi-transparent lines blend over the background.
TEST_F(RenderTest, LinesWithAlphaOverBackground) {
  GltfBuilder b;
  const int red = b.add_material({.base_color = Vec4(1, 0, 0, 0.5f), .alpha_mode = "BLEND", .unlit = true});
  b.add_root(b.add_node({.mesh = b.add_mesh({line_rows(0.f, 20, 44, red)})}));
  const Scene scene = load(b);
  const Image img = render(scene, look(Vec3(0, 0, 2)), small(64, 1));
  keep(img, "lines_alpha");
  const Rgba8 want{std::uint8_t(std::lround(0.5 * 255 + 0.5 * 191)), std::uint8_t(std::lround(0.5 * 204)),
                   std::uint8_t(std::lround(0.5 * 217)), 255};
  for (int row : {20, 30, 43}) EXPECT_TRUE(near(img.at(32, row), want)) << "row " << row;
  EXPECT_TRUE(near(img.at(32, 19), kBackground, 0));
  EXPECT_TRUE(near(img.at(32, 44), kBackground, 0));
}

// LINES are unlit even with normals and a lit material (three.js's GLTFLoader draws them with
// LineBasicMaterial): the colour is the base colour whatever the light and the normals.
TEST_F(RenderTest, LinesAreUnlitAsInThreeJs) {
  GltfBuilder b;
  const int grey = b.add_material({.base_color = Vec4(0.5f, 0.25f, 0.125f, 1)});
  PrimitiveData p = line_rows(0.f, 20, 44, grey);
  for (std::size_t i = 0; i < p.positions.size(); ++i)
    p.normals.push_back(i % 4 < 2 ? Vec3(Vec3::UnitZ()) : Vec3(-Vec3::UnitZ()));
  b.add_root(b.add_node({.mesh = b.add_mesh({p})}));
  const Scene scene = load(b);
  RenderOptions o = small(64, 1);
  o.lighting.direction_to_light = -Vec3::UnitZ();  // behind the lines' +Z normals
  const Image img = render(scene, look(Vec3(0, 0, 2)), o);
  const Rgba8 want{std::uint8_t(srgb8(0.5)), std::uint8_t(srgb8(0.25)), std::uint8_t(srgb8(0.125)), 255};
  for (int row : {20, 21, 30, 43}) EXPECT_TRUE(near(img.at(32, row), want)) << "row " << row;
}

// Zhang 6.1: blended lines are drawn far to near whatever the file order, both across draws
// (two meshes) and inside one primitive. Near red over far blue over the background.
TEST_F(RenderTest, BlendedLinesDrawnFarToNear) {
  const Rgba8 want{std::uint8_t(std::lround(0.5 * 255 + 0.25 * 191)), std::uint8_t(std::lround(0.25 * 204)),
                   std::uint8_t(std::lround(0.25 * 255 + 0.25 * 217)), 255};
  {
    GltfBuilder b;
    const int red = b.add_material({.base_color = Vec4(1, 0, 0, 0.5f), .alpha_mode = "BLEND", .unlit = true});
    const int blue =
        b.add_material({.base_color = Vec4(0, 0, 1, 0.5f), .alpha_mode = "BLEND", .unlit = true});
    b.add_root(b.add_node({.mesh = b.add_mesh({line_rows(0.5f, 20, 44, red)})}));    // near, first in file
    b.add_root(b.add_node({.mesh = b.add_mesh({line_rows(-0.5f, 20, 44, blue)})}));  // far, second
    const Image img = render(load(b, "two.glb"), look(Vec3(0, 0, 2)), small(64, 1));
    keep(img, "lines_two_draws");
    EXPECT_TRUE(near(img.at(32, 30), want, 2));
  }
  {
    GltfBuilder b;
    const int white =
        b.add_material({.base_color = Vec4(1, 1, 1, 0.5f), .alpha_mode = "BLEND", .unlit = true});
    PrimitiveData near_red = line_rows(0.5f, 20, 44, white);
    PrimitiveData far_blue = line_rows(-0.5f, 20, 44, white);
    near_red.colors.assign(near_red.positions.size(), Vec4(1, 0, 0, 1));
    far_blue.colors.assign(far_blue.positions.size(), Vec4(0, 0, 1, 1));
    PrimitiveData both = near_red;  // near segments first in the index order
    both.positions.insert(both.positions.end(), far_blue.positions.begin(), far_blue.positions.end());
    both.colors.insert(both.colors.end(), far_blue.colors.begin(), far_blue.colors.end());
    b.add_root(b.add_node({.mesh = b.add_mesh({both})}));
    const Image img = render(load(b, "one.glb"), look(Vec3(0, 0, 2)), small(64, 1));
    keep(img, "lines_one_primitive");
    EXPECT_TRUE(near(img.at(32, 30), want, 2));
  }
}

// POINTS with _SIZE: the diameter in metres projects to pixels (size * focal / distance); the
// points are round discs in their COLOR_0.
TEST_F(RenderTest, PointsWithSizes) {
  GltfBuilder b;
  PrimitiveData pts;
  pts.mode = TINYGLTF_MODE_POINTS;
  pts.positions = {{-0.5f, 0, 0}, {0.5f, 0, 0}};
  pts.colors = {{1, 0, 0, 1}, {0, 1, 0, 1}};
  pts.sizes = {0.2f, 0.05f};
  b.add_root(b.add_node({.mesh = b.add_mesh({pts})}));
  const Scene scene = load(b);
  const Camera cam = look(Vec3(0, 0, 2));
  const RenderOptions o = small(128);
  const Image img = render(scene, cam, o);
  keep(img, "points");
  // Focal length in pixels: 64 / tan(22.5 deg) = 154.5; at 2 m: 0.2 m -> 15.5 px, 0.05 m -> 3.9 px.
  const auto a = project(cam, o, Vec3(-0.5f, 0, 0));
  const auto c = project(cam, o, Vec3(0.5f, 0, 0));
  EXPECT_TRUE(near(img.at(a.x(), a.y()), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(a.x() + 6, a.y()), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(a.x(), a.y() - 6), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(a.x() + 6, a.y() - 6), kBackground, 0));  // outside the disc (8.5 px > 7.7)
  EXPECT_TRUE(near(img.at(a.x() + 10, a.y()), kBackground, 0));
  EXPECT_TRUE(near(img.at(c.x(), c.y()), {0, 255, 0, 255}, 0));
  EXPECT_TRUE(near(img.at(c.x() + 4, c.y()), kBackground, 0));
}

// EXT_mesh_gpu_instancing under a translated parent: three instances with their own
// translation, rotation and scale.
TEST_F(RenderTest, InstancedMeshInHierarchy) {
  GltfBuilder b;
  const int red = b.add_material({.base_color = Vec4(1, 0, 0, 1)});
  NodeData inst;
  inst.mesh = b.add_mesh({testing::quad(0.2f, red)});
  inst.instance_translations = {{-0.6f, 0, 0}, {0, 0, 0}, {0.6f, 0, 0}};
  inst.instance_rotations = {Eigen::Quaternionf::Identity(),
                             Eigen::Quaternionf(Eigen::AngleAxisf(3.14159265f / 4, Vec3::UnitZ())),
                             Eigen::Quaternionf::Identity()};
  inst.instance_scales = {{1, 1, 1}, {1, 1, 1}, {2, 2, 2}};
  const int child = b.add_node(inst);
  b.add_root(b.add_node({.translation = Vec3(0, 0.3f, 0), .children = {child}}));
  const Scene scene = load(b);
  ASSERT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes[0].instances.size(), 3u);
  const Camera cam = look(Vec3(0, 0, 2));
  const RenderOptions o = unlit_options(128);
  const Image img = render(scene, cam, o);
  keep(img, "instances");
  auto at = [&](float x, float y) {
    const auto p = project(cam, o, Vec3(x, y, 0));
    return img.at(p.x(), p.y());
  };
  const Rgba8 r{255, 0, 0, 255};
  EXPECT_TRUE(near(at(-0.6f, 0.3f), r, 0));
  EXPECT_TRUE(near(at(0.f, 0.3f), r, 0));
  EXPECT_TRUE(near(at(0.6f, 0.3f), r, 0));
  EXPECT_TRUE(near(at(0.6f + 0.17f, 0.3f), r, 0));             // scaled x2: half size 0.2
  EXPECT_TRUE(near(at(-0.6f + 0.17f, 0.3f), kBackground, 0));  // unscaled: half size 0.1
  EXPECT_TRUE(near(at(0.f, 0.3f + 0.12f), r, 0));              // rotated 45: corner at 0.141
  EXPECT_TRUE(near(at(0.08f, 0.3f + 0.08f), kBackground, 0));  // ... and not at the old corner
  EXPECT_TRUE(near(at(0.f, 0.f), kBackground, 0));             // parent moved everything up
}

// A Draco-compressed cube renders like the uncompressed one.
TEST_F(RenderTest, DracoCompressedPrimitive) {
  auto build = [&](bool draco, const std::string& name) {
    GltfBuilder b;
    const int tex = b.add_texture(quadrant_texture());
    const int mat = b.add_material({.texture = tex});
    PrimitiveData c = testing::cube(1.f, mat);
    c.draco = draco;
    b.add_root(b.add_node({.mesh = b.add_mesh({c})}));
    return load(b, name);
  };
  const Scene plain = build(false, "plain.glb");
  const Scene draco = build(true, "draco.glb");
  ASSERT_EQ(draco.meshes.size(), 1u);
  EXPECT_EQ(draco.meshes[0].primitives[0].indices.size(), 36u);
  const Camera cam = look(Vec3(2.0f, 2.2f, 3.0f));
  const Image a = render(plain, cam, small(128));
  const Image d = render(draco, cam, small(128));
  keep(d, "draco_cube");
  const image::CompareResult r = image::compare_images(a, d);
  EXPECT_TRUE(r.passed) << r.failure;
  EXPECT_LT(r.failing_fraction, 0.002);
  const Image front = render(draco, look(Vec3(0, 0, 3)), unlit_options());
  EXPECT_TRUE(near(front.at(24, 24), {255, 0, 0, 255}, 0));
  EXPECT_TRUE(near(front.at(40, 40), {255, 255, 255, 255}, 0));
}

}  // namespace
}  // namespace sylva::render::render_test
