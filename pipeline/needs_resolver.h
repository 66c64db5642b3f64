// Pass 5 of recipe loading (docs/recipes.md, "needs"): each node's `needs:` names and glob
// patterns -> upstream node names, then the stage's input count, input types and its own
// input check (StageInfo::check_inputs).
#pragma once

#include <map>
#include <string>

#include "pipeline/diagnostic.h"
#include "pipeline/node_checker.h"
#include "pipeline/recipe.h"
#include "pipeline/yaml_tree.h"

namespace sylva {

// Fills NodeDecl::needs of every node of `recipe` (indexed: Recipe::reindex) from `needs_raw`
// (node name -> its `needs:` as written; a node without one needs nothing): plain names in
// pattern order, each pattern's matches sorted, duplicates dropped, never the node itself.
// Reports a pattern that matches nothing, a node needing itself, a wrong input count or type,
// and the problems check_inputs finds (located through `with_raw` and `defaults`, problem_loc).
void resolve_needs(Recipe& recipe, const std::map<std::string, RawNode>& needs_raw,
                   const std::map<std::string, RawNode>& with_raw, const RecipeDefaults& defaults,
                   const SourceFiles& src, Diagnostics& diags);

}  // namespace sylva
