// The level an impostor is baked from (source.h).
#include "stages/impostor/source.h"

#include <gtest/gtest.h>

namespace sylva::impostor {
namespace {

constexpr const char* kSummary = R"({"pixel_error_px": 0.5, "levels": [
  {"file": "lod0.glb", "epsilon_m": 0.001, "switch_distance_m": 2.6},
  {"file": "lod1.glb", "epsilon_m": 0.01, "pixel_error_px": 0.25},
  {"file": "lod2.glb", "epsilon_m": 0.1}]})";

TEST(Source, ReadsTheLevelsOfLodJson) {
  const auto levels = parse_lod_levels(kSummary, "lod.json");
  ASSERT_EQ(levels.size(), 3u);
  EXPECT_EQ(levels[1].file, "lod1.glb");
  EXPECT_DOUBLE_EQ(levels[1].epsilon, 0.01);
  EXPECT_DOUBLE_EQ(levels[1].pixel_error, 0.25);  // the level's own
  EXPECT_DOUBLE_EQ(levels[2].pixel_error, 0.5);   // else the chain's
  EXPECT_DOUBLE_EQ(levels[0].switch_distance, 2.6);
  EXPECT_DOUBLE_EQ(levels[2].switch_distance, 0);
}

// The coarsest level within one texel; the finest when none is.
TEST(Source, ChoosesTheCoarsestLevelWithinATexel) {
  const auto levels = parse_lod_levels(kSummary, "lod.json");
  EXPECT_EQ(choose_level(levels, 0.05), 1u);
  EXPECT_EQ(choose_level(levels, 0.1), 2u);
  EXPECT_EQ(choose_level(levels, 1e-4), 0u);
}

TEST(Source, BadSummariesAreOneLineErrors) {
  auto error = [](const char* text) {
    try {
      parse_lod_levels(text, "x/lod.json");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error(R"({"levels": []})"), "x/lod.json: not a lod summary (no 'levels' list)");
  EXPECT_EQ(error(R"({"levels": [{"epsilon_m": 1}]})"), "x/lod.json: levels[0] has no 'file'");
  EXPECT_EQ(error(R"({"levels": [{"file": "a", "epsilon_m": -1}]})"),
            "x/lod.json: levels[0] has no valid 'epsilon_m'");
  EXPECT_EQ(error("{").rfind("x/lod.json: invalid JSON: ", 0), 0u);
}

}  // namespace
}  // namespace sylva::impostor
