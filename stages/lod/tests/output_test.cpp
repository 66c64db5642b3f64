// Tests of the lod output: the stage adapter end to end, MSFT_lod linking, per-level files,
// extras and the glTF-Validator.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstring>
#include <set>

#include "libs/gltf/writer.h"
#include "libs/tree/sylt_format.h"
#include "stages/lod/lod_gltf.h"
#include "stages/lod/lod_stage.h"
#include "stages/lod/tests/test_trees.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

class FakeContext final : public StageContext {
 public:
  FakeContext(const Stage& stage, const fs::path& input_dir, fs::path out, Value::Object overrides = {})
      : out_(std::move(out)) {
    for (const ParamSpec& p : stage.info().params)
      if (!p.required()) params_[p.name] = p.default_value;
    for (auto& [k, v] : overrides) params_[k] = v;
    InputArtifact in;
    in.node = "gen";
    in.type = "tree";
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(input_dir)) names.insert(e.path().filename().string());
    for (const auto& n : names) in.files.push_back({n, input_dir / n, "0"});
    inputs_.push_back(std::move(in));
  }
  const std::string& node_name() const override { return name_; }
  const Value::Object& params() const override { return params_; }
  const std::vector<InputArtifact>& inputs() const override { return inputs_; }
  fs::path param_file(std::string_view) const override { throw std::logic_error("no file parameters"); }
  Rng rng(std::string_view stream) const override { return Rng(0, stream); }
  const fs::path& scratch_dir() const override { return out_; }
  fs::path output_path(std::string_view name) override {
    declared.insert(std::string(name));
    return out_ / std::string(name);
  }
  void write_output(std::string_view name, std::string_view bytes) override {
    sylva::test::write_file(output_path(name), std::string(bytes));
  }
  void check_cancelled() const override {}
  std::set<std::string> declared;

 private:
  std::string name_ = "lod_node";
  Value::Object params_;
  std::vector<InputArtifact> inputs_;
  fs::path out_;
};

nlohmann::json glb_json(const std::string& glb) {
  std::uint32_t len;
  std::memcpy(&len, glb.data() + 12, 4);
  return nlohmann::json::parse(glb.substr(20, len));
}

// The stage on a young oak (leaves) and a young Scots pine (needles): lod.glb links every level
// with MSFT_lod, lod<i>.glb and lod.json exist, extras carry epsilon/delta/switch distance and
// counts, lines are BLEND with the level alpha, and every file passes the glTF-Validator.
TEST(LodStage, WritesLinkedChainPerLevelFilesAndSummary) {
  const auto stage = make_lod_stage();
  std::vector<fs::path> to_validate;
  sylva::test::TempDir tmp;
  for (const std::string species : {"oak", "scots_pine"}) {
    const fs::path in = tmp / (species + "_in"), out = tmp / (species + "_out");
    fs::create_directories(in);
    fs::create_directories(out);
    tree::Tree t = lod::test::species_tree(fs::path(SYLVA_SOURCE_DIR) / "configs/species" / (species + ".yaml"), "young");
    t.materials.leaf_texture.clear();
    t.materials.bark_texture.clear();
    tree::write_sylt(in / "tree.sylt", t);
    FakeContext ctx(*stage, in, out, {{"levels", Value(4)}});
    stage->run(ctx);
    EXPECT_EQ(ctx.declared, (std::set<std::string>{"lod.glb", "lod.json", "lod0.glb", "lod1.glb", "lod2.glb", "lod3.glb"}));
    const nlohmann::json j = glb_json(sylva::test::read_file(out / "lod.glb"));
    EXPECT_EQ(j["nodes"][0]["extensions"]["MSFT_lod"]["ids"], nlohmann::json({1, 2, 3}));
    EXPECT_EQ(j["scene"], 0);
    EXPECT_EQ(j["scenes"][0]["nodes"], nlohmann::json({0}));
    EXPECT_NE(std::find(j["extensionsUsed"].begin(), j["extensionsUsed"].end(), "MSFT_lod"), j["extensionsUsed"].end());
    const auto cov = j["nodes"][0]["extras"]["MSFT_screencoverage"];
    ASSERT_EQ(cov.size(), 4u);
    for (std::size_t i = 0; i + 1 < cov.size(); ++i) EXPECT_GT(cov[i].get<double>(), cov[i + 1].get<double>());
    for (int i = 0; i < 4; ++i) {
      const auto& ex = j["nodes"][i]["extras"];
      EXPECT_GT(ex["epsilon_m"].get<double>(), 0);
      EXPECT_EQ(ex["pixel_error_px"].get<double>(), 0.5);
      EXPECT_GT(ex["switch_distance_m"].get<double>(), 0);
      EXPECT_TRUE(ex["counts"].contains("lines"));
    }
    // Line primitives use a BLEND material whose alpha is the level's.
    bool saw_lines = false;
    for (const auto& mesh : j["meshes"])
      for (const auto& p : mesh["primitives"])
        if (p.value("mode", 4) == 1) {
          saw_lines = true;
          EXPECT_EQ(j["materials"][p["material"].get<int>()]["alphaMode"], "BLEND");
        }
    EXPECT_TRUE(saw_lines);
    const nlohmann::json summary = nlohmann::json::parse(sylva::test::read_file(out / "lod.json"));
    ASSERT_EQ(summary["levels"].size(), 4u);
    EXPECT_NEAR(summary["levels"][3]["epsilon_m"].get<double>(), 0.22, 1e-12);
    if (species == "oak") EXPECT_GT(summary["levels"][0]["counts"]["leaves"].get<int>(), 0);
    else EXPECT_GT(summary["levels"][0]["counts"]["needle_lines"].get<int>() + summary["levels"][0]["counts"]["needle_quads"].get<int>(), 0);
    for (const char* f : {"lod.glb", "lod0.glb", "lod3.glb"}) to_validate.push_back(out / f);
  }
  const auto results = sylva::test::validate_gltf(to_validate);
  for (const auto& v : results) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << "\n" << v.report;
  }
}

// Bad input: a missing tree.sylt and a decreasing explicit ladder are StageErrors.
TEST(LodStage, RejectsBadInput) {
  const auto stage = make_lod_stage();
  sylva::test::TempDir tmp;
  fs::create_directories(tmp / "in");
  fs::create_directories(tmp / "out");
  FakeContext empty(*stage, tmp / "in", tmp / "out");
  EXPECT_THROW(stage->run(empty), StageError);
  tree::write_sylt(tmp / "in" / "tree.sylt", lod::test::helix(1, 2, 1, 16, 0.05));
  FakeContext bad(*stage, tmp / "in", tmp / "out", {{"errors_m", Value(Value::List{Value(0.1), Value(0.05)})}});
  EXPECT_THROW(stage->run(bad), StageError);
}

}  // namespace
}  // namespace sylva
