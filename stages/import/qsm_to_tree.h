// Cylinder table -> tree skeleton (libs/tree). Pure: no I/O.
//
// Rules (docs/stages/import.md states them for users):
//   - Frame: QSM files are Z up; sylva is Y up, right-handed: (x, y, z) -> (x, z, -y), then
//     multiplied by `scale`, then translated so the root cylinder's start is the origin when
//     `recenter` is set.
//   - Branches: a child cylinder *continues* its parent's branch when it agrees with the parent
//     on every key column the table has (branch id, branch order); when several children
//     qualify, the thickest continues (ties: the earlier row); every other child starts a new
//     branch. Without key columns the thickest child continues. This is exact for TreeQSM
//     (branch column) and SimpleForest/rTwig (exactly one same-order child at each fork).
//   - Nodes: the start of a branch's first cylinder, then the end of each of its cylinders.
//     Node radius: the first and last node take their cylinder's radius, an inner node the
//     mean of the two cylinders meeting there. A cylinder of zero length adds no node.
//   - Attachment: a new branch grows from its first cylinder's parent cylinder, at the point
//     of that cylinder's axis nearest to the child's start (parent_node + parent_t).
//   - Level: with a branch order column, the order minus the root's order (it must be the
//     parent branch's level or one more); without one, the parent's level + 1.
//   - Branch order in the result: breadth first from the trunk; the children of a branch in
//     the order of their parent cylinders along it, then in file order. Parents precede
//     children.
#pragma once

#include "libs/tree/tree.h"
#include "stages/import/qsm_table.h"

namespace sylva::import {

enum class UpAxis { kZ, kY };

struct QsmToTreeOptions {
  UpAxis up = UpAxis::kZ;  // the file's up axis; kY files are taken as they are
  double scale = 1.0;      // file units -> metres (0.001 for millimetres); > 0
  bool recenter = true;    // move the root cylinder's start to the origin
};

// Builds the skeleton of `table` (as returned by parse_cylinder_table, so its topology is
// already checked). The result passes tree::validate_tree. Throws ImportError (at the line of
// the offending row) when a branch has zero length or a branch order jumps by more than one.
// `source` names the file in messages. O(cylinders) time and memory.
tree::Tree qsm_to_tree(const CylinderTable& table, std::string_view source,
                       const QsmToTreeOptions& options = {});

}  // namespace sylva::import
