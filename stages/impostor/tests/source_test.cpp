// The level an impostor is baked from (source.h).
#include "stages/impostor/source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace sylva::impostor {
namespace {

// A chain of three levels as libs/lodchain reads lod.json.
lodchain::LodChain summary() {
  lodchain::LodChain c;
  c.tree = "t";
  const double eps[] = {0.001, 0.01, 0.1}, delta[] = {0.5, 0.25, 0.5}, dist[] = {2.6, 52, 260};
  for (int i = 0; i < 3; ++i) {
    lodchain::Level l;
    l.sylva_lod_level = std::uint64_t(i);
    l.file = "lod" + std::to_string(i) + ".glb";
    l.epsilon_m = eps[i];
    l.pixel_error_px = delta[i];
    l.switch_distance_m = dist[i];
    c.levels.push_back(l);
  }
  return c;
}

TEST(Source, TakesTheLevelsOfTheChain) {
  const auto levels = lod_level_refs(summary());
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[1].file, "lod1.glb");
  EXPECT_DOUBLE_EQ(levels[1].epsilon, 0.01);
  EXPECT_DOUBLE_EQ(levels[1].pixel_error, 0.25);  // the level's own
  EXPECT_DOUBLE_EQ(levels[0].switch_distance, 2.6);
  EXPECT_DOUBLE_EQ(levels[2].switch_distance, 260);
}

// The coarsest level within one texel; the finest when none is.
TEST(Source, ChoosesTheCoarsestLevelWithinATexel) {
  const auto levels = lod_level_refs(summary());
  EXPECT_EQ(choose_level(levels, 0.05), 1u);
  EXPECT_EQ(choose_level(levels, 0.1), 2u);
  EXPECT_EQ(choose_level(levels, 1e-4), 0u);
}

// A cube of half size 1 (corners sqrt 3 from its centre): a hemi atlas of 256 px frames with 16
// px of padding spans W = R 256 / 224, a texel 2 W / 256 = R / 112. Measured alone the texel is
// sqrt(3) / 112 = 0.0155 m; widened by the coarsest level's epsilon (0.5 m) it is 0.0199 m, which
// admits level 1 (0.018 m): the estimate never falls short of a finer level's extent.
TEST(Source, ChoosesFromTheCoarsestLevelWidenedByItsEpsilon) {
  render::Scene cube;
  render::Primitive p;
  for (float x : {-1.f, 1.f})
    for (float y : {-1.f, 1.f})
      for (float z : {-1.f, 1.f}) p.positions.push_back({x, y + 3, z});
  p.indices = {0, 1, 2, 1, 3, 2};
  render::Mesh m;
  m.primitives.push_back(p);
  m.instances.push_back(render::Mat4::Identity());
  cube.meshes.push_back(m);
  std::vector<LodLevelRef> levels = {
      {"lod0.glb", 0.001, 0.5, 0}, {"lod1.glb", 0.018, 0.5, 0}, {"lod2.glb", 0.5, 0.5, 0}};
  const SourceDesc d = choose_source(levels, cube, LayoutParams{});
  EXPECT_EQ(d.type, "lod");
  EXPECT_EQ(d.file, "lod1.glb");
  EXPECT_EQ(d.level, 1);
  EXPECT_DOUBLE_EQ(d.epsilon, 0.018);
  EXPECT_DOUBLE_EQ(d.line_pixel_m, 0.036);                    // epsilon / pixel error
  EXPECT_EQ(choose_level(levels, std::sqrt(3.0) / 112), 0u);  // unwidened: too small a texel
  // No pixel error: no line alphas to widen.
  levels[1].pixel_error = 0;
  EXPECT_DOUBLE_EQ(choose_source(levels, cube, LayoutParams{}).line_pixel_m, 0);
  // Coarser epsilons than any texel: the finest level.
  levels[1].epsilon = 0.03;
  EXPECT_EQ(choose_source(levels, cube, LayoutParams{}).level, 0);
  EXPECT_THROW(choose_source({}, cube, LayoutParams{}), std::invalid_argument);
}

}  // namespace
}  // namespace sylva::impostor
