// Matching runs over the checked nodes only (a refused node cannot be needed), and input types
// are checked after every pattern of a node is resolved, so each wrong input is reported once.
#include "pipeline/needs_resolver.h"

#include <fnmatch.h>

#include <algorithm>
#include <vector>

namespace sylva {
namespace {

// The node names `p` (a name or a glob pattern) matches, sorted; never `node` itself.
std::vector<std::string> match_pattern(const RawNode& p, const std::string& node, const Recipe& recipe,
                                       const std::vector<std::string>& names, const SourceFiles& src,
                                       Diagnostics& diags) {
  const bool glob = p.text.find_first_of("*?[") != std::string::npos;
  std::vector<std::string> matches;
  if (!glob) {
    if (p.text != node && recipe.find(p.text)) matches.push_back(p.text);
  } else {
    for (const auto& n : names)
      if (n != node && fnmatch(p.text.c_str(), n.c_str(), 0) == 0) matches.push_back(n);
  }
  std::sort(matches.begin(), matches.end());
  if (matches.empty()) {
    if (!glob && p.text == node)
      src.error(diags, p.loc, "dependency cycle: " + node + " -> " + node);
    else
      src.error(diags, p.loc,
                "missing input: " + std::string(glob ? "no node matches '" : "no node named '") + p.text +
                    "'" + (glob ? "" : did_you_mean(p.text, names)));
  }
  return matches;
}

// Resolves the node's `needs:` (`raw`, null when it has none) into node.needs; returns where
// input problems are reported: the `needs:` value, else the node's key.
SourceLoc resolve_patterns(NodeDecl& node, const RawNode* raw, const Recipe& recipe,
                           const std::vector<std::string>& names, const SourceFiles& src,
                           Diagnostics& diags) {
  std::vector<RawNode> patterns;
  SourceLoc where = node.loc;
  if (raw) {
    where = raw->loc;
    if (raw->is_scalar())
      patterns.push_back(*raw);
    else if (raw->is_seq())
      patterns = raw->items;
    else if (!raw->is_null())
      src.error(diags, raw->loc, "'needs' must be a node name, a pattern or a list of them");
  }
  for (const auto& p : patterns) {
    if (!p.is_scalar()) {
      src.error(diags, p.loc, "'needs' entries must be node names or patterns");
      continue;
    }
    for (auto& m : match_pattern(p, node.name, recipe, names, src, diags))
      if (std::find(node.needs.begin(), node.needs.end(), m) == node.needs.end()) node.needs.push_back(m);
  }
  return where;
}

// Checks the count and the output types of node.needs against the stage's InputSpec; returns
// the types in node.needs order and whether both were right.
bool check_inputs(const NodeDecl& node, const SourceLoc& where, const Recipe& recipe,
                  std::vector<std::string>& types, const SourceFiles& src, Diagnostics& diags) {
  const InputSpec& in = node.stage->info().inputs;
  const int count = static_cast<int>(node.needs.size());
  if (count < in.min || (in.max >= 0 && count > in.max)) {
    std::string want = in.max < 0         ? "at least " + std::to_string(in.min)
                       : in.min == in.max ? std::to_string(in.min)
                                          : std::to_string(in.min) + " to " + std::to_string(in.max);
    src.error(diags, where,
              "node '" + node.name + "' (stage '" + node.stage->info().name + "') needs " + want + " input" +
                  ((in.max < 0 ? in.min : in.max) == 1 ? "" : "s") + ", got " + std::to_string(count));
  }
  bool types_ok = !(count < in.min || (in.max >= 0 && count > in.max));
  for (const auto& up : node.needs) {
    const NodeDecl* u = recipe.find(up);
    const std::string& type = u->stage->info().output_type;
    types.push_back(type);
    if (std::find(in.types.begin(), in.types.end(), type) == in.types.end()) {
      types_ok = false;
      std::string accepted;
      for (const auto& t : in.types) accepted += (accepted.empty() ? "" : ", ") + t;
      src.error(diags, where,
                "node '" + node.name + "' cannot take '" + up + "' as input: stage '" +
                    node.stage->info().name + "' accepts " + (accepted.empty() ? "no inputs" : accepted) +
                    ", but '" + up + "' makes a " + type);
    }
  }
  return types_ok;
}

}  // namespace

void resolve_needs(Recipe& recipe, const std::map<std::string, RawNode>& needs_raw,
                   const std::map<std::string, RawNode>& with_raw, const RecipeDefaults& defaults,
                   const SourceFiles& src, Diagnostics& diags) {
  std::vector<std::string> names;
  for (const auto& n : recipe.nodes) names.push_back(n.name);
  for (auto& node : recipe.nodes) {
    const auto raw = needs_raw.find(node.name);
    const SourceLoc where =
        resolve_patterns(node, raw == needs_raw.end() ? nullptr : &raw->second, recipe, names, src, diags);
    std::vector<std::string> types;
    const bool types_ok = check_inputs(node, where, recipe, types, src, diags);
    const StageInfo& info = node.stage->info();
    if (info.check_inputs && types_ok && node.params.size() == info.params.size()) {
      const auto w = with_raw.find(node.name);
      for (const ParamProblem& p : info.check_inputs(node.params, types))
        src.error(diags, problem_loc(p.path, w == with_raw.end() ? nullptr : &w->second, defaults, node.loc),
                  param_problem_text(p));
    }
  }
}

}  // namespace sylva
