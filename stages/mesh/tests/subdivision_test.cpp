// Catmull-Clark: counts, the native implementation against OpenMesh's CatmullClarkT, the
// thesis's uv rule, and the cross-section the corner scale is chosen for.
#include "stages/mesh/subdivision.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "stages/mesh/box_joints.h"
#include "stages/mesh/tests/test_trees.h"
#include "stages/mesh/topology_check.h"

namespace sylva::mesh {
namespace {

using test::branch;

// A small tree with an ordinary joint, an equal split and a tip: all cases in a few quads.
QuadMesh joint_mesh(bool open_base = false, double corner_scale = 1.0) {
  tree::Tree t;
  t.branches.push_back(branch({{0, 0, 0}, {0, 1, 0}, {0, 1.3, 0}, {-0.3, 1.8, 0}, {-0.6, 2.4, 0}}, 0.1));
  t.branches[0].nodes[3].radius = t.branches[0].nodes[4].radius = 0.08;
  t.branches.push_back(branch({{0.3, 1.75, 0}, {0.6, 2.4, 0}}, 0.08, 0, 2, 0));
  t.branches.push_back(branch({{0.3, 1.1, 0.1}, {1.0, 1.3, 0.3}}, 0.03, 0, 1, 1));
  SkeletonOptions so;
  so.corner_scale = corner_scale;
  BarkOptions bo;
  bo.open_base = open_base;
  bo.corner_scale = corner_scale;
  return build_bark_mesh(build_skeleton(t, so), bo, nullptr);
}

std::size_t edge_count(const QuadMesh& m) { return check_topology(m).edges; }

// Each level: quads x 4; vertices V + E + F; still closed and genus 0.
TEST(Subdivision, CountsPerLevel) {
  const QuadMesh m0 = joint_mesh();
  QuadMesh m = m0;
  for (int level = 1; level <= 3; ++level) {
    const QuadMesh next = subdivide(m, 1);
    EXPECT_EQ(next.quads.size(), 4 * m.quads.size());
    EXPECT_EQ(next.positions.size(), m.positions.size() + edge_count(m) + m.quads.size());
    const TopologyReport r = check_topology(next);
    EXPECT_TRUE(r.manifold_and_oriented() && r.closed());
    EXPECT_EQ(r.euler, 2);
    m = next;
  }
  EXPECT_EQ(subdivide(m0, 3).quads.size(), 64 * m0.quads.size());
  EXPECT_EQ(subdivide(m0, 0).quads, m0.quads);
}

// The native implementation and OpenMesh's CatmullClarkT give the same surface: the same
// vertex positions and, per quad, the same corner positions and uvs (orders differ).
TEST(Subdivision, NativeMatchesOpenMesh) {
  QuadMesh m0 = joint_mesh();
  m0.crease.clear();  // OpenMesh's CatmullClarkT knows no creases: compare the smooth rules
  for (int levels = 1; levels <= 2; ++levels) {
    const QuadMesh a = subdivide(m0, levels, Subdivider::kNative);
    const QuadMesh b = subdivide(m0, levels, Subdivider::kOpenMesh);
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_EQ(a.quads.size(), b.quads.size());
    // Every quad as a sorted list of (position, uv) corners, the quads sorted; then compared
    // with a tolerance (the two sum the Catmull-Clark stencils in different orders).
    using Corner = std::array<double, 5>;
    auto quads = [](const QuadMesh& m) {
      std::vector<std::array<Corner, 4>> out;
      for (std::size_t f = 0; f < m.quads.size(); ++f) {
        std::array<Corner, 4> q;
        for (std::size_t i = 0; i < 4; ++i) {
          const Vec3& p = m.positions[m.quads[f][i]];
          q[i] = {p.x, p.y, p.z, m.uvs[f][i].u, m.uvs[f][i].v};
        }
        std::sort(q.begin(), q.end(), [](const Corner& x, const Corner& y) {
          for (std::size_t k = 0; k < 5; ++k)
            if (std::abs(x[k] - y[k]) > 1e-7) return x[k] < y[k];
          return false;
        });
        out.push_back(q);
      }
      std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) {
        for (std::size_t c = 0; c < 4; ++c)
          for (std::size_t k = 0; k < 5; ++k)
            if (std::abs(x[c][k] - y[c][k]) > 1e-7) return x[c][k] < y[c][k];
        return false;
      });
      return out;
    };
    const auto qa = quads(a), qb = quads(b);
    double worst_position = 0, worst_uv = 0;
    for (std::size_t f = 0; f < qa.size(); ++f)
      for (std::size_t c = 0; c < 4; ++c)
        for (std::size_t k = 0; k < 5; ++k) {
          double& worst = k < 3 ? worst_position : worst_uv;
          worst = std::max(worst, std::abs(qa[f][c][k] - qb[f][c][k]));
        }
    EXPECT_LT(worst_position, 1e-9) << "level " << levels;
    EXPECT_LT(worst_uv, 1e-6) << "level " << levels << " (float uvs, summed in another corner order)";
  }
}

// Nystad §3.4.3: an existing vertex keeps its uv in every quad around it; a new edge point takes
// the average of the edge's two uvs.
TEST(Subdivision, UvsFollowTheThesisRule) {
  const QuadMesh m0 = joint_mesh();
  const QuadMesh m1 = subdivide(m0, 1);
  for (std::size_t f = 0; f < m0.quads.size(); ++f)
    for (std::size_t i = 0; i < 4; ++i) {
      const auto& child = m1.uvs[4 * f + i];
      EXPECT_EQ(child[0], m0.uvs[f][i]);  // corner i of quad f keeps its uv
      EXPECT_DOUBLE_EQ(child[1].u, (m0.uvs[f][i].u + m0.uvs[f][(i + 1) % 4].u) / 2);
      EXPECT_DOUBLE_EQ(child[1].v, (m0.uvs[f][i].v + m0.uvs[f][(i + 1) % 4].v) / 2);
    }
}

// The bark of a straight trunk (test::straight_trunk(9)) made to be subdivided `levels` times:
// corners scaled by corner_scale_for_subdivision(levels).
QuadMesh trunk_bark(int levels) {
  const double k = corner_scale_for_subdivision(levels);
  SkeletonOptions so;
  so.corner_scale = k;
  BarkOptions bo;
  bo.corner_scale = k;
  return build_bark_mesh(build_skeleton(test::straight_trunk(9), so), bo, nullptr);
}

// The area of a section of a vertical tube: the polygon of `points` (angle about the y axis,
// position) taken in angle order, projected to x-z.
double section_area(std::vector<std::pair<double, Vec3>> points) {
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double area = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& a = points[i].second;
    const Vec3& b = points[(i + 1) % points.size()].second;
    area += a.z * b.x - a.x * b.z;
  }
  return std::abs(area) / 2;
}

// On a long straight tube, after L levels with corner_scale_for_subdivision(L), the section in
// the middle has the area of a circle of the branch radius.
TEST(Subdivision, CornerScaleGivesTheBranchArea) {
  for (int levels = 0; levels <= 3; ++levels) {
    const QuadMesh m = subdivide(trunk_bark(levels), levels);
    // Vertices at height 4 (a ring in the middle), sorted by angle: the section polygon.
    std::vector<std::pair<double, Vec3>> ring;
    for (const Vec3& p : m.positions)
      if (std::abs(p.y - 4) < 1e-9) ring.emplace_back(std::atan2(p.z, p.x), p);
    ASSERT_EQ(ring.size(), 4u << levels);
    EXPECT_NEAR(section_area(ring), std::numbers::pi * 0.01, 1e-9) << "level " << levels;
  }
}

// The open base is a boundary: it stays a boundary and follows the B-spline curve rule.
TEST(Subdivision, OpenBaseStaysOneBoundaryLoop) {
  const QuadMesh m = subdivide(joint_mesh(true), 2);
  const TopologyReport r = check_topology(m);
  EXPECT_TRUE(r.manifold_and_oriented());
  EXPECT_EQ(r.boundary_edges, 16u);
  // The base ring lies in y = 0 (a planar boundary stays planar under the curve rule).
  std::size_t base = 0;
  for (const Vec3& p : m.positions) {
    if (p.y < 0.05) {
      EXPECT_NEAR(p.y, 0, 1e-12);
      ++base;
    }
  }
  EXPECT_EQ(base, 16u);
}

// The capped base ring is a crease: at every level the foot stays in y = 0 (the cap flat, its
// boundary the B-spline curve of the ring, as wide as the tube above: the section area of a
// circle of the radius), where the same mesh without the crease lifts its foot off the ground.
TEST(Subdivision, CreasedBaseStandsOnTheGround) {
  for (int levels = 1; levels <= 3; ++levels) {
    const QuadMesh base = trunk_bark(levels);
    ASSERT_EQ(base.crease.size(), base.positions.size());
    EXPECT_EQ(std::count(base.crease.begin(), base.crease.end(), 1), 4);
    const QuadMesh m = subdivide(base, levels);
    double lowest = 1e9;
    std::vector<std::pair<double, Vec3>> foot;
    ASSERT_EQ(m.crease.size(), m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      const Vec3& p = m.positions[v];
      lowest = std::min(lowest, p.y);
      if (m.crease[v]) {
        EXPECT_NEAR(p.y, 0, 1e-12);
        foot.emplace_back(std::atan2(p.z, p.x), p);
      }
    }
    EXPECT_NEAR(lowest, 0, 1e-12) << "level " << levels;
    ASSERT_EQ(foot.size(), 4u << levels) << "level " << levels;  // the foot's boundary, in y = 0
    EXPECT_NEAR(section_area(foot), std::numbers::pi * 0.01, 1e-9) << "level " << levels;
    QuadMesh smooth = base;
    smooth.crease.clear();
    double lifted = 1e9;
    for (const Vec3& p : subdivide(smooth, levels).positions) lifted = std::min(lifted, p.y);
    // Without the crease the cap rounds up: from level 2 on nothing is left in y = 0 (at level 1
    // only the cap's face point is).
    if (levels >= 2) {
      EXPECT_GT(lifted, 0.01) << "level " << levels;
    }
  }
}

}  // namespace
}  // namespace sylva::mesh
