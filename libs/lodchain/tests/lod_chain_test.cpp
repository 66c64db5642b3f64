// lod.json's one reader/writer (libs/lodchain/lod_chain.h): round trip, real files from the
// default recipe byte for byte, and one exact message per class of bad input.
#include "libs/lodchain/lod_chain.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "tests/support/test_support.h"

namespace sylva::lodchain {
namespace {

Level sample_level(std::uint64_t i, double epsilon) {
  Level l;
  l.sylva_lod_level = i;
  l.epsilon_m = epsilon;
  l.pixel_error_px = 0.5;
  l.switch_distance_m = epsilon * 2607.5;
  l.e1_m = epsilon / 4;
  l.e2_m = epsilon / 4;
  l.e3_m = epsilon;
  l.e4_m = epsilon / 2;
  l.e5_m = epsilon;
  l.line_alpha = 0.375;
  l.line_alpha_eq12 = 0.8125;
  l.needle_line_alpha = 1;
  l.needle_line_alpha_eq12 = 1;
  l.max_polygon_error_m = epsilon / 3;
  l.counts = {10, 20 + i, 30, 40, 0, 0, 500, 60};
  l.file = "lod" + std::to_string(i) + ".gltf";
  l.screen_coverage = 0.5 / double(i + 1);
  l.coverage_switch_distance_m = 3.25 * double(i + 1);
  return l;
}

LodChain sample_chain() {
  LodChain c;
  c.tree = "oak/adult seed 7";
  c.camera_fov_y_deg = 45.000000000000007;
  c.camera_height_px = 1080;
  c.pixel_error_px = 0.5;
  c.tree_height_m = 12.25;
  c.bounding_radius_m = 7.1;
  c.source = {1200, 34000, 0};
  c.chain_file = "lod.gltf";
  c.levels = {sample_level(0, 0.001), sample_level(1, 0.0047), sample_level(2, 0.22)};
  c.levels[1].ribbons_file = "lod1_ribbons.gltf";
  c.levels[0].cards = CardChoice{"fsa", 0, 0, std::nullopt, false};
  c.levels[1].cards = CardChoice{"clusters", 812, 3, -0.0125, false};
  c.levels[2].cards = CardChoice{"fsa", 90, 0, 0.0625, true};
  c.levels[2].screen_coverage = 0;
  c.levels[2].coverage_switch_distance_m = std::nullopt;  // the last level: null
  return c;
}

TEST(LodChain, RoundTripsBitForBit) {
  const LodChain c = sample_chain();
  const std::string text = write_lod_chain(c);
  const LodChain back = parse_lod_chain(text, "lod.json");
  EXPECT_EQ(back, c);
  EXPECT_EQ(write_lod_chain(back), text);
  // Optional fields stay absent or null as written.
  EXPECT_EQ(text.find("\"ribbons_file\""), text.rfind("\"ribbons_file\""));  // one level has one
  EXPECT_NE(text.find("\"coverage_switch_distance_m\": null"), std::string::npos);
  EXPECT_NE(text.find("\"coverage_drift\": null"), std::string::npos);
  LodChain bare = c;
  for (Level& l : bare.levels) l.cards.reset();
  const std::string bare_text = write_lod_chain(bare);
  EXPECT_EQ(bare_text.find("\"cards\""), std::string::npos);
  EXPECT_EQ(parse_lod_chain(bare_text, "lod.json"), bare);
}

// The lod stage's bytes: sorted keys, two-space indent, a final newline.
TEST(LodChain, WritesTheLodStagesLayout) {
  const std::string text = write_lod_chain(sample_chain());
  EXPECT_EQ(
      text.rfind("{\n  \"bounding_radius_m\": 7.1,\n  \"camera\": {\n    \"fov_y_deg\": 45.00000000000001,",
                 0),
      0u);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_LT(text.find("\"E1_m\""), text.find("\"cards\""));  // upper case sorts first
  EXPECT_NE(text.find("\"epsilon_m\": 0.001,"), std::string::npos);
}

// Files the lod stage wrote for configs/default.yaml (lod version 10): lod_oak (cards) and
// lod_qsm_small (ribbons, line-only coarse levels). They parse, and write back byte for byte.
TEST(LodChain, RealFilesOfTheDefaultRecipeParseAndRewriteByteForByte) {
  for (const char* name :
       {"libs/lodchain/tests/data/lod_oak.json", "libs/lodchain/tests/data/lod_qsm_small.json"}) {
    SCOPED_TRACE(name);
    const std::string text = test::read_file(name);
    ASSERT_FALSE(text.empty());
    const LodChain c = read_lod_chain(name);
    EXPECT_EQ(c.levels.size(), 6u);
    EXPECT_EQ(c.chain_file, "lod.gltf");
    EXPECT_EQ(write_lod_chain(c), text);
  }
  const LodChain oak = read_lod_chain("libs/lodchain/tests/data/lod_oak.json");
  EXPECT_TRUE(oak.levels[0].cards.has_value());
  EXPECT_FALSE(oak.levels.back().coverage_switch_distance_m.has_value());
  const LodChain qsm = read_lod_chain("libs/lodchain/tests/data/lod_qsm_small.json");
  EXPECT_TRUE(qsm.levels.back().ribbons_file.has_value());
  EXPECT_FALSE(qsm.levels[0].cards.has_value());
}

// The message parse_lod_chain gives for the sample after `edit`, or "(no error)".
std::string error_after(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = nlohmann::json::parse(write_lod_chain(sample_chain()));
  edit(j);
  try {
    parse_lod_chain(j.dump(2), "x/lod.json");
  } catch (const LodChainFormatError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(LodChain, NotJsonOrNotAnObject) {
  try {
    parse_lod_chain("{", "x/lod.json");
    FAIL();
  } catch (const LodChainFormatError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("x/lod.json: error: invalid JSON: ", 0), 0u);
  }
  // nlohmann::json throws out_of_range, not parse_error, for a number beyond double (fuzz_lodchain).
  std::string text = write_lod_chain(sample_chain());
  text.replace(text.find("12.25"), 5, "1e999");
  try {
    parse_lod_chain(text, "x/lod.json");
    FAIL();
  } catch (const LodChainFormatError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("x/lod.json: error: invalid JSON: ", 0), 0u) << e.what();
  }
  EXPECT_EQ(error_after([](nlohmann::json& j) { j = nlohmann::json::array(); }),
            "x/lod.json: error: the top level must be an object");
  try {
    read_lod_chain("/nonexistent/lod.json");
    FAIL();
  } catch (const LodChainFormatError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/lod.json: error: No such file or directory");
  }
}

TEST(LodChain, MissingFields) {
  EXPECT_EQ(error_after([](nlohmann::json& j) { j.erase("tree_height_m"); }),
            "x/lod.json: error: missing 'tree_height_m'");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["camera"].erase("height_px"); }),
            "x/lod.json: error: missing 'camera.height_px'");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][2].erase("switch_distance_m"); }),
            "x/lod.json: error: missing 'levels[2].switch_distance_m'");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["counts"].erase("branches"); }),
            "x/lod.json: error: missing 'levels[1].counts.branches'");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][2].erase("coverage_switch_distance_m"); }),
            "x/lod.json: error: missing 'levels[2].coverage_switch_distance_m'");  // null, not absent
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["cards"].erase("coverage_drift"); }),
            "x/lod.json: error: missing 'levels[1].cards.coverage_drift'");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j.erase("levels"); }), "x/lod.json: error: missing 'levels'");
}

TEST(LodChain, WrongTypes) {
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["tree"] = 7; }),
            "x/lod.json: error: 'tree' must be a string");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["camera"] = "wide"; }),
            "x/lod.json: error: 'camera' must be an object");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["camera"]["height_px"] = 1080.5; }),
            "x/lod.json: error: 'camera.height_px' must be an integer");
  EXPECT_EQ(error_after([](nlohmann::json& j) {
              j["levels"] = {{"file", "lod0.gltf"}};
            }),
            "x/lod.json: error: 'levels' must be a list");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0] = "lod0.gltf"; }),
            "x/lod.json: error: 'levels[0]' must be an object");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["file"] = 3; }),
            "x/lod.json: error: 'levels[1].file' must be a string");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["epsilon_m"] = "0.01"; }),
            "x/lod.json: error: 'levels[1].epsilon_m' must be a finite number");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0]["counts"]["quads"] = -1; }),
            "x/lod.json: error: 'levels[0].counts.quads' must be a non-negative integer");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["source"]["leaves"] = 2.5; }),
            "x/lod.json: error: 'source.leaves' must be a non-negative integer");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0]["coverage_switch_distance_m"] = "far"; }),
            "x/lod.json: error: 'levels[0].coverage_switch_distance_m' must be a finite number or null");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0]["ribbons_file"] = nullptr; }),
            "x/lod.json: error: 'levels[0].ribbons_file' must be a string");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][2]["cards"]["rejected"] = 1; }),
            "x/lod.json: error: 'levels[2].cards.rejected' must be true or false");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][2]["cards"] = nlohmann::json::array(); }),
            "x/lod.json: error: 'levels[2].cards' must be an object");
}

TEST(LodChain, OutOfRange) {
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0]["epsilon_m"] = -0.001; }),
            "x/lod.json: error: 'levels[0].epsilon_m' = -0.001 must be greater than 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["pixel_error_px"] = 0; }),
            "x/lod.json: error: 'levels[1].pixel_error_px' = 0 must be greater than 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["pixel_error_px"] = -0.5; }),
            "x/lod.json: error: 'pixel_error_px' = -0.5 must be greater than 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["switch_distance_m"] = -2; }),
            "x/lod.json: error: 'levels[1].switch_distance_m' = -2 must be at least 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["E4_m"] = -0.5; }),
            "x/lod.json: error: 'levels[1].E4_m' = -0.5 must be at least 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["line_alpha"] = 1.5; }),
            "x/lod.json: error: 'levels[1].line_alpha' = 1.5 must be at most 1");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0]["screen_coverage"] = 2; }),
            "x/lod.json: error: 'levels[0].screen_coverage' = 2 must be at most 1");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][0]["coverage_switch_distance_m"] = -1; }),
            "x/lod.json: error: 'levels[0].coverage_switch_distance_m' = -1 must be at least 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["camera"]["fov_y_deg"] = 0; }),
            "x/lod.json: error: 'camera.fov_y_deg' = 0 must be greater than 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["camera"]["fov_y_deg"] = 180; }),
            "x/lod.json: error: 'camera.fov_y_deg' = 180 must be less than 180");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["camera"]["height_px"] = 0; }),
            "x/lod.json: error: 'camera.height_px' = 0 is outside [1, 1048576]");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["tree_height_m"] = -1; }),
            "x/lod.json: error: 'tree_height_m' = -1 must be at least 0");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["bounding_radius_m"] = 1e300; }),
            "x/lod.json: error: 'bounding_radius_m' = 1e+300 must be at most 1e+12");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["cards"]["from"] = "random"; }),
            "x/lod.json: error: 'levels[1].cards.from' must be \"clusters\" or \"fsa\"");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"][1]["file"] = ""; }),
            "x/lod.json: error: 'levels[1].file' must not be empty");
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["chain_file"] = ""; }),
            "x/lod.json: error: 'chain_file' must not be empty");
}

TEST(LodChain, LevelsMustFormAChain) {
  EXPECT_EQ(error_after([](nlohmann::json& j) { j["levels"] = nlohmann::json::array(); }),
            "x/lod.json: error: 'levels' is empty (a chain has at least one level)");
  EXPECT_EQ(error_after([](nlohmann::json& j) {
              for (int k = 0; k < 6; ++k) j["levels"].push_back(j["levels"][0]);
            }),
            "x/lod.json: error: 'levels' has 9 levels, at most 8");
  EXPECT_EQ(
      error_after([](nlohmann::json& j) { j["levels"][1]["epsilon_m"] = 0.001; }),
      "x/lod.json: error: 'levels[1].epsilon_m' = 0.001 must be greater than the previous level's 0.001");
  EXPECT_EQ(error_after([](nlohmann::json& j) { std::swap(j["levels"][1], j["levels"][2]); }),
            "x/lod.json: error: 'levels[1].sylva_lod_level' = 2 must be its index 1");
}

}  // namespace
}  // namespace sylva::lodchain
