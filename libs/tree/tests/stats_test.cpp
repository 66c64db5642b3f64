#include "libs/tree/stats.h"

#include <gtest/gtest.h>

#include "libs/tree/tests/sample_tree.h"

namespace sylva::tree {
namespace {

// Counts, height, DBH (interpolated between the nodes at y = 1 and 2), length and bounds of the
// hand-built sample tree.
TEST(Stats, SampleTree) {
  const TreeStats s = compute_stats(testing::sample_tree());
  EXPECT_EQ(s.branches, 2u);
  EXPECT_EQ(s.branches_per_level, (std::vector<std::size_t>{1, 1}));
  EXPECT_EQ(s.nodes, 6u);
  EXPECT_EQ(s.leaves, 1u);
  EXPECT_EQ(s.needles, 1u);
  EXPECT_DOUBLE_EQ(s.height, 3.0);
  ASSERT_TRUE(s.has_dbh);
  EXPECT_NEAR(s.dbh, 2 * (0.18 + 0.3 * (0.15 - 0.18)), 1e-12);
  EXPECT_NEAR(s.total_branch_length, 4.0, 1e-12);
  EXPECT_NEAR(s.bounds_min.x, 0, 1e-12);
  EXPECT_NEAR(s.bounds_max.x, 1.25, 1e-6);
  EXPECT_NEAR(s.bounds_max.y, 3, 1e-12);
  EXPECT_NEAR(s.bounds_max.z, 0.02, 1e-6);
}

// Leaves above the top node count towards the height.
TEST(Stats, LeafTipRaisesHeight) {
  Tree t = testing::sample_tree();
  t.leaves[0].position = {0, 3.0f, 0};
  t.leaves[0].length = 0.5f;
  EXPECT_NEAR(compute_stats(t).height, 3.5, 1e-6);
}

// A shrub shorter than breast height has no DBH.
TEST(Stats, NoDbhBelowBreastHeight) {
  Tree t;
  Branch b;
  b.nodes = {{{0, 0, 0}, 0.1}, {{0, 1.2, 0}, 0.05}};
  t.branches = {b};
  const TreeStats s = compute_stats(t);
  EXPECT_FALSE(s.has_dbh);
  EXPECT_NE(format_stats(s).find("dbh: n/a"), std::string::npos);
}

TEST(Stats, FormatText) {
  const std::string text = format_stats(compute_stats(testing::sample_tree()));
  EXPECT_EQ(text,
            "name: sample\n"
            "branches: 2 (level 0: 1, level 1: 1)\n"
            "nodes: 6\n"
            "leaves: 1\n"
            "needles: 1\n"
            "height: 3.000 m\n"
            "dbh: 0.342 m\n"
            "total branch length: 4.000 m\n"
            "bounds: [0.000, 0.000, 0.000] .. [1.250, 3.000, 0.020] m\n"
            "leaf area: 0.005 m2 (one-sided)\n"
            "crown projected area: 0.003 m2\n"
            "leaf area index: 1.825\n");
}

TEST(Stats, FormatJson) {
  const std::string json = format_stats_json(compute_stats(testing::sample_tree()));
  EXPECT_EQ(json.substr(0, 60), "{\"name\":\"sample\",\"branches\":2,\"branches_per_level\":[1,1],\"no");
  EXPECT_NE(json.find("\"dbh_m\":0.342000"), std::string::npos);
}

// An imported mesh adds its summary after the tree's lines (exact text); a tree without one
// prints none.
TEST(Stats, FormatSourceText) {
  Tree t = testing::sample_tree();
  t.source = testing::sample_source();
  t.source.materials[2].name = "Haze \"2\"";
  const std::string text = format_stats(compute_stats(t));
  const std::string plain = format_stats(compute_stats(testing::sample_tree()));
  ASSERT_EQ(text.substr(0, plain.size()), plain);
  EXPECT_EQ(text.substr(plain.size()),
            "source: 3 primitives, 4 triangles, 10 vertices\n"
            "source material 0: \"Bark\" (opaque)\n"
            "source material 1: \"Leaves\" (mask)\n"
            "source material 2: \"Haze \\\"2\\\"\" (blend)\n"
            "source image 0: \"bark.png\" (image/png, 13 bytes)\n"
            "source image 1: \"leaf.jpg\" (image/jpeg, 8 bytes)\n");
  EXPECT_EQ(plain.find("source"), std::string::npos);
}

TEST(Stats, FormatSourceJson) {
  Tree t = testing::sample_tree();
  t.source = testing::sample_source();
  const std::string json = format_stats_json(compute_stats(t));
  const std::string plain = format_stats_json(compute_stats(testing::sample_tree()));
  ASSERT_EQ(json.substr(0, plain.size() - 1), plain.substr(0, plain.size() - 1));
  EXPECT_EQ(json.substr(plain.size() - 1),
            ",\"source\":{\"primitives\":3,\"triangles\":4,\"vertices\":10,\"materials\":["
            "{\"name\":\"Bark\",\"alpha_mode\":\"opaque\"},{\"name\":\"Leaves\",\"alpha_mode\":\"mask\"},"
            "{\"name\":\"Haze\",\"alpha_mode\":\"blend\"}],\"images\":["
            "{\"name\":\"bark.png\",\"mime_type\":\"image/png\",\"bytes\":13},"
            "{\"name\":\"leaf.jpg\",\"mime_type\":\"image/jpeg\",\"bytes\":8}]}}");
}

}  // namespace
}  // namespace sylva::tree
