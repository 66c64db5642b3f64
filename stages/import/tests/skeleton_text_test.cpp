#include "stages/import/skeleton_text.h"

#include <gtest/gtest.h>

#include "stages/import/import_error.h"

namespace sylva::import {
namespace {

using tree::Vec3;

std::string error_of(std::string_view text) {
  try {
    parse_skeleton_text(text, "s.skel");
  } catch (const ImportError& e) {
    return e.what();
  }
  return "";
}

// The example of docs/formats-skeleton.md: a trunk and one lateral with defaults.
constexpr std::string_view kExample =
    "# a trunk and one branch\n"
    "0 -1  0 0   0  0.20\n"
    "0 -1  0 1   0  0.16   # node 1\n"
    "0 -1  0 2.5 0  0.12\n"
    "\n"
    "1  0  0   1.1 0 0.05\n"
    "1  0  0.6 1.6 0 0.02\n";

TEST(SkeletonText, ParsesExampleWithDefaults) {
  const tree::Tree t = parse_skeleton_text(kExample, "s.skel");
  ASSERT_EQ(t.branches.size(), 2u);
  EXPECT_EQ(t.branches[0].parent, -1);
  EXPECT_EQ(t.branches[0].nodes.size(), 3u);
  EXPECT_EQ(t.branches[0].nodes[2].position, (Vec3{0, 2.5, 0}));
  EXPECT_EQ(t.branches[0].nodes[2].radius, 0.12);
  const tree::Branch& b = t.branches[1];
  EXPECT_EQ(b.parent, 0);
  EXPECT_EQ(b.parent_node, 1u);  // nearest trunk node to (0, 1.1, 0)
  EXPECT_EQ(b.parent_t, 0.0);
  EXPECT_EQ(b.level, 1u);
  EXPECT_EQ(tree::validate_tree(t), std::vector<std::string>{});
}

// Explicit attachment fields, ids that are not indices, and a child written before its
// parent (it is moved after it; otherwise file order is kept).
TEST(SkeletonText, ExplicitFieldsAndReordering) {
  const tree::Tree t = parse_skeleton_text(
      "7 3 1 1 0 0.1 0 0.5 1\n"
      "7 3 2 1 0 0.05\n"
      "3 -1 0 0 0 0.3\n"
      "3 -1 0 2 0 0.2\n"
      "9 3 0 2 0 0.1 1 0 0\n"
      "9 3 0 3 0 0.1\n",
      "s.skel");
  ASSERT_EQ(t.branches.size(), 3u);
  EXPECT_EQ(t.branches[0].nodes[0].position, (Vec3{0, 0, 0}));  // branch 3
  EXPECT_EQ(t.branches[1].nodes[0].position, (Vec3{1, 1, 0}));  // branch 7
  EXPECT_EQ(t.branches[1].parent, 0);
  EXPECT_EQ(t.branches[1].parent_t, 0.5);
  EXPECT_EQ(t.branches[2].level, 0u);  // branch 9: a clone
  EXPECT_EQ(t.branches[2].parent_node, 1u);
  EXPECT_EQ(tree::validate_tree(t), std::vector<std::string>{});
}

// format -> parse gives the same branches bit for bit, including awkward doubles.
TEST(SkeletonText, RoundTrip) {
  tree::Tree t;
  tree::Branch trunk;
  trunk.nodes = {{{0.1, 0, -0.0}, 0.3}, {{1.0 / 3.0, 2.000000000000001, 1e-300}, 0.2}, {{0, 5, 0}, 0}};
  tree::Branch lat;
  lat.parent = 0;
  lat.parent_node = 1;
  lat.parent_t = 0.123456789012345678;
  lat.level = 1;
  lat.nodes = {{{0.5, 2.2, 0}, 0.05}, {{1.5, 2.7, 0.25}, 0.01}};
  tree::Branch clone = lat;
  clone.level = 0;
  clone.parent_node = 2;
  clone.parent_t = 0;
  t.branches = {trunk, lat, clone};
  ASSERT_EQ(tree::validate_tree(t), std::vector<std::string>{});
  const std::string text = format_skeleton_text(t);
  const tree::Tree back = parse_skeleton_text(text, "rt.skel");
  EXPECT_EQ(back.branches, t.branches);
  EXPECT_EQ(format_skeleton_text(back), text);
}

TEST(SkeletonText, Errors) {
  EXPECT_EQ(error_of(""), "s.skel:1: empty skeleton: no node lines");
  EXPECT_EQ(error_of("# nothing\n\n"), "s.skel:2: empty skeleton: no node lines");
  EXPECT_EQ(error_of("0 -1 0 0 0\n"),
            "s.skel:1: expected 6 to 9 fields (branch parent x y z radius [parent_node "
            "[parent_t [level]]]), got 5");
  EXPECT_EQ(error_of("0 -1 0 nan 0 0.1\n"), "s.skel:1: field 4 (y): not a finite number: 'nan'");
  EXPECT_EQ(error_of("0 -1 0 0 0 -0.1\n"), "s.skel:1: field 6 (radius): radius must be >= 0, got -0.1");
  // Issue 15 item 12: finite but absurd values are refused here, not by a later stage.
  EXPECT_EQ(error_of("0 -1 0 0 0 1e308\n"),
            "s.skel:1: field 6 (radius): radius 1e+308 m is larger than 100 m");
  EXPECT_EQ(error_of("0 -1 0 -1.7e308 0 0.1\n"),
            "s.skel:1: field 4 (y): coordinate -1.7e+308 m is farther than 100000 m from the origin");
  EXPECT_EQ(error_of("a -1 0 0 0 0.1\n"), "s.skel:1: field 1 (branch): expected an integer >= 0, got 'a'");
  EXPECT_EQ(error_of("0 -2 0 0 0 0.1\n"), "s.skel:1: field 2 (parent): expected an integer >= -1, got '-2'");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1\n0 -1 0 2 0 0.1\n"),
            "s.skel:4: branch 0 continues here after other branches; a branch's lines must be "
            "consecutive (it started on line 1)");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 2 0 1 0 0.1\n"),
            "s.skel:2: field 2 (parent): parent 2 here but -1 on the branch's first line (line 1)");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n"), "s.skel:1: branch 0 has 1 node; a branch needs at least 2");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 5 0 1 0 0.1\n1 5 0 2 0 0.1\n"),
            "s.skel:3: field 2 (parent): parent branch 5 is not in this file");
  EXPECT_EQ(error_of("1 2 0 0 0 0.1\n1 2 0 1 0 0.1\n2 1 0 1 0 0.1\n2 1 0 2 0 0.1\n"),
            "s.skel:1: field 2 (parent): branch 1 is in a parent cycle: 1 -> 2 -> 1");
  EXPECT_EQ(error_of("1 1 0 0 0 0.1\n"), "s.skel:1: field 2 (parent): branch 1 is its own parent");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1 0\n"),
            "s.skel:1: field 7 (parent_node): a root branch (parent -1) has no attachment fields");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1 2\n1 0 0 2 0 0.1\n"),
            "s.skel:3: field 7 (parent_node): node 2 is out of range (parent branch 0 has 2 nodes)");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1 1 0.5\n1 0 0 2 0 0.1\n"),
            "s.skel:3: field 8 (parent_t): must be 0 at the parent's last node (node 1)");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1 1 1.5\n"),
            "s.skel:3: field 8 (parent_t): must be in [0, 1], got 1.5");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1 1 0 2\n1 0 0 2 0 0.1\n"),
            "s.skel:3: field 9 (level): level 2 must be the parent's level (0) or one more");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1 1\n1 0 0 2 0 0.1 0\n"),
            "s.skel:4: field 7 (parent_node): 0 here but 1 on the branch's first line (line 3)");
  EXPECT_EQ(error_of("0 -1 0 0 0 0.1\n0 -1 0 1 0 0.1\n1 0 0 1 0 0.1\n1 0 0 2 0 0.1 0\n"),
            "s.skel:4: field 7 (parent_node): attachment fields go on the branch's first line (line 3)");
}

}  // namespace
}  // namespace sylva::import
