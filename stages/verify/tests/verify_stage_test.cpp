// The stage adapter through a minimal StageContext and the fake renderer: declaration, assets
// from inputs, outputs of a passing run, StageError for failing runs and bad input.
#include "stages/verify/verify_stage.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "stages/verify/tests/fake_renderer.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

struct FakeContext : test::FakeStageContext {
  FakeContext(const Stage& stage, const Value::Object& with, std::vector<InputArtifact> inputs,
              const fs::path& cameras, const fs::path& refs, fs::path out)
      : FakeStageContext(stage, {}, std::move(out), with) {
    name = "verify";
    for (auto& in : inputs) add_input(std::move(in));
    set_file("cameras", cameras);
    set_file("references", refs);
  }
};

class VerifyStageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(refs_);
    test::write_file(cameras_,
                     "version: 1\nwidth: 100\nheight: 100\nmsaa: 1\nviews:\n"
                     "  - name: front\n    orbit: {}\n  - name: side\n    orbit: { azimuth_deg: 90 }\n");
    fs::create_directories(dir_ / "mesh_oak");
    fs::create_directories(dir_ / "lod_oak");
    verify::testing::write_square_glb(dir_ / "mesh_oak" / "tree.glb", 0);
    verify::testing::write_square_glb(dir_ / "lod_oak" / "lod0.glb", 20);
    verify::testing::write_square_glb(dir_ / "lod_oak" / "lod1.glb", 40);
    test::write_file(dir_ / "lod_oak" / "lod.json", "{}");
  }
  std::vector<InputArtifact> inputs() const {
    return {InputArtifact{"mesh_oak", "mesh", {{"tree.glb", dir_ / "mesh_oak" / "tree.glb", "d1"}}},
            InputArtifact{"lod_oak",
                          "lod",
                          {{"lod.json", dir_ / "lod_oak" / "lod.json", "d2"},
                           {"lod0.glb", dir_ / "lod_oak" / "lod0.glb", "d3"},
                           {"lod1.glb", dir_ / "lod_oak" / "lod1.glb", "d4"}}}};
  }
  std::unique_ptr<Stage> stage() {
    return make_verify_stage([this]() -> render::Renderer& { return renderer_; });
  }
  // Runs the stage; returns the declared outputs.
  std::vector<std::string> run(const Value::Object& with = {}, std::vector<InputArtifact> in = {}) {
    auto s = stage();
    fs::remove_all(out_);
    FakeContext ctx(*s, with, in.empty() ? inputs() : std::move(in), cameras_, refs_, out_);
    s->run(ctx);
    return ctx.outputs;
  }
  void accept() {
    for (const auto& e : fs::directory_iterator(out_)) {
      const std::string n = e.path().filename().string();
      if (n.ends_with(".png") && !n.ends_with(".diff.png")) fs::copy_file(e.path(), refs_ / n);
    }
  }
  std::string error_of(const Value::Object& with = {}, std::vector<InputArtifact> in = {}) {
    try {
      run(with, std::move(in));
    } catch (const StageError& e) {
      return e.what();
    }
    return "(no StageError)";
  }

  test::TempDir dir_;
  fs::path cameras_ = dir_ / "cameras.yaml";
  fs::path refs_ = dir_ / "refs";
  fs::path out_ = dir_ / "out";
  verify::testing::FakeRenderer renderer_;
};

TEST_F(VerifyStageTest, Declaration) {
  auto s = stage();
  const StageInfo& info = s->info();
  EXPECT_EQ(info.name, "verify");
  EXPECT_EQ(info.output_type, "report");
  EXPECT_EQ(info.inputs.types, (std::vector<std::string>{"mesh", "lod", "impostor", "forest", "pack"}));
  EXPECT_EQ(info.inputs.min, 1);
  EXPECT_EQ(info.inputs.max, -1);
  std::vector<std::string> names;
  for (const auto& p : info.params) {
    names.push_back(p.name);
    EXPECT_FALSE(p.doc.empty()) << p.name;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"cameras", "references", "pixel_threshold",
                                             "max_failing_fraction", "min_psnr_db", "compare_alpha"}));
  EXPECT_EQ(info.params[0].type, ParamType::kPath);
  EXPECT_EQ(info.params[1].type, ParamType::kDir);
  EXPECT_EQ(info.params[2].default_value, Value(0.016));
  EXPECT_EQ(info.params[3].default_value, Value(0.01));
}

// One asset per glTF file: the node's name, or <node>.<stem> when the artifact has several.
TEST_F(VerifyStageTest, AssetsFromInputs) {
  const auto assets = verify::assets_from_inputs(inputs());
  ASSERT_EQ(assets.size(), 3u);
  EXPECT_EQ(assets[0].name, "mesh_oak");
  EXPECT_EQ(assets[1].name, "lod_oak.lod0");
  EXPECT_EQ(assets[2].name, "lod_oak.lod1");
  EXPECT_EQ(assets[2].file, dir_ / "lod_oak" / "lod1.glb");
  const std::vector<InputArtifact> gltf{InputArtifact{"pack", "pack", {{"oak.gltf", "x/oak.gltf", "d"}}}};
  EXPECT_EQ(verify::assets_from_inputs(gltf)[0].name, "pack");
}

// A passing run publishes the renderings, heat maps and the three reports.
TEST_F(VerifyStageTest, PassingRunWritesEverything) {
  EXPECT_NE(error_of(), "(no StageError)");  // no references yet
  accept();
  const auto outputs = run();
  EXPECT_EQ(outputs, (std::vector<std::string>{
                         "mesh_oak__front.png", "mesh_oak__front.diff.png", "mesh_oak__side.png",
                         "mesh_oak__side.diff.png", "lod_oak.lod0__front.png", "lod_oak.lod0__front.diff.png",
                         "lod_oak.lod0__side.png", "lod_oak.lod0__side.diff.png", "lod_oak.lod1__front.png",
                         "lod_oak.lod1__front.diff.png", "lod_oak.lod1__side.png",
                         "lod_oak.lod1__side.diff.png", "report.json", "junit.xml", "report.html"}));
  const auto j = nlohmann::json::parse(test::read_file(out_ / "report.json"));
  EXPECT_EQ(j["passed"], true);
  EXPECT_EQ(j["summary"]["cases"], 6);
  // Deterministic: a second run writes the same bytes.
  const std::string html = test::read_file(out_ / "report.html");
  run();
  EXPECT_EQ(test::read_file(out_ / "report.html"), html);
}

// Any view that does not pass fails the node with a one-line summary naming the views.
TEST_F(VerifyStageTest, FailingRunIsAStageError) {
  const std::string missing = error_of();
  EXPECT_EQ(missing.rfind("6 of 6 views did not pass verification: mesh_oak/front: no reference image "
                          "'mesh_oak__front.png' in the references directory; ",
                          0),
            0u)
      << missing;
  EXPECT_NE(missing.find("; and 1 more (run 'sylva verify RECIPE' for report.html, or add --update-refs"),
            std::string::npos)
      << missing;
  accept();
  verify::testing::write_square_glb(dir_ / "mesh_oak" / "tree.glb", 4);  // the oak moved 4 px
  const std::string moved = error_of();
  EXPECT_EQ(
      moved.rfind("2 of 6 views did not pass verification: mesh_oak/front: 2.40% of pixels differ by more "
                  "than 0.016 (allowed 1.00%); mesh_oak/side: 2.40%",
                  0),
      0u)
      << moved;
  // Thresholds come from the parameters.
  EXPECT_NO_THROW(run({{"max_failing_fraction", 0.03}}));
  EXPECT_NE(error_of({{"min_psnr_db", 60.0}, {"max_failing_fraction", 0.03}})
                .find("dB is below the minimum 60.00 dB"),
            std::string::npos);
}

TEST_F(VerifyStageTest, InputWithoutGltfIsAnError) {
  EXPECT_EQ(error_of({}, {InputArtifact{"mesh_x", "mesh", {{"tree.sylt", dir_ / "tree.sylt", "d"}}}}),
            "input 'mesh_x' (type mesh) has no .glb or .gltf file to verify");
}

TEST_F(VerifyStageTest, BadCameraSetNamesTheFile) {
  test::write_file(cameras_, "version: 1\nwidth: 0\nheight: 10\nviews: []\n");
  const std::string e = error_of();
  EXPECT_EQ(e.rfind(cameras_.string() + ":2:8: error: 'width' must be between 1 and 16384, got 0", 0), 0u)
      << e;
}

TEST_F(VerifyStageTest, NoRendererIsAStageError) {
  auto s = make_verify_stage([]() -> render::Renderer& {
    throw render::RenderUnavailableError("headless OpenGL is not available: no EGL display");
  });
  fs::remove_all(out_);
  FakeContext ctx(*s, {}, inputs(), cameras_, refs_, out_);
  try {
    s->run(ctx);
    FAIL();
  } catch (const StageError& e) {
    EXPECT_STREQ(e.what(), "headless OpenGL is not available: no EGL display");
  }
}

TEST(VerifyThresholds, FromParams) {
  const verify::Thresholds t = verify::thresholds_from_params({{"pixel_threshold", 0.02},
                                                               {"max_failing_fraction", 0.05},
                                                               {"min_psnr_db", 30.0},
                                                               {"compare_alpha", false}});
  EXPECT_EQ(t.pixel_threshold, 0.02);
  EXPECT_EQ(t.max_failing_fraction, 0.05);
  EXPECT_EQ(t.min_psnr_db, 30.0);
  EXPECT_FALSE(t.compare_alpha);
  EXPECT_EQ(verify::thresholds_from_params({{"pixel_threshold", 0}}).pixel_threshold,
            0.0);  // ints are reals too
}

}  // namespace
}  // namespace sylva
