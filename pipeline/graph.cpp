#include "pipeline/graph.h"

#include <algorithm>
#include <queue>

namespace sylva {

namespace {
std::vector<std::vector<std::size_t>> input_lists(const Recipe& r) {
  std::vector<std::vector<std::size_t>> in(r.nodes.size());
  for (std::size_t i = 0; i < r.nodes.size(); ++i)
    for (const auto& n : r.nodes[i].needs) {
      const std::size_t j = r.index_of(n);
      if (j < r.nodes.size()) in[i].push_back(j);
    }
  return in;
}
}  // namespace

std::optional<std::vector<std::size_t>> find_cycle(const Recipe& recipe) {
  const auto in = input_lists(recipe);
  enum { kWhite, kGrey, kBlack };
  std::vector<int> colour(in.size(), kWhite);
  std::vector<std::size_t> stack;
  std::optional<std::vector<std::size_t>> found;
  // Iterative DFS would be safer for very deep graphs; recipes are at most thousands of nodes.
  auto dfs = [&](auto&& self, std::size_t v) -> bool {
    colour[v] = kGrey;
    stack.push_back(v);
    for (std::size_t w : in[v]) {
      if (colour[w] == kGrey) {
        auto start = std::find(stack.begin(), stack.end(), w);
        found = std::vector<std::size_t>(start, stack.end());
        return true;
      }
      if (colour[w] == kWhite && self(self, w)) return true;
    }
    stack.pop_back();
    colour[v] = kBlack;
    return false;
  };
  for (std::size_t v = 0; v < in.size(); ++v)
    if (colour[v] == kWhite && dfs(dfs, v)) return found;
  return std::nullopt;
}

BuildGraph::BuildGraph(const Recipe& recipe) : inputs_(input_lists(recipe)) {
  const std::size_t n = inputs_.size();
  dependents_.resize(n);
  std::vector<std::size_t> pending(n);
  for (std::size_t i = 0; i < n; ++i) {
    pending[i] = inputs_[i].size();
    for (std::size_t j : inputs_[i]) dependents_[j].push_back(i);
  }
  std::priority_queue<std::size_t, std::vector<std::size_t>, std::greater<>> ready;
  for (std::size_t i = 0; i < n; ++i)
    if (pending[i] == 0) ready.push(i);
  while (!ready.empty()) {
    const std::size_t v = ready.top();
    ready.pop();
    order_.push_back(v);
    for (std::size_t d : dependents_[v])
      if (--pending[d] == 0) ready.push(d);
  }
}

std::vector<bool> BuildGraph::closure(const std::vector<std::size_t>& targets) const {
  std::vector<bool> mask(size(), false);
  std::vector<std::size_t> work(targets);
  while (!work.empty()) {
    const std::size_t v = work.back();
    work.pop_back();
    if (mask[v]) continue;
    mask[v] = true;
    for (std::size_t w : inputs_[v]) work.push_back(w);
  }
  return mask;
}

}  // namespace sylva
