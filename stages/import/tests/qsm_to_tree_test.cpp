#include "stages/import/qsm_to_tree.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libs/tree/frames.h"
#include "stages/import/import_error.h"

namespace sylva::import {
namespace {

using tree::Vec3;

tree::Tree build(std::string_view text, const QsmToTreeOptions& options = {}) {
  return qsm_to_tree(parse_cylinder_table(text, "t.csv"), "t.csv", options);
}

// The ImportError message building the tree from `text` gives ("(no error)" when it builds).
std::string error_of(std::string_view text) {
  try {
    build(text);
  } catch (const ImportError& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_valid(const tree::Tree& t) {
  EXPECT_EQ(tree::validate_tree(t), std::vector<std::string>{});
  for (const auto& frames : tree::compute_tree_frames(t))
    for (const auto& f : frames) {
      ASSERT_TRUE(tree::is_finite(f.t) && tree::is_finite(f.n) && tree::is_finite(f.b));
      EXPECT_NEAR(tree::length(f.t), 1, 1e-9);
    }
}

constexpr std::string_view kHead =
    "ID, parentID, startX, startY, startZ, endX, endY, endZ, radius, branchOrder, branchID\n";

// One vertical cylinder from (1, 2, 3) to (1, 2, 5), Z up: sylva's Y is the file's Z and
// sylva's Z is minus the file's Y. Without recentring the coordinates are kept.
TEST(QsmToTree, ZUpToYUp) {
  QsmToTreeOptions opt;
  opt.recenter = false;
  const tree::Tree t = build(std::string(kHead) +
                                 "0, -1, 1, 2, 3, 1, 2, 5, 0.1, 0, 0\n"
                                 "1, 0, 1, 2, 5, 4, 2, 5, 0.05, 0, 0\n",
                             opt);
  ASSERT_EQ(t.branches.size(), 1u);
  const auto& n = t.branches[0].nodes;
  ASSERT_EQ(n.size(), 3u);
  EXPECT_EQ(n[0].position, (Vec3{1, 3, -2}));
  EXPECT_EQ(n[1].position, (Vec3{1, 5, -2}));
  EXPECT_EQ(n[2].position, (Vec3{4, 5, -2}));
  // The conversion is a rotation (right-handed stays right-handed): x_qsm × y_qsm = z_qsm
  // maps to (1,0,0) × (0,0,-1) = (0,1,0).
  EXPECT_EQ(tree::cross(Vec3{1, 0, 0}, Vec3{0, 0, -1}), (Vec3{0, 1, 0}));
  expect_valid(t);
}

// Issue 15 item 12: finite values that would break every later stage are refused at their line.
TEST(QsmToTree, ValuesBeyondATreesRangeAreRefused) {
  auto error = [](std::string_view text, const QsmToTreeOptions& opt) {
    try {
      build(text, opt);
    } catch (const ImportError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  QsmToTreeOptions opt;
  EXPECT_EQ(error(std::string(kHead) + "0, -1, 0, 0, 0, 0, 0, 1, 1e308, 0, 0\n", opt),
            "t.csv:2: cylinder 0: radius 1e+308 m is larger than 100 m: check the scale parameter");
  EXPECT_EQ(error(std::string(kHead) +
                      "0, -1, 0, 0, 0, 0, 0, 1, 0.1, 0, 0\n1, 0, 0, 0, 1, 1.7e300, 0, 1, 0.1, 0, 0\n",
                  opt),
            "t.csv:3: cylinder 1: a point lies 1.7e+300 m from the root (at most 100000 m): check the scale "
            "parameter");
  opt.recenter = false;  // a georeferenced table (UTM northing) without recentring
  EXPECT_EQ(error(std::string(kHead) + "0, -1, 500000, 5300000, 0, 500000, 5300000, 1, 0.1, 0, 0\n", opt),
            "t.csv:2: cylinder 0: a point lies 5300000 m from the origin (at most 100000 m): check the scale "
            "parameter or set recenter: true");
  opt.recenter = true;  // the same tree recentred is fine
  EXPECT_NO_THROW(
      build(std::string(kHead) + "0, -1, 500000, 5300000, 0, 500000, 5300000, 1, 0.1, 0, 0\n", opt));
}

// Recentring puts the root cylinder's start at the origin; scale converts units.
TEST(QsmToTree, RecenterAndScale) {
  QsmToTreeOptions opt;
  opt.scale = 0.001;  // millimetres
  const tree::Tree t =
      build(std::string(kHead) + "0, -1, 1000, 2000, 3000, 1000, 2000, 5000, 100, 0, 0\n", opt);
  const auto& n = t.branches[0].nodes;
  EXPECT_EQ(n[0].position, (Vec3{0, 0, 0}));
  EXPECT_NEAR(n[1].position.y, 2.0, 1e-12);
  EXPECT_NEAR(n[0].radius, 0.1, 1e-15);
}

// Y-up files are taken as they are.
TEST(QsmToTree, YUpKept) {
  QsmToTreeOptions opt;
  opt.up = UpAxis::kY;
  opt.recenter = false;
  const tree::Tree t = build(std::string(kHead) + "0, -1, 1, 2, 3, 1, 4, 3, 0.1, 0, 0\n", opt);
  EXPECT_EQ(t.branches[0].nodes[1].position, (Vec3{1, 4, 3}));
}

// A fork: the same-order child continues the stem, the order+1 child starts a lateral at the
// node where its parent cylinder ends; radii of inner nodes are the mean of the two cylinders.
TEST(QsmToTree, ForkSplitsIntoBranches) {
  const tree::Tree t = build(std::string(kHead) +
                             "0, -1, 0, 0, 0, 0, 0, 1, 0.3, 0, 0\n"
                             "1, 0, 0, 0, 1, 0, 0, 2, 0.2, 0, 0\n"
                             "2, 0, 0, 0, 1, 1, 0, 1, 0.1, 1, 1\n"
                             "3, 2, 1, 0, 1, 2, 0, 1, 0.05, 1, 1\n");
  ASSERT_EQ(t.branches.size(), 2u);
  const tree::Branch& stem = t.branches[0];
  const tree::Branch& lat = t.branches[1];
  ASSERT_EQ(stem.nodes.size(), 3u);
  EXPECT_DOUBLE_EQ(stem.nodes[0].radius, 0.3);
  EXPECT_DOUBLE_EQ(stem.nodes[1].radius, 0.25);
  EXPECT_DOUBLE_EQ(stem.nodes[2].radius, 0.2);
  EXPECT_EQ(lat.parent, 0);
  EXPECT_EQ(lat.parent_node, 1u);
  EXPECT_EQ(lat.parent_t, 0.0);
  EXPECT_EQ(lat.level, 1u);
  ASSERT_EQ(lat.nodes.size(), 3u);
  EXPECT_EQ(lat.nodes[2].position, (Vec3{2, 1, 0}));
  expect_valid(t);
}

// TreeQSM children start on the parent cylinder's surface, part-way along it: the attachment
// is the nearest point of the parent's axis (parent_t in (0, 1)).
TEST(QsmToTree, MidCylinderAttachment) {
  const tree::Tree t = build(
      "radius,length,start_x,start_y,start_z,axis_x,axis_y,axis_z,parent,branch,BranchOrder\n"
      "0.3,4,0,0,0,0,0,1,0,1,0\n"
      "0.1,1,0.3,0,1,1,0,0,1,2,1\n");
  ASSERT_EQ(t.branches.size(), 2u);
  EXPECT_EQ(t.branches[1].parent_node, 0u);
  EXPECT_DOUBLE_EQ(t.branches[1].parent_t, 0.25);
  expect_valid(t);
}

// Without branch or order columns the thickest child continues; ties go to the earlier row;
// laterals get the parent's level + 1.
TEST(QsmToTree, ThickestChildContinuesWithoutKeys) {
  const tree::Tree t = build(
      "id,parent,startx,starty,startz,endx,endy,endz,radius\n"
      "1,0,0,0,0,0,0,1,0.3\n"
      "2,1,0,0,1,1,0,2,0.1\n"
      "3,1,0,0,1,0,0,2,0.2\n"
      "4,1,0,0,1,-1,0,2,0.2\n");
  ASSERT_EQ(t.branches.size(), 3u);
  EXPECT_EQ(t.branches[0].nodes.back().position, (Vec3{0, 2, 0}));  // row 3 continued
  EXPECT_EQ(t.branches[1].nodes.back().position, (Vec3{1, 2, 0}));  // then row 2, row 4
  EXPECT_EQ(t.branches[2].nodes.back().position, (Vec3{-1, 2, 0}));
  EXPECT_EQ(t.branches[1].level, 1u);
  EXPECT_EQ(t.branches[2].level, 1u);
}

// Two same-order children at a fork: the thicker continues, the other is a clone (same level).
TEST(QsmToTree, SameOrderSiblingBecomesClone) {
  const tree::Tree t = build(std::string(kHead) +
                             "0, -1, 0, 0, 0, 0, 0, 1, 0.3, 0, 0\n"
                             "1, 0, 0, 0, 1, 1, 0, 2, 0.1, 0, 0\n"
                             "2, 0, 0, 0, 1, -1, 0, 2, 0.2, 0, 0\n");
  ASSERT_EQ(t.branches.size(), 2u);
  EXPECT_EQ(t.branches[0].nodes.back().position, (Vec3{-1, 2, 0}));
  EXPECT_EQ(t.branches[1].level, 0u);
  EXPECT_TRUE(tree::is_clone(t, t.branches[1]));
  expect_valid(t);
}

// A zero-length cylinder inside a branch adds no node; its child attaches where it sits.
TEST(QsmToTree, ZeroLengthCylinderMerged) {
  const tree::Tree t = build(std::string(kHead) +
                             "0, -1, 0, 0, 0, 0, 0, 1, 0.3, 0, 0\n"
                             "1, 0, 0, 0, 1, 0, 0, 1, 0.25, 0, 0\n"
                             "2, 1, 0, 0, 1, 0, 0, 2, 0.2, 0, 0\n"
                             "3, 1, 0, 0, 1, 1, 0, 1, 0.1, 1, 1\n");
  ASSERT_EQ(t.branches.size(), 2u);
  EXPECT_EQ(t.branches[0].nodes.size(), 3u);
  EXPECT_EQ(t.branches[1].parent_node, 1u);
  expect_valid(t);
}

TEST(QsmToTree, ErrorZeroLengthBranch) {
  EXPECT_EQ(error_of(std::string(kHead) + "0, -1, 0, 0, 0, 0, 0, 0, 0.3, 0, 0\n"),
            "t.csv:2: cylinder 0 starts a branch of zero length (every cylinder of it has "
            "its end at its start)");
}

TEST(QsmToTree, ErrorOrderJump) {
  EXPECT_EQ(error_of(std::string(kHead) + "0, -1, 0, 0, 0, 0, 0, 1, 0.3, 0, 0\n"
                                          "1, 0, 0, 0, 1, 1, 0, 1, 0.1, 2, 1\n"),
            "t.csv:3: cylinder 1 starts a branch of order 2 on a branch of order 0; a child "
            "branch has its parent's order or one more");
}

// Levels count from the root's order, so a table whose stem is order 1 still gives level 0.
TEST(QsmToTree, LevelsRelativeToRootOrder) {
  const tree::Tree t = build(std::string(kHead) +
                             "0, -1, 0, 0, 0, 0, 0, 1, 0.3, 1, 0\n"
                             "1, 0, 0, 0, 1, 1, 0, 1, 0.1, 2, 1\n");
  EXPECT_EQ(t.branches[0].level, 0u);
  EXPECT_EQ(t.branches[1].level, 1u);
}

}  // namespace
}  // namespace sylva::import
