// `sylva impostorcheck` through the real binary on a small generate -> lod -> impostor recipe (a
// young birch at a 200-px camera): the table, impostorcheck.json and the images; exit 1 when the
// impostor is checked much closer than its switch distance; usage errors.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int code = -1;
  std::string out, err;
};

Outcome run(const test::TempDir& dir, const std::string& args) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  // The test recipes live in temp dirs and name the repository's presets: outside their
  // project root (docs/recipes.md), so they are run as trusted recipes.
  const std::string cmd =
      std::string(SYLVA_BINARY) + " --allow-outside-root " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::read_file(out), test::read_file(err)};
}

class ImpostorcheckCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::write_file(recipe_, "version: 1\nname: small\nnodes:\n"
                              "  tree_birch:\n    stage: generate\n    with: { preset: " +
                                  fs::absolute("configs/species/birch.yaml").string() +
                                  ", age: young, texture_size: 128 }\n"
                                  "  lod_birch:\n    stage: lod\n    needs: tree_birch\n"
                                  "    with: { camera: { height_px: 200 }, levels: 3 }\n"
                                  "  impostor_birch:\n    stage: impostor\n    needs: lod_birch\n"
                                  "    with: { camera: { height_px: 200 }, frames: 8, frame_px: 64, mip_levels: 2 }\n");
  }
  Outcome check(const std::string& extra = "") {
    return run(dir_, "--out " + out_.string() + " impostorcheck " + recipe_.string() + " " + extra);
  }
  test::TempDir dir_;
  fs::path recipe_ = dir_ / "small.yaml";
  fs::path out_ = dir_ / "out";
  fs::path report_ = out_ / "small" / "impostorcheck" / "impostor_birch";
};

TEST_F(ImpostorcheckCli, PassesAndReports) {
  const Outcome r = check("--azimuth 7.5 --azimuth 187.5 --elevation 4 --elevation 73");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("impostorcheck impostor_birch: hemi_octahedral, 8x8 frames of 64 px; epsilon "), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("full detail: lod_birch (lod chain at epsilon 0)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the colour change is <= max(0.1, 1.5 x lod2.gltf's in the view)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sylva impostorcheck: node 'impostor_birch' passed (4/4 views passed); report: " +
                       (report_ / "impostorcheck.json").string() + "\n"),
            std::string::npos)
      << r.out;
  const auto j = nlohmann::json::parse(test::read_file(report_ / "impostorcheck.json"));
  EXPECT_TRUE(j.at("passed").get<bool>());
  ASSERT_EQ(j.at("views").size(), 4u);
  for (const auto& v : j.at("views")) {
    EXPECT_GT(v.at("footprint_pixels").get<std::size_t>(), 0u);
    EXPECT_GT(v.at("nearest_frame_deg").get<double>(), 0.5);
    EXPECT_DOUBLE_EQ(v.at("distance_m").get<double>(), j.at("switch_distance_m").get<double>());
  }
  EXPECT_EQ(j.at("camera").at("height_px").get<int>(), 200);
  for (const char* f : {"full_az7.5_el4.png", "impostor_az187.5_el73.png", "impostor_az187.5_el73_diff.png"})
    EXPECT_TRUE(fs::exists(report_ / f)) << f;
  SYLVA_EXPECT_VALID_GLTF(out_ / "small" / "impostor_birch" / "impostor.glb");
}

// At a tenth of its switch distance the atlas's texels are five pixels wide: the check sees it.
TEST_F(ImpostorcheckCli, TooCloseFails) {
  const Outcome r = check("--no-images --azimuth 7.5 --elevation 33 --distance-scale 0.1");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("(checked at x0.1)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("FAIL: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sylva impostorcheck: node 'impostor_birch' FAILED (0/1 views passed)"), std::string::npos) << r.out;
}

TEST_F(ImpostorcheckCli, UsageErrors) {
  Outcome r = check("--node impostor_brch");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'impostor_brch' of stage 'impostor' in recipe 'small'; did you mean 'impostor_birch'?\n");
  r = check("--elevation 91");
  EXPECT_EQ(r.code, 2);
  test::write_file(dir_ / "plain.yaml", "version: 1\nname: plain\nnodes:\n  t:\n    stage: generate\n    with: { preset: " +
                                            fs::absolute("configs/species/birch.yaml").string() + " }\n");
  r = run(dir_, "--out " + out_.string() + " impostorcheck " + (dir_ / "plain.yaml").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: recipe 'plain' (" + (dir_ / "plain.yaml").string() +
                       ") has no node of stage 'impostor'; add one (docs/stages/impostor.md)\n");
}

}  // namespace
}  // namespace sylva
