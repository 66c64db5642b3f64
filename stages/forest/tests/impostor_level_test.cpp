// The impostor as the species' last level: the GLB split (impostor_level.h), the tile-level
// mapping (tileset.h species_level) and the stage end to end with impostor inputs.
#include "stages/forest/impostor_level.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "stages/forest/tests/card_glb.h"
#include "stages/forest/tileset.h"

namespace sylva::forest {
namespace {

using testing::card_glb;

TEST(ImpostorLevel, SplitsTheGlbIntoJsonAndItsBuffer) {
  const std::string glb = card_glb();
  const ImpostorLevel l = impostor_level_source(glb, "oak", "impostor.glb");
  EXPECT_EQ(l.source.bin_name, "oak_impostor.bin");
  EXPECT_EQ(l.source.bin_bytes, l.bin.size());
  EXPECT_EQ(l.source.gltf["buffers"][0]["byteLength"].get<std::size_t>(), l.bin.size());
  ASSERT_EQ(l.source.gltf["images"].size(), 1u);
  EXPECT_TRUE(l.source.gltf["images"][0].contains("bufferView"));
  // The PNG is inside the buffer, where the image's view says.
  const auto& view =
      l.source.gltf["bufferViews"][l.source.gltf["images"][0]["bufferView"].get<std::size_t>()];
  EXPECT_EQ(l.bin.substr(view.value("byteOffset", std::size_t(0)), 4), "\x89PNG");
  const nlohmann::json level = nlohmann::json::parse(species_level_gltf(l.source));
  EXPECT_EQ(level["buffers"][0]["uri"], "oak_impostor.bin");
}

TEST(ImpostorLevel, RejectsWhatIsNotASingleMeshGlb) {
  auto message = [](const std::string& bytes) {
    try {
      impostor_level_source(bytes, "oak", "in/impostor.glb");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("{\"asset\": {}}"), "in/impostor.glb: not a GLB file (no glTF header)");
  std::string glb = card_glb();
  std::string truncated = glb.substr(0, glb.size() - 8);
  EXPECT_EQ(message(truncated), "in/impostor.glb: the GLB header's length does not match the file's size");
  std::string v1 = glb;
  v1[4] = 1;
  EXPECT_EQ(message(v1), "in/impostor.glb: GLB version 1 (expected 2)");
}

// The switch distance itself (d = eps / (delta s(1))): libs/lodmodel/tests
// (LodModel.SwitchDistanceAndItsInverse).

TEST(ImpostorLevel, RecordedSwitchDistanceInTheChainsTerms) {
  const double fov = 45 * M_PI / 180;
  const lodmodel::Camera c45 = lodmodel::camera_from_degrees(45, 1080);
  // The same camera and delta: the recorded distance itself, to the bit.
  EXPECT_EQ(impostor_switch_distance_m(630, {fov, 1080}, 0.5, c45, 0.5), 630.0);
  // Twice the impostor's delta, or half its rows (twice its pixel size): the same error twice as far.
  EXPECT_NEAR(impostor_switch_distance_m(630, {fov, 1080}, 1.0, c45, 0.5), 1260, 1e-9);
  EXPECT_NEAR(impostor_switch_distance_m(630, {fov, 540}, 0.5, c45, 0.5), 1260, 1e-9);
  // A wider chain camera (larger pixels): nearer.
  const double k = std::tan(22.5 * M_PI / 180) / std::tan(30 * M_PI / 180);
  EXPECT_NEAR(impostor_switch_distance_m(630, {fov, 1080}, 0.5, lodmodel::camera_from_degrees(60, 1080), 0.5),
              630 * k, 1e-9);
}

TEST(SpeciesLevel, ImpostorAtTheTopLodLevelsClampedBelow) {
  Species with;
  for (int l = 0; l < 3; ++l) with.levels.push_back({"a", 0.1 * l, 1.0 * l, 1, false, "", {}});
  with.levels.push_back({"imp", 0.5, 9, 2, true, "", {}});  // 4 levels
  Species without;
  for (int l = 0; l < 2; ++l) without.levels.push_back({"b", 0.1 * l, 1.0 * l, 1, false, "", {}});
  const int n = 4;
  EXPECT_EQ(species_level(with, 0, n), 0u);
  EXPECT_EQ(species_level(with, 2, n), 2u);
  EXPECT_EQ(species_level(with, 3, n), 3u);  // the impostor
  EXPECT_EQ(species_level(without, 1, n), 1u);
  EXPECT_EQ(species_level(without, 2, n), 1u);
  EXPECT_EQ(species_level(without, 3, n), 1u);
  // A forest whose largest chain is longer: the impostor only at the forest's last tile level.
  EXPECT_EQ(species_level(with, 3, 6), 2u);
  EXPECT_EQ(species_level(with, 5, 6), 3u);
}

// One tree of one species with `levels` on one 20 m tile; the tileset's chain of (content uri,
// geometricError), top (coarsest) first.
std::vector<std::pair<std::string, double>> one_tree_chain(std::vector<Level> levels) {
  Forest f;
  f.extent_min = {-10, -10};
  f.extent_max = {10, 10};
  f.tile_size_m = 20;
  Species s;
  s.name = "a";
  s.bounds = {{-1, 0, -1}, {1, 5, 1}};
  s.levels = std::move(levels);
  f.species = {s};
  f.instances = {{0, 0, 0, {0, 0, 0}, 0, {1, 1, 1}}};
  f.tiles = {{0, 0, {{-1, 0, -1}, {1, 5, 1}}, {0}}};
  const auto ts = nlohmann::json::parse(tileset_json(
      f, int(s.levels.size()), {}, [](std::size_t, int l) { return "t_lod" + std::to_string(l) + ".gltf"; }));
  const nlohmann::json* n = &ts["root"]["children"][0];
  std::vector<std::pair<std::string, double>> chain;
  for (;;) {
    chain.emplace_back((*n)["content"]["uri"].get<std::string>(), (*n)["geometricError"].get<double>());
    if (!n->contains("children")) break;
    n = &(*n)["children"][0];
  }
  return chain;
}

TEST(Tileset, ChainErrorsNeverGrowTowardTheLeaves) {
  // An impostor (epsilon 0.1, switching at 200 m) more accurate than the coarsest lod level
  // (0.3): the impostor's tile gets 0.3, so a client never refines from it into a larger error.
  const std::vector<std::pair<std::string, double>> expected{
      {"t_lod2.gltf", 0.3}, {"t_lod1.gltf", 0.3}, {"t_lod0.gltf", 0.001}};
  EXPECT_EQ(one_tree_chain({{"a_lod0.gltf", 0.001, 2, 10, false, "", {}},
                            {"a_lod1.gltf", 0.3, 600, 5, false, "", {}},
                            {"a_impostor.gltf", 0.1, 200, 2, true, "", {}}}),
            expected);
}

TEST(Tileset, ImpostorTileErrorIsTheErrorOfItsRecordedSwitchDistance) {
  // An impostor whose model epsilon (0.5 m) would switch at 1304 m but whose proven distance is
  // 200 m: its tile's error is 200 x 0.5 px x 2 tan(22.5 deg) / 1080 px, so a client with
  // maximumScreenSpaceError 0.5 shows it from 200 m on, where sylva's views do.
  const auto chain = one_tree_chain({{"a_lod0.gltf", 0.001, 2, 10, false, "", {}},
                                     {"a_lod1.gltf", 0.03, 78, 5, false, "", {}},
                                     {"a_impostor.gltf", 0.5, 200, 2, true, "", {}}});
  ASSERT_EQ(chain.size(), 3u);
  EXPECT_EQ(chain[0].first, "t_lod2.gltf");
  const double want = 200 * 0.5 * 2 * std::tan(std::numbers::pi / 8) / 1080;
  EXPECT_NEAR(chain[0].second, want, 1e-12);
  EXPECT_NEAR(want, 0.0767, 1e-4);
  EXPECT_EQ(chain[1].second, 0.03);
}

}  // namespace
}  // namespace sylva::forest
