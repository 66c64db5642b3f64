// The frame conversion on hand-made geometry: Z up turned Y up, units, and the trunk foot.
#include "stages/import/mesh_frame.h"

#include <gtest/gtest.h>

namespace sylva::import {
namespace {

tree::SourceGeometry points(std::vector<tree::Vec3f> positions) {
  tree::SourceGeometry g;
  g.primitives.push_back({"p", 0, std::move(positions), {}, {}, {0, 1, 2}});
  return g;
}

// Z up: (x, y, z) -> (x, z, -y), a rotation; normals turn with it; the unit and scale multiply.
TEST(MeshFrame, ZUpTurnedAndScaled) {
  tree::SourceGeometry g = points({{1, 2, 3}, {0, 0, 0}, {0, 0, 1}});
  g.primitives[0].normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  MeshFacts facts;
  facts.up = 'z';
  facts.unit_scale = 0.01;  // centimetres
  MeshOptions o;
  o.scale = 10;
  o.recenter = false;
  to_sylva_frame(g, facts, o);
  EXPECT_EQ(g.primitives[0].positions[0], (tree::Vec3f{0.1f, 0.3f, -0.2f}));
  EXPECT_EQ(g.primitives[0].normals[0], (tree::Vec3f{0, 1, 0}));
  EXPECT_EQ(g.primitives[0].normals[1], (tree::Vec3f{0, 0, -1}));
  EXPECT_NEAR(facts.height, 0.3, 1e-7);
}

// The foot is the centre of the box of the vertices within 1 % of the height above the lowest
// point (here a root flare from x = 2 to 4 at y = 10 and 10.05), not the centre of the whole
// model (a crown leaning to x = 40).
TEST(MeshFrame, FootToOrigin) {
  tree::SourceGeometry g = points({{2, 10, 1}, {4, 10.05f, 3}, {40, 20, 2}, {3, 30, 2}});
  MeshFacts facts;
  to_sylva_frame(g, facts, {});
  const auto& p = g.primitives[0].positions;
  EXPECT_EQ(p[0], (tree::Vec3f{-1, 0, -1}));
  EXPECT_EQ(p[1].x, 1);
  EXPECT_EQ(p[2], (tree::Vec3f{37, 10, 0}));
  EXPECT_DOUBLE_EQ(facts.height, 20);
}

}  // namespace
}  // namespace sylva::import
