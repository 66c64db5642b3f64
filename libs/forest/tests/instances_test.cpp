#include "libs/forest/instances.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace sylva::forest {
namespace {

Forest sample_forest(bool binary) {
  Forest f;
  f.extent_min = {-50, -25};
  f.extent_max = {50, 25};
  f.tile_size_m = 50;
  f.nodes_per_node = 4;
  f.method = "celba";
  f.seed = 7;
  Species s;
  s.name = "oak";
  s.source = "oak/adult seed 7";
  s.bounds = {{-3, 0, -2.5}, {3, 12.25, 2.5}};
  s.base_rotation_deg = {0, 90, 0};
  s.base_translation_y_m = -0.1;
  s.levels = {{"oak_lod0.gltf", 0.001, 2.6, 1000, false, "", {}},
              {"oak_impostor.gltf", 0.4, 1100, 12, true, "oak_impostor.json", {{1100, 4}, {1374.125, 0}}}};
  f.species.push_back(s);
  f.stats.push_back({3, 2, 1});
  f.ground = "ground.glb";
  f.instances.push_back({0, 0, 0, {-10.125, 1.5, 3.0 / 7.0}, 0.1, {1.1, 0.9, 1.0}});
  f.instances.push_back({1, 0, 1, {20, 0, -1e-9}, 6.2, {1, 1, 1}});
  f.tiles.push_back({0, 0, {{-13, 1.4, -2}, {-7, 14, 3}}, {0}});
  f.tiles.push_back({1, 0, {{17, 0, -3}, {23, 12, 3}}, {1}});
  f.hierarchy.push_back({{{-13, 0, -3}, {23, 14, 3}}, true, {0, 1}});
  f.binary_table = binary;
  return f;
}

TEST(Instances, RoundTripsBitForBitInlineAndBinary) {
  for (bool binary : {false, true}) {
    const Forest f = sample_forest(binary);
    const EncodedForest e = write_instances(f);
    EXPECT_EQ(e.bin.size(), binary ? 2 * kRecordBytes : 0u);
    const Forest back = parse_instances(e.json, e.bin, "x.json");
    EXPECT_EQ(back, f);
    EXPECT_EQ(write_instances(back).json, e.json);  // deterministic bytes
  }
}

TEST(Instances, BadInputNamesTheProblem) {
  const EncodedForest e = write_instances(sample_forest(true));
  try {
    parse_instances(e.json, e.bin.substr(1), "f/instances.json");
    FAIL();
  } catch (const FormatError& err) {
    EXPECT_STREQ(err.what(),
                 "f/instances.json: error: instances.bin holds 135 bytes, expected 136 (2 records)");
  }
  std::string j = write_instances(sample_forest(false)).json;
  j.replace(j.find("\"species\": 0"), 12, "\"species\": 5");
  try {
    parse_instances(j, "", "i.json");
    FAIL();
  } catch (const FormatError& err) {
    EXPECT_STREQ(err.what(), "i.json: error: instance 0 names species 5, which does not exist");
  }
  std::string o = write_instances(sample_forest(false)).json;
  o.replace(o.find("\"oak_impostor.json\""), 19, "\"../x.json\"");
  try {
    parse_instances(o, "", "i.json");
    FAIL();
  } catch (const FormatError& err) {
    EXPECT_STREQ(
        err.what(),
        "i.json: error: species[0].levels[1].octahedral must be a file name of this artifact, on the "
        "impostor level only");
  }
  for (const char* file : {"\"../../etc/passwd\"", "\"/etc/passwd\"", "\"\""}) {
    std::string l = write_instances(sample_forest(false)).json;
    l.replace(l.find("\"oak_lod0.gltf\""), 15, file);
    try {
      parse_instances(l, "", "i.json");
      FAIL() << file;
    } catch (const FormatError& err) {
      EXPECT_STREQ(err.what(),
                   "i.json: error: species[0].levels[0].file must be a file name of this artifact");
    }
  }
  std::string h = write_instances(sample_forest(false)).json;
  h.replace(h.find("\"height_px\": 1080"), 17, "\"height_px\": 0");
  try {
    parse_instances(h, "", "i.json");
    FAIL();
  } catch (const FormatError& err) {
    EXPECT_STREQ(err.what(), "i.json: error: species[0].camera.height_px is out of range");
  }
  std::string p = write_instances(sample_forest(false)).json;
  p.replace(p.find("1374.125"), 8, "1000");
  try {
    parse_instances(p, "", "i.json");
    FAIL();
  } catch (const FormatError& err) {
    EXPECT_STREQ(
        err.what(),
        "i.json: error: species[0].levels[1].parallax[1].from_m must be greater than the row before's");
  }
  EXPECT_THROW(parse_instances("{", "", "i.json"), FormatError);
  try {  // a number no double holds: the format's error, not nlohmann's out_of_range escaping
    parse_instances("{\"format\": 1e999}", "", "i.json");
    FAIL();
  } catch (const FormatError& err) {
    EXPECT_EQ(std::string(err.what()).rfind("i.json: error: not JSON: ", 0), 0u) << err.what();
  }
  EXPECT_THROW(parse_instances("[]", "", "i.json"), FormatError);
}

// A FIFO in place of instances.json or instances.bin would block the open; a link to a device
// never end: both are refused by name, without opening them.
TEST(Instances, ReadsRegularFilesOnly) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("sylva_instances_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const EncodedForest e = write_instances(sample_forest(true));
  std::ofstream(dir / "instances.json", std::ios::binary) << e.json;
  ASSERT_EQ(::mkfifo((dir / "instances.bin").c_str(), 0600), 0);
  auto error = [&] {
    try {
      read_instances(dir / "instances.json");
    } catch (const FormatError& err) {
      return std::string(err.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error(), (dir / "instances.bin").string() + ": error: not a regular file");
  std::filesystem::remove(dir / "instances.bin");
  std::filesystem::create_symlink("/dev/zero", dir / "instances.bin");
  EXPECT_EQ(error(), (dir / "instances.bin").string() + ": error: not a regular file");
  std::filesystem::remove(dir / "instances.bin");
  std::ofstream(dir / "instances.bin", std::ios::binary) << e.bin;
  EXPECT_EQ(error(), "no error");
  std::filesystem::remove(dir / "instances.json");
  ASSERT_EQ(::mkfifo((dir / "instances.json").c_str(), 0600), 0);
  EXPECT_EQ(error(), (dir / "instances.json").string() + ": error: not a regular file");
  std::filesystem::remove(dir / "instances.json");
  EXPECT_EQ(error(), (dir / "instances.json").string() + ": error: No such file or directory");
  std::filesystem::remove_all(dir);
}

TEST(Instances, MatrixIsTranslateYawScaleBase) {
  Species s;
  s.base_rotation_deg = {90, 0, 0};  // R_x(90): y -> z, z -> -y
  s.base_translation_y_m = 1;
  Instance in;
  in.position = {10, 2, -3};
  in.yaw_rad = std::numbers::pi / 2;  // R_y(90): x -> -z, z -> x
  in.scale = {2, 3, 4};
  const auto m = instance_matrix(s, in);
  auto apply = [&](Vec3d p) {
    Vec3d o{};
    for (int r = 0; r < 3; ++r) o[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    return o;
  };
  // (0, 0, 1): R_x(90) -> (0, -1, 0); +1 y -> (0, 0, 0); scale -> (0, 0, 0); yaw; + position.
  Vec3d p = apply({0, 0, 1});
  EXPECT_NEAR(p[0], 10, 1e-12);
  EXPECT_NEAR(p[1], 2, 1e-12);
  EXPECT_NEAR(p[2], -3, 1e-12);
  // (1, 0, 0): base keeps it, +1 y -> (1, 1, 0); scale -> (2, 3, 0); yaw 90 -> (0, 3, -2).
  p = apply({1, 0, 0});
  EXPECT_NEAR(p[0], 10, 1e-12);
  EXPECT_NEAR(p[1], 5, 1e-12);
  EXPECT_NEAR(p[2], -5, 1e-12);
  const Box3 b = transform_box(m, {{-1, -1, -1}, {1, 1, 1}});
  EXPECT_NEAR(b.min[1], 2 + 3 * 0, 1e-12);  // base: y in [-1, 1] after R_x, +1 -> [0, 2], x3 -> [0, 6]
  EXPECT_NEAR(b.max[1], 8, 1e-12);
}

}  // namespace
}  // namespace sylva::forest
