// The lod stage on an imported tree (docs/stages/lod.md "Imported trees"): level 0 and full.glb
// are the user's own model (its triangles, materials and images unchanged), the coarser levels
// the reconstruction's; lod.json says so (source.model_triangles); a tree with source geometry
// but no skeleton is refused with a message naming the hierarchy stage.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "libs/sourcegltf/testing/sample_source.h"
#include "libs/tree/sylt_format.h"
#include "stages/lod/lod_stage.h"
#include "stages/lod/tests/test_trees.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// A helix skeleton (what the hierarchy stage would have reconstructed) carrying an imported
// model whose leaf reaches 3 m above the skeleton's top (sourcegltf::testing::strip_and_leaf).
tree::Tree imported_tree() {
  tree::Tree t = lod::test::helix(1, 2, 1, 16, 0.05);
  t.name = "imported";
  t.source = sourcegltf::testing::strip_and_leaf();
  return t;
}

struct LodRun {
  sylva::test::TempDir tmp;
  fs::path out;
  explicit LodRun(const tree::Tree& t) {
    const auto stage = make_lod_stage();
    const fs::path in = tmp / "in";
    out = tmp / "out";
    fs::create_directories(in);
    fs::create_directories(out);
    tree::write_sylt(in / "tree.sylt", t);
    sylva::test::FakeStageContext ctx(*stage, {{"hier", "tree", in}}, out, {{"levels", Value(3)}});
    stage->run(ctx);
  }
  nlohmann::json json(const std::string& f) const {
    return nlohmann::json::parse(sylva::test::read_file(out / f));
  }
};

TEST(LodImported, LevelZeroAndFullDetailAreTheImportedModel) {
  const LodRun r(imported_tree());
  const nlohmann::json summary = r.json("lod.json");
  EXPECT_EQ(summary["source"]["model_triangles"], 3);
  ASSERT_EQ(summary["levels"].size(), 3u);
  EXPECT_EQ(summary["levels"][0]["counts"]["triangles"], 3);
  EXPECT_DOUBLE_EQ(summary["tree_height_m"].get<double>(), 5.0);  // the model's top, above the skeleton's 2 m

  const nlohmann::json l0 = r.json("lod0.gltf");
  ASSERT_EQ(l0["meshes"].size(), 1u);
  ASSERT_EQ(l0["meshes"][0]["primitives"].size(), 2u);
  ASSERT_EQ(l0["materials"].size(), 2u);
  EXPECT_EQ(l0["materials"][0]["name"], "BarkMat");
  EXPECT_EQ(l0["materials"][1]["name"], "LeafMat");
  EXPECT_EQ(l0["materials"][1]["alphaMode"], "MASK");
  ASSERT_EQ(l0["images"].size(), 1u);
  EXPECT_EQ(l0["images"][0]["uri"], "source0.png");
  EXPECT_EQ(sylva::test::read_file(r.out / "source0.png"), sylva::test::tiny_png());

  // The coarser levels are the reconstruction's, with the lod stage's own materials.
  const nlohmann::json l1 = r.json("lod1.gltf");
  EXPECT_EQ(l1["materials"][0]["name"], "bark");

  // full.glb, the reference lodcheck judges against, is the model too: its JSON chunk names
  // the model's materials and no reconstruction material.
  const std::string glb = sylva::test::read_file(r.out / "full.glb");
  EXPECT_NE(glb.find("\"LeafMat\""), std::string::npos);
  EXPECT_EQ(glb.find("\"bark\""), std::string::npos);

  const std::vector<fs::path> files{r.out / "lod.gltf", r.out / "lod0.gltf", r.out / "full.glb"};
  const auto results = sylva::test::validate_gltf(files);
  for (const auto& v : results) {
    if (v.skipped) GTEST_SKIP() << v.skip_reason;
    EXPECT_TRUE(v.ok()) << v.file << "\n" << v.tool_error << "\n" << v.report;
  }
}

TEST(LodImported, GeneratedTreesKeepTheirOwnLevelZero) {
  const LodRun r(lod::test::helix(1, 2, 1, 16, 0.05));
  const nlohmann::json summary = r.json("lod.json");
  EXPECT_FALSE(summary["source"].contains("model_triangles"));
  EXPECT_EQ(r.json("lod0.gltf")["materials"][0]["name"], "bark");
}

TEST(LodImported, AnImportedMeshWithoutSkeletonNamesTheHierarchyStage) {
  tree::Tree t = imported_tree();
  t.branches.clear();
  sylva::test::TempDir tmp;
  fs::create_directories(tmp / "in");
  fs::create_directories(tmp / "out");
  tree::write_sylt(tmp / "in" / "tree.sylt", t);
  const auto stage = make_lod_stage();
  sylva::test::FakeStageContext ctx(*stage, {{"imp", "tree", tmp / "in"}}, tmp / "out");
  try {
    stage->run(ctx);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_STREQ(e.what(),
                 "tree 'imported' has no skeleton: it is an imported mesh; run the hierarchy stage on it "
                 "first (docs/stages/hierarchy.md)");
  }
}

}  // namespace
}  // namespace sylva
