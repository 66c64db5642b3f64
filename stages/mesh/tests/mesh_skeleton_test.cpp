// Tree -> meshing skeleton: rings, attachments, virtual rings, clearance, bad input.
#include "stages/mesh/mesh_skeleton.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "stages/mesh/tests/test_trees.h"

namespace sylva::mesh {
namespace {

using test::branch;

// One ring per node; frames orthonormal with t along the branch; v grows by length/(2 pi r).
TEST(MeshSkeleton, StraightTrunkHasOneRingPerNode) {
  const MeshSkeleton sk = build_skeleton(test::straight_trunk(4), {});
  ASSERT_EQ(sk.branches.size(), 1u);
  ASSERT_EQ(sk.branches[0].rings.size(), 4u);
  for (const Ring& r : sk.branches[0].rings) {
    EXPECT_NEAR(r.frame.t.y, 1, 1e-12);
    EXPECT_NEAR(tree::dot(r.frame.n, r.frame.t), 0, 1e-12);
    EXPECT_NEAR(tree::length(tree::cross(r.frame.t, r.frame.n) - r.frame.b), 0, 1e-12);
    EXPECT_DOUBLE_EQ(r.radius, 0.1);
  }
  // r = r0 everywhere: one v unit per trunk circumference.
  EXPECT_NEAR(sk.branches[0].rings[3].v, 3 / (2 * std::numbers::pi * 0.1), 1e-12);
  EXPECT_EQ(sk.ring_count(), 4u);
}

// A child hanging in the middle of a segment gets a virtual ring in its parent; near a node it
// snaps to the node (Nystad's 10 % rule). (Children as thick as the continuation: they go on
// top of the ring, so the junction collapse below leaves the rings alone.)
TEST(MeshSkeleton, MidSegmentAttachmentInsertsAVirtualRing) {
  tree::Tree t = test::straight_trunk(3);
  t.branches.push_back(branch({{0.3, 0.7, 0}, {1.0, 1.2, 0}}, 0.1, 0, 0, 0, 0.5));
  t.branches.push_back(branch({{0, 1.3, 0.3}, {0, 1.8, 1.2}}, 0.1, 0, 0, 0, 0.97));
  const MeshSkeleton sk = build_skeleton(t, {});
  ASSERT_EQ(sk.branches.size(), 3u);
  EXPECT_EQ(sk.stats.virtual_rings, 1u);
  EXPECT_EQ(sk.stats.collapsed_junctions, 0u);
  ASSERT_EQ(sk.branches[0].rings.size(), 4u);
  EXPECT_NEAR(sk.branches[0].rings[1].center.y, 0.5, 1e-12);
  EXPECT_EQ(sk.branches[1].parent_ring, 1u);  // the virtual ring
  EXPECT_EQ(sk.branches[2].parent_ring, 2u);  // snapped to node 1 (ring 2 after the insert)
  EXPECT_EQ(sk.children[0][1], (std::vector<std::uint32_t>{1}));
  EXPECT_EQ(sk.children[0][2], (std::vector<std::uint32_t>{2}));
}

// Junction collapse: a lateral hangs from the generator's prepended node, so its joint box runs
// from the prepended to the appended node, centred on it; the junction ring goes.
TEST(MeshSkeleton, LateralJunctionCollapsesOntoThePrependedRing) {
  tree::Tree t;
  t.branches.push_back(branch({{0, 0, 0}, {0, 0.96, 0}, {0, 1, 0}, {0, 1.04, 0}, {0, 2, 0}}, 0.1));
  t.branches.push_back(branch({{0.2, 1, 0}, {1, 1.3, 0}}, 0.04, 0, 2, 1));
  const MeshSkeleton sk = build_skeleton(t, {});
  EXPECT_EQ(sk.stats.collapsed_junctions, 1u);
  ASSERT_EQ(sk.branches[0].rings.size(), 4u);
  EXPECT_EQ(sk.branches[1].parent_ring, 1u);
  EXPECT_NEAR(sk.branches[0].rings[1].center.y, 0.96, 1e-12);
  EXPECT_NEAR(sk.branches[0].rings[2].center.y, 1.04, 1e-12);
}

// Rings microns apart (the generator's intermediate nodes next to a tapered tip) merge.
TEST(MeshSkeleton, NearlyCoincidentRingsMerge) {
  tree::Tree t = test::straight_trunk(3);
  t.branches[0].nodes.insert(t.branches[0].nodes.begin() + 2, tree::Node{{0, 1.000001, 0}, 0.1});
  const MeshSkeleton sk = build_skeleton(t, {});
  EXPECT_EQ(sk.stats.merged_rings, 1u);
  EXPECT_EQ(sk.branches[0].rings.size(), 3u);
}

// max_level leaves deeper branches out, and with them everything that grows from them.
TEST(MeshSkeleton, MaxLevelLeavesDeeperBranchesOut) {
  tree::Tree t = test::straight_trunk(3);
  t.branches.push_back(branch({{0.5, 1, 0}, {1.5, 1.2, 0}}, 0.03, 0, 1, 1));
  t.branches.push_back(branch({{1.5, 1.3, 0.1}, {1.6, 1.6, 0.5}}, 0.01, 1, 1, 2));
  SkeletonOptions o;
  o.max_level = 1;
  EXPECT_EQ(build_skeleton(t, o).branches.size(), 2u);
  o.max_level = 0;
  EXPECT_EQ(build_skeleton(t, o).branches.size(), 1u);
  o.max_level = -1;
  EXPECT_EQ(build_skeleton(t, o).branches.size(), 3u);
}

// Zero radii (a tapered tip) are meshed at min_radius; the source radius is kept for ordering.
TEST(MeshSkeleton, ZeroRadiiAreClampedToMinRadius) {
  tree::Tree t = test::straight_trunk(3);
  t.branches[0].nodes[2].radius = 0;
  SkeletonOptions o;
  o.min_radius = 0.002;
  const MeshSkeleton sk = build_skeleton(t, o);
  EXPECT_EQ(sk.stats.clamped_radii, 1u);
  EXPECT_DOUBLE_EQ(sk.branches[0].rings[2].radius, 0.002);
  EXPECT_DOUBLE_EQ(sk.branches[0].rings[2].source_radius, 0);
}

// A QSM-style child that starts on its parent's axis: rings inside the joint box are dropped
// and the first kept ring is moved along the child to where it leaves the box face.
TEST(MeshSkeleton, ChildStartingInsideItsParentIsCutAtTheBoxFace) {
  tree::Tree t = test::straight_trunk(3);
  // Along +X from the axis at y = 1: nodes at x = 0, 0.05, 0.3, 0.8.
  t.branches.push_back(branch({{0, 1, 0}, {0.05, 1, 0}, {0.3, 1, 0}, {0.8, 1, 0}}, 0.02, 0, 1, 1));
  SkeletonOptions o;
  o.corner_scale = 1.0;
  const MeshSkeleton sk = build_skeleton(t, o);
  ASSERT_EQ(sk.branches.size(), 2u);
  EXPECT_EQ(sk.stats.dropped_rings, 1u);
  EXPECT_EQ(sk.stats.pushed_rings, 1u);
  const auto& rings = sk.branches[1].rings;
  ASSERT_EQ(rings.size(), 3u);
  // The trunk's frame has n = +X, so a box face looks along +X, at sqrt(2)/2 * 0.1 from the
  // axis; the ring must lie a quarter of its own corner distance beyond it.
  const double required = std::numbers::sqrt2 / 2 * 0.1 + 0.25 * 0.02;
  EXPECT_NEAR(rings[0].center.x, required, 1e-9);
  EXPECT_NEAR(rings[0].center.y, 1, 1e-12);  // moved along the child, which runs along +X
  EXPECT_NEAR(rings[0].frame.t.x, 1, 1e-9);
}

// A child entirely inside its parent is not meshed; its own children hang from its attachment.
TEST(MeshSkeleton, ChildEntirelyInsideIsDroppedAndItsChildrenReattached) {
  tree::Tree t = test::straight_trunk(3);
  t.branches.push_back(branch({{0.01, 1, 0}, {0.03, 1.05, 0}}, 0.01, 0, 1, 1));
  t.branches.push_back(branch({{0.3, 1.1, 0}, {0.8, 1.3, 0}}, 0.005, 1, 1, 2));
  const MeshSkeleton sk = build_skeleton(t, {});
  EXPECT_EQ(sk.stats.dropped_branches, 1u);
  ASSERT_EQ(sk.branches.size(), 2u);
  EXPECT_EQ(sk.branches[1].source, 2u);
  EXPECT_EQ(sk.branches[1].parent, 0);
  EXPECT_EQ(sk.branches[1].parent_ring, 0u);  // the dropped child's ring, collapsed onto ring 0
}

// Bad input: a clear MeshError naming the problem, never a crash.
TEST(MeshSkeleton, BadInputIsAClearError) {
  EXPECT_THROW(
      {
        try {
          build_skeleton(tree::Tree{}, {});
        } catch (const MeshError& e) {
          EXPECT_STREQ(e.what(), "the tree has no branches: nothing to mesh");
          throw;
        }
      },
      MeshError);
  tree::Tree one = test::straight_trunk(2);
  one.branches[0].nodes.pop_back();  // a branch with one node
  try {
    build_skeleton(one, {});
    FAIL() << "expected MeshError";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("invalid tree: branch 0"), std::string::npos) << e.what();
  }
  tree::Tree nan = test::straight_trunk(2);
  nan.branches[0].nodes[1].position.x = std::nan("");
  EXPECT_THROW(build_skeleton(nan, {}), MeshError);
}

}  // namespace
}  // namespace sylva::mesh
