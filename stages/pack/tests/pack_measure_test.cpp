// The pack's measured level choice (issue 14: "choose per distance band the representation with
// the fewest primitives whose image error at the band's switch distance stays within the pixel
// budget — measured"): a four-level chain and an impostor whose levels are boxes, measured by the
// RenderedLevelMeter (lodcheck's views and verdict, libs/check/view_check.h) through a fake
// renderer that draws each scene's bounding box with exact area coverage. Each level's box is the
// full detail's with its top lowered by e: at distance d the top edge moves by about f e / d
// pixels, so with no failing pixel allowed a level passes where that (with its quantisation,
// per axis at most epsilon/4 / sqrt(3)) stays within half a pixel. Epsilons grow 3x per level;
// honest levels (e = epsilon / 2) pass at their own switch distance (0.32 px) and fail one band
// early (>= 0.53 px): the error model's choice. A level worse than its epsilon fails and is
// dropped; a level better than its epsilon replaces the finer one a band early.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "libs/gltf/writer.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/render/gltf_scene.h"
#include "pipeline/filesystem.h"
#include "pipeline/lazy_stage.h"
#include "pipeline/recipe_loader.h"
#include "pipeline/registry.h"
#include "stages/pack/level_meter.h"
#include "stages/pack/pack_core.h"
#include "stages/pack/pack_info.h"
#include "stages/pack/pack_stage.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/test_support.h"

namespace sylva::pack {
namespace {

constexpr int kHeight = 200;                               // the chain's image height, px
constexpr double kFov = std::numbers::pi / 4;              // 45 degrees
const double kFocal = kHeight / (2 * std::tan(kFov / 2));  // px per metre at 1 m
// The lod stage's switch distance of a level of spatial error eps (delta 0.5 px).
double switch_distance(double eps) { return eps * kFocal / 0.5; }

// Draws, for every camera, the scene's world bounding box as the rectangle its 8 corners
// project to, each pixel's alpha the fraction of it the rectangle covers (exact area coverage),
// over the options' background.
class BoxRenderer final : public render::Renderer {
 public:
  std::vector<image::Image> render_views(const render::Scene& scene, std::span<const render::Camera> cameras,
                                         const render::RenderOptions& o) override {
    ++calls;
    std::vector<image::Image> out;
    const render::Bounds b = scene.bounds();
    for (const render::Camera& cam : cameras) {
      image::Image img(o.width, o.height, o.background);
      const render::Mat4 m = cam.projection_matrix(float(o.width) / float(o.height)) * cam.view_matrix();
      double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
      for (int c = 0; c < 8; ++c) {
        const render::Vec3 p((c & 1) ? b.max.x() : b.min.x(), (c & 2) ? b.max.y() : b.min.y(),
                             (c & 4) ? b.max.z() : b.min.z());
        const Eigen::Vector4f q = m * p.homogeneous();
        const double x = (q.x() / q.w() + 1) / 2 * o.width, y = (1 - q.y() / q.w()) / 2 * o.height;
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
      for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
          const double a = std::max(0.0, std::min(x + 1.0, x1) - std::max(double(x), x0)) *
                           std::max(0.0, std::min(y + 1.0, y1) - std::max(double(y), y0));
          if (a > 0) img.set(x, y, {200, 150, 100, std::uint8_t(std::lround(255 * a))});
        }
      out.push_back(std::move(img));
    }
    return out;
  }
  std::string device_description() const override { return "box renderer (tests)"; }
  int calls = 0;
};

// A box 1 x (1 - lower) x 1 m on the ground, each face an n x n grid (12 n^2 triangles).
gltf::Mesh box(int n, double lower) {
  gltf::Mesh m;
  gltf::Primitive p;
  const float top = float(1 - lower);
  auto corner = [&](int axis, int sign, double u, double v) {
    float c[3];
    c[axis] = sign > 0 ? 1.f : 0.f;
    c[(axis + 1) % 3] = float(u);
    c[(axis + 2) % 3] = float(v);
    c[1] *= top;
    return std::array<float, 3>{c[0] - 0.5f, c[1], c[2] - 0.5f};
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      const std::uint32_t base = std::uint32_t(p.positions.size() / 3);
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          const auto q = corner(axis, sign, double(i) / n, double(j) / n);
          p.positions.insert(p.positions.end(), q.begin(), q.end());
          float nrm[3] = {0, 0, 0};
          nrm[axis] = float(sign);
          p.normals.insert(p.normals.end(), nrm, nrm + 3);
        }
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const auto at = [&](int a, int b) { return base + std::uint32_t(a * (n + 1) + b); };
          p.indices.insert(p.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j),
                                             at(i + 1, j + 1), at(i, j + 1)});
        }
    }
  p.material = 0;
  m.primitives.push_back(std::move(p));
  return m;
}

gltf::Scene one_mesh_scene(gltf::Mesh mesh, nlohmann::json node_extras) {
  gltf::Scene s;
  gltf::Material mat;
  mat.name = "bark";
  mat.double_sided = true;
  s.materials.push_back(mat);
  s.meshes.push_back(std::move(mesh));
  gltf::Node n;
  n.mesh = 0;
  n.extras = std::move(node_extras);
  s.nodes.push_back(n);
  s.roots = {0};
  return s;
}

struct Level {
  int grid;        // faces' subdivision: primitives 12 grid^2
  double eps;      // the level's epsilon, m
  double lowered;  // its geometric error: the top lowered by this, m
};

// The chain (lod.gltf as the lod stage links it), its levels and, with `impostor_lowered` >= 0,
// an impostor of epsilon 0.162 m (a box of grid 1, 12 triangles).
SpeciesInput chain(const std::vector<Level>& levels, double impostor_lowered = 0.5 * 0.162) {
  SpeciesInput in;
  in.species = "box";
  nlohmann::json ids = nlohmann::json::array(), coverage = nlohmann::json::array();
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Level& l = levels[i];
    const nlohmann::json extras = {{"sylva_lod_level", i},
                                   {"epsilon_m", l.eps},
                                   {"pixel_error_px", 0.5},
                                   {"switch_distance_m", switch_distance(l.eps)}};
    in.levels.push_back(one_mesh_scene(box(l.grid, l.lowered), extras));
    gltf::Node n = in.levels.back().nodes[0];
    n.mesh = int(i);
    in.chain.meshes.push_back(in.levels.back().meshes[0]);
    in.chain.nodes.push_back(n);
    if (i > 0) ids.push_back(int(i));
    // The lod stage's coverages (unclamped here: the chain's camera follows from them).
    const double top = 1 - levels[0].lowered, r = 0.5 * std::sqrt(2 + top * top), t = std::tan(kFov / 2);
    const double d = i + 1 < levels.size() ? switch_distance(levels[i + 1].eps) : 0;
    coverage.push_back(d > 0 ? std::numbers::pi * r * r / ((2 * d * t) * (2 * d * t)) : 0.0);
  }
  in.chain.materials = in.levels[0].materials;
  in.chain.roots = {0};
  in.chain.nodes[0].extensions = {{"MSFT_lod", {{"ids", ids}}}};
  in.chain.nodes[0].extras["MSFT_screencoverage"] = coverage;
  in.level_inputs.assign(levels.size(), {});
  if (impostor_lowered >= 0) {
    ImpostorLevelInput im;
    im.scene = one_mesh_scene(box(1, impostor_lowered), nlohmann::json::object());
    im.kind = "billboards";
    im.epsilon_m = 0.162;
    im.pixel_error_px = 0.5;
    im.switch_distance_m = switch_distance(0.162);
    im.camera.fov_y_rad = kFov;
    in.impostor = std::move(im);
  }
  return in;
}

// Levels of epsilon 2, 6, 18 and 54 mm (switch distances 0.97, 2.9, 8.7 and 26.1 m; the
// impostor's 78.2 m), each honest (its box within epsilon / 2 of the full detail's), 768, 432,
// 192 and 108 triangles.
std::vector<Level> honest() {
  return {{8, 0.002, 0.001}, {6, 0.006, 0.003}, {4, 0.018, 0.009}, {3, 0.054, 0.027}};
}

// lodcheck's views (azimuths 0 and 90, supersample 2), no failing pixel allowed (header).
check::ViewCheckOptions no_failing_pixel() {
  check::ViewCheckOptions o;
  o.max_failing_fraction = 0;
  return o;
}

class PackMeasure : public ::testing::Test {
 protected:
  PackMeasure()
      : meter_(renderer_,
               render::load_gltf_scene_from_memory(gltf::encode(one_mesh_scene(box(10, 0), {})), "full"),
               {kFov, kHeight}, no_failing_pixel()) {}
  // Kept levels as "source_level@switch distance" ("imp" for the impostor), nearest first.
  static std::vector<std::string> kept(const std::vector<LevelChoice>& choice) {
    std::vector<std::string> out;
    for (const LevelChoice& c : choice) {
      if (!c.kept) continue;
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s@%.3g", c.impostor ? "imp" : std::to_string(c.source_level).c_str(),
                    c.switch_distance_m);
      out.push_back(buf);
    }
    return out;
  }
  BoxRenderer renderer_;
  RenderedLevelMeter meter_;
};

TEST_F(PackMeasure, HonestLevelsAllPassAndAreTheErrorModelsChoice) {
  const SpeciesInput in = chain(honest());
  const std::vector<LevelChoice> model = select_levels(in, {});
  const std::vector<LevelChoice> measured = select_levels(in, {}, &meter_);
  EXPECT_EQ(kept(model), (std::vector<std::string>{"0@0.966", "1@2.9", "2@8.69", "3@26.1", "imp@78.2"}));
  EXPECT_EQ(kept(measured), kept(model));
  for (const LevelChoice& c : measured) {
    ASSERT_TRUE(c.measured.has_value());
    EXPECT_TRUE(c.measured->passed);
    EXPECT_LE(c.measured->failing_fraction, 0.01);
  }
  // Level 0 at its own distance; each band: the impostor, the band's own level, the next coarser
  // one (it fails: not one band early; level 3's band has none); the impostor's band: the impostor.
  EXPECT_EQ(meter_.subject_renders(), 1u + 3 + 3 + 2 + 1);
  EXPECT_EQ(meter_.reference_renders(), 5u);
  EXPECT_EQ(measured[0].reason, "");
}

TEST_F(PackMeasure, ALevelWorseThanItsEpsilonFailsAndIsDropped) {
  std::vector<Level> levels = honest();
  levels[2].lowered = 3 * levels[2].eps;  // 5.4 cm, 3 epsilon: 1.5 px at its own 8.7 m
  const SpeciesInput in = chain(levels);
  const std::vector<LevelChoice> choice = select_levels(in, {}, &meter_);
  // Level 2 fails at its 8.7 m (so does level 3 there); level 1 draws that band; level 3 at its
  // own 26.1 m.
  EXPECT_EQ(kept(choice), (std::vector<std::string>{"0@0.966", "1@2.9", "3@26.1", "imp@78.2"}));
  EXPECT_FALSE(choice[2].kept);
  EXPECT_EQ(choice[2].reason.rfind("fails at 8.69117 m: az0: coverage of ", 0), 0u) << choice[2].reason;
  EXPECT_NE(choice[2].reason.find(": coverage of "), std::string::npos) << choice[2].reason;
  // The files follow the choice: three mesh levels, level 3 is the pack's lod2.
  LodDescription d;
  const std::vector<PackedFile> files = pack_species(in, {}, &d, &meter_);
  ASSERT_EQ(d.levels.size(), 4u);
  EXPECT_EQ(d.levels[2].file, "box_lod2.glb");
  EXPECT_EQ(d.levels[2].source_level, 3);
  ASSERT_EQ(d.dropped.size(), 1u);
  EXPECT_EQ(d.dropped[0].source_level, 2);
  EXPECT_EQ(d.dropped[0].reason, choice[2].reason);
  const nlohmann::json lod = nlohmann::json::parse(files.back().bytes);
  EXPECT_EQ(lod["levels"][2]["measured"]["passed"], true);
}

TEST_F(PackMeasure, ALevelBetterThanItsEpsilonReplacesTheFinerOneABandEarly) {
  std::vector<Level> levels = honest();
  levels[2].lowered = 0.3 * levels[1].eps;  // 1.8 mm: within level 1's error at level 1's 2.9 m
  const SpeciesInput in = chain(levels);
  const std::vector<LevelChoice> choice = select_levels(in, {}, &meter_);
  EXPECT_EQ(kept(choice), (std::vector<std::string>{"0@0.966", "2@2.9", "3@26.1", "imp@78.2"}));
  EXPECT_FALSE(choice[1].kept);
  EXPECT_EQ(choice[1].reason, "level 2 (192 primitives) passes at 2.89706 m too");
  // Drawn from 2.9 m: lod.json, the level's node in the chain file and the coverage before it say
  // so; the level's own file carries no extras (pack version 10).
  LodDescription d;
  const std::vector<PackedFile> files = pack_species(in, {}, &d, &meter_);
  ASSERT_EQ(d.levels.size(), 4u);
  EXPECT_EQ(d.levels[1].source_level, 2);
  EXPECT_DOUBLE_EQ(d.levels[1].switch_distance_m, switch_distance(0.006));
  const double top = 1 - levels[0].lowered, r = 0.5 * std::sqrt(2 + top * top);
  const double t = std::tan(kFov / 2), at = switch_distance(0.006);
  EXPECT_NEAR(d.levels[0].screen_coverage, std::numbers::pi * r * r / ((2 * at * t) * (2 * at * t)), 1e-6);
  EXPECT_NE(files[0].bytes.find("\"switch_distance_m\":" + nlohmann::json(at).dump()), std::string::npos);
  EXPECT_EQ(files[2].bytes.find("\"extras\":{\"epsilon_m\""), std::string::npos);
  EXPECT_EQ(files[2].bytes.find("switch_distance_m"), std::string::npos);
}

TEST_F(PackMeasure, MinSavingSkipsLevelsWithoutMeasuringThem) {
  std::vector<Level> levels = honest();
  levels[2].grid = 6;  // as many triangles as level 1: saves nothing
  const SpeciesInput in = chain(levels);
  const std::vector<LevelChoice> choice = select_levels(in, {}, &meter_);
  EXPECT_EQ(kept(choice), (std::vector<std::string>{"0@0.966", "1@2.9", "3@26.1", "imp@78.2"}));
  EXPECT_EQ(choice[2].reason.rfind("saves 0 of the primitives of level 1 (432 -> 432) at ", 0), 0u)
      << choice[2].reason;
}

TEST_F(PackMeasure, TheSameChoiceAndBytesEveryRun) {
  const SpeciesInput in = chain(honest());
  const std::vector<PackedFile> a = pack_species(in, {}, nullptr, &meter_);
  BoxRenderer other;
  RenderedLevelMeter again(
      other, render::load_gltf_scene_from_memory(gltf::encode(one_mesh_scene(box(10, 0), {})), "full"),
      {kFov, kHeight}, {});
  const std::vector<PackedFile> b = pack_species(in, {}, nullptr, &again);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].bytes == b[i].bytes) << a[i].name;
}

// A level whose epsilon / 4 grid would need more than 16 bits (level 0 at epsilon 20 um over 1 m:
// 18 bits; 16 bits round by 13 um, within epsilon) gets the coarsest grid from position_bits_min
// on that measures as passing at its switch distance: 14 bits here (the box renderer draws the
// box that fills the frame at 9.7 mm alike); without a meter, or with position_bits_min 16, 16.
TEST_F(PackMeasure, AFineLevelGetsTheCoarsestGridThatPasses) {
  std::vector<Level> levels = honest();
  levels[0] = {8, 0.00002, 0.0};
  const SpeciesInput in = chain(levels);
  LodDescription d;
  pack_species(in, {}, &d, &meter_);
  EXPECT_EQ(d.levels[0].position_bits, 14);
  EXPECT_DOUBLE_EQ(d.levels[0].position_error_m, std::sqrt(3.0) / 2 * (1.0 / 16383));
  ASSERT_TRUE(d.levels[0].measured.has_value());
  EXPECT_TRUE(d.levels[0].measured->passed);
  pack_species(in, {}, &d);
  EXPECT_EQ(d.levels[0].position_bits, 16);
  PackOptions o;
  o.position_bits_min = 16;
  pack_species(in, o, &d, &meter_);
  EXPECT_EQ(d.levels[0].position_bits, 16);
}

// A level kept from a band start b nearer than its own switch distance s gets the grid of
// epsilon x b / s (the same fraction of a pixel at b as its epsilon / 4 grid at s): level 2
// (epsilon 18 mm over 1 m, s 8.69 m) kept from level 1's 2.90 m needs sqrt(3)/2 / (2^B - 1) <=
// 0.25 x 6 mm, B = 10 bits (1.5 mm), not its own 8 bits (4.5 mm, 3x the pixels at 2.9 m). With
// position_bits_min 9, that grid has more bits than the floor, so it is searched from 9 bits on,
// measured at 2.9 m (the box renderer draws the box's corners alike on any grid): 9. The model
// choice draws every level from its own switch distance: 8 bits.
TEST_F(PackMeasure, ALevelDrawnNearerThanItsSwitchDistanceGetsTheGridOfThatDistance) {
  std::vector<Level> levels = honest();
  levels[2].lowered = 0.3 * levels[1].eps;  // passes from level 1's 2.9 m (test above)
  const SpeciesInput in = chain(levels);
  LodDescription d;
  pack_species(in, {}, &d, &meter_);
  ASSERT_EQ(d.levels.size(), 4u);
  ASSERT_EQ(d.levels[1].source_level, 2);
  EXPECT_DOUBLE_EQ(d.levels[1].switch_distance_m, switch_distance(0.006));
  EXPECT_EQ(d.levels[1].position_bits, 10);
  EXPECT_DOUBLE_EQ(d.levels[1].position_error_m, std::sqrt(3.0) / 2 * (1.0 / 1023));
  EXPECT_LE(d.levels[1].position_error_m, 0.25 * 0.018 * switch_distance(0.006) / switch_distance(0.018));
  ASSERT_TRUE(d.levels[1].measured.has_value());
  EXPECT_TRUE(d.levels[1].measured->passed);
  // Level 3 and the impostor are drawn from their own switch distances: their own grids (level 3:
  // 13.5 mm, 7 bits).
  EXPECT_EQ(d.levels[2].source_level, 3);
  EXPECT_EQ(d.levels[2].position_bits, 7);
  PackOptions o;
  o.position_bits_min = 9;
  pack_species(in, o, &d, &meter_);
  ASSERT_EQ(d.levels[1].source_level, 2);
  EXPECT_EQ(d.levels[1].position_bits, 9);
  pack_species(in, {}, &d);
  ASSERT_EQ(d.levels[2].source_level, 2);
  EXPECT_EQ(d.levels[2].position_bits, 8);
}

// With nearer_line_coverage, a level drawn nearer draws its blended lines with their coverage at
// that distance. The lod stage's line
// alpha a is the coverage c = 1 - (1 - a)^3 of a branch at the level's switch distance s split
// over three lines; from b the branch covers s / b times the pixels: level 2 (s 8.69 m) drawn
// from 2.90 m (s / b = 3) with lines of alpha 0.05 (c 0.1426, at b 0.4279: alpha 0.1698), 0.5
// (c 0.875, at b 1: alpha 1) and 1. Its lines of an opaque material, and level 3's (drawn from
// its own switch distance), keep their alpha. Without the option every alpha stays as written.
TEST_F(PackMeasure, WithNearerLineCoverageALevelDrawnNearerDrawsItsLinesWithTheirCoverageThere) {
  std::vector<Level> levels = honest();
  levels[2].lowered = 0.3 * levels[1].eps;  // passes from level 1's 2.9 m (tests above)
  SpeciesInput in = chain(levels);
  const std::vector<float> alphas = {0.05f, 0.5f, 1.0f, 0.05f};
  for (std::size_t l = 0; l < in.levels.size(); ++l) {
    gltf::Scene& s = in.levels[l];
    gltf::Material blend = s.materials[0];
    blend.name = "bark_lines";
    blend.alpha_mode = gltf::AlphaMode::kBlend;
    s.materials.push_back(blend);
    gltf::Primitive lines;  // inside the box: the box renderer draws the same
    lines.mode = gltf::PrimitiveMode::kLines;
    lines.positions = {0, 0.1f, 0, 0, 0.2f, 0, 0, 0.3f, 0, 0, 0.4f, 0};
    lines.indices = {0, 1, 1, 2, 2, 3};
    for (const float a : alphas) lines.colors.insert(lines.colors.end(), {1, 1, 1, a});
    lines.material = 1;
    gltf::Primitive opaque = lines;
    opaque.material = 0;
    s.meshes[0].primitives.push_back(lines);
    s.meshes[0].primitives.push_back(opaque);
    in.chain.meshes[l] = s.meshes[0];
  }
  in.chain.materials = in.levels[0].materials;
  PackOptions o;
  o.compression = Compression::kNone;  // plain float GLBs: COLOR_0 as written
  o.quantize = false;
  o.nearer_line_coverage = true;
  LodDescription d;
  const std::vector<PackedFile> files = pack_species(in, o, &d, &meter_);
  ASSERT_EQ(d.levels.size(), 4u);
  ASSERT_EQ(d.levels[1].source_level, 2);
  ASSERT_EQ(d.levels[2].source_level, 3);
  EXPECT_DOUBLE_EQ(switch_distance(0.018) / d.levels[1].switch_distance_m, 3.0);
  // COLOR_0 alpha of primitive p of a level file (float VEC4).
  auto alpha_of = [](const std::vector<PackedFile>& in_files, const std::string& name, std::size_t p) {
    const auto it =
        std::find_if(in_files.begin(), in_files.end(), [&](const PackedFile& f) { return f.name == name; });
    if (it == in_files.end()) {
      ADD_FAILURE() << name;
      return std::vector<float>{};
    }
    const test::Glb g = test::parse_glb(it->bytes);
    const nlohmann::json& a =
        g.json["accessors"][g.json["meshes"][0]["primitives"][p]["attributes"]["COLOR_0"].get<std::size_t>()];
    const nlohmann::json& v = g.json["bufferViews"][a["bufferView"].get<std::size_t>()];
    std::vector<float> out;
    const std::size_t at = v.value("byteOffset", std::size_t(0)) + a.value("byteOffset", std::size_t(0));
    for (std::size_t i = 0; i < a["count"].get<std::size_t>(); ++i) {
      float x = 0;
      std::memcpy(&x, g.bin.data() + at + 16 * i + 12, 4);
      out.push_back(x);
    }
    return out;
  };
  const float thin = float(1 - std::cbrt(1 - 3 * (1 - std::pow(0.95, 3))));  // 0.1698
  const std::vector<float> drawn = alpha_of(files, d.levels[1].file, 1);
  ASSERT_EQ(drawn.size(), 4u);
  EXPECT_NEAR(drawn[0], thin, 1e-6);
  EXPECT_NEAR(thin, 0.1698, 1e-4);
  EXPECT_EQ(drawn[1], 1.0f);
  EXPECT_EQ(drawn[2], 1.0f);
  EXPECT_NEAR(drawn[3], thin, 1e-6);
  EXPECT_EQ(alpha_of(files, d.levels[1].file, 2), alphas);  // opaque material: not coverage
  EXPECT_EQ(alpha_of(files, d.levels[2].file, 1), alphas);  // level 3 from its own 26.1 m
  // The model choice draws every level from its own switch distance: alphas as written; and so
  // does the measured choice without nearer_line_coverage (the default).
  const std::vector<PackedFile> model = pack_species(in, o, &d);
  ASSERT_EQ(d.levels[2].source_level, 2);
  EXPECT_EQ(alpha_of(model, d.levels[2].file, 1), alphas);
  o.nearer_line_coverage = false;
  const std::vector<PackedFile> off = pack_species(in, o, &d, &meter_);
  ASSERT_EQ(d.levels[1].source_level, 2);
  EXPECT_EQ(alpha_of(off, d.levels[1].file, 1), alphas);
}

// An impostor that fails at its own distance (its box 3 epsilon too low: 1.5 px at 78.2 m) is
// measured farther out, at 78.2 m x 1.25^k, and kept from the first distance where it passes
// (without that search the chain would end at level 3).
TEST_F(PackMeasure, AnImpostorFailingAtItsDistanceIsKeptFromFartherOut) {
  const SpeciesInput in = chain(honest(), 3 * 0.162);
  const std::vector<LevelChoice> choice = select_levels(in, {}, &meter_);
  ASSERT_TRUE(choice.back().impostor);
  ASSERT_TRUE(choice.back().kept) << choice.back().reason;
  const double own = switch_distance(0.162);
  const double k = std::log(choice.back().switch_distance_m / own) / std::log(1.25);
  EXPECT_NEAR(k, std::round(k), 1e-9);
  // 1.5 px at 78.2 m is within the check's half pixel from about three times as far: 1.25^5.
  EXPECT_EQ(std::lround(k), 5);
  ASSERT_TRUE(choice.back().measured.has_value());
  EXPECT_TRUE(choice.back().measured->passed);
  EXPECT_EQ(choice.back().reason, "");
  EXPECT_EQ(kept(choice).size(), 5u);
}

// The stage: a lod input as the lod stage writes it (lod.gltf over lod<i>.gltf and .bin files,
// lod.json with the chain's camera, full.glb), measured through the renderer the stage is given.
void write_lod_dir(const std::filesystem::path& dir, const std::vector<Level>& levels, bool full) {
  std::filesystem::create_directories(dir);
  SpeciesInput in = chain(levels, -1);
  gltf::Scene c = in.chain;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    c.meshes[i].buffer = int(i);
    c.buffer_uris.push_back("lod" + std::to_string(i) + ".bin");
  }
  const gltf::EncodedFiles files = gltf::encode_external(c);
  test::write_file(dir / "lod.gltf", files.gltf);
  for (const auto& r : files.resources) test::write_file(dir / r.name, r.bytes);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    gltf::Scene l = in.levels[i];
    l.buffer_uris = {"lod" + std::to_string(i) + ".bin"};
    test::write_file(dir / ("lod" + std::to_string(i) + ".gltf"), gltf::encode_external(l).gltf);
  }
  lodchain::LodChain summary;  // lod.json (libs/lodchain): the stage reads its camera and delta
  summary.tree = "box";
  summary.camera_fov_y_deg = 45.0;
  summary.camera_height_px = 200;
  summary.pixel_error_px = 0.5;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    lodchain::Level l;
    l.sylva_lod_level = i;
    l.file = "lod" + std::to_string(i) + ".gltf";
    l.epsilon_m = levels[i].eps;
    l.pixel_error_px = 0.5;
    summary.levels.push_back(l);
  }
  test::write_file(dir / "lod.json", lodchain::write_lod_chain(summary));
  if (full) test::write_file(dir / "full.glb", gltf::encode(one_mesh_scene(box(10, 0), {})));
}

TEST(PackMeasureStage, MeasuresWithTheRendererItIsGivenAndRecordsTheErrors) {
  test::TempDir tmp;
  std::vector<Level> levels = honest();
  levels[2].lowered = 3 * levels[2].eps;  // fails at its own switch distance (above)
  write_lod_dir(tmp.path() / "lod", levels, true);
  BoxRenderer renderer;
  const auto stage = make_pack_stage([&]() -> render::Renderer& { return renderer; });
  for (const bool measure : {true, false}) {
    const std::filesystem::path out = tmp.path() / (measure ? "measured" : "model");
    std::filesystem::create_directories(out);
    test::FakeStageContext ctx(*stage, {{"lod_box", "lod", tmp.path() / "lod"}}, out,
                               {{"species", Value::List{Value("box")}},
                                {"measure", Value(measure)},
                                {"measure_max_failing_fraction", Value(0.0)}});
    stage->run(ctx);
    const nlohmann::json lod = nlohmann::json::parse(test::read_file(out / "box.lod.json"));
    const nlohmann::json manifest = nlohmann::json::parse(test::read_file(out / "manifest.json"));
    EXPECT_EQ(manifest["species"][0]["levels"], lod["levels"]);
    std::vector<int> kept;
    for (const auto& l : lod["levels"]) {
      kept.push_back(l["source_level"].get<int>());
      EXPECT_EQ(l.contains("measured"), measure) << l.dump();
    }
    EXPECT_EQ(kept, measure ? std::vector<int>({0, 1, 3}) : std::vector<int>({0, 1, 2, 3}));
  }
  EXPECT_GT(renderer.calls, 0);
}

TEST(PackMeasureStage, ALodInputWithoutFullDetailIsAnError) {
  test::TempDir tmp;
  write_lod_dir(tmp.path() / "lod", honest(), false);
  BoxRenderer renderer;
  const auto stage = make_pack_stage([&]() -> render::Renderer& { return renderer; });
  test::FakeStageContext ctx(*stage, {{"lod_box", "lod", tmp.path() / "lod"}}, tmp.path(),
                             {{"species", Value::List{Value("box")}}});
  try {
    stage->run(ctx);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_STREQ(e.what(),
                 "input 'lod_box' has no full.glb, the full-detail model the measured level choice judges "
                 "against (a lod node of stage version 10 or later writes it; or set `measure: false`)");
  }
  EXPECT_EQ(renderer.calls, 0);
}

// lod.json is read with libs/lodchain: a summary that lacks what the lod stage writes (here the
// old fixture's camera and delta alone) is its one-line error, before anything is rendered.
TEST(PackMeasureStage, AnIncompleteLodJsonIsTheReadersError) {
  test::TempDir tmp;
  write_lod_dir(tmp.path() / "lod", honest(), true);
  test::write_file(tmp.path() / "lod" / "lod.json",
                   R"({"camera": {"fov_y_deg": 45.0, "height_px": 200}, "pixel_error_px": 0.5})");
  BoxRenderer renderer;
  const auto stage = make_pack_stage([&]() -> render::Renderer& { return renderer; });
  test::FakeStageContext ctx(*stage, {{"lod_box", "lod", tmp.path() / "lod"}}, tmp.path(),
                             {{"species", Value::List{Value("box")}}});
  try {
    stage->run(ctx);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_EQ(std::string(e.what()),
              "input 'lod_box': " + (tmp.path() / "lod" / "lod.json").string() + ": error: missing 'tree'");
  }
  EXPECT_EQ(renderer.calls, 0);
}

// The measurement's azimuths are the schema's to check (pack_info.cpp), so a bad list is a recipe
// error at its position before anything builds, not a failed node.
TEST(PackMeasureStage, AzimuthsOutOfRangeOrNoneAreRecipeErrors) {
  struct NoResolver final : StageResolver {
    const Stage& resolve(std::string_view) override { throw StageError("not loaded in this test"); }
  } resolver;
  StageRegistry registry;
  registry.add(make_lazy_stage(pack_stage_info(), resolver));
  test::TempDir tmp;
  RealFileSystem fs;
  // The loader's messages for a pack node with these azimuths (the node has no inputs, which is
  // an error of its own every time).
  auto errors = [&](const std::string& azimuths) {
    test::write_file(tmp.path() / "r.yaml",
                     "version: 1\nname: r\nnodes:\n  p:\n    stage: pack\n"
                     "    with: { species: [a], measure_azimuths_deg: " +
                         azimuths + " }\n");
    Diagnostics diags;
    EXPECT_FALSE(load_recipe(tmp.path() / "r.yaml", registry, fs, diags).has_value());
    std::string s = diags.str();
    const std::string prefix = tmp.path().string() + "/";
    for (std::size_t at; (at = s.find(prefix)) != std::string::npos;) s.erase(at, prefix.size());
    return s;
  };
  const std::string no_inputs = "r.yaml:4:3: error: node 'p' (stage 'pack') needs at least 1 input, got 0\n";
  EXPECT_EQ(errors("[0, 90]").find("measure_azimuths_deg"), std::string::npos) << errors("[0, 90]");
  EXPECT_NE(errors("[0, 90]").find(no_inputs), std::string::npos) << errors("[0, 90]");
  EXPECT_NE(errors("[0, 400]")
                .find("r.yaml:6:53: error: value out of range: parameter 'measure_azimuths_deg'[1] "
                      "must be in [-360, 360], got 400\n"),
            std::string::npos)
      << errors("[0, 400]");
  EXPECT_NE(
      errors("[]").find("r.yaml:6:49: error: parameter 'measure_azimuths_deg' must have at least 1 item, "
                        "got 0\n"),
      std::string::npos)
      << errors("[]");
}

}  // namespace
}  // namespace sylva::pack
