#include "pipeline/plan.h"

#include <fnmatch.h>

#include <algorithm>

#include "pipeline/diagnostic.h"

namespace sylva {

std::optional<BuildPlan> plan_build(const Recipe& recipe, const BuildGraph& graph,
                                    const std::vector<std::string>& targets, std::string* error) {
  const std::size_t n = recipe.nodes.size();
  BuildPlan plan;
  plan.wanted.assign(n, targets.empty());
  if (!targets.empty()) {
    std::vector<std::size_t> roots;
    for (const auto& t : targets) {
      bool any = false;
      for (std::size_t i = 0; i < n; ++i)
        if (fnmatch(t.c_str(), recipe.nodes[i].name.c_str(), 0) == 0) {
          roots.push_back(i);
          any = true;
        }
      if (!any) {
        if (error) {
          std::vector<std::string> names;
          for (const auto& nd : recipe.nodes) names.push_back(nd.name);
          *error = "unknown target '" + t + "'" + did_you_mean(t, names);
        }
        return std::nullopt;
      }
    }
    plan.wanted = graph.closure(roots);
  }
  plan.total = static_cast<std::size_t>(std::count(plan.wanted.begin(), plan.wanted.end(), true));
  return plan;
}

}  // namespace sylva
