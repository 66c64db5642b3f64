// The stage adapter, run through a minimal in-memory StageContext: outputs, determinism,
// parameter overrides and user-facing errors.
#include "stages/generate/generate_stage.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "libs/image/image_io.h"
#include "libs/tree/stats.h"
#include "libs/tree/sylt_format.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

struct FakeContext : test::FakeStageContext {
  FakeContext(const Stage& stage, const Value::Object& with, const std::filesystem::path& preset,
              std::filesystem::path out)
      : FakeStageContext(stage, {}, std::move(out), with) {
    name = "tree";
    set_file("preset", preset);
  }
};

void run(const Value::Object& with, const std::filesystem::path& preset, const std::filesystem::path& out,
         std::vector<std::string>* outputs = nullptr) {
  auto stage = make_generate_stage();
  FakeContext ctx(*stage, with, preset, out);
  stage->run(ctx);
  if (outputs) *outputs = ctx.outputs;
}

TEST(GenerateStage, Declaration) {
  auto stage = make_generate_stage();
  const StageInfo& info = stage->info();
  EXPECT_EQ(info.name, "generate");
  EXPECT_EQ(info.output_type, "tree");
  std::vector<std::string> names;
  for (const auto& p : info.params) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"preset", "age", "seed", "levels", "max_node_spacing_m",
                                             "leaf_density", "texture_size", "foliage"}));
  for (const auto& p : info.params) EXPECT_FALSE(p.doc.empty()) << p.name;
}

// Writes tree.sylt, stats.json, bark.png and leaves.png; the tree is the preset's young oak, in
// twig cards (the default) on a 4 x 2 atlas whose cells carry their leaf coverage, and its
// statistics report the crown's LAI within the preset's published range.
TEST(GenerateStage, WritesOutputs) {
  test::TempDir dir;
  std::vector<std::string> outputs;
  run({{"age", "young"}, {"texture_size", 64}}, "configs/species/oak.yaml", dir / "a", &outputs);
  EXPECT_EQ(outputs, (std::vector<std::string>{"tree.sylt", "stats.json", "bark.png", "leaves.png"}));
  {
    const tree::Tree t = tree::read_sylt(dir / "a" / "tree.sylt");
    EXPECT_EQ(t.materials.leaf_kind, tree::LeafKind::kTwigCards);
    EXPECT_EQ(t.materials.atlas_columns, 4);
    EXPECT_EQ(t.materials.atlas_rows, 2);
    ASSERT_EQ(t.materials.cell_coverage.size(), 8u);
    for (float c : t.materials.cell_coverage) {
      EXPECT_GT(c, 0.05f);
      EXPECT_LT(c, 0.9f);
    }
    const auto stats = nlohmann::json::parse(test::read_file(dir / "a" / "stats.json"));
    EXPECT_EQ(stats["foliage"]["kind"], "twig_cards");
    const double lai = stats["lai"].get<double>();
    EXPECT_NEAR(lai, tree::compute_stats(t).lai, 1e-5);
    EXPECT_GE(lai, stats["foliage"]["published_lai_range"][0].get<double>());
    EXPECT_LE(lai, stats["foliage"]["published_lai_range"][1].get<double>());
    EXPECT_EQ(stats["leaves"].get<std::size_t>(), t.leaves.size());
  }
  const tree::Tree t = tree::read_sylt(dir / "a" / "tree.sylt");
  EXPECT_EQ(t.name, "oak/young seed 1");
  EXPECT_EQ(t.materials.bark_texture, "bark.png");
  const tree::TreeStats s = tree::compute_stats(t);
  EXPECT_GE(s.height, 4.0);
  EXPECT_LE(s.height, 9.0);
  EXPECT_EQ(image::read_image(dir / "a" / "bark.png").width(), 64);
  EXPECT_EQ(image::read_image(dir / "a" / "leaves.png").height(), 64);
}

// Same parameters -> byte-identical files; another seed -> a different tree.
TEST(GenerateStage, DeterministicBytes) {
  test::TempDir dir;
  const Value::Object with = {{"age", "young"}, {"texture_size", 32}, {"seed", 4}};
  run(with, "configs/species/birch.yaml", dir / "a");
  run(with, "configs/species/birch.yaml", dir / "b");
  for (const char* f : {"tree.sylt", "bark.png", "leaves.png"})
    EXPECT_EQ(test::read_file(dir / "a" / f), test::read_file(dir / "b" / f)) << f;
  Value::Object other = with;
  other["seed"] = 5;
  run(other, "configs/species/birch.yaml", dir / "c");
  EXPECT_NE(test::read_file(dir / "a" / "tree.sylt"), test::read_file(dir / "c" / "tree.sylt"));
}

// The `levels` override replaces the preset's Levels.
TEST(GenerateStage, LevelsOverride) {
  test::TempDir dir;
  run({{"age", "young"}, {"texture_size", 16}, {"levels", 2}}, "configs/species/oak.yaml", dir / "a");
  const tree::TreeStats s = tree::compute_stats(tree::read_sylt(dir / "a" / "tree.sylt"));
  EXPECT_EQ(s.branches_per_level.size(), 2u);
}

// A bad preset fails the node with the file:line:col message and no trace.
TEST(GenerateStage, BadPresetIsAStageError) {
  test::TempDir dir;
  std::string text = test::read_file("configs/species/holly.yaml");
  text.replace(text.find("Ratio: 0.02"), 11, "Ratio: 2.5 ");
  test::write_file(dir / "holly.yaml", text);
  try {
    run({}, dir / "holly.yaml", dir / "out");
    FAIL() << "expected a StageError";
  } catch (const StageError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind((dir / "holly.yaml").string() + ":", 0), 0u) << msg;
    EXPECT_NE(msg.find(": ages.young: Ratio must be in (0, 1)"), std::string::npos) << msg;
  }
}

// `foliage: leaves` gives one quad per leaf on the 2 x 2 leaf atlas; asking a broadleaf preset
// for needles (or a conifer for leaves) is an error naming the preset.
TEST(GenerateStage, SingleLeavesAndFoliageMismatch) {
  test::TempDir dir;
  run({{"age", "young"}, {"texture_size", 32}, {"foliage", "leaves"}}, "configs/species/birch.yaml",
      dir / "a");
  const tree::Tree t = tree::read_sylt(dir / "a" / "tree.sylt");
  EXPECT_EQ(t.materials.leaf_kind, tree::LeafKind::kLeaves);
  EXPECT_EQ(t.materials.atlas_cells(), 4u);
  EXPECT_GT(t.leaves.size(), 5000u);
  try {
    run({{"age", "young"}, {"foliage", "needles"}}, "configs/species/birch.yaml", dir / "b");
    FAIL() << "expected a StageError";
  } catch (const StageError& e) {
    EXPECT_NE(
        std::string(e.what()).find("birch.yaml: foliage 'needles' needs a conifer preset; birch has leaves"),
        std::string::npos)
        << e.what();
  }
  EXPECT_THROW(run({{"age", "young"}, {"foliage", "leaves"}}, "configs/species/scots_pine.yaml", dir / "c"),
               StageError);
}

TEST(GenerateStage, TextureSizeMustBePowerOfTwo) {
  test::TempDir dir;
  EXPECT_THROW(run({{"age", "young"}, {"texture_size", 100}}, "configs/species/oak.yaml", dir / "a"),
               StageError);
}

}  // namespace
}  // namespace sylva
