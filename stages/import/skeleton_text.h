// The sylva text skeleton: a hand-writable tree skeleton, one node per line.
// The format is specified in docs/formats-skeleton.md; in short:
//
//   # comment (a '#' starts a comment anywhere on a line)
//   # branch parent x y z radius [parent_node [parent_t [level]]]
//   0 -1  0 0   0  0.20
//   0 -1  0 2.5 0  0.12
//   1  0  0 1.0 0  0.05  1
//   1  0  0.6 1.6 0 0.02
//
// Fields are separated by blanks. `branch` is any integer id >= 0; a branch's lines are
// consecutive and list its nodes from base to tip (>= 2 nodes). `parent` is the parent
// branch's id or -1 for a root. Coordinates are sylva's frame (metres, Y up); radius >= 0.
// The optional fields describe where a child grows from its parent (tree.h's parent_node,
// parent_t and level); they may be written on the branch's first line only (or repeated with
// the same values). Defaults: parent_node = the parent's node nearest to the child's first
// node (the lowest index on ties), parent_t = 0, level = the parent's level + 1.
// Branches come out in file order, except that a branch is moved after its parent if it was
// written before it (a stable topological order), so format_skeleton_text's output reads back
// as the same skeleton.
#pragma once

#include <string>
#include <string_view>

#include "libs/tree/tree.h"

namespace sylva::import {

// Parses a text skeleton into a tree with branches only (no foliage, default materials,
// name "text skeleton"). The result passes tree::validate_tree. Throws ImportError for
// malformed lines, non-finite numbers, negative radii, inconsistent or missing parents,
// parent cycles, branches with fewer than 2 nodes, attachment fields out of range, and an
// empty file. `source` names the text in messages.
tree::Tree parse_skeleton_text(std::string_view text, std::string_view source);

// Writes the branches of `tree` (which must be valid) in the text skeleton format: branch ids
// are the branch indices, every number in its shortest exact decimal form, and every non-root
// branch's first line carries parent_node, parent_t and level, so parsing the text gives back
// tree.branches exactly (foliage, materials and name are not part of the format).
std::string format_skeleton_text(const tree::Tree& tree);

}  // namespace sylva::import
