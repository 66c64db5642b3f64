// Round trip with exact truth: a hand-built skeleton (trunk, two laterals, a level-2 twig, all
// tapering, one lateral curved) tessellated as open tubes here, reconstructed without names;
// every branch comes back at its level with radius error < 10 % and position error < 1 radius.
#include <gtest/gtest.h>

#include "stages/hierarchy/reconstruct.h"
#include "stages/hierarchy/tests/test_meshes.h"

namespace sylva::hierarchy {
namespace {

using tree::Vec3;

tree::Branch branch(std::int32_t parent, std::uint32_t level, std::vector<tree::Node> nodes) {
  tree::Branch b;
  b.parent = parent;
  b.level = level;
  b.nodes = std::move(nodes);
  return b;
}

tree::Tree truth() {
  tree::Tree t;
  std::vector<tree::Node> trunk, lateral, curved, twig;
  for (int k = 0; k <= 10; ++k) trunk.push_back({{0.02 * k, 0.5 * k, 0}, 0.25 - 0.015 * k});
  for (int k = 0; k <= 6; ++k)
    lateral.push_back({{0.1 + 0.3 * k, 2.0 + 0.12 * k, 0.05 * k}, 0.08 - 0.008 * k});
  for (int k = 0; k <= 8; ++k) {
    const double a = 0.15 * k;
    curved.push_back({{-0.1 - 1.2 * std::sin(a), 3.0 + 1.2 * (1 - std::cos(a)), 0.0}, 0.07 - 0.005 * k});
  }
  for (int k = 0; k <= 4; ++k) twig.push_back({{1.0 + 0.05 * k, 2.36 + 0.15 * k, 0.15}, 0.03 - 0.003 * k});
  t.branches = {branch(-1, 0, trunk), branch(0, 1, lateral), branch(0, 1, curved), branch(1, 2, twig)};
  return t;
}

// Each branch as an open tube with 3 rings per segment (radii interpolated), all in one
// primitive without names, as ez-tree writes them.
tree::SourceGeometry tessellate(const tree::Tree& t) {
  tree::SourcePrimitive p;
  p.name = "tree";
  for (const tree::Branch& b : t.branches) {
    std::vector<Vec3> c;
    std::vector<double> r;
    for (std::size_t i = 0; i + 1 < b.nodes.size(); ++i)
      for (int s = 0; s < 3; ++s) {
        const double f = s / 3.0;
        c.push_back(b.nodes[i].position + (b.nodes[i + 1].position - b.nodes[i].position) * f);
        r.push_back(b.nodes[i].radius + (b.nodes[i + 1].radius - b.nodes[i].radius) * f);
      }
    c.push_back(b.nodes.back().position);
    r.push_back(b.nodes.back().radius);
    testing::add_tube(p, c, r, 10);
  }
  tree::SourceGeometry g;
  g.primitives = {p};
  g.materials.resize(1);
  return g;
}

// Distance from p to a polyline, and the radius interpolated at the closest point.
std::pair<double, double> closest(const std::vector<tree::Node>& nodes, Vec3 p) {
  double best = INFINITY, radius = 0;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    const Vec3 a = nodes[i].position, seg = nodes[i + 1].position - a;
    const double t = std::clamp(dot(p - a, seg) / dot(seg, seg), 0.0, 1.0);
    const double d = length(p - (a + seg * t));
    if (d < best) {
      best = d;
      radius = nodes[i].radius + (nodes[i + 1].radius - nodes[i].radius) * t;
    }
  }
  return {best, radius};
}

TEST(RoundTrip, EveryBranchRecovered) {
  const tree::Tree truth_tree = truth();
  tree::Tree in;
  in.source = tessellate(truth_tree);
  const Reconstruction r = reconstruct(in, {});
  const tree::Tree& got = r.tree;
  EXPECT_EQ(tree::validate_tree(got), std::vector<std::string>{});
  ASSERT_EQ(got.branches.size(), truth_tree.branches.size());
  for (std::size_t b = 0; b < got.branches.size(); ++b) {
    // Parts keep the primitive's order and levels sort stably: output b is part b here.
    ASSERT_EQ(r.report.branches[b].part, b);
    EXPECT_EQ(got.branches[b].parent, truth_tree.branches[b].parent) << b;
    EXPECT_EQ(got.branches[b].level, truth_tree.branches[b].level) << b;
    EXPECT_GE(got.branches[b].nodes.size(), 3u) << b;
    for (const tree::Node& n : got.branches[b].nodes) {
      const auto [d, radius] = closest(truth_tree.branches[b].nodes, n.position);
      EXPECT_LT(d, radius) << "branch " << b;
      EXPECT_NEAR(n.radius, radius, 0.1 * radius) << "branch " << b;
    }
    // And the other way: every true node is near the reconstructed line.
    for (const tree::Node& n : truth_tree.branches[b].nodes)
      EXPECT_LT(closest(got.branches[b].nodes, n.position).first, n.radius) << "branch " << b;
  }
}

}  // namespace
}  // namespace sylva::hierarchy
