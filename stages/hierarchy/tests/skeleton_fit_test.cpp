// Skeletons by slicing: a curved tube's centre line and radius against the analytic ones, a
// tapering tube's radii, and the 2-node fallback for a part too short for two slices.
#include "stages/hierarchy/skeleton_fit.h"

#include <gtest/gtest.h>

#include "stages/hierarchy/tests/test_meshes.h"

namespace sylva::hierarchy {
namespace {

using tree::Vec3;

Part only_part(const tree::SourcePrimitive& p) {
  tree::SourceGeometry g;
  g.primitives = {p};
  g.materials.resize(1);
  auto parts = split_parts(g, 1e-5);
  EXPECT_EQ(parts.size(), 1u);
  return parts.front();
}

// A quarter circle of radius 1 m in the xy plane around (1, 0, 0), from the origin (going up) to
// (1, 1, 0), as a tube of radius 0.1 m: every fitted node within 5 % of the radius of the arc,
// every radius within 5 %.
TEST(SkeletonFit, CurvedTubeFollowsTheArc) {
  const double kR = 1.0, kr = 0.1;
  std::vector<Vec3> c;
  std::vector<double> r;
  for (int k = 0; k <= 48; ++k) {
    const double a = M_PI / 2 * k / 48;
    c.push_back({kR - kR * std::cos(a), kR * std::sin(a), 0});
    r.push_back(kr);
  }
  tree::SourcePrimitive p;
  testing::add_tube(p, c, r, 16);
  const Part part = only_part(p);
  const BranchBase base = branch_base(part);
  EXPECT_NEAR(length(base.point), 0, 1e-6);  // the lower end (equal radii): the origin
  const SkeletonFit fit = fit_skeleton(part, base, {});
  EXPECT_FALSE(fit.axis_fallback);
  EXPECT_GE(fit.nodes.size(), 10u);  // 1.57 m in slices of 0.1-0.15 m (whole rings each)
  for (const tree::Node& n : fit.nodes) {
    const double in_plane = std::hypot(n.position.x - kR, n.position.y) - kR;
    EXPECT_LT(std::hypot(in_plane, n.position.z), 0.05 * kr) << n.position.x << " " << n.position.y;
    EXPECT_NEAR(n.radius, kr, 0.05 * kr);
  }
  EXPECT_LT(length(fit.nodes.front().position - Vec3{0, 0, 0}), kr);
  EXPECT_LT(length(fit.nodes.back().position - Vec3{1, 1, 0}), kr);
  EXPECT_LT(fit.rms_residual, 0.02 * kr);  // two rings per slice, tilted by the bend
}

// A tapering tube: the base is its wide end even when it is the upper one, and radii follow the
// taper.
TEST(SkeletonFit, TaperingTubeFromItsWideEnd) {
  tree::SourcePrimitive p;
  testing::add_straight_tube(p, {0, 2, 0}, {0, -1, 0}, 2.0, 0.1, 0.05, 21);  // hangs down
  const Part part = only_part(p);
  const BranchBase base = branch_base(part);
  EXPECT_NEAR(base.point.y, 2.0, 1e-6);
  EXPECT_NEAR(base.radius, 0.1, 1e-3);
  const SkeletonFit fit = fit_skeleton(part, base, {});
  ASSERT_GE(fit.nodes.size(), 10u);
  for (const tree::Node& n : fit.nodes) {
    const double expected = 0.1 - 0.05 * (2.0 - n.position.y) / 2.0;
    EXPECT_NEAR(n.radius, expected, 0.05 * expected);
    EXPECT_LT(std::hypot(n.position.x, n.position.z), 1e-3);
  }
  EXPECT_GT(fit.nodes.front().position.y, fit.nodes.back().position.y);
}

// 5 cm long, radius 5 cm: one slice only, so 2 nodes along the principal axis from the base.
TEST(SkeletonFit, ShortPartFallsBackToItsAxis) {
  tree::SourcePrimitive p;
  testing::add_straight_tube(p, {0, 0, 0}, {1, 0, 0}, 0.05, 0.05, 0.05, 2);
  const Part part = only_part(p);
  const SkeletonFit fit = fit_skeleton(part, branch_base(part), {});
  EXPECT_TRUE(fit.axis_fallback);
  ASSERT_EQ(fit.nodes.size(), 2u);
  EXPECT_NEAR(fit.nodes[1].position.x - fit.nodes[0].position.x, 0.05, 1e-6);
  EXPECT_NEAR(fit.nodes[0].radius, 0.05, 1e-6);
}

}  // namespace
}  // namespace sylva::hierarchy
