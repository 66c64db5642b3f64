// Scene::impostors: the scene renderer draws (hemi-)octahedral impostors with the reference shader
// exactly as ImpostorRenderer::render_octahedral does (the drawer `sylva impostorcheck` proves),
// and in the same depth buffer as the meshes. A hand-made atlas: every frame a disc of one colour
// with a constant depth and normal, so each expectation follows from the shader's contract.
#include "libs/render/impostor_draw.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "libs/image/compare.h"
#include "libs/image/image_io.h"
#include "libs/render/gl_context.h"
#include "libs/render/gl_util.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_atlas.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/renderer.h"
#include "libs/render/testing/gltf_builder.h"
#include "libs/render/testing/headless_renderer_test.h"
#include "tests/support/test_support.h"

namespace sylva::render {
namespace {

using image::Image;
using image::Rgba8;

constexpr Rgba8 kBackground{191, 204, 217, 255};
constexpr Rgba8 kDisc{200, 40, 40, 255};

struct Maps {
  Image color, normal_depth;
  ImpostorGeometry geometry;
};

// Empty maps of n x n frames of frame_px texels, the sphere (R = 1 m) filling each frame inside
// its padding (W = R F / (F - 2 padding)).
Maps empty_maps(int n, int frame_px, int padding_px, int mip_levels) {
  Maps m;
  ImpostorGeometry& g = m.geometry;
  g.frames_per_side = n;
  g.frame_px = frame_px;
  g.padding_px = padding_px;
  g.mip_levels = mip_levels;
  g.radius = 1;
  g.half_extent = float(frame_px) / float(frame_px - 2 * padding_px);
  m.color = Image(n * frame_px, n * frame_px, {0, 0, 0, 0});
  m.normal_depth = Image(n * frame_px, n * frame_px, {0, 0, 0, 0});
  return m;
}

// 4 x 4 frames of 32 px, padding 4 (2 mip levels): a disc of radius 12 px = the sphere, normal +Z
// (object space), depth 0.5 = the sphere's centre plane.
Maps disc_maps() {
  Maps m = empty_maps(4, 32, 4, 2);
  const ImpostorGeometry& g = m.geometry;
  const int px = g.frames_per_side * g.frame_px;
  for (int y = 0; y < px; ++y)
    for (int x = 0; x < px; ++x) {
      const double fx = (x % g.frame_px) + 0.5 - 16, fy = (y % g.frame_px) + 0.5 - 16;
      if (fx * fx + fy * fy > 12.0 * 12.0) continue;
      m.color.set(x, y, kDisc);
      m.normal_depth.set(x, y, {128, 128, 255, 128});
    }
  return m;
}

Camera look(const Vec3& eye) {
  Camera c;
  c.eye = eye;
  c.target = Vec3::Zero();
  c.fov_y_deg = 45;
  c.z_near = 0.05f;
  c.z_far = 50.f;
  return c;
}

Mat4 translation(const Vec3& t) {
  Mat4 m = Mat4::Identity();
  m.block<3, 1>(0, 3) = t;
  return m;
}

// The scene renderer of HeadlessRendererTest and, beside it, an impostor renderer.
class ImpostorDrawTest : public testing::HeadlessRendererTest {
 protected:
  static void SetUpTestSuite() {
    HeadlessRendererTest::SetUpTestSuite();
    if (!renderer_) return;
    try {
      impostors_ = ImpostorRenderer::create_headless();
    } catch (const RenderUnavailableError& e) {
      unavailable_ = e.what();
    }
  }
  static void TearDownTestSuite() {
    HeadlessRendererTest::TearDownTestSuite();
    impostors_.reset();
  }
  void SetUp() override {
    if (!renderer_ || !impostors_) testing::fail_or_skip_without_gl(unavailable_);
  }

  static inline std::unique_ptr<ImpostorRenderer> impostors_;
  test::TempDir dir_;
};

RenderOptions options() {
  RenderOptions o;
  o.width = o.height = 96;
  o.msaa = 4;
  return o;
}

Scene impostor_scene(const Maps& m, std::vector<Mat4> instances) {
  Scene s;
  s.source = "impostor test";
  s.impostors.push_back({std::make_shared<const ImpostorAtlas>(
                             make_impostor_atlas("disc", m.color, m.normal_depth, m.geometry)),
                         std::move(instances)});
  return s;
}

// Two blue quads around the impostor at the origin: x in [-0.9, -0.1] at z = 1.5 (in front),
// 6 m wide at z = -2 (behind); the disc impostor of `m` at the origin.
Scene quads_around_impostor(const Maps& m, const std::filesystem::path& dir) {
  testing::GltfBuilder b;
  const int blue = b.add_material({.base_color = Vec4(0, 0, 1, 1)});
  const int quad = b.add_mesh({testing::quad(1.f, blue)});
  b.add_root(b.add_node({.mesh = quad, .translation = Vec3(-0.5f, 0, 1.5f), .scale = Vec3(0.8f, 0.8f, 1)}));
  b.add_root(b.add_node({.mesh = quad, .translation = Vec3(0, 0, -2), .scale = Vec3(6, 6, 1)}));
  b.write_glb(dir / "quads.glb");
  Scene s = load_gltf_scene(dir / "quads.glb");
  s.impostors = impostor_scene(m, {Mat4::Identity()}).impostors;
  return s;
}

// Same pixels as the reference drawer, for overlapping instances drawn far to near.
TEST_F(ImpostorDrawTest, SceneImpostorsMatchTheReferenceDrawer) {
  const Maps m = disc_maps();
  const std::vector<Mat4> instances = {translation(Vec3(0.6f, 0, -1)), translation(Vec3(0, 0, 0)),
                                       translation(Vec3(-0.8f, 0.3f, 0.5f))};
  const Camera cam = look(Vec3(0, 0.5f, 5));
  OctahedralImpostor ref;
  ref.color = m.color;
  ref.normal_depth = m.normal_depth;
  ref.geometry = m.geometry;
  ref.instances = instances;
  const Image want = impostors_->render_octahedral(ref, std::span<const Camera>(&cam, 1), options()).front();
  const Image got = renderer_->render(impostor_scene(m, instances), cam, options());
  ASSERT_EQ(got.bytes().size(), want.bytes().size());
  std::size_t differ = 0, drawn = 0;
  for (std::size_t i = 0; i < got.bytes().size(); i += 4) {
    differ += std::memcmp(&got.bytes()[i], &want.bytes()[i], 4) != 0;
    drawn += got.bytes()[i] != kBackground.r;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(drawn, 1000u);  // three discs of ~13 px radius
  const Rgba8 corner = got.at(1, 1);
  EXPECT_EQ(corner.r, kBackground.r);
  EXPECT_EQ(corner.b, kBackground.b);
}

// 6 x 6 frames of 64 px, padding 8 (3 mip levels), R = 1 m: per frame (seeded) four blobs of
// texels with their own depth, normal and colour, coverage full, half or thin (< 0.5), and a few
// texels with only a depth stored; everything else empty. The frames differ, so frame blending,
// the march's thin and full texels and every mip level's reach show in the pixels.
Maps varied_maps() {
  Maps m = empty_maps(6, 64, 8, 3);
  const ImpostorGeometry& g = m.geometry;
  std::uint32_t state = 12345;
  auto next = [&](int n) {
    state = state * 1664525u + 1013904223u;
    return int((state >> 8) % std::uint32_t(n));
  };
  for (int f = 0; f < g.frames_per_side * g.frames_per_side; ++f) {
    const int fx = (f % g.frames_per_side) * g.frame_px, fy = (f / g.frames_per_side) * g.frame_px;
    for (int b = 0; b < 4; ++b) {
      const int cx = 18 + next(28), cy = 14 + next(36), r = 3 + next(8);
      const std::uint8_t cover[3] = {255, 128, 60};
      const Rgba8 c{std::uint8_t(40 + next(200)), std::uint8_t(40 + next(200)), std::uint8_t(40 + next(200)),
                    cover[next(3)]};
      const Rgba8 nd{std::uint8_t(60 + next(136)), std::uint8_t(60 + next(136)),
                     std::uint8_t(150 + next(100)), std::uint8_t(40 + next(176))};
      for (int y = cy - r; y <= cy + r; ++y)
        for (int x = cx - r; x <= cx + r; ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) {
            m.color.set(fx + x, fy + y, c);
            m.normal_depth.set(fx + x, fy + y, nd);
          }
    }
    for (int k = 0; k < 3; ++k)
      m.normal_depth.set(fx + 12 + next(40), fy + 12 + next(40), {0, 0, 0, std::uint8_t(1 + next(254))});
  }
  return m;
}

// The scene renderer's impostor program (one texture for the march's depth and coverage, the
// empty-distance cull: impostor_draw.h) draws the reference drawer's pixels, byte for byte, with
// every parallax step count, near (mip level 0) and far (the last level), from the side, from
// above and from below the hemisphere, and along a frame's own direction (cameras 5 and 6: one
// frame of weight 1, its rays' segments short, so the cull turns on the filtered reads' reach).
TEST_F(ImpostorDrawTest, SceneImpostorsMatchTheReferenceDrawerOnVariedMaps) {
  const Maps m = varied_maps();
  std::vector<Mat4> instances;
  for (int i = 0; i < 9; ++i)
    instances.push_back(translation(Vec3(float(i % 3) * 1.7f - 1.7f, 0, float(i / 3) * -1.9f)));
  const std::vector<Camera> cams = {
      look(Vec3(0.3f, 0.4f, 4)), look(Vec3(-3, 2.5f, 2)), look(Vec3(0.5f, 6, 0.8f)), look(Vec3(2, -1.2f, 3)),
      look(Vec3(1, 1.5f, 40)),   look(Vec3(-40, 0, 0)),   look(Vec3(-14, 0, 0))};
  OctahedralImpostor ref;
  ref.color = m.color;
  ref.normal_depth = m.normal_depth;
  ref.geometry = m.geometry;
  ref.instances = instances;
  for (const int steps : {0, 8, 16}) {
    const std::vector<Image> want =
        impostors_->render_octahedral(ref, cams, options(), {.parallax_steps = steps});
    Scene s = impostor_scene(m, instances);
    s.impostors.front().parallax_steps = steps;
    const std::vector<Image> got = renderer_->render_views(s, cams, options());
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t c = 0; c < cams.size(); ++c) {
      std::size_t differ = 0, drawn = 0;
      for (std::size_t i = 0; i < got[c].bytes().size(); i += 4) {
        differ += std::memcmp(&got[c].bytes()[i], &want[c].bytes()[i], 4) != 0;
        drawn += std::memcmp(&got[c].bytes()[i], &kBackground, 3) != 0;
      }
      EXPECT_EQ(differ, 0u) << "steps " << steps << ", camera " << c;
      EXPECT_GT(drawn, c == 4 || c == 5 ? 20u : 300u) << "steps " << steps << ", camera " << c;
    }
  }
}

// One depth buffer: an opaque quad in front of the impostor hides it, one behind is hidden by it.
TEST_F(ImpostorDrawTest, MeshesInFrontHideImpostorsAndImpostorsHideMeshesBehind) {
  const Maps m = disc_maps();
  const Scene s = quads_around_impostor(m, dir_.path());
  const Camera cam = look(Vec3(0, 0, 5));
  const RenderOptions o = options();
  const Image img = renderer_->render(s, cam, o);
  image::write_png(img, dir_ / "depth.png");
  // Centre right of the disc: the impostor (red, lit), over the blue quad behind it.
  const Rgba8 disc = img.at(56, 48);
  EXPECT_GT(disc.r, 100);
  EXPECT_LT(disc.b, 60);
  // Left of centre, where the front quad is: blue.
  const Rgba8 front = img.at(38, 48);
  EXPECT_LT(front.r, 30);
  EXPECT_GT(front.b, 100);
  // Outside the disc: the back quad (blue), not the background.
  const Rgba8 back = img.at(48, 10);
  EXPECT_LT(back.r, 30);
  EXPECT_GT(back.b, 100);
}

// Supersampled by 2 with 4 samples per pixel ("hybrid"): the meshes are drawn 2 x 2 supersampled,
// their colour and depth moved into a 4-sample target (a pixel's samples = its sub-pixels) where
// the impostors are drawn multisampled, then back. The depth test between the two holds as in
// one buffer; away from the impostor the image is exactly the supersampled one, and the whole is
// within the verifier's thresholds of the 4x MSAA image (the impostor shaded once per pixel, as
// there; supersampled, its outline would be shaded per sub-pixel).
TEST_F(ImpostorDrawTest, HybridDrawsImpostorsMultisampledOverSupersampledMeshes) {
  const Maps m = disc_maps();
  const Scene s = quads_around_impostor(m, dir_.path());
  const Camera cam = look(Vec3(0, 0, 5));
  RenderOptions hybrid = options(), ss = options();
  hybrid.supersample = ss.supersample = 2;
  ss.msaa = 1;
  const Image img = renderer_->render(s, cam, hybrid), want = renderer_->render(s, cam, ss);
  image::write_png(img, dir_ / "hybrid.png");
  const Rgba8 disc = img.at(56, 48), front = img.at(38, 48), back = img.at(48, 10);
  EXPECT_GT(disc.r, 100);
  EXPECT_LT(disc.b, 60);
  EXPECT_LT(front.r, 30);
  EXPECT_GT(front.b, 100);
  EXPECT_LT(back.r, 30);
  EXPECT_GT(back.b, 100);
  std::size_t outside = 0, differ = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      if (x >= 20 && x < 76 && y >= 20 && y < 76) continue;  // the impostor's quad: ~23 px around the centre
      ++outside;
      const Rgba8 a = img.at(x, y), c = want.at(x, y);
      differ += a.r != c.r || a.g != c.g || a.b != c.b || a.a != c.a;
    }
  EXPECT_GT(outside, 5000u);
  EXPECT_EQ(differ, 0u);
  const image::CompareResult r = image::compare_images(renderer_->render(s, cam, options()), img);
  EXPECT_TRUE(r.passed) << r.failure;
  EXPECT_FALSE(image::compare_images(want, img).passed) << "the supersampled impostor's outline differs";
}

// SYLVA_SCENE_DEPTH (the drawer with a scene-depth texture): a fragment is discarded before the
// march where that texture's depth is below the fragment's, whatever the target's own depth says.
// The drawer alone into a 96 x 96 target whose depth is clear: without the texture the whole
// disc; with one holding 0 on the left half and 1 on the right, the right half only, the same
// pixels there.
TEST_F(ImpostorDrawTest, SceneDepthDiscardsFragmentsTheSceneHides) {
  const Maps m = disc_maps();
  const Scene s = impostor_scene(m, {Mat4::Identity()});
  const Camera cam = look(Vec3(0, 0, 5));
  constexpr int kSize = 96;
  const std::unique_ptr<detail::GlContext> ctx = detail::create_egl_context();
  detail::CurrentContext current(*ctx);
  detail::ImpostorDrawer drawer;
  {
    detail::GlObjects gl;
    const GLuint fbo = gl.framebuffer(), color = gl.renderbuffer(), depth = gl.renderbuffer();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, kSize, kSize);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, kSize, kSize);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    ASSERT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), GLenum(GL_FRAMEBUFFER_COMPLETE));
    std::vector<float> half(kSize * kSize);
    for (int i = 0; i < kSize * kSize; ++i) half[std::size_t(i)] = i % kSize < kSize / 2 ? 0.f : 1.f;
    const GLuint scene_depth = gl.texture();
    glBindTexture(GL_TEXTURE_2D, scene_depth);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, kSize, kSize, 0, GL_RED, GL_FLOAT, half.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    auto draw = [&](GLuint with) {
      const detail::ImpostorDrawer::Uploaded up = drawer.upload(gl, s.impostors, 4096, with != 0);
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glViewport(0, 0, kSize, kSize);
      glClearColor(0, 0, 0, 0);
      glClearDepth(1.0);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      drawer.draw(s.impostors, up, cam, 1.f, Lighting{}, with);
      std::vector<std::uint8_t> px(kSize * kSize * 4);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
      return px;
    };
    const std::vector<std::uint8_t> whole = draw(0), right = draw(scene_depth);
    ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    std::size_t left_drawn = 0, right_drawn = 0, left_kept = 0, right_same = 0;
    for (int i = 0; i < kSize * kSize; ++i) {
      const bool left = i % kSize < kSize / 2;
      const bool drawn = whole[std::size_t(i) * 4 + 3] > 0, kept = right[std::size_t(i) * 4 + 3] > 0;
      (left ? left_drawn : right_drawn) += drawn;
      if (left) left_kept += kept;
      if (!left)
        right_same += std::equal(&whole[std::size_t(i) * 4], &whole[std::size_t(i) * 4 + 4],
                                 &right[std::size_t(i) * 4]);
    }
    EXPECT_GT(left_drawn, 500u);
    EXPECT_GT(right_drawn, 500u);
    EXPECT_EQ(left_kept, 0u);
    EXPECT_EQ(right_same, std::size_t(kSize * kSize / 2));
  }
  drawer.destroy();
}

// Hybrid antialiasing discards the impostor fragments the meshes hide in every sample
// (RenderOptions::impostor_hidden_discard) with the same pixels: disc impostors at three depths
// and a quad turned 60 degrees about the vertical through them (in front of part of each, behind
// part), its edge and its crossing with each impostor's quad inside pixels.
TEST_F(ImpostorDrawTest, HybridDiscardOfHiddenImpostorFragmentsKeepsThePixels) {
  const Maps m = disc_maps();
  testing::GltfBuilder b;
  const int blue = b.add_material({.base_color = Vec4(0, 0, 1, 1)});
  const int quad = b.add_mesh({testing::quad(1.f, blue)});
  b.add_root(b.add_node({.mesh = quad,
                         .translation = Vec3(0.3f, 0.1f, 0),
                         .rotation = Eigen::Quaternionf(Eigen::AngleAxisf(1.05f, Vec3::UnitY())),
                         .scale = Vec3(3.f, 1.7f, 1)}));
  b.write_glb(dir_.path() / "tilted.glb");
  Scene s = load_gltf_scene(dir_.path() / "tilted.glb");
  s.impostors = impostor_scene(m, {translation(Vec3(-0.6f, 0.2f, -0.4f)), Mat4::Identity(),
                                   translation(Vec3(0.7f, -0.3f, 0.5f))})
                    .impostors;
  const Camera cam = look(Vec3(0.4f, 0.3f, 5));
  RenderOptions on = options(), off = options();
  on.supersample = off.supersample = 2;
  off.impostor_hidden_discard = false;
  const Image with = renderer_->render(s, cam, on), without = renderer_->render(s, cam, off);
  image::write_png(with, dir_ / "hidden_discard.png");
  EXPECT_EQ(with.bytes(), without.bytes());
  std::size_t red = 0, blue_px = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const Rgba8 p = with.at(x, y);
      red += p.r > 100 && p.b < 60;
      blue_px += p.b > 100 && p.r < 30;
    }
  EXPECT_GT(red, 300u);
  EXPECT_GT(blue_px, 300u);
}

// The maps stay uploaded between calls while their atlas lives (a second call with the same atlas
// uploads nothing) and are deleted once it is gone; a new atlas is drawn with its own maps.
TEST_F(ImpostorDrawTest, MapsStayUploadedWhileTheirAtlasLives) {
  const Maps m = disc_maps();
  {
    const std::unique_ptr<detail::GlContext> ctx = detail::create_egl_context();
    detail::CurrentContext current(*ctx);
    detail::ImpostorDrawer drawer;
    {
      const Scene a = impostor_scene(m, {Mat4::Identity()}), b = impostor_scene(m, {Mat4::Identity()});
      GLuint first = 0;
      {
        detail::GlObjects gl;
        first = drawer.upload(gl, a.impostors, 4096).color.at(0);
      }
      EXPECT_EQ(drawer.kept(), 1u);
      {
        detail::GlObjects gl;
        EXPECT_EQ(drawer.upload(gl, a.impostors, 4096).color.at(0), first);  // the same texture
      }
      EXPECT_EQ(drawer.kept(), 1u);
      {
        detail::GlObjects gl;
        std::vector<ImpostorSet> both = a.impostors;
        both.push_back(b.impostors.front());  // another atlas, same pixels: its own maps
        const auto up = drawer.upload(gl, both, 4096);
        EXPECT_EQ(up.color.at(0), first);
        EXPECT_NE(up.color.at(1), first);
      }
      EXPECT_EQ(drawer.kept(), 2u);
    }
    detail::GlObjects gl;
    drawer.upload(gl, {}, 4096);  // both atlases are gone
    EXPECT_EQ(drawer.kept(), 0u);
    drawer.destroy();
  }
  // Through the renderer: a red disc, then (the red atlas gone) a blue one where it was.
  const Camera cam = look(Vec3(0, 0, 5));
  EXPECT_GT(renderer_->render(impostor_scene(m, {Mat4::Identity()}), cam, options()).at(56, 48).r, 100);
  Maps blue = disc_maps();
  for (std::size_t i = 0; i < blue.color.bytes().size(); i += 4)
    if (blue.color.bytes()[i + 3])
      blue.color.set(int(i / 4) % blue.color.width(), int(i / 4) / blue.color.width(), {40, 40, 200, 255});
  const Rgba8 px = renderer_->render(impostor_scene(blue, {Mat4::Identity()}), cam, options()).at(56, 48);
  EXPECT_LT(px.r, 60);
  EXPECT_GT(px.b, 100);
}

// Renderer::prepare uploads what a view keeps (the meshes naming shared geometry, the impostor
// maps) without drawing; the view drawn next uploads nothing more and has a fresh upload's pixels.
TEST_F(ImpostorDrawTest, PrepareUploadsWhatTheViewKeepsWithoutDrawing) {
  const Maps m = disc_maps();
  Scene s = quads_around_impostor(m, dir_.path());
  ASSERT_FALSE(s.meshes.empty());
  const auto names = std::make_shared<int>(0);
  for (Mesh& mesh : s.meshes) mesh.shared_geometry = std::shared_ptr<const void>(names, &mesh);
  const Camera cam = look(Vec3(0, 0, 5));
  RenderOptions o = options();
  o.supersample = 2;  // hybrid: the impostors' programs with SYLVA_SCENE_DEPTH
  const Image want = renderer_->render(s, cam, o);
  const std::unique_ptr<Renderer> fresh = Renderer::create_headless();
  fresh->prepare(s, o);
  EXPECT_EQ(fresh->kept_geometry(), s.meshes.size());
  EXPECT_EQ(fresh->kept_impostor_atlases(), 1u);
  EXPECT_EQ(fresh->render(s, cam, o), want);
  EXPECT_EQ(fresh->kept_geometry(), s.meshes.size());
  EXPECT_EQ(fresh->kept_impostor_atlases(), 1u);
}

TEST_F(ImpostorDrawTest, BadAtlasesAreClearErrors) {
  Maps m = disc_maps();
  Scene s;
  s.impostors.push_back({nullptr, {Mat4::Identity()}});
  EXPECT_THROW(
      {
        try {
          renderer_->render(s, look(Vec3(0, 0, 5)), options());
        } catch (const RenderError& e) {
          EXPECT_STREQ(e.what(), "an impostor set has no atlas");
          throw;
        }
      },
      RenderError);
  m.geometry.frame_px = 16;
  try {
    make_impostor_atlas("disc", m.color, m.normal_depth, m.geometry);
    FAIL() << "no error";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(),
                 "impostor 'disc': its maps must be 64x64 pixels (frames_per_side x frame_px), got 128x128");
  }
}

// Premultiplied by coverage: half-covered texels darken (in linear light) by half.
TEST(ImpostorAtlas, PremultipliesByCoverage) {
  ImpostorGeometry g;
  g.frames_per_side = 2;
  g.frame_px = 1;
  g.padding_px = 0;
  Image color(2, 2, {255, 128, 0, 255}), nd(2, 2, {200, 100, 255, 77});
  color.set(1, 0, {255, 128, 0, 128});
  color.set(0, 1, {255, 128, 0, 0});
  const ImpostorAtlas a = make_impostor_atlas("t", color, nd, g);
  EXPECT_EQ(a.color[0], 255);  // opaque: unchanged
  EXPECT_EQ(a.color[1], 128);
  EXPECT_EQ(a.color[4], 188);  // 255 * sRGB(linear(1) * 128 / 255) = 187.8
  EXPECT_EQ(a.color[7], 128);
  EXPECT_EQ(a.normal_depth[4], (200 * 128 + 127) / 255);
  EXPECT_EQ(a.normal_depth[7], 77);  // depth unchanged
  EXPECT_EQ(a.color[8], 0);          // uncovered
  EXPECT_EQ(a.normal_depth[8], 0);
}

// The cull's distances: per cell, the gap in texels between its box and the nearest cell of the
// same frame holding a texel with any byte set (depth alone counts); an empty frame is 255.
TEST(ImpostorAtlas, EmptyDistanceIsTheGapToTheNearestStoredTexelOfItsFrame) {
  Maps m = empty_maps(2, 16, 2, 1);
  m.color.set(5, 5, {10, 20, 30, 255});               // frame (0, 0), cell (2, 2) of 2 px
  m.normal_depth.set(16 + 15, 16 + 0, {0, 0, 0, 9});  // frame (1, 1): a depth only, cell (7, 0)
  const std::vector<std::uint8_t> d =
      impostor_empty_distance(make_impostor_atlas("t", m.color, m.normal_depth, m.geometry), 2);
  ASSERT_EQ(d.size(), 16u * 16u);
  auto at = [&](int x, int y) { return int(d[std::size_t(y) * 16 + std::size_t(x)]); };
  EXPECT_EQ(at(2, 2), 0);
  EXPECT_EQ(at(3, 3), 0);  // touching
  EXPECT_EQ(at(4, 2), 2);  // one cell between
  EXPECT_EQ(at(6, 0), 6);
  EXPECT_EQ(at(0, 7), 8);  // chessboard: max(2, 5) cells away
  EXPECT_EQ(at(7, 7), 8);
  EXPECT_EQ(at(8 + 3, 2), 255);  // frame (1, 0): empty, and frame (0, 0)'s texel does not count
  EXPECT_EQ(at(8 + 7, 8 + 0), 0);
  EXPECT_EQ(at(8 + 0, 8 + 7), 12);
  EXPECT_EQ(at(8 + 7, 8 + 1), 0);
}

}  // namespace
}  // namespace sylva::render
