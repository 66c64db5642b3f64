// A quantised pack level draws like the lod level it came from, within the level's error (issue
// 14: KHR_mesh_quantization with steps from each level's epsilon). A real third-party tree (the
// ez-tree aspen: bark mesh and alpha-masked, double-sided leaf cards with a texture) is packed as
// a three-level chain; each level is rendered by sylva's renderer from its switch distance, once as
// the lod stage's float geometry and once from the pack GLB (meshopt + quantisation decoded), and
// the images are compared as `sylva lodcheck` compares (coverage per pixel, delta = 0.5 px), and
// by colour. A grid far coarser than epsilon must fail the same comparison.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "libs/gltf/reader.h"
#include "libs/gltf/writer.h"
#include "libs/image/png.h"
#include "libs/render/distance_camera.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/shared_renderer.h"
#include "stages/pack/pack_core.h"
#include "tests/support/test_support.h"

namespace sylva::pack {
namespace {

constexpr int kHeight = 512;           // image height of the error model's camera, px
constexpr double kFovY = 0.785398163;  // 45 degrees
constexpr double kDelta = 0.5;         // pixel error of the chain, px

// The switch distance of a level of spatial error eps: eps projects to kDelta pixels.
double switch_distance(double eps) { return eps / (kDelta * 2 * std::tan(kFovY / 2) / kHeight); }

struct Diff {
  std::size_t footprint = 0;    // pixels covered in either image
  double failing_fraction = 0;  // footprint pixels whose coverage changed by more than kDelta
  double mean_coverage = 0;     // mean |coverage change| over the footprint
  double colour_fraction = 0;   // pixels covered in both whose RGB differs by more than 4/255
  double mean_colour = 0;       // mean per-channel |RGB change| (0..1) over those pixels
};

Diff compare(const image::Image& a, const image::Image& b) {
  Diff d;
  std::size_t failing = 0, both = 0, colour_failing = 0;
  double coverage = 0, colour = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const image::Rgba8 p = a.at(x, y), q = b.at(x, y);
      if (p.a == 0 && q.a == 0) continue;
      ++d.footprint;
      const double dc = std::abs(int(p.a) - int(q.a)) / 255.0;
      coverage += dc;
      if (dc > kDelta) ++failing;
      if (p.a == 255 && q.a == 255) {
        ++both;
        const int dr = std::abs(p.r - q.r), dg = std::abs(p.g - q.g), db = std::abs(p.b - q.b);
        colour += (dr + dg + db) / (3 * 255.0);
        if (std::max({dr, dg, db}) > 4) ++colour_failing;
      }
    }
  if (d.footprint) d.failing_fraction = double(failing) / double(d.footprint);
  if (d.footprint) d.mean_coverage = coverage / double(d.footprint);
  if (both) d.colour_fraction = double(colour_failing) / double(both), d.mean_colour = colour / double(both);
  return d;
}

// The aspen as one mesh (its two nodes carry identity transforms).
gltf::Scene aspen(const std::filesystem::path& file) {
  gltf::Scene s = gltf::read_scene(file);
  gltf::Mesh merged;
  merged.name = "aspen";
  for (const gltf::Mesh& m : s.meshes)
    merged.primitives.insert(merged.primitives.end(), m.primitives.begin(), m.primitives.end());
  s.meshes = {merged};
  s.nodes = {gltf::Node{}};
  s.nodes[0].mesh = 0;
  s.roots = {0};
  return s;
}

gltf::Node level_node(int i, double eps) {
  gltf::Node n;
  n.name = "lod" + std::to_string(i);
  n.mesh = i;
  n.extras = {{"epsilon_m", eps}, {"pixel_error_px", kDelta}, {"switch_distance_m", switch_distance(eps)}};
  return n;
}

class PackRender : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = test::data_dir();
    if (!data_) GTEST_SKIP() << "no test data";
    try {
      renderer_ = &render::shared_renderer();
    } catch (const render::RenderUnavailableError& e) {
      std::error_code ec;
      const char* require = std::getenv("SYLVA_REQUIRE_GL");
      if ((require && std::string(require) == "1") ||
          std::filesystem::exists("/usr/share/glvnd/egl_vendor.d/50_mesa.json", ec))
        FAIL() << e.what();
      GTEST_SKIP() << e.what();
    }
  }

  // Both views of a level at its switch distance: (lod image, pack image) pairs.
  std::vector<Diff> diffs(const gltf::Scene& lod_level, const std::string& pack_glb, double eps,
                          const std::string& keep_as) {
    const render::Scene a = render::load_gltf_scene_from_memory(gltf::encode(lod_level), "lod.glb");
    const render::Scene b = render::load_gltf_scene_from_memory(pack_glb, "pack.glb");
    render::RenderOptions o;
    o.width = o.height = kHeight;
    o.background = {0, 0, 0, 0};
    std::vector<Diff> out;
    for (double az : {0.0, 90.0}) {
      const render::Camera c =
          render::camera_at_box_distance(a.bounds(), switch_distance(eps), az, 0, kFovY, kHeight);
      const image::Image ia = renderer_->render(a, c, o), ib = renderer_->render(b, c, o);
      if (!keep_as.empty() && az == 0) {
        std::filesystem::create_directories("out/test-images");
        image::write_png(ia, "out/test-images/pack_" + keep_as + "_lod.png");
        image::write_png(ib, "out/test-images/pack_" + keep_as + "_pack.png");
      }
      out.push_back(compare(ia, ib));
    }
    return out;
  }

  std::optional<std::filesystem::path> data_;
  render::Renderer* renderer_ = nullptr;
};

TEST_F(PackRender, QuantisedLevelsDrawWithinTheirErrorOfTheLodLevels) {
  const gltf::Scene tree = aspen(*data_ / "meshes/eztree/aspen_small_seed36330.glb");
  // Three levels of the same geometry: the pack's grid follows epsilon alone. At 2 mm the 39 m
  // tree would need 17 bits for a quarter of epsilon: it gets 16 (0.52 mm, within epsilon:
  // position_error_max), then 13 and 11 bits.
  const double eps[3] = {0.002, 0.02, 0.08};
  SpeciesInput in;
  in.species = "aspen";
  in.chain = tree;
  in.chain.meshes = {tree.meshes[0], tree.meshes[0], tree.meshes[0]};
  in.chain.nodes = {level_node(0, eps[0]), level_node(1, eps[1]), level_node(2, eps[2])};
  in.chain.nodes[0].extensions = {{"MSFT_lod", {{"ids", {1, 2}}}}};
  in.chain.nodes[0].extras["MSFT_screencoverage"] = {1.0, 0.2, 0.05};
  in.chain.roots = {0};
  in.levels = {tree, tree, tree};
  PackOptions options;
  options.min_saving = 0;  // the same geometry thrice: keep every level (this test is about quantisation)
  const std::vector<PackedFile> files = pack_species(in, options);
  ASSERT_EQ(files.size(), 5u);
  const nlohmann::json lod = nlohmann::json::parse(files[4].bytes);
  EXPECT_FALSE(lod["levels"][0]["position_float"].get<bool>());
  EXPECT_EQ(lod["levels"][0]["position_bits"], 16);
  EXPECT_EQ(lod["levels"][1]["position_bits"], 13);
  EXPECT_EQ(lod["levels"][2]["position_bits"], 11);
  EXPECT_EQ(files[1].bytes.find("\"EXPONENTIAL\""), std::string::npos);
  const double err0 = lod["levels"][0]["position_error_m"].get<double>();
  EXPECT_GT(err0, 0.25 * eps[0]);
  EXPECT_LE(err0, eps[0]);
  for (int i = 0; i < 3; ++i) {
    const nlohmann::json& l = lod["levels"][std::size_t(i)];
    // The rounding error is within a quarter of epsilon (level 0: within epsilon, 16 bits); a
    // grid is not needlessly fine.
    if (i > 0) {
      EXPECT_LE(l["position_error_m"].get<double>(), 0.25 * eps[i]) << i;
      EXPECT_FALSE(l["position_float"].get<bool>()) << i;
      EXPECT_GT(l["position_error_m"].get<double>(), 0.125 * eps[i]) << i;
    }
    EXPECT_NE(files[std::size_t(i) + 1].bytes.find("KHR_mesh_quantization"), std::string::npos);
    for (const Diff& d : diffs(tree, files[std::size_t(i) + 1].bytes, eps[i], i == 2 ? "aspen_lod2" : "")) {
      SCOPED_TRACE("level " + std::to_string(i));
      EXPECT_GT(d.footprint, 2000u);
      EXPECT_LE(d.failing_fraction, 0.01);
      EXPECT_LE(d.mean_coverage, 0.03);
      EXPECT_LE(d.colour_fraction, 0.05);
      EXPECT_LE(d.mean_colour, 0.01);
      std::printf(
          "level %d: footprint %zu, failing %.4f, mean coverage %.4f, colour failing %.4f, mean colour "
          "%.4f\n",
          i, d.footprint, d.failing_fraction, d.mean_coverage, d.colour_fraction, d.mean_colour);
    }
  }
  // With position_error_max a quarter, level 0 keeps float positions (EXPONENTIAL filter) within a
  // quarter of epsilon.
  PackOptions strict = options;
  strict.position_error_max = 0.25;
  const std::vector<PackedFile> floats = pack_species(in, strict);
  const nlohmann::json lod_float = nlohmann::json::parse(floats[4].bytes);
  EXPECT_TRUE(lod_float["levels"][0]["position_float"].get<bool>());
  EXPECT_EQ(lod_float["levels"][0]["position_bits"], 0);
  EXPECT_LE(lod_float["levels"][0]["position_error_m"].get<double>(), 0.25 * eps[0]);
  EXPECT_NE(floats[1].bytes.find("\"EXPONENTIAL\""), std::string::npos);
  EXPECT_LT(files[1].bytes.size(), floats[1].bytes.size());
  std::printf("level 0: 16 bits %zu bytes, float (EXPONENTIAL) %zu bytes\n", files[1].bytes.size(),
              floats[1].bytes.size());
  // A grid of 6 bits (a 0.6 m step for this 39 m tree) at level 2's distance is far outside
  // epsilon: the same comparison sees it.
  gltf::WriteOptions coarse;
  coarse.meshopt = true;
  coarse.quantize.enabled = true;
  coarse.quantize.position_bits = {6};
  const std::vector<Diff> bad = diffs(tree, gltf::encode(tree, coarse), eps[2], "");
  std::printf("6-bit grid: failing %.4f, mean coverage %.4f\n", bad[0].failing_fraction,
              bad[0].mean_coverage);
  EXPECT_TRUE(bad[0].failing_fraction > 0.01 || bad[0].mean_coverage > 0.03)
      << bad[0].failing_fraction << " " << bad[0].mean_coverage;
}

}  // namespace
}  // namespace sylva::pack
