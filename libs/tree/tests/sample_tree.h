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

// A small imported mesh: a bark quad (normals and uvs, opaque material with a PNG), a leaf
// triangle (uvs only, masked material with a JPEG) and a bare triangle (no normals or uvs,
// blended material without image). 10 vertices, 4 triangles.
inline SourceGeometry sample_source() {
  SourceGeometry g;
  SourcePrimitive bark;
  bark.name = "tree/trunk/br0_trunk";
  bark.material = 0;
  bark.positions = {{0, 0, 0}, {0.1f, 0, 0}, {0.1f, 1, 0}, {0, 1, 0}};
  bark.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  bark.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  bark.indices = {0, 1, 2, 0, 2, 3};
  SourcePrimitive leaf;
  leaf.name = "tree/crown/lf_12";
  leaf.material = 1;
  leaf.positions = {{0, 1, 0}, {0.05f, 1.1f, 0}, {-0.05f, 1.1f, 0}};
  leaf.uvs = {{0.5f, 0}, {1, 1}, {0, 1}};
  leaf.indices = {0, 1, 2};
  SourcePrimitive bare;
  bare.name = "tree/misc";
  bare.material = 2;
  bare.positions = {{0, 2, 0}, {0.1f, 2, 0}, {0, 2.1f, 0}};
  bare.indices = {0, 1, 2};
  g.primitives = {bark, leaf, bare};
  SourceMaterial bark_m;
  bark_m.name = "Bark";
  bark_m.base_color = {0.4f, 0.3f, 0.2f, 1};
  bark_m.base_color_image = 0;
  bark_m.metallic = 0;
  bark_m.roughness = 0.9f;
  SourceMaterial leaf_m;
  leaf_m.name = "Leaves";
  leaf_m.base_color_image = 1;
  leaf_m.alpha_mode = AlphaMode::kMask;
  leaf_m.alpha_cutoff = 0.3f;
  leaf_m.double_sided = true;
  SourceMaterial glass;
  glass.name = "Haze";
  glass.base_color = {1, 1, 1, 0.25f};
  glass.alpha_mode = AlphaMode::kBlend;
  g.materials = {bark_m, leaf_m, glass};
  g.images = {{"bark.png", "image/png", std::string("\x89PNG\r\n\x1a\n\0bark", 13)},
              {"leaf.jpg", "image/jpeg", std::string("\xff\xd8\xff\xe0leaf", 8)}};
  return g;
}

}  // namespace sylva::tree::testing
