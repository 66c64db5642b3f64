// The real QSM files in the shared data (see ../shared/data/README.md). Expected values were
// computed independently of this code by tests/qsm_reference.py (Python's csv module over the
// raw tables; docs/stages/import.md, "Fixtures"): height = max z - z of the root cylinder's start
// (= max z - min z for all four files); DBH = 2 x the trunk radius at 1.3 m above the trunk
// base, interpolated between the trunk's node radii as libs/tree's stats define it (node radius
// = mean of the two cylinders meeting there); branches = 1 + children that do not continue
// their parent's branch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <ostream>

#include "libs/tree/frames.h"
#include "libs/tree/stats.h"
#include "stages/import/import_file.h"
#include "stages/import/qsm_table.h"
#include "stages/import/skeleton_text.h"
#include "tests/support/test_support.h"

namespace sylva::import {
namespace {

struct Fixture {
  const char* file;
  std::size_t cylinders;
  double readme_height;  // the README's figure (±0.1 m)
  double height;         // exact, from the raw table
  double dbh;            // m, see above
  std::uint32_t max_order;
  std::size_t branches;
  double total_length;  // m, sum of the branch polylines
};

// clang-format off
constexpr Fixture kFixtures[] = {
  {"canopyHydro_5_SmallTree.csv", 517, 15.4, 15.372684, 1.0587346782, 4, 83, 45.3693001908},
  {"canopyHydro_example_tree.csv", 9998, 11.7, 11.742155, 0.4884839950, 6, 1831, 970.490888751},
  {"rTwig_QSM.csv", 1149, 3.7, 3.701954, 0.0820740711, 4, 69, 31.4263677771},
  {"rTwig_QSM_mat_TreeQSM241_cylinders.tsv", 1136, 3.7, 3.7177071899, 0.0726623033, 5, 82, 32.9690998128},
};
// clang-format on

void PrintTo(const Fixture& f, std::ostream* os) { *os << f.file; }

class QsmFixture : public ::testing::TestWithParam<Fixture> {};

TEST_P(QsmFixture, ImportsWithExpectedShape) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  const Fixture& f = GetParam();
  const auto path = *data / "qsm" / f.file;
  const std::string bytes = test::read_file(path);

  const CylinderTable table = parse_cylinder_table(bytes, path.string());
  EXPECT_EQ(table.cylinders.size(), f.cylinders);

  const tree::Tree t = import_tree(bytes, path.string(), {});
  EXPECT_EQ(tree::validate_tree(t), std::vector<std::string>{});
  const tree::TreeStats s = tree::compute_stats(t);
  EXPECT_NEAR(s.height, f.readme_height, 0.1);
  EXPECT_NEAR(s.height, f.height, 1e-6);
  ASSERT_TRUE(s.has_dbh);
  EXPECT_NEAR(s.dbh, f.dbh, 1e-6);
  EXPECT_EQ(s.branches_per_level.size(), f.max_order + 1);
  EXPECT_EQ(s.branches, f.branches);
  EXPECT_NEAR(s.total_branch_length, f.total_length, 1e-6);
  EXPECT_EQ(s.branches_per_level[0], 1u);  // one trunk

  // Parents first, no empty branch, radii > 0, frames finite.
  for (std::size_t i = 0; i < t.branches.size(); ++i) {
    EXPECT_LT(t.branches[i].parent, static_cast<std::int32_t>(i));
    for (const auto& n : t.branches[i].nodes) ASSERT_GT(n.radius, 0);
  }
  for (const auto& frames : tree::compute_tree_frames(t))
    for (const auto& fr : frames) ASSERT_TRUE(tree::is_finite(fr.t) && tree::is_finite(fr.n));
  // An imported tree survives the text skeleton exactly.
  EXPECT_EQ(parse_skeleton_text(format_skeleton_text(t), "rt.skel").branches, t.branches);
  // Recentred: the trunk starts at the origin and the tree grows up +Y.
  EXPECT_EQ(t.branches[0].nodes[0].position, (tree::Vec3{0, 0, 0}));
  EXPECT_GT(s.bounds_max.y, 0.9 * s.height);
}

INSTANTIATE_TEST_SUITE_P(Files, QsmFixture, ::testing::ValuesIn(kFixtures), [](const auto& param_info) {
  std::string n = param_info.param.file;
  n = n.substr(0, n.find('.'));
  std::replace_if(
      n.begin(), n.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return n;
});

// rTwig ships the same Kentucky coffee tree as a SimpleForest CSV and as a TreeQSM model: two
// reconstructions of one point cloud, so they agree closely but not exactly. Height within
// 2 cm (measured: 1.6 cm) and total branch length within 6 % (measured: 4.9 %; TreeQSM fills
// gaps with extra cylinders and segments differently).
TEST(QsmFixtures, RTwigCsvAndTreeQsmAgree) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  auto stats = [&](const char* name) {
    const auto path = *data / "qsm" / name;
    return tree::compute_stats(import_tree(test::read_file(path), path.string(), {}));
  };
  const tree::TreeStats csv = stats("rTwig_QSM.csv");
  const tree::TreeStats tsv = stats("rTwig_QSM_mat_TreeQSM241_cylinders.tsv");
  EXPECT_NEAR(csv.height, tsv.height, 0.02);
  EXPECT_NEAR(csv.total_branch_length / tsv.total_branch_length, 1.0, 0.06);
}

// Variant detection on the real headers.
TEST(QsmFixtures, VariantsDetected) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  auto variant = [&](const char* name) {
    const auto path = *data / "qsm" / name;
    return parse_cylinder_table(test::read_file(path), path.string()).variant;
  };
  EXPECT_EQ(variant("canopyHydro_5_SmallTree.csv"), "simpleforest");
  EXPECT_EQ(variant("rTwig_QSM.csv"), "simpleforest");
  EXPECT_EQ(variant("rTwig_QSM_mat_TreeQSM241_cylinders.tsv"), "treeqsm");
}

// The same TreeQSM table without its header, read as headerless TreeQSM text (default column
// order), gives the same tree.
TEST(QsmFixtures, HeaderlessTreeQsmMatchesHeader) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  const auto path = *data / "qsm" / "rTwig_QSM_mat_TreeQSM241_cylinders.tsv";
  const std::string bytes = test::read_file(path);
  // Drop the comment and the header line.
  std::size_t at = bytes.find('\n');
  at = bytes.find('\n', at + 1);
  const std::string headerless = bytes.substr(at + 1);
  ImportOptions opt;
  opt.format = "treeqsm_txt";
  const tree::Tree a = import_tree(bytes, "with_header.tsv", {});
  const tree::Tree b = import_tree(headerless, "headerless.txt", opt);
  EXPECT_EQ(a.branches, b.branches);
}

}  // namespace
}  // namespace sylva::import
