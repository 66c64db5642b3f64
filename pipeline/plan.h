// What a build is asked to do, decided before anything runs (ninja's Plan): which nodes are
// wanted (the targets and everything they transitively need; every node without targets).
// Deciding which of them are stale is per node, in the build loop (pipeline/executor.cpp), since a
// node's action key needs its inputs' outputs.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/graph.h"
#include "pipeline/recipe.h"

namespace sylva {

struct BuildPlan {
  std::vector<bool> wanted;  // per node index
  std::size_t total = 0;     // wanted nodes
};

// `targets`: node names or fnmatch globs; empty = every node. nullopt (and `error`: "unknown
// target 'x'; did you mean 'y'?") if a target matches no node.
std::optional<BuildPlan> plan_build(const Recipe& recipe, const BuildGraph& graph,
                                    const std::vector<std::string>& targets, std::string* error);

}  // namespace sylva
