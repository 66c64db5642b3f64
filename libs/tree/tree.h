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
//     unit length (1e-3) and orthogonal (1e-3), variant < the leaf atlas's cell count; needle
//     radius > 0;
//   - materials: the leaf atlas has 1..16 columns and rows, its cell coverage list is empty or
//     holds one value in [0, 1] per cell, the bark tint is in [0, 1] with from <= to;
//   - the name and the texture references are at most kMaxTextBytes bytes (the .sylt limit).
//   - source: the imported mesh's invariants (source_geometry.h, validate_source_geometry()).
// A child's first node is its first cross-section, *not* the attachment point: the segment from
// the attachment point to nodes[0] is implicit (Nystad's DAG edge from the prepended node to the
// child's root segment). For generated trees parent_t is 0 and the attachment node is a
// *junction*; see docs/tree-format.md for the da Vinci relation generated junctions satisfy.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/tree/source_geometry.h"
#include "libs/tree/vec3.h"

namespace sylva::tree {

struct Node {
  Vec3 position;      // m, object space
  double radius = 0;  // m, >= 0
  friend bool operator==(const Node&, const Node&) = default;
};

struct Branch {
  std::int32_t parent = -1;       // branch index (< own index) or -1 for a root
  std::uint32_t parent_node = 0;  // node of the parent it grows from (0 for roots)
  double parent_t = 0;            // [0, 1] along parent segment parent_node -> parent_node + 1
  std::uint32_t level = 0;        // trunk 0; clone = parent's level; lateral = parent's + 1
  std::vector<Node> nodes;        // base to tip, >= 2
  friend bool operator==(const Branch&, const Branch&) = default;
};

// A flat leaf quad: one leaf, or a card showing a twig or a shoot (Materials::leaf_kind). It
// spans `length` along `direction` from `position` (the petiole end, or the twig's base) and
// `width` across cross(normal, direction); texture v runs from that end (v low) to the tip, in
// the atlas cell of `variant` (libs/tree/foliage.h: atlas_cell()).
struct Leaf {
  std::uint32_t branch = 0;  // branch it grows on
  Vec3f position;            // m, petiole end of the blade
  Vec3f direction;           // unit, petiole -> tip
  Vec3f normal;              // unit, front face, orthogonal to direction
  float length = 0;          // m, > 0
  float width = 0;           // m, > 0
  std::uint8_t variant = 0;  // cell of the leaf atlas, < Materials::atlas_cells()
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

// What a leaf quad shows (all leaves of a tree are of one kind).
//   kLeaves      one leaf per quad (the atlas holds single leaves);
//   kTwigCards   a card: a twig with several leaves, petioles and its stem (broadleaves);
//   kShootCards  a card: a conifer shoot with its needles.
// With cards, a branch that carries cards and has no children is drawn by its cards (each card
// shows its piece of the twig): twigs_drawn_by_cards() in foliage.h, used by mesh and lod.
enum class LeafKind : std::uint8_t { kLeaves = 0, kTwigCards = 1, kShootCards = 2 };

// Texture references are file names inside the same artifact (e.g. "bark.png"); empty = none.
// The leaf atlas is a grid of atlas_columns x atlas_rows cells; variant i occupies column
// i % atlas_columns, row i / atlas_columns (row 0 at the image top); foliage.h's atlas_cell()
// is the one definition of that layout. cell_coverage[i] is the fraction of cell i's rectangle
// covered by leaf blades (or needles) — not stems or petioles — so that a quad of area A carries
// A * cell_coverage[variant] m^2 of one-sided leaf area; empty = 1 for every cell.
// Bark tint: the bark is multiplied by bark_tint below bark_tint_from_m (height above the tree's
// base, m), by white above bark_tint_to_m, smoothly between (e.g. a Scots pine's grey-brown
// lower trunk under its orange upper bark); bark_tint white = no tint.
struct Materials {
  std::string bark_texture;
  std::string leaf_texture;
  Color bark_color;
  Color leaf_color;
  LeafKind leaf_kind = LeafKind::kLeaves;
  std::uint8_t atlas_columns = 2;
  std::uint8_t atlas_rows = 2;
  std::vector<float> cell_coverage;  // empty or atlas_columns * atlas_rows values in [0, 1]
  Color bark_tint{1, 1, 1};
  float bark_tint_from_m = 0;
  float bark_tint_to_m = 0;
  std::size_t atlas_cells() const { return std::size_t(atlas_columns) * atlas_rows; }
  friend bool operator==(const Materials&, const Materials&) = default;
};

// The longest name or texture reference a tree may have (bytes): what .sylt stores.
inline constexpr std::size_t kMaxTextBytes = 1 << 16;

struct Tree {
  std::string name;  // free text for people, e.g. "oak/adult seed 1"; <= kMaxTextBytes
  std::vector<Branch> branches;
  std::vector<Leaf> leaves;
  std::vector<Needle> needles;
  Materials materials;
  SourceGeometry source;  // an imported mesh as the file had it; empty for generated and QSM trees
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
