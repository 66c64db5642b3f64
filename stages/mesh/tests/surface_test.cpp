// The glTF surface of a quad mesh: unit normals that point out, no tangents (no normal map),
// seams split into separate vertices, two counter-clockwise triangles per quad. And foliage.
#include "stages/mesh/surface.h"

#include <gtest/gtest.h>

#include <cmath>

#include "stages/mesh/box_joints.h"
#include "stages/mesh/foliage.h"
#include "stages/mesh/subdivision.h"
#include "stages/mesh/tests/test_trees.h"

namespace sylva::mesh {
namespace {

using tree::Vec3;

Vec3 at(const std::vector<float>& v, std::size_t i, std::size_t stride = 3) {
  return {v[stride * i], v[stride * i + 1], v[stride * i + 2]};
}

// A straight trunk subdivided once: every attribute as glTF wants it.
TEST(Surface, AttributesAreValidForGltf) {
  const double k = corner_scale_for_subdivision(1);
  SkeletonOptions so;
  so.corner_scale = k;
  BarkOptions bo;
  bo.corner_scale = k;
  const QuadMesh m = subdivide(build_bark_mesh(build_skeleton(test::straight_trunk(4), so), bo, nullptr), 1);
  const gltf::Primitive p = to_primitive(m);
  const std::size_t n = p.vertex_count();
  ASSERT_EQ(p.normals.size(), 3 * n);
  EXPECT_TRUE(p.tangents.empty());  // tangents only with a normal map (the lead's rule)
  ASSERT_EQ(p.texcoords.size(), 2 * n);
  EXPECT_EQ(p.indices.size(), 6 * m.quads.size());
  // The seam: more glTF vertices than mesh vertices, but only along the seam and the caps.
  EXPECT_GT(n, m.positions.size());
  EXPECT_LT(n, m.positions.size() * 2);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(tree::length(at(p.normals, i)), 1, 1e-6);
  }
  // Side vertices (away from the caps) have normals pointing away from the axis.
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 x = at(p.positions, i);
    if (x.y < 0.9 || x.y > 2.1) continue;
    const Vec3 radial = tree::normalized(Vec3{x.x, 0, x.z});
    EXPECT_GT(tree::dot(at(p.normals, i), radial), 0.9);
  }
  // Triangles wind counter-clockwise seen from outside: their normal agrees with the vertex normals.
  for (std::size_t t = 0; t < p.indices.size(); t += 3) {
    const Vec3 a = at(p.positions, p.indices[t]), b = at(p.positions, p.indices[t + 1]),
               c = at(p.positions, p.indices[t + 2]);
    const Vec3 fn = tree::cross(b - a, c - a);
    EXPECT_GT(tree::dot(fn, at(p.normals, p.indices[t])), 0) << "triangle " << t / 3;
  }
}

// Leaf cards: 4 vertices and 2 triangles per leaf facing the leaf normal, uvs inside the
// variant's atlas quadrant, petiole at low v; needles: closed tetrahedra.
TEST(Foliage, LeafCardsAndNeedles) {
  tree::Tree t = test::straight_trunk(2);
  tree::Leaf leaf;
  leaf.position = {0.2f, 1.0f, 0};
  leaf.direction = {1, 0, 0};
  leaf.normal = {0, 1, 0};
  leaf.length = 0.1f;
  leaf.width = 0.05f;
  leaf.variant = 3;
  t.leaves.push_back(leaf);
  const gltf::Primitive p = leaf_cards(t);
  ASSERT_EQ(p.vertex_count(), 4u);
  ASSERT_EQ(p.indices.size(), 6u);
  EXPECT_TRUE(p.tangents.empty());
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_GE(p.texcoords[2 * i], 0.5f);  // variant 3: column 1, row 1
    EXPECT_GE(p.texcoords[2 * i + 1], 0.5f);
    EXPECT_EQ(at(p.normals, i), (Vec3{0, 1, 0}));
  }
  for (std::size_t tri = 0; tri < 6; tri += 3) {
    const Vec3 a = at(p.positions, p.indices[tri]), b = at(p.positions, p.indices[tri + 1]),
               c = at(p.positions, p.indices[tri + 2]);
    EXPECT_GT(tree::cross(b - a, c - a).y, 0);
  }
  // The petiole end (x = 0.2) has the low v of the quadrant.
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_FLOAT_EQ(p.texcoords[2 * i + 1], p.positions[3 * i] < 0.25f ? 0.5f : 1.0f);

  // A 4 x 2 card atlas: variant 5 is column 1, row 1 (libs/tree atlas_cell), u0 on the -side
  // edge, v0 at the card's base.
  t.materials.atlas_columns = 4;
  t.materials.atlas_rows = 2;
  t.leaves[0].variant = 5;
  const gltf::Primitive c = leaf_cards(t);
  const float want[8] = {0.25f, 0.5f, 0.5f, 0.5f, 0.5f, 1.0f, 0.25f, 1.0f};
  for (std::size_t i = 0; i < 8; ++i) EXPECT_FLOAT_EQ(c.texcoords[i], want[i]) << i;

  tree::Needle nd;
  nd.base = {0, 1, 0};
  nd.tip = {0, 1, 0.05f};
  nd.radius = 0.0005f;
  t.needles.push_back(nd);
  const gltf::Primitive q = needle_geometry(t);
  EXPECT_EQ(q.vertex_count(), 4u);
  EXPECT_EQ(q.indices.size(), 12u);
  // Closed: every directed edge appears once, its reverse once.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t i = 0; i < 12; i += 3)
    for (std::size_t j = 0; j < 3; ++j) ++edges[{q.indices[i + j], q.indices[i + (j + 1) % 3]}];
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
}

}  // namespace
}  // namespace sylva::mesh
