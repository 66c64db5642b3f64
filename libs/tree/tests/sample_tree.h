// A small hand-built tree shared by the libs/tree tests: a 3 m vertical trunk (radius 0.2 at
// the base, 0.1 at the top) with nodes at y = 0, 1, 2, 3; one lateral at the node y = 2 going
// +X (two nodes, 1 m long); one leaf and one needle on the lateral.
#pragma once

#include "libs/tree/tree.h"

namespace sylva::tree::testing {

inline Tree sample_tree() {
  Tree t;
  t.name = "sample";
  Branch trunk;
  trunk.nodes = {{{0, 0, 0}, 0.2}, {{0, 1, 0}, 0.18}, {{0, 2, 0}, 0.15}, {{0, 3, 0}, 0.1}};
  Branch lateral;
  lateral.parent = 0;
  lateral.parent_node = 2;
  lateral.level = 1;
  lateral.nodes = {{{0.25, 2, 0}, 0.05}, {{1.25, 2, 0}, 0.02}};
  t.branches = {trunk, lateral};
  Leaf leaf;
  leaf.branch = 1;
  leaf.position = {1.25f, 2.0f, 0.0f};
  leaf.direction = {0, 1, 0};
  leaf.normal = {0, 0, 1};
  leaf.length = 0.1f;
  leaf.width = 0.05f;
  leaf.variant = 3;
  t.leaves = {leaf};
  Needle needle;
  needle.branch = 1;
  needle.base = {1.0f, 2.0f, 0.0f};
  needle.tip = {1.0f, 2.0f, 0.02f};
  needle.radius = 0.0005f;
  t.needles = {needle};
  t.materials.bark_texture = "bark.png";
  t.materials.leaf_texture = "leaves.png";
  t.materials.bark_color = {0.3f, 0.2f, 0.1f};
  t.materials.leaf_color = {0.1f, 0.4f, 0.05f};
  return t;
}

}  // namespace sylva::tree::testing
