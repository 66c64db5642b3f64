// `sylva explain` (executor.h explain_node): the same key computation as the build, compared with
// the action recorded when the node was last built (ninja's -d explain).
#include "pipeline/action.h"
#include "pipeline/executor.h"
#include "pipeline/graph.h"
#include "pipeline/out_dir.h"

namespace sylva {

std::vector<std::string> explain_node(const Recipe& recipe, const BuildEnv& env, const std::string& node) {
  ActionCache& actions = env.actions ? *env.actions : env.cache;
  BlobStore& blobs = env.blobs ? *env.blobs : env.cache;
  OutDir out(env.fs, blobs, env.out_dir);
  const std::size_t target = recipe.index_of(node);
  const BuildGraph graph(recipe);
  const auto wanted = graph.closure({target});
  std::vector<std::optional<std::vector<OutputEntry>>> outputs(recipe.nodes.size());
  std::vector<std::string> lines;
  for (std::size_t i : graph.topo_order()) {
    if (!wanted[i]) continue;
    const NodeDecl& nd = recipe.nodes[i];
    std::vector<std::vector<OutputEntry>> upstream;
    std::string stale_input;
    for (const auto& up : nd.needs) {
      const auto& o = outputs[recipe.index_of(up)];
      if (!o) stale_input = up;
      upstream.push_back(o.value_or(std::vector<OutputEntry>{}));
    }
    if (!stale_input.empty()) {
      if (i == target)
        lines.push_back("'" + node + "' will rebuild because its input '" + stale_input + "' will rebuild");
      continue;
    }
    std::string why;
    auto action = describe_action(recipe, i, upstream, out.digests(), &why);
    if (!action) {
      if (i == target) lines.push_back("'" + node + "' cannot be planned: " + why);
      continue;
    }
    if (auto hit = actions.lookup(action->key(), nd.stage->info().outputs)) {
      outputs[i] = hit->outputs;
      if (i == target)
        lines.push_back("'" + node + "' is up to date (action " + action->key().substr(0, 12) +
                        " is cached)");
      continue;
    }
    if (i != target) continue;
    auto text = env.fs.read(out.explain_record(node), nullptr, kMaxActionBytes);
    auto before = text ? ActionRecord::from_json(*text) : std::nullopt;
    if (!before) {
      lines.push_back("'" + node + "' will build: no earlier build of it is recorded and action " +
                      action->key().substr(0, 12) + " is not in the cache");
      continue;
    }
    auto diffs = explain_difference(*before, *action);
    if (diffs.empty())
      lines.push_back("'" + node +
                      "' will rebuild: its action is unchanged but its result is no longer in the cache");
    for (const auto& d : diffs) lines.push_back("'" + node + "' will rebuild: " + d);
  }
  return lines;
}

}  // namespace sylva
