// The tree model every stage links: a skeleton of branches (ordered nodes with radii), foliage
// (leaves and conifer needles) and materials.
//
// Seeds: Zhang et al. 2017 §4.1–4.2 (a branch is a polyline of nodes P_k with radii R_k);
// Nystad 2010 §5.1 and §4.3.1 (branches, split clones and lateral children; every non-root
// branch grows from a node of its parent).
//
// Conventions: metres, Y up, right-handed (glTF). Plain structs; the invariants below are what
// validate_tree() checks, what the .sylt writer refuses to break and what the reader enforces,
// so every stage may rely on them:
//   - branches[i].parent is -1 (a root, level 0) or an index < i: parents come first, so a
//     single forward pass sees every parent before its children and there are no cycles;
//   - a branch has >= 2 nodes; positions are finite, radii finite and >= 0;
//   - a child grows from the point lerp(P[parent_node], P[parent_node + 1], parent_t) of its
//     parent's axis: parent_node < parent's node count, parent_t in [0, 1], and parent_t == 0
//     when parent_node is the parent's last node;
//   - level: roots 0; otherwise the parent's level (a *clone*, made by a split: it continues the
//     same axis order) or the parent's level + 1 (a *lateral* child);
//   - leaves and needles name an existing branch; leaf length/width > 0, direction and normal
//     unit length (1e-3) and orthogonal (1e-3), variant 0..3; needle radius > 0.
// A child's first node is its first cross-section, *not* the attachment point: the segment from
// the attachment point to nodes[0] is implicit (Nystad's DAG edge from the prepended node to the
// child's root segment). For generated trees parent_t is 0 and the attachment node is a
// *junction*; see docs/tree-format.md for the da Vinci relation generated junctions satisfy.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/tree/vec3.h"

namespace sylva::tree {

struct Node {
  Vec3 position;      // m, object space
  double radius = 0;  // m, >= 0
  friend bool operator==(const Node&, const Node&) = default;
};

struct Branch {
  std::int32_t parent = -1;        // branch index (< own index) or -1 for a root
  std::uint32_t parent_node = 0;   // node of the parent it grows from (0 for roots)
  double parent_t = 0;             // [0, 1] along parent segment parent_node -> parent_node + 1
  std::uint32_t level = 0;         // trunk 0; clone = parent's level; lateral = parent's + 1
  std::vector<Node> nodes;         // base to tip, >= 2
  friend bool operator==(const Branch&, const Branch&) = default;
};

// A flat leaf card. The blade spans `length` along `direction` from `position` (the petiole
// end) and `width` across cross(normal, direction); texture v runs from petiole (v low) to tip.
struct Leaf {
  std::uint32_t branch = 0;  // branch it grows on
  Vec3f position;            // m, petiole end of the blade
  Vec3f direction;           // unit, petiole -> tip
  Vec3f normal;              // unit, front face, orthogonal to direction
  float length = 0;          // m, > 0
  float width = 0;           // m, > 0
  std::uint8_t variant = 0;  // 0..3: quadrant of the leaf atlas (docs/tree-format.md)
  friend bool operator==(const Leaf&, const Leaf&) = default;
};

// A conifer needle: a thin cylinder from base to tip.
struct Needle {
  std::uint32_t branch = 0;
  Vec3f base;        // m
  Vec3f tip;         // m
  float radius = 0;  // m, > 0
  friend bool operator==(const Needle&, const Needle&) = default;
};

// Linear RGB in [0, 1] (glTF baseColorFactor convention).
struct Color {
  float r = 0, g = 0, b = 0;
  friend bool operator==(const Color&, const Color&) = default;
};

// Texture references are file names inside the same artifact (e.g. "bark.png"); empty = none.
// The leaf atlas is 2x2: variant i occupies column i % 2, row i / 2 (row 0 at the image top).
struct Materials {
  std::string bark_texture;
  std::string leaf_texture;
  Color bark_color;
  Color leaf_color;
  friend bool operator==(const Materials&, const Materials&) = default;
};

struct Tree {
  std::string name;  // free text for people, e.g. "oak/adult seed 1"
  std::vector<Branch> branches;
  std::vector<Leaf> leaves;
  std::vector<Needle> needles;
  Materials materials;
  friend bool operator==(const Tree&, const Tree&) = default;
};

// Every broken invariant (see the top of this file), one message per problem, naming the
// element ("branch 7: parent 9 is not before it"). Empty when the tree is valid. Stops after
// `max_errors` messages.
std::vector<std::string> validate_tree(const Tree& tree, std::size_t max_errors = 20);

// True for a branch made by a split (same level as its parent), false for roots and laterals.
inline bool is_clone(const Tree& tree, const Branch& b) {
  return b.parent >= 0 && tree.branches[static_cast<std::size_t>(b.parent)].level == b.level;
}

// The point on the parent's axis a non-root branch grows from (m).
Vec3 attachment_point(const Tree& tree, const Branch& b);

}  // namespace sylva::tree
