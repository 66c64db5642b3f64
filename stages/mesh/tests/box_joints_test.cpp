// The box joints of Appendix D on tiny hand-built trees, one scenario per test: every result is a
// closed, consistently oriented 2-manifold quad mesh (checked with OpenMesh), genus 0, with the
// vertex count the construction promises.
#include "stages/mesh/box_joints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "stages/mesh/tests/test_trees.h"
#include "stages/mesh/topology_check.h"

namespace sylva::mesh {
namespace {

using test::branch;

struct Built {
  MeshSkeleton skeleton;
  QuadMesh mesh;
  JointStats joints;
  TopologyReport topo;
};

Built build(const tree::Tree& t, BarkOptions o = {}) {
  Built b;
  SkeletonOptions so;
  so.corner_scale = o.corner_scale;
  b.skeleton = build_skeleton(t, so);
  b.mesh = build_bark_mesh(b.skeleton, o, &b.joints);
  b.topo = check_topology(b.mesh);
  // The half-edge check agrees with OpenMesh.
  const TopologyReport fast = check_topology_fast(b.mesh);
  EXPECT_EQ(fast.refused_faces, b.topo.refused_faces);
  EXPECT_EQ(fast.boundary_edges, b.topo.boundary_edges);
  EXPECT_EQ(fast.euler, b.topo.euler);
  return b;
}

// Closed genus-0 quad meshes have F = V - 2 per component (Euler: V - 2F + F = 2); vertices are
// 4 per ring plus 4 per crotch, inset and backward box.
void expect_closed_sphere(const Built& b) {
  EXPECT_TRUE(b.topo.manifold_and_oriented()) << b.topo.refused_faces << " quads refused";
  EXPECT_TRUE(b.topo.closed()) << b.topo.boundary_edges << " boundary edges";
  EXPECT_EQ(b.topo.components, b.joints.components);
  EXPECT_EQ(b.topo.euler, 2 * static_cast<long long>(b.topo.components));
  EXPECT_EQ(b.mesh.quads.size(), b.mesh.positions.size() - 2 * b.topo.components);
  EXPECT_EQ(b.mesh.positions.size(), 4 * (b.skeleton.ring_count() + b.joints.split_joints + b.joints.insets +
                                          b.joints.backward_fallbacks));
  EXPECT_GT(b.topo.signed_volume, 0) << "faces point inwards";
  EXPECT_EQ(b.mesh.uvs.size(), b.mesh.quads.size());
}

// A straight trunk: a closed square prism, 4 vertices per ring, 4 quads per segment + 2 caps.
TEST(BoxJoints, StraightTrunkIsAClosedPrism) {
  const Built b = build(test::straight_trunk(4));
  expect_closed_sphere(b);
  EXPECT_EQ(b.mesh.positions.size(), 16u);
  EXPECT_EQ(b.mesh.quads.size(), 14u);
  EXPECT_EQ(b.joints.tip_caps, 1u);
  EXPECT_EQ(b.joints.base_caps, 1u);
  // Corner distance r (corner_scale 1): a square of area 2 r^2, 3 m long.
  EXPECT_NEAR(b.topo.signed_volume, 2 * 0.1 * 0.1 * 3, 1e-12);
}

// open_base leaves the first ring open: one boundary loop of 4 edges, nothing else.
TEST(BoxJoints, OpenBaseLeavesOneLoop) {
  BarkOptions o;
  o.open_base = true;
  const Built b = build(test::straight_trunk(4), o);
  EXPECT_TRUE(b.topo.manifold_and_oriented());
  EXPECT_EQ(b.topo.boundary_edges, 4u);
  EXPECT_EQ(b.mesh.quads.size(), 13u);
  EXPECT_EQ(b.joints.base_caps, 0u);
}

// One lateral child: an ordinary joint; the side of the box facing the child is bridged. As the
// generator does (Nystad §4.2.2), rings sit just before and after the attachment, so the box is
// about one child diameter tall.
TEST(BoxJoints, OneLateralIsAnOrdinaryJoint) {
  tree::Tree t;
  t.branches.push_back(branch({{0, 0, 0}, {0, 0.96, 0}, {0, 1.0, 0}, {0, 1.04, 0}, {0, 2, 0}}, 0.1));
  t.branches.push_back(branch({{0.2, 1.0, 0}, {1.2, 1.4, 0}, {2.0, 1.6, 0}}, 0.04, 0, 2, 1));
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_EQ(b.joints.ordinary_joints, 1u);
  EXPECT_EQ(b.joints.split_joints, 0u);
  EXPECT_EQ(b.joints.backward_fallbacks, 0u);
  EXPECT_EQ(b.joints.insets, 0u);
  EXPECT_EQ(b.joints.tip_caps, 2u);
  EXPECT_EQ(b.skeleton.stats.collapsed_junctions, 1u);
  EXPECT_EQ(b.mesh.positions.size(), 28u);  // 7 rings (the junction ring collapsed)
}

// Two equal segments (a split: continuation and clone share the radius): the crotch adds 4
// vertices and 3 quads, each side is bridged.
TEST(BoxJoints, EqualSplitBuildsACrotch) {
  tree::Tree t;
  t.branches.push_back(branch({{0, 0, 0}, {0, 1, 0}, {-0.3, 1.5, 0}, {-0.6, 2.2, 0}}, 0.1));
  t.branches[0].nodes[2].radius = t.branches[0].nodes[3].radius = 0.08;
  t.branches.push_back(branch({{0.3, 1.5, 0}, {0.6, 2.2, 0}}, 0.08, 0, 1, 0));
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_EQ(b.joints.split_joints, 1u);
  EXPECT_EQ(b.joints.ordinary_joints, 0u);
  EXPECT_EQ(b.mesh.positions.size(), 4u * 6 + 4);
}

// Three equal members (BaseSplits 2): the crotch sides recurse, never all on one side.
TEST(BoxJoints, ThreeWayEqualSplitRecurses) {
  tree::Tree t;
  t.branches.push_back(branch({{0, 0, 0}, {0, 1, 0}, {0, 1.6, 0}, {0, 2.2, 0}}, 0.1));
  for (int i = 2; i < 4; ++i) t.branches[0].nodes[static_cast<std::size_t>(i)].radius = 0.07;
  t.branches.push_back(branch({{0.35, 1.5, 0.2}, {0.8, 2.1, 0.4}}, 0.07, 0, 1, 0));
  t.branches.push_back(branch({{-0.35, 1.5, 0.2}, {-0.8, 2.1, 0.4}}, 0.07, 0, 1, 0));
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_EQ(b.joints.split_joints, 2u);
}

// Nystad's Fig. 6.2: a continuation and five non-primary children on one ring; sides that take
// more than one child recurse.
TEST(BoxJoints, FiveChildrenOnOneRing) {
  tree::Tree t = test::straight_trunk(3);
  const double r[5] = {0.05, 0.045, 0.04, 0.035, 0.03};
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * std::numbers::pi * i / 5 + 0.3;
    const tree::Vec3 d{std::cos(a), 0.3, std::sin(a)};
    t.branches.push_back(
        branch({tree::Vec3{0, 1, 0} + d * 0.25, tree::Vec3{0, 1, 0} + d * 1.0}, r[i], 0, 1, 1));
  }
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_GE(b.joints.recursive_sides, 1u);
  EXPECT_EQ(b.joints.tip_caps, 6u);
}

// Children at the tip (no continuation): Connect on the tip's port; the largest goes on top.
TEST(BoxJoints, ChildrenAtTheTip) {
  tree::Tree t = test::straight_trunk(3);
  t.branches.push_back(branch({{0.1, 2.3, 0}, {0.4, 3.0, 0}}, 0.07, 0, 2, 1));
  t.branches.push_back(branch({{-0.3, 2.1, 0.1}, {-1.0, 2.5, 0.2}}, 0.04, 0, 2, 1));
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_EQ(b.joints.ordinary_joints, 1u);
}

// The half-edge check finds what OpenMesh finds: a flipped quad, a hole, a pinched vertex.
TEST(BoxJoints, FastCheckFindsBrokenMeshes) {
  const Built b = build(test::straight_trunk(3));
  QuadMesh flipped = b.mesh;
  std::swap(flipped.quads[2][1], flipped.quads[2][3]);
  EXPECT_GT(check_topology_fast(flipped).refused_faces, 0u);
  EXPECT_GT(check_topology(flipped).refused_faces, 0u);
  QuadMesh holed = b.mesh;
  holed.quads.pop_back();
  holed.uvs.pop_back();
  EXPECT_EQ(check_topology_fast(holed).boundary_edges, 4u);
  EXPECT_EQ(check_topology(holed).boundary_edges, 4u);
  // Two prisms sharing one vertex: each edge is fine, the shared vertex is not one fan.
  QuadMesh pinched = b.mesh;
  const std::uint32_t n = static_cast<std::uint32_t>(pinched.positions.size());
  for (const Vec3& p : b.mesh.positions) pinched.positions.push_back(p + Vec3{1, 0, 0});
  for (std::size_t f = 0; f < b.mesh.quads.size(); ++f) {
    Quad q = b.mesh.quads[f];
    for (auto& v : q) v = v == 0 ? 0 : v + n;
    pinched.quads.push_back(q);
    pinched.uvs.push_back(b.mesh.uvs[f]);
  }
  EXPECT_GT(check_topology_fast(pinched).refused_faces, 0u);
  EXPECT_GT(check_topology(pinched).refused_faces, 0u);
}

// A backward connection (a child whose first segment turns back into its parent, as imported
// skeletons can have): the port is extruded into a box and the child joins the box face that
// faces it best.
TEST(BoxJoints, BackwardChildFallsBackToABox) {
  tree::Tree t = test::straight_trunk(3);
  t.branches.push_back(branch({{0.4, 1.0, 0}, {0.3, 0.2, 0}}, 0.04, 0, 1, 1));
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_GE(b.joints.backward_fallbacks, 1u);
}

// A twig on a thick branch: the side face is inset before it is bridged.
TEST(BoxJoints, ThinChildOnAThickBranchIsInset) {
  tree::Tree t;
  t.branches.push_back(branch({{0, 0, 0}, {0, 1, 0}, {0, 1.5, 0}, {0, 2.5, 0}}, 0.3));
  t.branches.push_back(branch({{0.5, 1.2, 0}, {1.2, 1.4, 0}}, 0.01, 0, 1, 1));
  const Built b = build(t);
  expect_closed_sphere(b);
  EXPECT_EQ(b.joints.insets, 1u);
}

// Texture coordinates: u = 0, 1/4, 1/2, 3/4 around a ring and 1 at the seam; v along the branch.
TEST(BoxJoints, TubeUvsWrapOnceWithASeam) {
  BarkOptions o;
  o.open_base = true;
  const Built b = build(test::straight_trunk(3), o);
  // Quads 0..3 join rings 0 and 1 (the first bridge); quad i spans u from i/4 to (i+1)/4.
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& uv = b.mesh.uvs[i];
    EXPECT_FLOAT_EQ(uv[0].u, static_cast<float>(i) / 4);
    EXPECT_FLOAT_EQ(uv[1].u, static_cast<float>(i + 1) / 4);
    EXPECT_FLOAT_EQ(uv[0].v, 0);
    EXPECT_NEAR(uv[3].v, 1 / (2 * std::numbers::pi * 0.1), 1e-5);
  }
  // The seam: vertex 0 has u = 0 in quad 0 and u = 1 in quad 3.
  EXPECT_EQ(b.mesh.quads[3][1], b.mesh.quads[0][0]);
  EXPECT_FLOAT_EQ(b.mesh.uvs[3][1].u, 1.0f);
}

// The ring size compensates Catmull-Clark's shrinkage: sqrt(pi/2) at level 0, growing to the
// B-spline limit (about 1.52) for higher levels.
TEST(BoxJoints, CornerScaleKeepsTheSectionArea) {
  EXPECT_DOUBLE_EQ(corner_scale_for_subdivision(0), std::sqrt(std::numbers::pi / 2));
  EXPECT_GT(corner_scale_for_subdivision(1), corner_scale_for_subdivision(0));
  EXPECT_GT(corner_scale_for_subdivision(2), corner_scale_for_subdivision(1));
  EXPECT_NEAR(corner_scale_for_subdivision(3), 1.52, 0.02);
}

}  // namespace
}  // namespace sylva::mesh
