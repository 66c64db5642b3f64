#include "libs/tree/tree.h"

#include <gtest/gtest.h>

#include <limits>

#include "libs/tree/tests/sample_tree.h"

namespace sylva::tree {
namespace {

using testing::sample_tree;

TEST(Tree, SampleIsValid) { EXPECT_TRUE(validate_tree(sample_tree()).empty()); }

// Each broken invariant is reported with the element it concerns.
TEST(Tree, ValidateMessages) {
  auto first_error = [](const Tree& t) {
    auto e = validate_tree(t);
    return e.empty() ? std::string() : e.front();
  };
  Tree t = sample_tree();
  t.branches[1].level = 3;
  EXPECT_EQ(first_error(t), "branch 1: level 3 must be the parent's level 0 or one more");
  t = sample_tree();
  t.branches[1].nodes.resize(1);
  EXPECT_EQ(first_error(t), "branch 1: has 1 nodes, needs at least 2");
  t = sample_tree();
  t.branches[1].parent_node = 3;
  t.branches[1].parent_t = 0.5;
  EXPECT_EQ(first_error(t), "branch 1: parent_t must be 0 at the parent's last node");
  t = sample_tree();
  t.leaves[0].variant = 4;
  EXPECT_EQ(first_error(t), "leaf 0: variant 4 is not a cell of the 2x2 leaf atlas");
  t = sample_tree();
  t.leaves[0].normal = {0, 1, 0};
  EXPECT_EQ(first_error(t), "leaf 0: direction and normal must be orthogonal unit vectors");
  t = sample_tree();
  t.needles[0].branch = 7;
  EXPECT_EQ(first_error(t), "needle 0: branch 7 does not exist");
  t = sample_tree();
  t.materials.bark_color.g = 2;
  EXPECT_EQ(first_error(t), "materials: bark colour components must be in [0, 1]");
  t = sample_tree();
  t.materials.leaf_color.b = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(first_error(t), "materials: leaf colour components must be in [0, 1]");
}

TEST(Tree, AttachmentPointAndClone) {
  Tree t = sample_tree();
  EXPECT_EQ(attachment_point(t, t.branches[1]), (Vec3{0, 2, 0}));
  t.branches[1].parent_node = 0;
  t.branches[1].parent_t = 0.25;
  EXPECT_EQ(attachment_point(t, t.branches[1]), (Vec3{0, 0.25, 0}));
  EXPECT_FALSE(is_clone(t, t.branches[1]));
  t.branches[1].level = 0;
  EXPECT_TRUE(is_clone(t, t.branches[1]));
}

}  // namespace
}  // namespace sylva::tree
