// The full-detail model of a lod node: the tree it was built from, through the lod stage's own
// chain with epsilon = 0 (no merging, no decimation, every leaf and needle; stages/lod/chain.h
// build_full_detail), written as glTF the way the levels are. What `sylva lodcheck` and
// `sylva impostorcheck` measure LOD levels and impostors against.
#pragma once

#include <string>

#include "app/recipe_build.h"
#include "pipeline/recipe.h"

namespace sylva {

// GLB bytes of the full-detail model of `lod_node` (a built node of stage lod). With
// `branches_only` the leaves and needles are left out. Throws std::exception with a one-line
// message when the tree or the node's parameters cannot be read.
std::string lod_full_detail_glb(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& lod_node,
                                bool branches_only = false);

}  // namespace sylva
