// The adapter: its declaration, and a tree without source geometry refused with the file named.
// (Running it end to end needs the .sylt source-geometry section; the core's tests cover the
// reconstruction.)
#include "stages/hierarchy/hierarchy_stage.h"

#include <gtest/gtest.h>

#include "libs/tree/sylt_format.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

TEST(HierarchyStage, Declaration) {
  const auto stage = make_hierarchy_stage();
  const StageInfo& info = stage->info();
  EXPECT_EQ(info.name, "hierarchy");
  EXPECT_EQ(info.output_type, "tree");
  EXPECT_EQ(info.inputs.types, (std::vector<std::string>{"tree"}));
  EXPECT_EQ(info.inputs.min, 1);
  EXPECT_EQ(info.inputs.max, 1);
  std::vector<std::string> names;
  for (const auto& p : info.params) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"weld_tolerance", "classify", "leaf_max_size", "leaf_flatness",
                                             "leaf_point", "tolerance", "slice_radii", "max_slices",
                                             "fit_iterations"}));
  for (const auto& p : info.params) EXPECT_FALSE(p.doc.empty()) << p.name;
  EXPECT_EQ(info.outputs,
            (std::vector<std::string>{"tree.sylt", "hierarchy.json", "*.png", "*.jpg", "*.jpeg"}));
}

TEST(HierarchyStage, TreeWithoutSourceGeometryRefused) {
  test::TempDir in, out;
  tree::Tree t;
  t.branches.resize(1);
  t.branches[0].nodes = {{{0, 0, 0}, 0.1}, {{0, 1, 0}, 0.1}};
  tree::write_sylt(in / "tree.sylt", t);
  const auto stage = make_hierarchy_stage();
  test::FakeStageContext ctx(*stage, {{"imp", "tree", in.path()}}, out.path());
  try {
    stage->run(ctx);
    FAIL();
  } catch (const StageError& e) {
    EXPECT_EQ(std::string(e.what()), (in / "tree.sylt").string() +
                                         ": the tree has no source geometry: stage hierarchy reconstructs a "
                                         "skeleton from an imported mesh");
  }
  EXPECT_TRUE(ctx.declared.empty());
}

}  // namespace
}  // namespace sylva
