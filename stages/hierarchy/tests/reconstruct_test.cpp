// The whole core on the test tree, with Celba's names and without, its report, and the exact
// messages for input it cannot use.
#include "stages/hierarchy/reconstruct.h"

#include <gtest/gtest.h>

#include "stages/hierarchy/hierarchy_error.h"
#include "stages/hierarchy/report.h"
#include "stages/hierarchy/tests/test_meshes.h"

namespace sylva::hierarchy {
namespace {

using tree::Vec3;

tree::Tree imported(tree::SourceGeometry g) {
  tree::Tree t;
  t.name = "imported";
  t.source = std::move(g);
  return t;
}

std::string error_of(const tree::Tree& t, const ReconstructOptions& o = {}) {
  try {
    reconstruct(t, o);
  } catch (const HierarchyError& e) {
    return e.what();
  }
  return "no error";
}

// The test tree comes back as trunk + two laterals with one leaf each, whichever rule found it.
void expect_test_tree(const Reconstruction& r) {
  const tree::Tree& t = r.tree;
  EXPECT_EQ(tree::validate_tree(t), std::vector<std::string>{});
  ASSERT_EQ(t.branches.size(), 3u);
  EXPECT_EQ(t.branches[0].parent, -1);
  EXPECT_EQ(t.branches[1].parent, 0);
  EXPECT_EQ(t.branches[2].parent, 0);
  EXPECT_EQ(t.branches[1].level, 1u);
  EXPECT_EQ(t.branches[2].level, 1u);
  // Each lateral grows from the trunk at its base height.
  EXPECT_NEAR(tree::attachment_point(t, t.branches[1]).y, 2.0, 0.01);
  EXPECT_NEAR(tree::attachment_point(t, t.branches[2]).y, 3.0, 0.01);
  EXPECT_NEAR(t.branches[0].nodes.front().radius, 0.2, 0.01);
  EXPECT_NEAR(t.branches[1].nodes.front().radius, 0.06, 0.003);
  ASSERT_EQ(t.leaves.size(), 2u);
  EXPECT_EQ(t.leaves[0].branch, 1u);
  EXPECT_EQ(t.leaves[1].branch, 2u);
  // The quad: at the petiole, up, facing -x (its triangles wind that way), 0.2 x 0.1 m.
  EXPECT_LT(length(tree::to_double(t.leaves[0].position) - testing::tip_a()), 1e-5);
  EXPECT_EQ(t.leaves[0].direction, (tree::Vec3f{0, 1, 0}));
  EXPECT_EQ(t.leaves[0].normal, (tree::Vec3f{-1, 0, 0}));
  EXPECT_NEAR(t.leaves[0].length, 0.2, 1e-6);
  EXPECT_NEAR(t.leaves[0].width, 0.1, 1e-6);
  EXPECT_EQ(t.materials.leaf_kind, tree::LeafKind::kTwigCards);
  EXPECT_EQ(t.materials.atlas_cells(), 1u);
  EXPECT_EQ(t.materials.bark_color, (tree::Color{0.4f, 0.3f, 0.2f}));
  EXPECT_EQ(t.materials.leaf_color, (tree::Color{0.1f, 0.5f, 0.1f}));
  EXPECT_EQ(r.report.parts, 5u);
  EXPECT_EQ(r.report.branches_by_level, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(r.report.left_out.size(), 0u);
  for (const BranchReport& b : r.report.branches) EXPECT_LT(b.fit_rms_m, 1e-3);
}

TEST(Reconstruct, WithCelbaNames) {
  const tree::Tree in = imported(testing::named_tree());
  const Reconstruction r = reconstruct(in, {});
  expect_test_tree(r);
  EXPECT_TRUE(r.report.levels_from_names);
  EXPECT_EQ(r.tree.source, in.source);  // passed through unchanged
  EXPECT_EQ(r.tree.name, "imported");
}

TEST(Reconstruct, WithoutNames) {
  const Reconstruction r = reconstruct(imported(testing::nameless_tree()), {});
  expect_test_tree(r);
  EXPECT_FALSE(r.report.levels_from_names);
}

// Names that call every part a leaf (bark included): auto falls back to the geometry rule and
// says so in the report; without the fallback the report says "none".
TEST(Reconstruct, ClassifyFallsBackToGeometry) {
  tree::SourceGeometry g = testing::nameless_tree();
  EXPECT_EQ(report_json(reconstruct(imported(g), {}).report, g)["classify_fallback"], "none");
  g.primitives[0].name = "tree/lf_bark";
  g.primitives[1].name = "tree/lf_leaves";
  const Reconstruction r = reconstruct(imported(g), {});
  expect_test_tree(r);
  EXPECT_TRUE(r.report.classify_fallback);
  EXPECT_EQ(report_json(r.report, g)["classify_fallback"], "geometry");
}

TEST(Reconstruct, Deterministic) {
  const tree::Tree in = imported(testing::nameless_tree());
  EXPECT_EQ(reconstruct(in, {}).tree, reconstruct(in, {}).tree);
}

// A lateral 0.5 m from the trunk, beyond the tolerance: left out and reported with its size.
TEST(Reconstruct, UnconnectedPartsReported) {
  tree::SourceGeometry g = testing::named_tree();
  for (tree::Vec3f& p : g.primitives[2].positions) p.x -= 0.5f;
  const Reconstruction r = reconstruct(imported(g), {});
  ASSERT_EQ(r.tree.branches.size(), 2u);
  ASSERT_EQ(r.tree.leaves.size(), 1u);  // b's leaf is beyond every grown box now
  ASSERT_EQ(r.report.left_out.size(), 2u);
  EXPECT_EQ(r.report.left_out[0].part, 2u);
  EXPECT_EQ(r.report.left_out[0].kind, "branch");
  EXPECT_EQ(r.report.left_out[0].triangles, 12u * 12 * 2);
  EXPECT_EQ(r.report.left_out[1].kind, "leaf");
  const nlohmann::json j = report_json(r.report, g);
  EXPECT_EQ(j["unconnected"]["count"], 2);
  EXPECT_EQ(j["unconnected"]["triangles"], 12 * 12 * 2 + 2);
  EXPECT_EQ(j["unconnected"]["parts"][0]["primitive"], "tree/br1b");
  EXPECT_EQ(j["levels"], "names");
  EXPECT_EQ(j["branches_by_level"], nlohmann::json::array({1, 1}));
  EXPECT_GT(j["unconnected"]["parts"][0]["size_m"].get<double>(), 1.0);
}

TEST(Reconstruct, Errors) {
  EXPECT_EQ(error_of(tree::Tree{}),
            "the tree has no source geometry: stage hierarchy reconstructs a skeleton from an imported mesh");
  tree::Tree with_skeleton = imported(testing::named_tree());
  with_skeleton.branches.resize(2);
  EXPECT_EQ(
      error_of(with_skeleton),
      "the tree already has a skeleton (2 branches): stage hierarchy builds one from source geometry alone");
  tree::SourceGeometry empty;
  empty.primitives.resize(2);
  empty.materials.resize(1);
  EXPECT_EQ(error_of(imported(empty)), "the source geometry has no triangles (2 primitives)");
  tree::SourceGeometry leaves_only;
  leaves_only.primitives = {testing::leaves("lf")};
  leaves_only.materials = testing::materials();
  EXPECT_EQ(error_of(imported(leaves_only)),
            "no branch part among the 2 parts (2 leaves, 0 skipped): nothing to fit a skeleton to");
  tree::SourceGeometry no_trunk = testing::named_tree();
  no_trunk.primitives[0].name = "tree/br1Trunk";
  EXPECT_EQ(error_of(imported(no_trunk)), "no trunk: no branch part is named br0* (3 branch parts)");
}

}  // namespace
}  // namespace sylva::hierarchy
