// The proof (stages/impostor/check) on a real chain: a young oak's impostors pass at their switch
// distances from 36 views that are not frame directions, and the check fails for impostors that
// are wrong: too few frames, a hemi impostor seen from below, an atlas shifted by a few pixels.
// The tree and its chain come from the generate and lod cores (test fixtures only, as the lod
// tests make theirs); the check itself links neither.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "libs/gltf/writer.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/shared_renderer.h"
#include "stages/impostor/bake.h"
#include "stages/impostor/check/impostorcheck.h"
#include "stages/impostor/check/subject.h"
#include "stages/impostor/source.h"
#include "stages/lod/chain.h"
#include "stages/lod/lod_gltf.h"
#include "stages/lod/tests/test_trees.h"

namespace sylva::impostor {
namespace {

namespace fs = std::filesystem;

constexpr int kHeightPx = 360;  // the camera of the chain and of the impostors: small, so renders are cheap

struct Chain {
  render::Scene full;
  std::vector<render::Scene> levels;
  std::vector<LodLevelRef> refs;
};

render::Scene to_scene(const tree::Tree& t, const lod::Level& level, std::size_t i) {
  return render::load_gltf_scene_from_memory(gltf::encode(lod::level_scene(t, level, i, {})), "level");
}

const Chain& oak_chain() {
  static const Chain chain = [] {
    Chain c;
    const tree::Tree& t =
        lod::test::species_tree(fs::path(SYLVA_SOURCE_DIR) / "configs/species/oak.yaml", "young");
    lod::ChainOptions o;
    o.camera.height_px = kHeightPx;
    const lod::Precomputed pre = lod::precompute(t, o);
    c.full = to_scene(t, lod::build_full_detail(t, pre, o), 0);
    const auto specs = lod::plan_levels(o);
    for (std::size_t i = 0; i < specs.size(); ++i) {
      c.levels.push_back(to_scene(t, lod::build_level(t, pre, specs[i], o), i));
      c.refs.push_back(
          {"lod" + std::to_string(i) + ".glb", specs[i].epsilon, o.pixel_error, specs[i].switch_distance});
    }
    return c;
  }();
  return chain;
}

// Bakes as the stage does from a lod chain: the coarsest level within one texel.
ImpostorSubject bake(const BakeParams& p) {
  const Chain& c = oak_chain();
  const SourceDesc src = choose_source(c.refs, c.levels.back(), p.layout);
  const BakeOutput b =
      bake_impostor(render::shared_impostor_renderer(), c.levels[std::size_t(src.level)], p, src);
  ImpostorSubject s;
  s.label = "test";
  s.info = b.info;
  if (b.info.kind == Kind::kBillboards) {
    s.cards = render::load_gltf_scene_from_memory(b.glb, "impostor.glb");
  } else {
    s.octahedral = octahedral_of(b.info, b.color, b.normal_depth);
  }
  return s;
}

BakeParams params(Kind kind = Kind::kHemiOctahedral, int frames = 16, int frame_px = 128) {
  BakeParams p;
  p.layout.kind = kind;
  p.layout.frames_per_side = frames;
  p.layout.frame_px = frame_px;
  p.layout.mip_levels = 3;
  p.camera.height_px = kHeightPx;
  return p;
}

ImpostorCheckResult run(const ImpostorSubject& s, const ImpostorCheckOptions& o = {}) {
  ColourBaseline baseline;
  baseline.scene = &oak_chain().levels.back();
  return check_impostor(render::shared_renderer(), render::shared_impostor_renderer(), oak_chain().full, s, o,
                        baseline);
}

std::size_t failed(const ImpostorCheckResult& r) {
  std::size_t n = 0;
  for (const auto& v : r.views) n += v.passed ? 0 : 1;
  return n;
}

TEST(ImpostorCheck, HemiOctahedralAndBillboardsPassAtTheirSwitchDistances) {
  for (Kind kind : {Kind::kHemiOctahedral, Kind::kBillboards}) {
    const ImpostorSubject s = bake(params(kind));
    const ImpostorCheckResult r = run(s);
    ASSERT_EQ(r.views.size(), 36u);
    for (const auto& v : r.views) {
      EXPECT_TRUE(v.passed) << kind_name(kind) << " " << v.view << ": " << v.failure;
      EXPECT_GT(v.footprint_pixels, 0u);
      EXPECT_GT(v.frame_angle_deg, 0.5) << v.view << " is a frame direction";  // the views lie between frames
    }
    EXPECT_GE(r.baseline_colour_max, 0);
    EXPECT_TRUE(r.passed()) << kind_name(kind) << ": " << r.failure;
  }
}

// Two frames per side (the four horizon directions, nothing above) checked where the 16 x 16
// impostor is proven: the views from above see the wrong frames.
TEST(ImpostorCheck, TooFewFramesFail) {
  const double proven = bake(params()).info.switch_distance_m;
  ImpostorSubject few = bake(params(Kind::kHemiOctahedral, 2, 512));
  few.info.switch_distance_m = proven;
  ImpostorCheckOptions o;
  o.elevations_deg = {33, 73};
  o.azimuths_deg = {7.5, 127.5, 247.5};
  const ImpostorCheckResult r = run(few, o);
  EXPECT_EQ(failed(r), r.views.size());
  for (const auto& v : r.views) EXPECT_GT(v.coverage_failing_fraction, 0.01) << v.view;
}

// A hemi impostor has no frame below the horizon: from below it shows the side (here the young oak
// covers ~19 % less coverage seen 60° from below, ~27 % less 75°). The full octahedron has those
// frames and passes.
TEST(ImpostorCheck, AHemiImpostorSeenFromBelowFails) {
  ImpostorCheckOptions o;
  o.elevations_deg = {-60, -75};
  o.azimuths_deg = {7.5, 127.5, 247.5};
  const ImpostorCheckResult hemi = run(bake(params()), o);
  EXPECT_EQ(failed(hemi), hemi.views.size());
  const ImpostorCheckResult full = run(bake(params(Kind::kOctahedral)), o);
  EXPECT_EQ(failed(full), 0u) << full.views.front().failure;
  EXPECT_TRUE(full.passed()) << full.failure;
}

// Every map shifted right by what 4 pixels at the switch distance cover: frames show the tree
// beside where it stands.
TEST(ImpostorCheck, AShiftedAtlasFails) {
  ImpostorSubject s = bake(params());
  const double px = lodmodel::pixel_size(s.info.camera, s.info.switch_distance_m);
  const int shift = int(std::ceil(4 * px / s.info.error.texel_m));
  ASSERT_LT(shift, s.info.frame_px / 4);
  for (image::Image* m : {&s.octahedral.color, &s.octahedral.normal_depth}) {
    image::Image moved(m->width(), m->height(), {0, 0, 0, 0});
    for (int y = 0; y < m->height(); ++y)
      for (int x = shift; x < m->width(); ++x) moved.set(x, y, m->at(x - shift, y));
    *m = std::move(moved);
  }
  ImpostorCheckOptions o;
  o.elevations_deg = {4, 33};
  o.azimuths_deg = {7.5, 127.5, 247.5};
  const ImpostorCheckResult r = run(s, o);
  EXPECT_EQ(failed(r), r.views.size());
}

// A colour map in the wrong colour space, where coverage cannot see it: linear values stored as
// sRGB (too dark) and sRGB encoded twice (washed out). The colour judgement fails both.
TEST(ImpostorCheck, AColourMapInTheWrongColourSpaceFailsOnColour) {
  const ImpostorSubject good = bake(params());
  ImpostorSubject dark = good, washed = good;
  auto recode = [](ImpostorSubject& s, bool to_linear) {
    for (std::size_t i = 0; i < s.octahedral.color.bytes().size(); i += 4)
      for (std::size_t c = 0; c < 3; ++c) {
        std::uint8_t& v = s.octahedral.color.bytes()[i + c];
        const double x = v / 255.0;
        const double y = to_linear ? (x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4))
                                   : (x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055);
        v = std::uint8_t(std::lround(255 * y));
      }
  };
  recode(dark, true);
  recode(washed, false);
  ImpostorCheckOptions o;
  o.elevations_deg = {33};
  o.azimuths_deg = {7.5, 127.5, 247.5};
  for (const ImpostorSubject* s : {&dark, &washed}) {
    const ImpostorCheckResult r = run(*s, o);
    for (const auto& v : r.views) {
      EXPECT_FALSE(v.passed) << v.view << " colour " << v.shade_mean_error;
      EXPECT_NE(v.failure.find("mean colour difference"), std::string::npos) << v.failure;
      EXPECT_LT(v.coverage_failing_fraction, 0.01) << v.view;  // the coverage is right
    }
  }
}

// The distance search (find_proven_distance): the proven distance passes, a tenth nearer fails
// (the bracket it ends on), every step reported is what the check says at that distance, and the
// proof lies below the error model's sufficient bound.
TEST(ImpostorCheck, TheDistanceSearchEndsOnAPassingDistanceWithAFailingOneJustNearer) {
  const ImpostorSubject s = bake(params());
  ColourBaseline baseline;
  baseline.scene = &oak_chain().levels.back();
  ImpostorCheckOptions o;  // 8 of the 36 views: the search runs the check several times
  o.azimuths_deg = {7.5, 97.5, 187.5, 277.5};
  o.elevations_deg = {4, 33};
  DistanceSearchOptions search;
  search.lo = 1.0 / 8;
  search.tolerance = 0.25;
  const DistanceSearchResult r =
      find_proven_distance(render::shared_renderer(), render::shared_impostor_renderer(), oak_chain().full, s,
                           o, search, baseline);
  ASSERT_GT(r.proven_distance_m, 0);
  EXPECT_TRUE(r.at_proven.passed());
  EXPECT_LE(r.proven_distance_m, s.info.switch_distance_m);
  EXPECT_DOUBLE_EQ(r.model_distance_m, s.info.switch_distance_m);
  double nearest_fail = 0;
  for (const DistanceSearchStep& st : r.steps) {
    if (!st.passed && st.scale < r.proven_scale) nearest_fail = std::max(nearest_fail, st.scale);
    if (st.passed) {
      EXPECT_GE(st.scale, r.proven_scale);
    }
  }
  if (!r.below_lo) {
    ASSERT_GT(nearest_fail, 0);
    EXPECT_LE(r.proven_scale / nearest_fail, 1 + search.tolerance + 1e-12);
    o.distance_scale = nearest_fail;
    EXPECT_FALSE(run(s, o).passed());
  }
}

}  // namespace
}  // namespace sylva::impostor
