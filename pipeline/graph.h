// The dependency graph of a recipe: nodes are Recipe::nodes indices, edges point from an input
// to the node that needs it. Ordering is deterministic (declaration order breaks ties).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/recipe.h"

namespace sylva {

// A cycle as node indices (each needs the next... in `needs` direction: a -> b means a needs b),
// or nullopt if the graph is acyclic. Deterministic: the cycle through the earliest node found.
std::optional<std::vector<std::size_t>> find_cycle(const Recipe& recipe);

class BuildGraph {
 public:
  explicit BuildGraph(const Recipe& recipe);  // recipe must be acyclic (the loader checks)

  std::size_t size() const { return inputs_.size(); }
  const std::vector<std::size_t>& inputs(std::size_t n) const { return inputs_[n]; }
  const std::vector<std::size_t>& dependents(std::size_t n) const { return dependents_[n]; }
  // Every node after all of its inputs; ties in declaration order (Kahn's algorithm).
  const std::vector<std::size_t>& topo_order() const { return order_; }
  // `targets` plus everything they transitively need, as a mask.
  std::vector<bool> closure(const std::vector<std::size_t>& targets) const;

 private:
  std::vector<std::vector<std::size_t>> inputs_, dependents_;
  std::vector<std::size_t> order_;
};

}  // namespace sylva
