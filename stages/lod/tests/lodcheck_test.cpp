// lodcheck's core (stages/lod/check): the camera sits exactly at the switch distance from the
// tree's box; every level of real chains passes the image thresholds at its switch distance;
// a level with a visible error (a level drawn too close, a shifted or truncated model) fails.
#include "stages/lod/check/lodcheck.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "libs/gltf/writer.h"
#include "libs/render/gltf_scene.h"
#include "stages/lod/chain.h"
#include "stages/lod/lod_gltf.h"
#include "stages/lod/tests/test_trees.h"

namespace sylva::lod {
namespace {

namespace fs = std::filesystem;

double box_distance(const render::Bounds& b, const render::Vec3& p) {
  const render::Vec3 d = (b.min - p).cwiseMax(p - b.max).cwiseMax(render::Vec3::Zero());
  return d.norm();
}

TEST(LodCheckCamera, EyeIsAtTheDistanceFromTheBox) {
  render::Bounds b;
  b.extend(render::Vec3(-2, 0, -1));
  b.extend(render::Vec3(3, 8, 1.5f));
  for (double az : {0.0, 90.0, 37.0, -120.0}) {
    for (double el : {0.0, 25.0}) {
      const render::Camera c = check_camera(b, 4.0, az, el, std::numbers::pi / 4);
      EXPECT_NEAR(box_distance(b, c.eye), 4.0, 1e-4) << az << " " << el;
      EXPECT_LT(c.z_near, 4.0f);
      EXPECT_GT(c.z_far, (c.eye - b.center()).norm() + b.radius());
      EXPECT_NEAR((c.target - b.center()).norm(), 0.0, 1e-5);
      EXPECT_FLOAT_EQ(c.fov_y_deg, 45.0f);
    }
  }
  EXPECT_EQ(check_camera(b, 1.0, 90, 0, 1.0).name, "az90");
}

// The chain of a young preset tree at a small image height (cheap renders; the bound is in
// pixels of that height), the full-detail model and every level as scenes.
struct Fixture {
  ChainOptions options;
  render::Scene full;
  std::vector<CheckSubject> levels;
};

render::Scene to_scene(const tree::Tree& t, const Level& level, std::size_t index) {
  return render::load_gltf_scene_from_memory(gltf::encode(level_scene(t, level, index, {})), "level");
}

Fixture make_fixture(const std::string& species, int height_px) {
  Fixture f;
  const tree::Tree& t =
      test::species_tree(fs::path(SYLVA_SOURCE_DIR) / "configs/species" / (species + ".yaml"), "young");
  f.options.camera.height_px = height_px;
  f.options.levels = 4;
  const Precomputed pre = precompute(t, f.options);
  f.full = to_scene(t, build_full_detail(t, pre, f.options), 0);
  const auto specs = plan_levels(f.options);
  for (std::size_t i = 0; i < specs.size(); ++i)
    f.levels.push_back({"sylva", i, specs[i].epsilon, specs[i].switch_distance,
                        to_scene(t, build_level(t, pre, specs[i], f.options), i)});
  return f;
}

class LodCheckRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { renderer_ = render::Renderer::create_headless(); }
  static void TearDownTestSuite() { renderer_.reset(); }
  static std::unique_ptr<render::Renderer> renderer_;
};
std::unique_ptr<render::Renderer> LodCheckRender::renderer_;

// The full-detail model has no simplification: every leaf and max_edges-gons everywhere.
TEST(LodFullDetail, KeepsEverything) {
  const tree::Tree& t = test::species_tree(fs::path(SYLVA_SOURCE_DIR) / "configs/species/oak.yaml", "young");
  ChainOptions o;
  const Precomputed pre = precompute(t, o);
  const Level full = build_full_detail(t, pre, o);
  EXPECT_EQ(full.counts.leaves, t.leaves.size());
  EXPECT_EQ(full.counts.branches, t.branches.size());
  EXPECT_EQ(full.counts.lines, 0u);
  EXPECT_EQ(full.counts.triangles % static_cast<std::size_t>(o.max_edges), 0u);  // only 12-gon caps, if any
  const Level level0 = build_level(t, pre, plan_levels(o).front(), o);
  EXPECT_GT(full.counts.quads, level0.counts.quads);
}

TEST_F(LodCheckRender, EveryLevelPassesAtItsSwitchDistance) {
  const Fixture f = make_fixture("oak", 240);
  const auto results = check_subjects(*renderer_, f.full, f.levels, f.options.camera, LodCheckOptions{});
  ASSERT_EQ(results.size(), f.levels.size() * 2);
  for (const auto& r : results) {
    EXPECT_TRUE(r.passed) << "oak level " << r.level << " " << r.view << ": " << r.failure;
    EXPECT_GT(r.stats.footprint_pixels, 0u) << "oak level " << r.level;
    EXPECT_LE(r.stats.failing_fraction, 0.01);
  }
}

// The branch simplification (prisms, lines with eq. 12's alpha, carried coverage) of a conifer
// passes on its own. The whole young Scots pine at 240 px does not pass at its coarsest level:
// its shoot cards' leaf collapse (stages/lod/foliage.*) over-covers (+0.20 mean coverage, 6 % of
// its 49 pixels failing, foliage alone), a known defect of the foliage collapse (docs/stages/lod.md).
TEST_F(LodCheckRender, ConiferBranchesPassAtTheirSwitchDistance) {
  Fixture f = make_fixture("scots_pine", 240);
  for (auto& l : f.levels) l.scene = branches_only(l.scene);
  const auto results =
      check_subjects(*renderer_, branches_only(f.full), f.levels, f.options.camera, LodCheckOptions{});
  ASSERT_EQ(results.size(), f.levels.size() * 2);
  for (const auto& r : results) {
    EXPECT_TRUE(r.passed) << "scots_pine branches level " << r.level << " " << r.view << ": " << r.failure;
    EXPECT_GT(r.stats.footprint_pixels, 0u) << "scots_pine branches level " << r.level;
  }
}

// Cropping (LodCheckOptions::crop) renders the centred window that holds the tree, with the
// frame's eye and pixels: far levels get small images, each the centre of the full frame's image,
// and every number matches the full frame.
TEST_F(LodCheckRender, CroppedWindowsMeasureWhatTheFullFrameMeasures) {
  const Fixture f = make_fixture("oak", 240);
  std::vector<image::Image> windows, frames;
  const CheckImageSink keep_windows = [&](const ViewCheck&, const image::Image& full,
                                          const image::Image& test, const image::Image&) {
    EXPECT_EQ(full.width(), test.width());
    windows.push_back(test);
  };
  const CheckImageSink keep_frames = [&](const ViewCheck&, const image::Image&, const image::Image& test,
                                         const image::Image&) { frames.push_back(test); };
  LodCheckOptions whole;
  whole.crop = false;
  const auto cropped =
      check_subjects(*renderer_, f.full, f.levels, f.options.camera, LodCheckOptions{}, keep_windows);
  const auto framed = check_subjects(*renderer_, f.full, f.levels, f.options.camera, whole, keep_frames);
  ASSERT_EQ(cropped.size(), framed.size());
  ASSERT_EQ(windows.size(), cropped.size());
  ASSERT_EQ(frames.size(), cropped.size());
  EXPECT_LT(windows.back().width(), 240 / 2);  // the coarsest level is a small window
  for (std::size_t i = 0; i < cropped.size(); ++i) {
    const image::Image& w = windows[i];
    const image::Image& fr = frames[i];
    ASSERT_EQ(fr.width(), 240);
    ASSERT_EQ(w.width(), w.height());
    ASSERT_EQ((fr.width() - w.width()) % 2, 0) << i;
    // The window is the frame's centre: its coverage equals the frame's pixels there but for
    // rasterisation round-off in a few edge pixels, and the frame is empty outside it.
    const int o = (fr.width() - w.width()) / 2;
    std::size_t differing = 0, covered = 0, outside = 0;
    int max_change = 0;
    for (int y = 0; y < fr.height(); ++y)
      for (int x = 0; x < fr.width(); ++x) {
        const int a = fr.at(x, y).a;
        if (x < o || y < o || x >= o + w.width() || y >= o + w.height()) {
          outside += a != 0;
          continue;
        }
        const int b = w.at(x - o, y - o).a;
        covered += a != 0 || b != 0;
        differing += a != b;
        max_change = std::max(max_change, std::abs(a - b));
      }
    EXPECT_EQ(outside, 0u) << i;
    EXPECT_GT(covered, 0u) << i;
    EXPECT_LE(double(differing), 0.01 * double(covered)) << i << ": " << differing << " of " << covered;
    EXPECT_LE(max_change, 16) << i;  // 6 % coverage, far below the 0.5 a pixel must change to fail
    EXPECT_NEAR(double(cropped[i].stats.footprint_pixels), double(framed[i].stats.footprint_pixels),
                0.01 * double(framed[i].stats.footprint_pixels) + 2)
        << i;
    EXPECT_NEAR(cropped[i].stats.coverage_mean_error, framed[i].stats.coverage_mean_error, 0.005) << i;
    EXPECT_NEAR(cropped[i].stats.failing_fraction, framed[i].stats.failing_fraction, 0.002) << i;
    EXPECT_EQ(cropped[i].passed, framed[i].passed) << i;
  }
}

// Seen from a tenth of its switch distance, a coarse level's error is about 10 delta = 5 px:
// the check must see it.
TEST_F(LodCheckRender, ACoarseLevelSeenTooCloseFails) {
  Fixture f = make_fixture("oak", 240);
  std::vector<CheckSubject> close;
  CheckSubject s = f.levels.back();
  s.distance /= 10;
  close.push_back(std::move(s));
  const auto results = check_subjects(*renderer_, f.full, close, f.options.camera, LodCheckOptions{});
  ASSERT_EQ(results.size(), 2u);
  for (const auto& r : results) {
    EXPECT_FALSE(r.passed) << r.view;
    EXPECT_NE(r.failure.find("of the tree's"), std::string::npos) << r.failure;
  }
}

// A level without its bark (trunk and branches gone, foliage floating), and a level shifted by
// 4 px: both fail.
TEST_F(LodCheckRender, AVisibleErrorFails) {
  Fixture f = make_fixture("oak", 240);
  CheckSubject bare = f.levels[2];
  for (auto& m : bare.scene.meshes)
    std::erase_if(m.primitives, [&](const render::Primitive& p) {
      return bare.scene.materials[static_cast<std::size_t>(p.material)].name == "bark";
    });
  CheckSubject shifted = f.levels[2];
  const double px =
      2 * shifted.distance * std::tan(f.options.camera.fov_y_rad / 2) / f.options.camera.height_px;
  for (auto& m : shifted.scene.meshes)
    for (auto& p : m.primitives)
      for (auto& v : p.positions) v.y() += static_cast<float>(4 * px);  // up: across both views
  const auto results =
      check_subjects(*renderer_, f.full, {bare, shifted}, f.options.camera, LodCheckOptions{});
  ASSERT_EQ(results.size(), 4u);
  for (const auto& r : results)
    EXPECT_FALSE(r.passed) << r.label << " " << r.view << " fail " << r.stats.failing_fraction << " mean "
                           << r.stats.coverage_mean_error;
  EXPECT_LT(results[0].primitives, f.levels[2].scene.triangle_count() + f.levels[2].scene.line_count());
}

TEST(LodCheckScene, BranchesOnlyKeepsBarkPrimitives) {
  const tree::Tree& t = test::species_tree(fs::path(SYLVA_SOURCE_DIR) / "configs/species/oak.yaml", "young");
  ChainOptions o;
  const Precomputed pre = precompute(t, o);
  const auto specs = plan_levels(o);
  const render::Scene s = to_scene(t, build_level(t, pre, specs.back(), o), specs.size() - 1);
  const render::Scene b = branches_only(s);
  std::size_t leaf_prims = 0, kept = 0;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives)
      leaf_prims += s.materials[static_cast<std::size_t>(p.material)].name == "leaves";
  for (const auto& m : b.meshes)
    for (const auto& p : m.primitives) {
      const std::string& name = b.materials[static_cast<std::size_t>(p.material)].name;
      EXPECT_TRUE(name == "bark" || name == "bark_lines") << name;
      ++kept;
    }
  EXPECT_EQ(leaf_prims, 1u);
  EXPECT_GE(kept, 1u);
  EXPECT_EQ(b.line_count(), s.line_count());
  EXPECT_LT(b.triangle_count(), s.triangle_count());
}

}  // namespace
}  // namespace sylva::lod
