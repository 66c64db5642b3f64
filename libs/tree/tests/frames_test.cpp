#include "libs/tree/frames.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "libs/tree/tests/sample_tree.h"

namespace sylva::tree {
namespace {

std::vector<Node> helix(int n, double turns, double radius, double pitch) {
  std::vector<Node> nodes;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * turns * i / (n - 1);
    nodes.push_back({{radius * std::cos(a), pitch * a, radius * std::sin(a)}, 0.1});
  }
  return nodes;
}

void expect_orthonormal(const std::vector<Frame>& f) {
  for (std::size_t k = 0; k < f.size(); ++k) {
    EXPECT_NEAR(length(f[k].t), 1, 1e-12) << k;
    EXPECT_NEAR(length(f[k].n), 1, 1e-12) << k;
    EXPECT_NEAR(length(f[k].b), 1, 1e-12) << k;
    EXPECT_NEAR(dot(f[k].t, f[k].n), 0, 1e-12) << k;
    EXPECT_NEAR(dot(f[k].t, f[k].b), 0, 1e-12) << k;
    EXPECT_NEAR(dot(f[k].n, f[k].b), 0, 1e-12) << k;
    EXPECT_NEAR(length(cross(f[k].t, f[k].n) - f[k].b), 0, 1e-12) << k;  // right-handed
  }
}

// Twist about T between consecutive frames, beyond the minimal rotation taking T_k to T_{k+1}.
double twist(const Frame& a, const Frame& b) {
  const Vec3 axis = cross(a.t, b.t);
  const double s = length(axis), c = dot(a.t, b.t);
  Vec3 rn = a.n;  // Rodrigues rotation of a.n by the minimal rotation
  if (s > 1e-15) {
    const Vec3 k = axis / s;
    rn = a.n * c + cross(k, a.n) * s + k * (dot(k, a.n) * (1 - c));
  }
  return std::atan2(dot(cross(rn, b.n), b.t), dot(rn, b.n));
}

// The tangent is the bisector of the two adjacent segments (A1), one-sided at the ends.
TEST(Frames, TangentIsBisector) {
  const std::vector<Node> nodes = {{{0, 0, 0}, 1}, {{0, 1, 0}, 1}, {{1, 1, 0}, 1}};
  const auto f = compute_frames(nodes, {1, 0, 0});
  EXPECT_NEAR(length(f[0].t - Vec3{0, 1, 0}), 0, 1e-15);
  EXPECT_NEAR(length(f[1].t - normalized(Vec3{1, 1, 0})), 0, 1e-15);
  EXPECT_NEAR(length(f[2].t - Vec3{1, 0, 0}), 0, 1e-15);
}

// Frames along a helix stay orthonormal and right-handed.
TEST(Frames, OrthonormalOnHelix) { expect_orthonormal(compute_frames(helix(200, 3, 1, 0.3), {1, 0, 0})); }

// A planar curve has no torsion: B stays the plane normal at every node (exactly).
TEST(Frames, PlanarCurveDoesNotTwist) {
  std::vector<Node> nodes;
  for (int i = 0; i < 50; ++i) nodes.push_back({{std::sin(i * 0.2) * i * 0.1, i * 0.1, 0}, 0.1});
  const auto f = compute_frames(nodes, {0, 0, 1});
  for (const Frame& fr : f) EXPECT_NEAR(std::abs(fr.n.z), 1, 1e-12);
  for (const Frame& fr : f) EXPECT_NEAR(std::abs(fr.b.z), 0, 1e-12);
}

// Rotation-minimising: the twist beyond the minimal rotation is second order in the turning
// angle theta (the projection of A1 twists by at most ~theta^2/4), and the frames satisfy
// Zhang's Theorem 1 (A2). A Frenet frame on the same helix twists by the torsion, far more.
TEST(Frames, RotationMinimisingOnHelix) {
  const auto nodes = helix(400, 2, 1, 0.5);
  const auto f = compute_frames(nodes, {1, 0, 0});
  const auto beta = node_angles(nodes);
  double total_twist = 0;
  for (std::size_t k = 0; k + 1 < f.size(); ++k) {
    const double theta = std::acos(std::min(1.0, dot(f[k].t, f[k + 1].t)));
    const double tw = twist(f[k], f[k + 1]);
    EXPECT_LE(std::abs(tw), 0.26 * theta * theta + 1e-12) << k;
    total_twist += tw;
    const double bound = std::cos(beta[k] + beta[k + 1]) - 1e-12;
    EXPECT_GE(dot(f[k].t, f[k + 1].t), bound) << k;
    EXPECT_GE(dot(f[k].n, f[k + 1].n), bound) << k;
    EXPECT_GE(dot(f[k].b, f[k + 1].b), bound) << k;
  }
  // The Frenet normal of this helix turns by 2 turns x 2 pi about the tangent; the RMF doesn't.
  EXPECT_LT(std::abs(total_twist), 0.01);
}

// node angle beta_k = arccos(L_k . L_{k-1}) / 2; zero at the ends.
TEST(Frames, NodeAngle) {
  const std::vector<Node> nodes = {{{0, 0, 0}, 1}, {{0, 1, 0}, 1}, {{1, 1, 0}, 1}, {{2, 1, 0}, 1}};
  const auto beta = node_angles(nodes);
  ASSERT_EQ(beta.size(), 4u);
  EXPECT_DOUBLE_EQ(beta[0], 0);
  EXPECT_NEAR(beta[1], std::numbers::pi / 4, 1e-15);
  EXPECT_NEAR(beta[2], 0, 1e-15);
  EXPECT_DOUBLE_EQ(beta[3], 0);
}

// Degenerate input (repeated points, a seed normal parallel to T) still gives valid frames.
TEST(Frames, DegenerateInput) {
  const std::vector<Node> nodes = {{{0, 0, 0}, 1}, {{0, 0, 0}, 1}, {{0, 1, 0}, 1}, {{0, 1, 0}, 1}};
  const auto f = compute_frames(nodes, {0, 1, 0});
  expect_orthonormal(f);
  for (const Frame& fr : f) EXPECT_NEAR(length(fr.t - Vec3{0, 1, 0}), 0, 1e-15);
}

// A child's frames continue from its parent's normal at the attachment node.
TEST(Frames, TreeFramesContinueAcrossJoints) {
  const Tree t = testing::sample_tree();
  const auto frames = compute_tree_frames(t);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_NEAR(length(frames[0][0].n - Vec3{1, 0, 0}), 0, 1e-15);
  // Lateral goes +X; the parent's N (+X) is parallel to it, so B is carried over instead.
  expect_orthonormal(frames[1]);
  EXPECT_NEAR(length(frames[1][0].b - frames[0][2].b), 0, 1e-12);
}

}  // namespace
}  // namespace sylva::tree
