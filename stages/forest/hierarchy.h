// Celba §4.5.3, the forest's spatial hierarchy: "Nodes are then subdivided by quad tree into
// groups with maximal number of nodes determined by NodesPerNode ... For each group higher level
// node is created carrying nodes with instance info as its children. Axis-aligned bounding box is
// computed for all nodes ... This process is repeated until only one node is created as top of
// hierarchy." Plus square streaming tiles (tile_size_m), which 3D Tiles and the renderer use.
#pragma once

#include <vector>

#include "libs/forest/instances.h"

namespace sylva::forest {

// The hierarchy over `boxes` (one per instance, world space): node 0 is the root, children
// listed in quadrant order; each node has at most nodes_per_node (>= 2) children. A quadrant is
// split while it holds more than nodes_per_node items (down to a size where its items' centres
// coincide, which then form one node however many they are). A level of nodes the quadtree
// cannot shrink (2 or 3 children per node, each item alone in its quadrant) is grouped in runs of
// nodes_per_node in quadrant order instead, so the root is always reached. Empty input: one empty
// leaf root.
std::vector<HierarchyNode> build_hierarchy(const std::vector<Box3>& boxes, int nodes_per_node);

// Assigns each instance to the square tile holding its position (tiles of size `tile_size_m`
// from `extent_min`); returns the non-empty tiles ordered by (iz, ix) and sets Instance::tile.
std::vector<Tile> build_tiles(std::vector<Instance>& instances, const std::vector<Box3>& boxes,
                              const std::array<double, 2>& extent_min, double tile_size_m);

}  // namespace sylva::forest
