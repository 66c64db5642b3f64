// impostor.json: round trip, deterministic bytes, and one clear error per kind of bad file.
#include "libs/impostor/impostor_json.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace sylva::impostor {
namespace {

ImpostorInfo sample() {
  ImpostorInfo i;
  i.kind = Kind::kHemiOctahedral;
  i.hemi = true;
  i.frames_per_side = 4;
  i.frame_px = 64;
  i.atlas_width_px = i.atlas_height_px = 256;
  i.padding_px = 8;
  i.mip_levels = 3;
  i.bounds_min = {-1, 0, -1};
  i.bounds_max = {1, 3, 1};
  i.sphere_center = {0, 1.5, 0};
  i.sphere_radius = 1.8;
  i.frame_half_extent = 1.8 * 64 / 48.0;
  i.color_map = "impostor_color.png";
  i.normal_depth_map = "impostor_normal.png";
  i.camera = {0.5, 720};
  i.pixel_error_px = 0.5;
  i.error = {0.01, 0.075, 0.02};
  i.switch_distance_m = 123.25;
  i.source_type = "lod";
  i.source_file = "lod3.glb";
  i.source_level = 3;
  Card c;
  c.name = "az0";
  c.dir = {0, 0, 1};
  c.right = {1, 0, 0};
  c.up = {0, 1, 0};
  c.center = {0, 1.5, 0};
  c.half_width = c.half_height = 2.4;
  c.x = 192, c.y = 0, c.w = 64, c.h = 64;
  c.cutout = {{0.1, 0.6}, {0.9, 0.6}, {0.8, 0.1}, {0.2, 0.1}};
  c.lower_cutout = {{0.45, 0.9}, {0.55, 0.9}, {0.55, 0.6}, {0.45, 0.6}};
  i.cards.push_back(c);
  i.glb_triangles = 2;
  i.glb_file = "oak_impostor.gltf";  // not the default impostor.glb: the round trip must carry it
  return i;
}

TEST(ImpostorJson, RoundTripsAndIsDeterministic) {
  const ImpostorInfo in = sample();
  const std::string text = write_impostor_json(in);
  EXPECT_EQ(text, write_impostor_json(in));
  ImpostorInfo out = parse_impostor_json(text, "impostor.json");
  EXPECT_NEAR(out.camera.fov_y_rad, in.camera.fov_y_rad, 1e-15);
  out.camera.fov_y_rad = in.camera.fov_y_rad;
  EXPECT_EQ(out, in);
  // The file carries the formulas a reader needs, and the summed epsilon.
  const auto j = nlohmann::json::parse(text);
  EXPECT_EQ(j.at("frame_direction_formula").get<std::string>(), kFrameDirectionFormula);
  EXPECT_EQ(j.at("depth_encoding").get<std::string>(), kDepthEncoding);
  EXPECT_DOUBLE_EQ(j.at("error").at("epsilon_m").get<double>(), 0.01 + 0.075 + 0.02);
  EXPECT_EQ(j.at("kind").get<std::string>(), "hemi_octahedral");
  EXPECT_EQ(j.at("glb").at("file").get<std::string>(), "oak_impostor.gltf");
}

// Replaces the value at a JSON pointer (or removes it when `value` is discarded) and parses.
std::string error_for(const std::string& pointer, const nlohmann::json& value, bool remove = false) {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(write_impostor_json(sample()));
  const nlohmann::ordered_json::json_pointer ptr(pointer);
  if (remove) {
    j[ptr.parent_pointer()].erase(ptr.back());
  } else {
    j[ptr] = value;
  }
  try {
    parse_impostor_json(j.dump(), "x/impostor.json");
  } catch (const ImpostorFormatError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ImpostorJson, BadFilesGiveOneLineErrors) {
  EXPECT_EQ(
      error_for("/kind", "sprite"),
      "x/impostor.json: error: unknown kind 'sprite' (expected hemi_octahedral, octahedral or billboards)");
  EXPECT_EQ(error_for("/sphere/radius_m", nullptr, true),
            "x/impostor.json: error: missing 'sphere.radius_m'");
  EXPECT_EQ(error_for("/sphere/radius_m", -1),
            "x/impostor.json: error: 'sphere.radius_m' = -1 is outside [1e-09, 1e+09]");
  EXPECT_EQ(error_for("/atlas/frame_px", "64"),
            "x/impostor.json: error: 'atlas.frame_px' must be an integer");
  EXPECT_EQ(error_for("/atlas/width_px", 512),
            "x/impostor.json: error: 'atlas': width_px and height_px must be frames_per_side * frame_px");
  EXPECT_EQ(error_for("/hemi", false),
            "x/impostor.json: error: 'hemi' must be true exactly for kind hemi_octahedral");
  EXPECT_EQ(error_for("/version", 2), "x/impostor.json: error: unsupported version 2 (this reader knows 1)");
  EXPECT_EQ(error_for("/glb/cards/0/rect_px", nlohmann::json::array({250, 0, 64, 64})),
            "x/impostor.json: error: 'glb.cards[0].rect_px' lies outside the atlas");
  EXPECT_EQ(error_for("/glb/cards/0/dir", nlohmann::json::array({0, 0, 2})),
            "x/impostor.json: error: 'glb.cards[0].dir' must be a unit vector");
  EXPECT_EQ(error_for("/bounds/min", nlohmann::json::array({0, 1})),
            "x/impostor.json: error: 'bounds.min' must be a list of three numbers");
  try {
    parse_impostor_json("{\"format\": ", "y.json");
    FAIL();
  } catch (const ImpostorFormatError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("y.json: error: invalid JSON: ", 0), 0u) << e.what();
  }
  try {  // a number no double holds: the format's error, not nlohmann's out_of_range escaping
    parse_impostor_json("{\"format\": 1e999}", "y.json");
    FAIL();
  } catch (const ImpostorFormatError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("y.json: error: invalid JSON: ", 0), 0u) << e.what();
  }
  EXPECT_THROW(read_impostor_json("/nonexistent/impostor.json"), ImpostorFormatError);
}

}  // namespace
}  // namespace sylva::impostor
