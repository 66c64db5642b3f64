// How the renderer is called: determinism, threads, renderers beside each other, what stays
// uploaded between calls, supersampling, options and their errors, a missing EGL, and real trees
// (render_fixture.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <thread>

#include "libs/image/compare.h"
#include "libs/render/line_merge.h"
#include "libs/render/tests/render_fixture.h"

namespace sylva::render::render_test {
namespace {

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

// A camera set's supersampling and msaa reach its render options (camera_test.cpp's
// CameraSet.Supersample parses them).
TEST(CameraSet, SupersampleReachesTheRenderOptions) {
  const CameraSet set = parse_camera_set(
      "version: 1\nwidth: 64\nheight: 32\nmsaa: 4\nsupersample: 2\n"
      "views:\n  - name: a\n    orbit: {}\n",
      "cams.yaml");
  EXPECT_EQ(options_for(set).supersample, 2);
  EXPECT_EQ(options_for(set).msaa, 4);
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
}  // namespace sylva::render::render_test
