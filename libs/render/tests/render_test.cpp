// Renders small hand-built glTF scenes and checks pixels at chosen spots.
//
// These tests need EGL + OpenGL (Mesa llvmpipe). They skip only on a machine without any EGL
// vendor; with Mesa's EGL installed, or SYLVA_REQUIRE_GL=1, failing to create a renderer fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <thread>

#include "libs/image/compare.h"
#include "libs/image/image_io.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/line_merge.h"
#include "libs/render/renderer.h"
#include "libs/render/testing/gltf_builder.h"
#include "tests/support/test_support.h"

namespace sylva::render {
namespace {

using image::Image;
using image::Rgba8;
using testing::GltfBuilder;
using testing::MaterialData;
using testing::NodeData;
using testing::PrimitiveData;

constexpr Rgba8 kBackground{191, 204, 217, 255};  // RenderOptions' default

// Linear [0, 1] -> 8-bit sRGB, as the fragment shader encodes.
int srgb8(double c) {
  c = std::clamp(c, 0.0, 1.0);
  const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return int(std::lround(s * 255.0));
}

::testing::AssertionResult near(Rgba8 got, Rgba8 want, int tol = 1) {
  const bool ok = std::abs(got.r - want.r) <= tol && std::abs(got.g - want.g) <= tol &&
                  std::abs(got.b - want.b) <= tol && std::abs(got.a - want.a) <= tol;
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "got (" << int(got.r) << "," << int(got.g) << "," << int(got.b) << "," << int(got.a)
         << "), want (" << int(want.r) << "," << int(want.g) << "," << int(want.b) << "," << int(want.a)
         << ") +-" << tol;
}

// Pixel (column, row) where a world point lands.
Eigen::Vector2i project(const Camera& cam, const RenderOptions& o, const Vec3& p) {
  const Vec4 clip =
      cam.projection_matrix(float(o.width) / float(o.height)) * cam.view_matrix() * p.homogeneous();
  const float x = (clip.x() / clip.w() * 0.5f + 0.5f) * float(o.width);
  const float y = (0.5f - clip.y() / clip.w() * 0.5f) * float(o.height);
  return {int(std::floor(x)), int(std::floor(y))};
}

Camera look(const Vec3& eye, const Vec3& target = Vec3::Zero(), float fov = 45.f) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.fov_y_deg = fov;
  c.z_near = 0.05f;
  c.z_far = 50.f;
  return c;
}

RenderOptions small(int size = 64, int msaa = 4) {
  RenderOptions o;
  o.width = o.height = size;
  o.msaa = msaa;
  return o;
}

RenderOptions unlit_options(int size = 64, int msaa = 4) {
  RenderOptions o = small(size, msaa);
  o.lighting.ambient = Vec3::Ones();
  o.lighting.light_color = Vec3::Zero();
  return o;
}

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      renderer_ = Renderer::create_headless();
    } catch (const RenderUnavailableError& e) {
      unavailable_ = e.what();
    }
  }
  static void TearDownTestSuite() { renderer_.reset(); }

  void SetUp() override {
    if (renderer_) return;
    // Skipping is only for machines with no EGL vendor at all; where Mesa's EGL is installed
    // (every sylva build machine and CI) or SYLVA_REQUIRE_GL=1, a missing renderer is a failure.
    const char* require = std::getenv("SYLVA_REQUIRE_GL");
    std::error_code ec;
    if ((require && std::string(require) == "1") ||
        std::filesystem::exists("/usr/share/glvnd/egl_vendor.d/50_mesa.json", ec))
      FAIL() << unavailable_;
    GTEST_SKIP() << unavailable_;
  }

  Scene load(const GltfBuilder& b, const std::string& name = "scene.glb") {
    b.write_glb(dir_ / name);
    return load_gltf_scene(dir_ / name);
  }

  Image render(const Scene& s, const Camera& c, const RenderOptions& o) { return renderer_->render(s, c, o); }

  // Writes the image under out/test-images/ for looking at it (not an assertion).
  static void keep(const Image& img, const std::string& name) {
    std::filesystem::create_directories("out/test-images");
    image::write_png(img, "out/test-images/" + name + ".png");
  }

  static std::unique_ptr<Renderer> renderer_;
  static std::string unavailable_;
  test::TempDir dir_;
};

std::unique_ptr<Renderer> RenderTest::renderer_;
std::string RenderTest::unavailable_;

// A 2x2 texture: red, green / blue, white (top row first).
Image quadrant_texture() {
  Image t(2, 2);
  t.set(0, 0, {255, 0, 0, 255});
  t.set(1, 0, {0, 255, 0, 255});
  t.set(0, 1, {0, 0, 255, 255});
  t.set(1, 1, {255, 255, 255, 255});
  return t;
}

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
  GltfBuilder b;
  const int tex = b.add_texture(mask);
  const int two_sided =
      b.add_material({.texture = tex, .alpha_mode = "MASK", .alpha_cutoff = 0.5f, .double_sided = true});
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f, two_sided)})}));
  const Scene leaf = load(b, "leaf.glb");
  GltfBuilder b1;
  const int tex1 = b1.add_texture(mask);
  const int one_sided =
      b1.add_material({.texture = tex1, .alpha_mode = "MASK", .alpha_cutoff = 0.5f, .double_sided = false});
  b1.add_root(b1.add_node({.mesh = b1.add_mesh({testing::quad(1.f, one_sided)})}));
  const Scene single = load(b1, "single.glb");

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

// Horizontal lines one pixel apart, one per pixel row, at depth z (camera on +Z at distance 2,
// 45 degree fov, 64 pixels): rows [first, last).
PrimitiveData line_rows(float z, int first, int last, int material) {
  PrimitiveData p;
  p.mode = TINYGLTF_MODE_LINE;
  p.material = material;
  const float pixel = 2.f * (2.f - z) * std::tan(22.5f * 3.14159265f / 180.f) / 64.f;
  for (int r = first; r < last; ++r) {
    const float y = (32.f - float(r) - 0.5f) * pixel;
    p.positions.emplace_back(-3.f, y, z);
    p.positions.emplace_back(3.f, y, z);
  }
  return p;
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

// Same input, same bytes: two renders encode to identical PNGs, and rendering several views at
// once gives the same images as rendering them one by one.
TEST_F(RenderTest, Deterministic) {
  GltfBuilder b;
  const int tex = b.add_texture(quadrant_texture(), false);
  const int mat = b.add_material({.texture = tex});
  const int leafmat = b.add_material(
      {.base_color = Vec4(0.2f, 0.6f, 0.1f, 0.6f), .alpha_mode = "BLEND", .double_sided = true});
  PrimitiveData lines = line_rows(0.7f, 10, 50, leafmat);
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::cube(1.f, mat), lines})}));
  const Scene scene = load(b);
  const Camera c1 = look(Vec3(2.0f, 2.2f, 3.0f)), c2 = look(Vec3(-3.f, 1.f, 1.f));
  const RenderOptions o = small(200);
  const Image a = render(scene, c1, o);
  const Image a2 = render(scene, c1, o);
  EXPECT_EQ(image::encode_png(a), image::encode_png(a2));
  const std::vector<Camera> both = {c1, c2};
  const auto views = renderer_->render_views(scene, both, o);
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0], a);
  EXPECT_EQ(views[1], render(scene, c2, o));
}

// One renderer shared by threads: calls take turns and give the same image as a lone call.
TEST_F(RenderTest, SharedAcrossThreads) {
  GltfBuilder b;
  const int tex = b.add_texture(quadrant_texture());
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::cube(1.f, b.add_material({.texture = tex}))})}));
  const Scene scene = load(b);
  const Camera cam = look(Vec3(2.0f, 2.2f, 3.0f));
  const RenderOptions o = small(96);
  const Image want = render(scene, cam, o);
  std::vector<Image> got(4);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] { got[i] = renderer_->render(scene, cam, o); });
  for (auto& t : threads) t.join();
  for (const Image& g : got) EXPECT_EQ(g, want);
}

// Renderers in one process share EGL's display: creating and destroying other renderers beside
// this one (in turn, then from threads at once, as pipeline nodes do) leaves it drawing the same.
TEST_F(RenderTest, OtherRenderersComingAndGoingLeaveThisOneWorking) {
  GltfBuilder b;
  const int tex = b.add_texture(quadrant_texture());
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::cube(1.f, b.add_material({.texture = tex}))})}));
  const Scene scene = load(b);
  const Camera cam = look(Vec3(2.0f, 2.2f, 3.0f));
  const RenderOptions o = small(64);
  const Image want = render(scene, cam, o);
  {
    auto other = Renderer::create_headless();
    EXPECT_EQ(other->render(scene, cam, o), want);
  }
  EXPECT_EQ(render(scene, cam, o), want);
  std::vector<int> same(3, 0);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < same.size(); ++i)
    threads.emplace_back([&, i] {
      for (int k = 0; k < 4; ++k) same[i] += Renderer::create_headless()->render(scene, cam, o) == want;
    });
  for (int k = 0; k < 8; ++k) EXPECT_EQ(render(scene, cam, o), want) << k;
  for (auto& t : threads) t.join();
  EXPECT_EQ(same, std::vector<int>(3, 4));
  EXPECT_EQ(render(scene, cam, o), want);
}

// A transparent background gives alpha 0 around the object and straight colour on it.
TEST_F(RenderTest, TransparentBackground) {
  GltfBuilder b;
  const int red = b.add_material({.base_color = Vec4(1, 0, 0, 1)});
  const int glass = b.add_material({.base_color = Vec4(0, 0, 1, 0.5f), .alpha_mode = "BLEND", .unlit = true});
  PrimitiveData pane = testing::quad(0.5f, glass);
  for (auto& p : pane.positions) p += Vec3(0.5f, 0, 0.1f);
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::quad(1.f, red), pane})}));
  RenderOptions o = unlit_options();
  o.background = {0, 0, 0, 0};
  const Image img = render(load(b), look(Vec3(0, 0, 2)), o);
  keep(img, "transparent_background");
  EXPECT_EQ(img.at(2, 2).a, 0);
  EXPECT_TRUE(near(img.at(28, 32), {255, 0, 0, 255}, 0));
  // The blue pane over nothing: colour blue, alpha one half.
  const Camera cam = look(Vec3(0, 0, 2));
  const auto p = project(cam, o, Vec3(0.65f, 0.f, 0.1f));
  EXPECT_TRUE(near(img.at(p.x(), p.y()), {0, 0, 255, 128}, 1));
}

// The camera-set path: every view of the default set sees the asset.
TEST_F(RenderTest, CameraSetRendersEveryView) {
  GltfBuilder b;
  const int tex = b.add_texture(quadrant_texture());
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::cube(1.f, b.add_material({.texture = tex}))})}));
  const Scene scene = load(b);
  CameraSet set = load_camera_set("configs/cameras/default.yaml");
  set.width = set.height = 96;  // keep the test fast
  const auto views = render_camera_set(*renderer_, scene, set);
  ASSERT_EQ(views.size(), 4u);
  for (const auto& v : views) {
    EXPECT_EQ(v.image.width(), 96);
    EXPECT_FALSE(near(v.image.at(48, 48), kBackground, 0)) << v.camera.name;
    EXPECT_TRUE(near(v.image.at(1, 1), kBackground, 0)) << v.camera.name;
    keep(v.image, "default_set_" + v.camera.name);
  }
  EXPECT_EQ(views[1].camera.name, "right");
}

// One opaque unlit quad of `rgb`, 0.8 m wide, centred at (x, 0, 0), facing +z.
Scene quad_scene(float x, const Vec4& rgb) {
  Scene s;
  Material m;
  m.base_color = rgb;
  m.unlit = true;
  s.materials.push_back(m);
  Primitive p;
  p.positions = {Vec3(x - 0.4f, -0.4f, 0), Vec3(x + 0.4f, -0.4f, 0), Vec3(x + 0.4f, 0.4f, 0),
                 Vec3(x - 0.4f, 0.4f, 0)};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = 0;
  Mesh mesh;
  mesh.name = "quad";
  mesh.primitives.push_back(std::move(p));
  mesh.instances.push_back(Mat4::Identity());
  s.meshes.push_back(std::move(mesh));
  return s;
}

// A mesh naming shared geometry is drawn as its primitives, the first time and from the kept
// buffers later; they are kept while the name lives and dropped once it is dead. A name is an
// address and an owner: another owner aliasing the same address names other geometry (here the
// quad moved to the right, which buffers kept by address alone would draw on the left).
TEST_F(RenderTest, SharedGeometryIsKeptWhileItsNameLives) {
  static const int kAddress = 0;  // the address both names point at
  const Camera cam = look(Vec3(0, 0, 3));
  const RenderOptions o = unlit_options(64, 1);
  Scene left = quad_scene(-0.5f, Vec4(1, 0, 0, 1)), right = quad_scene(0.5f, Vec4(1, 0, 0, 1));
  const Image want_left = render(left, cam, o), want_right = render(right, cam, o);
  ASSERT_NE(want_left, want_right);
  EXPECT_EQ(renderer_->kept_geometry(), 0u);  // nothing named: nothing kept

  auto first = std::make_shared<int>(1);
  left.meshes[0].shared_geometry = std::shared_ptr<const void>(first, &kAddress);
  EXPECT_EQ(render(left, cam, o), want_left);
  EXPECT_EQ(renderer_->kept_geometry(), 1u);
  // Another scene naming the same geometry, with another material and instance: drawn from the
  // kept buffers, as a fresh upload draws it.
  Scene green = quad_scene(-0.5f, Vec4(0, 1, 0, 1));
  green.meshes[0].instances[0] = Eigen::Affine3f(Eigen::Translation3f(0, 0.3f, 0)).matrix();
  const Image want_green = render(green, cam, o);
  green.meshes[0].shared_geometry = left.meshes[0].shared_geometry;
  EXPECT_EQ(render(green, cam, o), want_green);
  EXPECT_EQ(renderer_->kept_geometry(), 1u);

  auto second = std::make_shared<int>(2);
  right.meshes[0].shared_geometry = std::shared_ptr<const void>(second, &kAddress);
  EXPECT_EQ(render(right, cam, o), want_right);
  EXPECT_EQ(renderer_->kept_geometry(), 2u);
  EXPECT_EQ(render(left, cam, o), want_left);  // both kept, each drawn with its own buffers
  EXPECT_EQ(renderer_->kept_geometry(), 2u);

  left.meshes[0].shared_geometry.reset();
  green.meshes[0].shared_geometry.reset();
  first.reset();  // the first name is dead: dropped at the next call
  EXPECT_EQ(render(right, cam, o), want_right);
  EXPECT_EQ(renderer_->kept_geometry(), 1u);
  right.meshes[0].shared_geometry.reset();
  second.reset();
  EXPECT_EQ(render(Scene{}, cam, o), render(Scene{}, cam, o));
  EXPECT_EQ(renderer_->kept_geometry(), 0u);
}

// Lines standing for coincident copies (Primitive::copies, merge_line_copies) draw what the
// copies drawn one over the other draw, to a level of 255 per blend: 12 horizontal lines of alpha
// 0.3 over a grey quad, each drawn three times, then merged; one copy each is far lighter.
TEST_F(RenderTest, MergedLineCopiesDrawWhatTheCopiesDraw) {
  Scene s = quad_scene(0.f, Vec4(0.5f, 0.5f, 0.5f, 1));
  s.meshes[0].primitives[0].positions = {Vec3(-0.9f, -0.9f, -0.1f), Vec3(0.9f, -0.9f, -0.1f),
                                         Vec3(0.9f, 0.9f, -0.1f), Vec3(-0.9f, 0.9f, -0.1f)};
  Material red;
  red.base_color = Vec4(1, 0.1f, 0.1f, 1);
  red.alpha_mode = AlphaMode::kBlend;
  s.materials.push_back(red);
  Primitive lines;
  lines.topology = Topology::kLines;
  lines.material = 1;
  for (int row = 0; row < 12; ++row)
    for (int copy = 0; copy < 3; ++copy) {
      const auto base = std::uint32_t(lines.positions.size());
      const float y = -0.55f + 0.1f * float(row), a = 0.3f;
      lines.positions.insert(lines.positions.end(), {Vec3(-0.8f, y, 0), Vec3(0.8f, y + 0.05f, 0)});
      lines.normals.insert(lines.normals.end(), 2, Vec3(0, float(copy) - 1, 1).normalized());
      lines.colors.insert(lines.colors.end(), 2, Vec4(1, 1, 1, a));
      lines.indices.insert(lines.indices.end(), {base, base + 1});
    }
  Mesh mesh;
  mesh.primitives.push_back(lines);
  mesh.instances.push_back(Mat4::Identity());
  s.meshes.push_back(mesh);
  const Camera cam = look(Vec3(0, 0, 3));
  RenderOptions o = unlit_options(96, 1);
  o.supersample = 2;
  const Image copies = render(s, cam, o);

  Scene merged = s;
  merge_line_copies(merged);
  Primitive& m = merged.meshes[1].primitives[0];
  ASSERT_EQ(m.element_count(), 12u);
  ASSERT_EQ(m.copies, std::vector<float>(24, 3.f));
  const Image got = render(merged, cam, o);
  m.copies.clear();
  const Image once = render(merged, cam, o);

  int worst = 0, worst_once = 0;
  for (std::size_t i = 0; i < got.bytes().size(); ++i) {
    worst = std::max(worst, std::abs(int(got.bytes()[i]) - int(copies.bytes()[i])));
    worst_once = std::max(worst_once, std::abs(int(once.bytes()[i]) - int(copies.bytes()[i])));
  }
  EXPECT_LE(worst, 2);
  EXPECT_GE(worst_once, 30);  // 0.3 against 1 - 0.7^3 = 0.657 of red over grey
}

// Supersampled by 2, the image is the mean of each 2 x 2 block of the same scene drawn at twice
// the size (one sample per pixel there), lines twice as wide: edges of a lit wavy sheet, a
// slanted diagonal line and blended lines, to 8-bit rounding.
TEST_F(RenderTest, SupersampledIsTheMeanOfEachBlockOfTheLargerImage) {
  GltfBuilder b;
  const int green = b.add_material({.base_color = Vec4(0.2f, 0.7f, 0.3f, 1), .double_sided = true});
  const int red = b.add_material({.base_color = Vec4(1, 0, 0, 0.5f), .alpha_mode = "BLEND", .unlit = true});
  PrimitiveData diagonal;
  diagonal.mode = TINYGLTF_MODE_LINE;
  diagonal.material = red;
  diagonal.positions = {Vec3(-0.7f, -0.6f, 0.2f), Vec3(0.6f, 0.7f, 0.2f)};
  NodeData sheet{.mesh = b.add_mesh({testing::dense_grid(6, green)})};
  sheet.rotation = Eigen::Quaternionf(Eigen::AngleAxisf(0.4f, Vec3(0.3f, 1, 0.2f).normalized()));
  b.add_root(b.add_node(sheet));
  b.add_root(b.add_node({.mesh = b.add_mesh({line_rows(0.1f, 40, 44, red), diagonal})}));
  const Scene scene = load(b);
  const Camera cam = look(Vec3(0, 0, 2));
  RenderOptions o = small(48, 1);
  o.supersample = 2;
  RenderOptions big = small(96, 1);
  big.line_width_px = 2;
  const Image got = render(scene, cam, o), full = render(scene, cam, big),
              plain = render(scene, cam, small(48, 1));
  keep(got, "supersampled");
  ASSERT_EQ(got.width(), 48);
  ASSERT_EQ(got.height(), 48);
  int worst = 0;
  std::size_t unlike_plain = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const Rgba8 g = got.at(x, y), p = plain.at(x, y);
      const std::uint8_t* gc = &g.r;
      bool differs = false;
      for (int c = 0; c < 4; ++c) {
        int sum = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const Rgba8 f = full.at(2 * x + dx, 2 * y + dy);
            sum += (&f.r)[c];
          }
        worst = std::max(worst, std::abs(4 * int(gc[c]) - sum));
        differs = differs || std::abs(int(gc[c]) - int((&p.r)[c])) > 2;
      }
      unlike_plain += differs;
    }
  EXPECT_LE(worst, 2) << "4 x pixel - block sum: at most the rounding of a mean of four";
  EXPECT_GT(unlike_plain, 60u) << "the edges are antialiased, unlike one sample per pixel";
}

// Supersampled by 2 with 4 samples: meshes are drawn supersampled, impostors multisampled. A
// scene without impostors is exactly the supersampled one; msaa must be 1 or k^2.
TEST_F(RenderTest, HybridWithoutImpostorsIsTheSupersampledImage) {
  GltfBuilder b;
  const int green = b.add_material({.base_color = Vec4(0.2f, 0.7f, 0.3f, 1), .double_sided = true});
  const int red = b.add_material({.base_color = Vec4(1, 0, 0, 0.5f), .alpha_mode = "BLEND", .unlit = true});
  b.add_root(b.add_node({.mesh = b.add_mesh({testing::dense_grid(6, green)})}));
  b.add_root(b.add_node({.mesh = b.add_mesh({line_rows(0.1f, 20, 24, red)})}));
  const Scene scene = load(b);
  const Camera cam = look(Vec3(0.3f, 0.4f, 2));
  RenderOptions hybrid = small(40, 4), ss = small(40, 1);
  hybrid.supersample = ss.supersample = 2;
  EXPECT_EQ(render(scene, cam, hybrid).bytes(), render(scene, cam, ss).bytes());
  hybrid.msaa = 2;
  try {
    render(scene, cam, hybrid);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(),
                 "supersample 2 needs msaa 1 or 4 (the samples of a pixel are its sub-pixels), got msaa 2");
  }
  hybrid.msaa = 1;
  hybrid.supersample = 5;
  try {
    render(scene, cam, hybrid);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(), "supersample 5 is not supported (1..4)");
  }
}

// Invalid options are refused with a clear message, not a GL error.
TEST_F(RenderTest, InvalidOptions) {
  const Scene empty;
  RenderOptions o = small();
  o.msaa = 64;
  try {
    render(empty, look(Vec3(0, 0, 2)), o);
    FAIL() << "expected RenderError";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("msaa 64 is not supported"), std::string::npos) << e.what();
  }
  o = small();
  o.width = 0;
  EXPECT_THROW(render(empty, look(Vec3(0, 0, 2)), o), RenderError);
  // An empty scene renders the background.
  EXPECT_TRUE(near(render(empty, look(Vec3(0, 0, 2)), small()).at(10, 10), kBackground, 0));
}

// Without any EGL vendor the renderer fails with one clear message instead of crashing. Runs in
// a fresh process (threadsafe death-test style re-executes the binary) so EGL starts clean.
TEST(RendererUnavailable, ClearErrorWithoutEgl) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        setenv("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl_vendor.json", 1);
        setenv("__EGL_VENDOR_LIBRARY_DIRS", "/nonexistent", 1);
        try {
          Renderer::create_headless();
          std::fprintf(stderr, "created a renderer\n");
          std::exit(1);
        } catch (const RenderUnavailableError& e) {
          std::fprintf(stderr, "%s\n", e.what());
          std::exit(0);
        }
      },
      ::testing::ExitedWithCode(0), "^headless OpenGL is not available: ");
}

}  // namespace
}  // namespace sylva::render

namespace sylva::render {
namespace {

// Third-party trees from ../shared/data (skipped when the data is not there).
class RealTreeTest : public RenderTest {};

std::size_t non_background(const Image& img) {
  std::size_t n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) n += img.at(x, y) == kBackground ? 0 : 1;
  return n;
}

// The ez-tree aspen: merged branch mesh plus double-sided alpha-masked leaf cards; every view of
// the verification set shows the tree, and the render is reproducible.
TEST_F(RealTreeTest, EzTreeAspenRenders) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data";
  const Scene s = load_gltf_scene(*data / "meshes/eztree/aspen_small_seed36330.glb");
  ASSERT_EQ(s.meshes.size(), 2u);
  bool masked_two_sided = false;
  for (const Material& m : s.materials)
    masked_two_sided |= m.alpha_mode == AlphaMode::kMask && m.double_sided;
  EXPECT_TRUE(masked_two_sided);
  CameraSet set = load_camera_set("configs/cameras/verify.yaml");
  set.width = set.height = 128;
  const auto views = render_camera_set(*renderer_, s, set);
  ASSERT_EQ(views.size(), 4u);
  for (const auto& v : views) {
    const double covered = double(non_background(v.image)) / double(v.image.pixel_count());
    EXPECT_GT(covered, 0.01) << v.camera.name;
    EXPECT_LT(covered, 0.6) << v.camera.name;
  }
  const auto again = render_camera_set(*renderer_, s, set);
  EXPECT_EQ(again[2].image, views[2].image);
}

// Quaternius' pine ships without its bark textures: the error names the glTF file and both
// missing images.
TEST(RealTreeData, MissingBarkTexturesAreNamed) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data";
  const auto file = *data / "meshes/quaternius/Pine_1.gltf";
  try {
    load_gltf_scene(file);
    FAIL() << "expected SceneLoadError";
  } catch (const SceneLoadError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(
        msg.rfind(
            file.string() +
                ": error: texture 'Bark_NormalTree_Normal.png' (image 0) could not be loaded: no such file ",
            0),
        0u)
        << msg;
    EXPECT_NE(msg.find("texture 'Bark_NormalTree.png' (image 1)"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("Leaf_Pine_C"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace sylva::render
