// Pass 4 of recipe loading (docs/recipes.md, "Nodes"): one node entry, after matrix expansion,
// -> a NodeDecl: its name, its stage, its `with:` parameters converted against the stage's
// schema, recipe defaults and schema defaults filled in, and the stage's own parameter check.
#pragma once

#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "pipeline/diagnostic.h"
#include "pipeline/param_checker.h"
#include "pipeline/recipe.h"
#include "pipeline/registry.h"
#include "pipeline/yaml_tree.h"

namespace sylva {

// The recipe's `defaults:`: parameter name -> (its key, its value), from every file read.
using RecipeDefaults = std::map<std::string, std::pair<RawNode, RawNode>>;

// Where the recipe spells out the value at `path` (ParamProblem::path): the deepest node of it
// that `with` (a node's `with:`, may be null) or, for a parameter taken from there, `defaults`
// holds; `node_loc` for a parameter left at its schema default.
SourceLoc problem_loc(const std::vector<std::string>& path, const RawNode* with,
                      const RecipeDefaults& defaults, const SourceLoc& node_loc);

class NodeChecker {
 public:
  // `defaults` and `nodes` are not owned; checked nodes are appended to `nodes`.
  NodeChecker(const StageRegistry& registry, const SourceFiles& src, Diagnostics& diags, ParamChecker& params,
              const RecipeDefaults& defaults, std::vector<NodeDecl>& nodes)
      : reg_(registry), src_(src), diags_(diags), params_(params), defaults_(defaults), nodes_(nodes) {}

  void reserve(std::size_t entries) { node_loc_.reserve(entries); }

  // Checks the node `key: body` and appends it to `nodes` unless its name, its keys or its stage
  // is wrong (a node with bad parameters is still appended, so later passes see it; the errors
  // stop the load). Reports every problem found.
  void check(const RawNode& key, const RawNode& body);

  // After every node: reports each default that no stage declares, or that no stage this recipe
  // uses declares (almost certainly misspelled).
  void check_defaults() const;

  // Names checked so far, refused duplicates and bad stages included (the recipe's node count).
  std::size_t names_seen() const { return node_loc_.size(); }
  // Each node's `needs:` and `with:` as written, by node name, for the later passes.
  const std::map<std::string, RawNode>& needs_raw() const { return needs_raw_; }
  const std::map<std::string, RawNode>& with_raw() const { return with_raw_; }

 private:
  struct NodeKeys {
    const RawNode* stage = nullptr;
    const RawNode* with = nullptr;
    const RawNode* needs = nullptr;
  };

  // Reports an invalid, reserved or duplicate name; records a new one.
  bool check_name(const RawNode& key);
  NodeKeys find_keys(const RawNode& body, const std::string& node) const;
  // The stage `stage` names; nullptr (reported) if it is not one known stage name.
  const Stage* find_stage(const RawNode& stage) const;
  // Converts the node's `with:` parameters into node.params; `given` receives their names.
  void convert_with(const StageInfo& info, const RawNode* with, NodeDecl& node, std::set<std::string>& given);
  // Fills each parameter not in `given` from the recipe's defaults, else the schema's default;
  // reports a missing required one at `key`.
  void fill_unset(const StageInfo& info, const std::set<std::string>& given, NodeDecl& node,
                  const RawNode& key);

  const StageRegistry& reg_;
  const SourceFiles& src_;
  Diagnostics& diags_;
  ParamChecker& params_;
  const RecipeDefaults& defaults_;
  std::vector<NodeDecl>& nodes_;
  std::set<std::string> used_defaults_;
  std::unordered_map<std::string, SourceLoc> node_loc_;
  std::map<std::string, RawNode> needs_raw_;
  std::map<std::string, RawNode> with_raw_;  // each node's `with:`, for StageInfo::check_inputs
};

}  // namespace sylva
