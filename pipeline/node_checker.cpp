// A node is checked as far as it can be: a bad parameter does not stop the others from being
// converted, and the stage's own check runs only when every parameter converted (it may assume
// a complete, typed parameter set).
#include "pipeline/node_checker.h"

#include <algorithm>

namespace sylva {
namespace {

// Node names that would clash with the out dir's own bookkeeping (.sylva/, .<node>.tmp.*):
// refused, so publishing into out/<recipe>/<node>/ can never replace or delete them.
bool reserved_node_name(const std::string& n) { return n.front() == '.'; }

const ParamSpec* find_param(const StageInfo& info, const std::string& name) {
  for (const auto& p : info.params)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace

SourceLoc problem_loc(const std::vector<std::string>& path, const RawNode* with,
                      const RecipeDefaults& defaults, const SourceLoc& node_loc) {
  if (path.empty()) return node_loc;
  const RawNode* at = nullptr;
  if (with && with->is_map())
    for (const auto& [k, v] : with->entries)
      if (k.text == path[0]) at = &v;
  if (!at)
    if (auto d = defaults.find(path[0]); d != defaults.end()) at = &d->second.second;
  if (!at) return node_loc;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const RawNode* next = nullptr;
    if (at->is_map()) {
      for (const auto& [k, v] : at->entries)
        if (k.text == path[i]) next = &v;
    } else if (at->is_seq() && !path[i].empty() && path[i].size() < 10 &&
               path[i].find_first_not_of("0123456789") == std::string::npos) {
      const std::size_t index = std::stoul(path[i]);
      if (index < at->items.size()) next = &at->items[index];
    }
    if (!next) break;
    at = next;
  }
  return at->loc;
}

void NodeChecker::check(const RawNode& key, const RawNode& body) {
  if (!check_name(key)) return;
  NodeDecl node;
  node.name = key.text;
  node.loc = key.loc;
  if (!body.is_map()) {
    src_.error(diags_, body.loc, "node '" + key.text + "' must be a map with 'stage', 'needs' and 'with'");
    return;
  }
  const NodeKeys keys = find_keys(body, node.name);
  if (!keys.stage) {
    src_.error(diags_, key.loc, "node '" + node.name + "' has no 'stage'");
    return;
  }
  node.stage = find_stage(*keys.stage);
  if (!node.stage) return;
  const StageInfo& info = node.stage->info();
  std::set<std::string> given;
  convert_with(info, keys.with, node, given);
  fill_unset(info, given, node, key);
  if (info.check && node.params.size() == info.params.size()) {
    for (const ParamProblem& p : info.check(node.params))
      src_.error(diags_, problem_loc(p.path, keys.with, defaults_, key.loc), param_problem_text(p));
  }
  if (keys.needs) needs_raw_.emplace(node.name, *keys.needs);
  if (keys.with) with_raw_.emplace(node.name, *keys.with);
  nodes_.push_back(std::move(node));
}

bool NodeChecker::check_name(const RawNode& key) {
  if (!key.is_scalar() || !is_valid_name(key.text)) {
    src_.error(diags_, key.loc,
               "invalid node name '" + excerpt(key.text) +
                   "': use letters, digits, '_', '-' and '.' (no path separators)");
    return false;
  }
  if (reserved_node_name(key.text)) {
    src_.error(diags_, key.loc,
               "reserved node name '" + key.text +
                   "': names starting with '.' belong to sylva's bookkeeping in the out dir");
    return false;
  }
  if (auto it = node_loc_.find(key.text); it != node_loc_.end()) {
    src_.error(diags_, key.loc,
               "duplicate node '" + key.text + "' (first defined at " + it->second.prefix() + ")");
    return false;
  }
  node_loc_.emplace(key.text, key.loc);
  return true;
}

NodeChecker::NodeKeys NodeChecker::find_keys(const RawNode& body, const std::string& node) const {
  static const std::vector<std::string> kNodeKeys = {"stage", "needs", "with", "matrix", "description"};
  NodeKeys keys;
  for (const auto& [k, v] : body.entries) {
    if (std::find(kNodeKeys.begin(), kNodeKeys.end(), k.text) == kNodeKeys.end()) {
      src_.error(
          diags_, k.loc,
          "unknown key '" + excerpt(k.text) + "' in node '" + node + "'" + did_you_mean(k.text, kNodeKeys));
      continue;
    }
    const RawNode** slot = k.text == "stage"   ? &keys.stage
                           : k.text == "with"  ? &keys.with
                           : k.text == "needs" ? &keys.needs
                                               : nullptr;
    if (!slot) continue;
    if (*slot)
      src_.error(diags_, k.loc, "duplicate key '" + k.text + "' in node '" + node + "'");
    else
      *slot = &v;
  }
  return keys;
}

const Stage* NodeChecker::find_stage(const RawNode& stage) const {
  if (!stage.is_scalar()) {
    src_.error(diags_, stage.loc,
               "'stage' must be one stage name, got a " + std::string(stage.kind_name()) +
                   (stage.is_seq() && stage.items.size() == 1 && stage.items[0].is_scalar()
                        ? " (write 'stage: " + excerpt(stage.items[0].text) + "')"
                        : std::string()));
    return nullptr;
  }
  const Stage* found = reg_.find(stage.text);
  if (!found)
    src_.error(diags_, stage.loc,
               "unknown stage '" + excerpt(stage.text) + "'" + did_you_mean(stage.text, reg_.names()));
  return found;
}

void NodeChecker::convert_with(const StageInfo& info, const RawNode* with, NodeDecl& node,
                               std::set<std::string>& given) {
  if (!with || with->is_null()) return;
  if (!with->is_map()) {
    src_.error(diags_, with->loc, "'with' must be a map of parameter name to value");
    return;
  }
  for (const auto& [k, v] : with->entries) {
    const ParamSpec* spec = find_param(info, k.text);
    if (!spec) {
      std::vector<std::string> names;
      for (const auto& p : info.params) names.push_back(p.name);
      src_.error(diags_, k.loc,
                 "unknown parameter '" + excerpt(k.text) + "' for stage '" + info.name + "'" +
                     did_you_mean(k.text, names));
      continue;
    }
    if (!given.insert(k.text).second) {
      src_.error(diags_, k.loc, "duplicate parameter '" + k.text + "'");
      continue;
    }
    if (auto val = params_.convert(*spec, v, "parameter '" + k.text + "'", &node))
      node.params.emplace(k.text, std::move(*val));
  }
}

void NodeChecker::fill_unset(const StageInfo& info, const std::set<std::string>& given, NodeDecl& node,
                             const RawNode& key) {
  for (const auto& spec : info.params) {
    if (given.count(spec.name)) continue;
    if (auto d = defaults_.find(spec.name); d != defaults_.end()) {
      used_defaults_.insert(spec.name);
      if (auto val = params_.convert(spec, d->second.second, "default '" + spec.name + "'", &node))
        node.params.emplace(spec.name, std::move(*val));
    } else if (spec.required()) {
      src_.error(diags_, key.loc,
                 "node '" + node.name + "' (stage '" + info.name + "') is missing required parameter '" +
                     spec.name + "'");
    } else {
      node.params.emplace(spec.name, spec.default_value);
    }
  }
}

void NodeChecker::check_defaults() const {
  std::vector<std::string> all;
  for (const auto* s : reg_.all())
    for (const auto& p : s->info().params) all.push_back(p.name);
  for (const auto& [name, kv] : defaults_) {
    if (used_defaults_.count(name)) continue;
    const bool anywhere = std::find(all.begin(), all.end(), name) != all.end();
    bool declared_by_used_stage = false;
    for (const auto& n : nodes_)
      if (find_param(n.stage->info(), name)) declared_by_used_stage = true;
    if (!anywhere)
      src_.error(diags_, kv.first.loc,
                 "unknown parameter '" + name + "' in defaults" + did_you_mean(name, all));
    else if (!declared_by_used_stage)
      src_.error(diags_, kv.first.loc,
                 "default '" + name + "' is not a parameter of any stage this recipe uses");
  }
}

}  // namespace sylva
