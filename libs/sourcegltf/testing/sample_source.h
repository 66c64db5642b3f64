// Test data shared by the tests of imported trees (libs/sourcegltf, stages/lod, stages/mesh): a
// small imported model as an importer would produce it.
#pragma once

#include <string>

#include "libs/tree/source_geometry.h"

namespace sylva::sourcegltf::testing {

// Two primitives: "Tree/br0Trunk", a bark strip at x = 1 from y = 0 to 1 (two triangles, no
// normals or uvs, material 0 "BarkMat", opaque, colour (0.3, 0.2, 0.1)), and "Tree/lf0", one
// leaf triangle from y = 1 to 5 with uvs (material 1 "LeafMat", alpha MASK, double-sided,
// texture image 0 = sylva::test::tiny_png() named "leaf.png").
tree::SourceGeometry strip_and_leaf();

}  // namespace sylva::sourcegltf::testing
